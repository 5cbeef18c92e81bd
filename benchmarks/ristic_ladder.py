"""Where Ristic et al.'s success is lost: an oracle ladder on the paper's lattice.

    python benchmarks/ristic_ladder.py [--runs 100] [--source 0,7] [--workers 2]

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
Success as in the paper (Sec. 5.1: on the source within 100 steps and self-localised),
with Wilson 95 % intervals (``scipy.stats.binomtest``); mean steps over the successes.
``--experiment control`` keeps rung 1 and changes one setting of the control at a time
(ideal measurements drawn instead of the mean, no anti-oscillation rule, no stay, M = 4000);
``--experiment stay`` runs the paper's set-up with and without the stay control;
``--experiment controls`` scores Algorithm 2's five controls every step;
``--experiment sensor`` changes the reach of the link sensor (secondary links uninformative,
or seen perfectly).
Results: ``docs/papers/ristic2014.md``.
"""

from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor

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

RUNGS = (
    ("1. map known, lattice field", {"map": "known", "field": "lattice"}, {"map": "known"}),
    ("1'. as 1, path planner", {"map": "known", "field": "lattice", "planner": "path"}, {"map": "known"}),
    ("2. map known, eq. (25)", {"map": "known"}, {"map": "known"}),
    ("3. map unknown, eq. (25), perfect self-localisation", {}, {"localisation": "known"}),
    ("4. the paper: map unknown, eq. (25)", {}, {}),
)


def one(job):
    params, world, seed = job
    from reciprocity.api import execute
    s = execute("ristic-lattice-paper", "rbpf", seed=seed, params=params, world=world)[0].summary
    return bool(s["success"]), int(s["steps"]), bool(s.get("reached", s["distance_at_stop"] == 0.0))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--source", default="0,7")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rungs", default=None, help="comma-separated rung numbers to run (default: all)")
    ap.add_argument("--experiment", choices=("ladder", "control", "stay", "controls", "sensor"), default="ladder",
                    help="the ladder, or rung 1 with one control setting changed at a time")
    args = ap.parse_args(argv)
    source = [int(v) for v in args.source.split(",")]
    print(f"source {tuple(source)}, {args.runs} runs per rung (seeds 0..{args.runs - 1})\n")
    print("| rung | success | 95 % CI | reached | mean steps (successes) |\n|---|---:|---|---:|---:|")
    with ProcessPoolExecutor(args.workers) as pool:
        rows = {"ladder": RUNGS, "control": CONTROL, "stay": STAY, "controls": FIVE,
                "sensor": SENSOR}[args.experiment]
        if args.rungs:
            rows = [r for r in rows if r[0].split(" ")[0].rstrip(".") in args.rungs.split(",")]
        for label, params, world in rows:
            jobs = [(params, {**world, "source": source}, seed) for seed in range(args.runs)]
            out = list(pool.map(one, jobs))
            k = sum(o[0] for o in out)
            ci = stats.binomtest(k, len(out)).proportion_ci(method="wilson")
            steps = [o[1] for o in out if o[0]]
            reached = sum(o[2] for o in out)
            print(f"| {label} | {100 * k / len(out):.0f} % | [{100 * ci.low:.0f}, {100 * ci.high:.0f}] % | "
                  f"{100 * reached / len(out):.0f} % | {np.mean(steps) if steps else float('nan'):.1f} |", flush=True)


if __name__ == "__main__":
    main()
