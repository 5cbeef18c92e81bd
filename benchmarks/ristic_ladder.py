"""Where Ristic et al.'s success is lost: an oracle ladder on the paper's lattice.

    nice -n 10 python benchmarks/ristic_ladder.py --runs 100 --out benchmarks/ristic_ladder.csv
    python benchmarks/ristic_ladder.py --table benchmarks/ristic_ladder.csv

On ``ristic-lattice-paper`` (the one lattice of the paper's Fig. 2 as described; every run
differs only in noise, slips and the filter's randomness), the paper's searcher ``rbpf``
(N = 4000, M = 400) is given more and more of the truth, one rung at a time:

1. the map known, and the lattice's own field ``A0 F`` in the filter (the truth's model);
2. the map known, the paper's conformal approximation, eq. (25);
3. the map unknown, eq. (25), and perfect self-localisation (``localisation: known``:
   every reading carries the true node);
4. the map unknown and the position estimated (the full paper set-up).

and, to separate the model from the control, rung 1 with the ``path`` planner (shortest
paths on the known map toward the source particles) instead of the one-step gain.
Success as in the paper (Sec. 5.1: on the source within 100 steps and self-localised);
``reached``: on the source within 100 steps, localised or not.

``--experiment control`` keeps rung 1 and changes one setting of the control at a time
(ideal measurements drawn instead of the mean, no anti-oscillation rule, no stay, M = 4000);
``--experiment stay`` runs the paper's set-up with and without the stay control;
``--experiment controls`` scores Algorithm 2's five controls every step;
``--experiment sensor`` changes the reach of the link sensor (secondary links uninformative,
or seen perfectly);
``--experiment lattices`` runs rung 1 on ten lattices with every property the paper states
of its Fig. 2.

**One seed stream for every rung.** Run ``i`` of every rung has the episode seed of seed
index ``i`` of the reproduce campaign ``reproduce ristic2014-table1 --protocol paper``
(``reciprocity.campaign.spec.episode_seed`` of that table's campaign seed and ``i``), so
rung 4 at source (0, 7) runs the table's row (0, 7) episode for episode, and the rungs
differ only in what the searcher is given. ``--stream integers`` takes the seeds 0, 1, 2,
... instead (the stream of the ladder's first runs), to measure what the stream changes.

Rows are appended to ``--out`` as episodes finish, seed index by seed index with every
chosen rung in turn (so a run cut short covers the rungs alike); the same command again
resumes. ``--minutes M`` starts no new episode after M minutes. The table gives, per rung,
success and reached with Wilson 95 % intervals, the runs that reached the source but
failed the self-localisation test, the mean steps of the successes with a Student-t
95 % interval, and the differences between rungs with Newcombe's 95 % interval for a
difference of two independent proportions (his method 10, from the Wilson intervals).
Results: ``docs/papers/ristic2014.md``.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats

#: Rung 1 with one setting of the control changed at a time (``--experiment control``).
_KNOWN = {"map": "known", "field": "lattice"}
CONTROL = (
    ("1. as the paper (one-step gain, ideal = mean, loop rule 10/3, stay allowed)", _KNOWN, {"map": "known"}),
    ("1a. ideal measurements drawn from G(eta, theta) (Sec. 4.3)", {**_KNOWN, "ideal": "sample"}, {"map": "known"}),
    ("1b. no anti-oscillation rule", {**_KNOWN, "loop_visits": 10_000}, {"map": "known"}),
    ("1c. stay only when no move is admissible", {**_KNOWN, "stay": False}, {"map": "known"}),
    ("1d. M = 4000 ideal measurements", {**_KNOWN, "n_gain": 4000}, {"map": "known"}),
)

#: The paper's set-up with the one control setting that mattered on rung 1 (``--experiment stay``).
STAY = (
    ("4. the paper: map unknown, eq. (25)", {}, {}),
    ("4c. as 4, stay only when no move is admissible", {"stay": False}, {}),
)

#: The five controls of Algorithm 2 scored every step (``--experiment controls``).
FIVE = (
    ("1e. rung 1, all five controls scored", {**_KNOWN, "controls": "all"}, {"map": "known"}),
    ("4e. the paper's set-up, all five controls scored", {"controls": "all"}, {}),
)

#: The link sensor's reach, which the paper fixes (primary p_d 1, p_fa 0; secondary 0.8, 0.1)
#: but whose effect it does not show (``--experiment sensor``): the paper's set-up with the
#: secondary links unobservable in effect (p_d = p_fa = 0.5 carries no information), and
#: with them seen perfectly.
SENSOR = (
    ("4. the paper: secondary links p_d 0.8, p_fa 0.1", {}, {}),
    ("4f. primary links only (secondary p_d = p_fa = 0.5)", {}, {"secondary": [0.5, 0.5]}),
    ("4g. secondary links seen perfectly (p_d 1, p_fa 0)", {}, {"secondary": [1.0, 0.0]}),
)

#: Ten lattices with every property the paper states of its Fig. 2 (R0 = 9, p = 0.35 within
#: 0.01, connected, shortest paths 20, 14 and 8 from the entry): the first ten lattice seeds
#: that ``benchmarks/ristic_lattice_search.py`` accepts (32 is ``ristic-fig2``, the scenario's).
FIG2_LIKE_SEEDS = (32, 69, 120, 136, 151, 212, 250, 300, 305, 313)

#: Rung 1 (map known, the lattice's own field) on each of those lattices
#: (``--experiment lattices``): is the scenario's lattice a hard one?
LATTICES = tuple((f"1L{s}. rung 1 on lattice_seed {s}", {"map": "known", "field": "lattice"},
                  {"map": "known", "links": None, "lattice_seed": s}) for s in FIG2_LIKE_SEEDS)

RUNGS = (
    ("1. map known, lattice field", {"map": "known", "field": "lattice"}, {"map": "known"}),
    ("1'. as 1, path planner", {"map": "known", "field": "lattice", "planner": "path"}, {"map": "known"}),
    ("2. map known, eq. (25)", {"map": "known"}, {"map": "known"}),
    ("3. map unknown, eq. (25), perfect self-localisation", {}, {"localisation": "known"}),
    ("4. the paper: map unknown, eq. (25)", {}, {}),
)


#: The rows of each experiment (``--experiment``).
EXPERIMENTS = {"ladder": RUNGS, "control": CONTROL, "stay": STAY, "controls": FIVE, "sensor": SENSOR,
               "lattices": LATTICES}
#: Differences reported along the ladder, ``(a, b, what changes from a to b)``, printed as
#: rate(a) − rate(b): what the change costs; in the other experiments, each row minus the first.
LADDER_STEPS = (("1'", "1", "the one-step control instead of shortest paths"),
                ("1", "2", "eq. (25) instead of the lattice's own field"),
                ("2", "3", "the map unknown"),
                ("3", "4", "the position estimated instead of known"))
#: Columns of the results CSV.
FIELDS = ["experiment", "rung", "stream", "source", "seed_index", "seed", "success", "reached", "steps",
          "wall_s"]
#: Streams of episode seeds (``--stream``).
STREAMS = ("campaign", "integers")
#: Most runs per rung.
MAX_RUNS = 10_000
#: The table whose episodes the ``campaign`` stream repeats.
TABLE = "ristic2014-table1"
SCENARIO = "ristic-lattice-paper"


def rung_id(label: str) -> str:
    """The short name of a row (``"1'"`` of ``"1'. as 1, path planner"``)."""
    return label.split(" ")[0].rstrip(".")


def episode_seeds(stream: str, runs: int) -> list[int]:
    """The episode seeds of seed indices ``0 ... runs - 1``.

    Parameters
    ----------
    stream : {"campaign", "integers"}
        ``campaign``: those of ``reproduce ristic2014-table1 --protocol paper`` (its
        campaign seed through ``episode_seed``); ``integers``: 0, 1, 2, ...
    runs : int
        Number of seeds.

    Returns
    -------
    list of int
    """
    if stream == "integers":
        return list(range(runs))
    from reciprocity.campaign.reproduce import TABLES
    from reciprocity.campaign.spec import episode_seed
    campaign = TABLES[TABLE].protocol("paper").spec(1).seed
    return [episode_seed(campaign, i) for i in range(runs)]


def one(job) -> tuple[bool, int, bool]:
    """``(success, steps, reached)`` of one episode ``(params, world, seed)``."""
    params, world, seed = job
    from reciprocity.api import execute
    s = execute(SCENARIO, "rbpf", seed=seed, params=params, world=world)[0].summary
    return bool(s["success"]), int(s["steps"]), bool(s.get("reached", s["distance_at_stop"] == 0.0))


def run(experiment: str, rungs: list[str], stream: str, source: tuple[int, int], runs: int, out: Path,
        minutes: float | None = None, workers: int = 1) -> int:
    """Run (or resume) the chosen rungs, appending a row to `out` per finished episode.

    Parameters
    ----------
    experiment : str
        A key of :data:`EXPERIMENTS`.
    rungs : list of str
        Row names (:func:`rung_id`) of that experiment.
    stream : {"campaign", "integers"}
        Seed stream (:func:`episode_seeds`).
    source : (int, int)
        Source node, lattice units.
    runs : int
        Runs per rung (seed indices ``0 ... runs - 1``).
    out : Path
        Results CSV (:data:`FIELDS`); rows already there are not run again.
    minutes : float, optional
        Start no new episode after this many minutes.
    workers : int
        Processes; 1 runs in this one.

    Returns
    -------
    int
        Episodes run by this call.
    """
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from resumable import appending, deadline, done_keys
    where = f"{source[0]},{source[1]}"
    done = done_keys(out, lambda r: (r["experiment"], r["rung"], r["stream"], r["source"], int(r["seed_index"])))
    rows = {rung_id(label): (params, world) for label, params, world in EXPERIMENTS[experiment]}
    todo = [(i, seed, r) for i, seed in enumerate(episode_seeds(stream, runs)) for r in rungs
            if (experiment, r, stream, where, i) not in done]
    jobs = [(rows[r][0], {**rows[r][1], "source": list(source)}, seed) for _, seed, r in todo]
    expired = deadline(minutes)
    pool = None
    if workers > 1:
        from concurrent.futures import ProcessPoolExecutor
        pool = ProcessPoolExecutor(workers)
    n = 0
    try:
        results = pool.map(one, jobs) if pool else map(one, jobs)
        with appending(out, FIELDS) as w:
            t0 = time.perf_counter()
            for (i, seed, r), (ok, steps, reached) in zip(todo, results):
                w.writerow(dict(experiment=experiment, rung=r, stream=stream, source=where, seed_index=i,
                                seed=seed, success=ok, reached=reached, steps=steps,
                                wall_s=round(time.perf_counter() - t0, 2)))
                w.file.flush()
                n += 1
                t0 = time.perf_counter()
                if expired():
                    break
    finally:
        if pool:
            pool.shutdown(cancel_futures=True)
    return n


def wilson(k: int, n: int) -> tuple[float, float, float]:
    """Rate ``k / n`` and its Wilson 95 % interval (scipy's ``binomtest``)."""
    ci = stats.binomtest(k, n).proportion_ci(method="wilson")
    return k / n, float(ci.low), float(ci.high)


def newcombe(k1: int, n1: int, k2: int, n2: int) -> tuple[float, float, float]:
    """Difference ``k1/n1 - k2/n2`` of two independent rates and its 95 % interval,
    Newcombe's hybrid score interval (method 10 of Newcombe, Stat. Med. 17, 873, 1998)."""
    p1, l1, u1 = wilson(k1, n1)
    p2, l2, u2 = wilson(k2, n2)
    d = p1 - p2
    return d, d - math.hypot(p1 - l1, u2 - p2), d + math.hypot(u1 - p1, p2 - l2)


def t_interval(x) -> tuple[float, float, float]:
    """Mean of `x` and its Student-t 95 % interval (nan bounds with fewer than two values)."""
    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return float("nan"), float("nan"), float("nan")
    m = float(x.mean())
    if x.size < 2:
        return m, float("nan"), float("nan")
    half = float(stats.t.ppf(0.975, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size))
    return m, m - half, m + half


def _pct(p: float, lo: float, hi: float) -> str:
    return f"{100 * p:.0f} % [{100 * lo:.0f}, {100 * hi:.0f}]"


def table(out: Path, experiment: str = "ladder", stream: str = "campaign", source: str = "0,7",
          runs: int | None = None) -> str:
    """The markdown table of the rows of `out` for one experiment, stream and source.

    Parameters
    ----------
    out : Path
        Results CSV written by :func:`run`.
    experiment, stream : str
        Which rows.
    source : str
        Source node as written in the CSV (``"0,7"``).
    runs : int, optional
        Only seed indices below this; default: all rows.

    Returns
    -------
    str
        Per rung: runs, success, reached, reached but not self-localised (Wilson 95 %),
        mean steps of the successes (Student-t 95 %); then the differences between rungs
        (:data:`LADDER_STEPS`, or each row against the first) in percentage points with
        Newcombe's 95 % interval.
    """
    with out.open() as f:
        rows = [r for r in csv.DictReader(f) if r["experiment"] == experiment and r["stream"] == stream
                and r["source"] == source and (runs is None or int(r["seed_index"]) < runs)]
    labels = {rung_id(label): label for label, _, _ in EXPERIMENTS[experiment]}
    per = {}
    for r in rows:
        per.setdefault(r["rung"], []).append(r)
    per = {k: per[k] for k in labels if k in per}
    count = {}
    lines = ["| rung | runs | success | reached | reached, not self-localised | mean steps (successes) |",
             "|---|---:|---|---|---|---|"]
    for k, sel in per.items():
        n = len(sel)
        ok = sum(r["success"] == "True" for r in sel)
        hit = sum(r["reached"] == "True" for r in sel)
        count[k] = (ok, hit, n)
        m, lo, hi = t_interval([int(r["steps"]) for r in sel if r["success"] == "True"])
        lines.append(f"| {labels[k]} | {n} | {_pct(*wilson(ok, n))} | {_pct(*wilson(hit, n))} | "
                     f"{_pct(*wilson(hit - ok, n))} | {m:.1f} [{lo:.1f}, {hi:.1f}] |")
    steps = LADDER_STEPS if experiment == "ladder" else [
        (k, first, "") for first in list(per)[:1] for k in list(per)[1:]]
    pairs = [(a, b, what) for a, b, what in steps if a in count and b in count]
    if pairs:
        lines += ["", "| difference | what changes | success (points) | reached (points) |", "|---|---|---|---|"]
        for a, b, what in pairs:
            (oa, ha, na), (ob, hb, nb) = count[a], count[b]
            ds, dr = newcombe(oa, na, ob, nb), newcombe(ha, na, hb, nb)
            lines.append(f"| {a} − {b} | {what} | {100 * ds[0]:+.0f} [{100 * ds[1]:+.0f}, {100 * ds[2]:+.0f}] | "
                         f"{100 * dr[0]:+.0f} [{100 * dr[1]:+.0f}, {100 * dr[2]:+.0f}] |")
    return "\n".join(lines)


def streams(out: Path, experiment: str = "ladder", source: str = "0,7") -> str:
    """Per rung, the ``integers`` stream against the ``campaign`` stream in the rows of `out`.

    Parameters
    ----------
    out : Path
        Results CSV written by :func:`run`.
    experiment : str
        Which rows.
    source : str
        Source node as written in the CSV (``"0,7"``).

    Returns
    -------
    str
        A markdown table: per rung, the runs and success and reached rates of each stream,
        and their differences (integers − campaign, percentage points) with Newcombe's 95 %
        interval. The two streams hold different episodes, so a difference whose interval
        holds 0 is what sampling alone would give.
    """
    with out.open() as f:
        rows = [r for r in csv.DictReader(f) if r["experiment"] == experiment and r["source"] == source]
    lines = ["| rung | integers: runs, success, reached | campaign: runs, success, reached "
             "| success, integers − campaign (points) | reached, integers − campaign (points) |",
             "|---|---|---|---|---|"]
    for label, _, _ in EXPERIMENTS[experiment]:
        k = rung_id(label)
        count = {}
        for stream in STREAMS:
            sel = [r for r in rows if r["rung"] == k and r["stream"] == stream]
            count[stream] = (sum(r["success"] == "True" for r in sel), sum(r["reached"] == "True" for r in sel),
                             len(sel))
        (oi, hi, ni), (oc, hc, nc) = count["integers"], count["campaign"]
        if not ni or not nc:
            continue
        ds, dr = newcombe(oi, ni, oc, nc), newcombe(hi, ni, hc, nc)
        lines.append(f"| {k} | {ni}, {100 * oi / ni:.0f} %, {100 * hi / ni:.0f} % "
                     f"| {nc}, {100 * oc / nc:.0f} %, {100 * hc / nc:.0f} % "
                     f"| {100 * ds[0]:+.0f} [{100 * ds[1]:+.0f}, {100 * ds[2]:+.0f}] "
                     f"| {100 * dr[0]:+.0f} [{100 * dr[1]:+.0f}, {100 * dr[2]:+.0f}] |")
    return "\n".join(lines)


def _fail(key: str, value: str, allowed: str) -> int:
    print(f"error: {key} {value!r}: {allowed}", file=sys.stderr)
    return 2


def _whole(text: str, low: int, high: int) -> int | None:
    try:
        v = int(text)
    except ValueError:
        return None
    return v if low <= v <= high else None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", default="100", help=f"runs per rung, 1 to {MAX_RUNS} (default 100)")
    ap.add_argument("--rungs", default=None, help="comma-separated rung names to run (default: all of the experiment)")
    ap.add_argument("--experiment", default="ladder", help=f"one of {', '.join(EXPERIMENTS)} (default ladder)")
    ap.add_argument("--stream", default="campaign", help="episode seeds: campaign (the reproduce table's, "
                    "default) or integers (0, 1, 2, ...)")
    ap.add_argument("--source", default="0,7", help="source node x,y, lattice units (default 0,7)")
    ap.add_argument("--out", default="benchmarks/ristic_ladder.csv", help="results CSV (appended; resumed)")
    ap.add_argument("--minutes", default=None, help="start no new episode after this many minutes")
    ap.add_argument("--workers", default="1", help="processes (default 1)")
    ap.add_argument("--table", action="store_true", help="print the table of --out without running")
    ap.add_argument("--streams", action="store_true",
                    help="print, per rung, the integers stream against the campaign stream in --out, without running")
    args = ap.parse_args(argv)
    if args.experiment not in EXPERIMENTS:
        return _fail("--experiment", args.experiment, f"one of {', '.join(EXPERIMENTS)}")
    runs = _whole(args.runs, 1, MAX_RUNS)
    if runs is None:
        return _fail("--runs", args.runs, f"a whole number from 1 to {MAX_RUNS}")
    names = [rung_id(label) for label, _, _ in EXPERIMENTS[args.experiment]]
    rungs = names if args.rungs is None else [r.strip() for r in args.rungs.split(",")]
    if not rungs or set(rungs) - set(names):
        return _fail("--rungs", args.rungs, f"comma-separated names among {', '.join(names)} "
                     f"(experiment {args.experiment})")
    if args.stream not in STREAMS:
        return _fail("--stream", args.stream, f"one of {', '.join(STREAMS)}")
    xy = [_whole(v, -9, 9) for v in args.source.split(",")]
    if len(xy) != 2 or None in xy or math.hypot(*xy) > 9:
        return _fail("--source", args.source, "two whole numbers x,y with x² + y² <= 81 (a node of the lattice)")
    minutes = None
    if args.minutes is not None:
        try:
            minutes = float(args.minutes)
        except ValueError:
            minutes = -1.0
        if not minutes > 0 or math.isinf(minutes):
            return _fail("--minutes", args.minutes, "a positive number of minutes")
    workers = _whole(args.workers, 1, 64)
    if workers is None:
        return _fail("--workers", args.workers, "a whole number from 1 to 64")
    out = Path(args.out)
    where = f"{xy[0]},{xy[1]}"
    reading = args.table or args.streams
    if not reading:
        run(args.experiment, rungs, args.stream, (xy[0], xy[1]), runs, out, minutes, workers)
    elif not out.exists():
        return _fail("--out", args.out, "an existing results CSV of this script (with --table or --streams)")
    if args.streams:
        print(f"{SCENARIO}, source ({where}), experiment {args.experiment}: the two seed streams\n")
        print(streams(out, args.experiment, where))
        return 0
    print(f"{SCENARIO}, source ({where}), seed stream {args.stream}, experiment {args.experiment}\n")
    print(table(out, args.experiment, args.stream, where, None if args.table else runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
