"""Fig. 5 of Song, He & Lei (2019): distance to the source against the particles' spread.

    nice -n 10 python benchmarks/song_fig5.py --seeds 10 --out runs/song_fig5

The paper's set-up for Fig. 5: the area [−300, 300] × [−150, 150], the source at
(−250, 0), the sensor starting at (200, −100) (its heading is not given: +y here, as in
the ``song-<side>`` scenarios), turns of at most ±3° per step, the plume and filter of
Table 1 (the ``song-100`` scenario's). ``infotaxis`` and ``free-energy`` (the printed α,
β, γ) run `--seeds` seeds each, capped at `--max-steps` steps. Every step of every run is
one CSV row (``fig5.csv``): the spread tr(Σ) of the particles, the distance of the
estimate (the particles' weighted mean) from the source and the distance of the sensor
from the source. The figure (``fig5.png``):

* (a) the estimate's distance against 1 / tr(Σ), every step (the paper: a Q-Q plot of the
  two, the distance falling to zero as the spread contracts);
* (b) the sensor's distance against tr(Σ), median and quartiles per bin of tr(Σ), per
  strategy (the paper: the distance falls as the spread contracts, faster with free
  energy).

The script prints the found runs and the binned medians of (b). Rows are appended as
runs end, and a rerun with the same ``--out`` resumes: it runs only what the CSV lacks,
then draws and prints from all the rows asked for; ``--minutes M`` starts no new run
after M minutes. Results: ``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from arguments import Parser, whole
from resumable import resume, truth

from arenas.files import atomic_output
from reciprocity.env import SearchEnv, rollout
from reciprocity.scenarios import MAX_STEPS, load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent

#: The paper's Fig. 5 world (papers/002, Section 4 and the caption of Fig. 5); start heading +y.
FIG5_WORLD = {"bounds": [-300, 300, -150, 150], "source": [-250, 0], "start": [200, -100, np.pi / 2],
              "max_turn": 3}
#: Strategies compared in Fig. 5(b).
FIG5_STRATEGIES = ("infotaxis", "free-energy")
#: CSV columns, one row per step, and how each is read back.
TYPES = dict(strategy=str, seed=int, success=truth, step=int, spread=float, estimate_distance=float,
             sensor_distance=float)
COLUMNS = tuple(TYPES)
#: Bin edges of tr(Σ) for panel (b) and the printed medians, length².
SPREAD_BINS = np.geomspace(1.0, 1e5, 11)


def run(strategy: str, seed: int, max_steps: int, world: dict = FIG5_WORLD) -> list[dict]:
    """One run of `strategy` in the Fig. 5 world; one row per step."""
    sc = load_scenario("song-100").with_world(world).with_limits(max_steps=max_steps)
    episode = rollout(SearchEnv(sc), StrategyAgent(STRATEGIES[strategy], {}), seed)
    src = np.asarray(episode.summary["source"], dtype=float)
    ok = bool(episode.summary["success"])
    return [dict(strategy=strategy, seed=seed, success=ok, step=int(r["step"]), spread=float(r["spread"]),
                 estimate_distance=float(np.hypot(*(np.asarray(r["estimate"]) - src))),
                 sensor_distance=float(np.hypot(*(np.asarray(r["pose"][:2]) - src))))
            for r in episode.trace]


def binned(rows: list[dict], strategy: str, bins=SPREAD_BINS) -> list[tuple]:
    """Per bin of tr(Σ): (low edge, high edge, steps, median, quartiles) of the sensor's
    distance over the steps of `strategy`."""
    mine = [r for r in rows if r["strategy"] == strategy]
    spread = np.array([r["spread"] for r in mine])
    dist = np.array([r["sensor_distance"] for r in mine])
    out = []
    for lo, hi in zip(bins[:-1], bins[1:]):
        d = dist[(spread >= lo) & (spread < hi)]
        if len(d):
            q1, med, q3 = np.percentile(d, [25, 50, 75])
            out.append((lo, hi, len(d), med, q1, q3))
    return out


def figure(rows: list[dict], path: Path) -> None:
    """Write the two panels of Fig. 5 to `path`."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=(11, 4.5), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    colours = {"infotaxis": "tab:red", "free-energy": "tab:blue"}
    for strategy in FIG5_STRATEGIES:
        mine = [r for r in rows if r["strategy"] == strategy]
        if not mine:
            continue
        inv = np.array([1.0 / max(r["spread"], 1e-12) for r in mine])
        ax_a.scatter(inv, [r["estimate_distance"] for r in mine], s=2, alpha=0.25, c=colours[strategy],
                     label=strategy, rasterized=True)
        b = binned(rows, strategy)
        mid = np.array([np.sqrt(lo * hi) for lo, hi, *_ in b])
        ax_b.plot(mid, [m for *_, m, _, _ in b], "-o", c=colours[strategy], ms=4, label=f"{strategy} (median)")
        ax_b.fill_between(mid, [q1 for *_, q1, _ in b], [q3 for *_, q3 in b], color=colours[strategy], alpha=0.2)
    ax_a.set_xscale("log")
    ax_a.set_xlabel("1 / tr(Σ)  (1 / length²)")
    ax_a.set_ylabel("distance of the estimate from the source")
    ax_a.set_title("(a) estimate against the inverse spread, every step")
    ax_a.legend(markerscale=5)
    ax_b.set_xscale("log")
    ax_b.invert_xaxis()
    ax_b.set_xlabel("tr(Σ)  (length², contracting to the right)")
    ax_b.set_ylabel("distance of the sensor from the source")
    ax_b.set_title("(b) sensor against the spread: median, quartiles")
    ax_b.legend()
    fig.savefig(path, dpi=110, format="png")


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one)."""
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--seeds", type=whole(1), default=10, help="runs per strategy")
    ap.add_argument("--max-steps", type=whole(1, MAX_STEPS), default=6000, help="step cap of a run")
    args = ap.parse_resumable(argv, "runs/song_fig5", "fig5.csv", COLUMNS, " and fig5.png")
    args.png = ap.output_file(args.out / "fig5.png")
    return args


def main(argv=None) -> list[dict]:
    """Run the seeds not yet in ``fig5.csv``, then draw and print from all its rows of
    the seeds asked for; those rows."""
    args = parse(argv)
    keys = [(strategy, seed) for seed in range(args.seeds) for strategy in FIG5_STRATEGIES]
    rows = resume(args.csv, TYPES, keys, lambda r: (r["strategy"], r["seed"]),
                  lambda k: run(*k, args.max_steps), args.minutes)
    with atomic_output(args.png) as tmp:
        figure(rows, tmp)
    for strategy in FIG5_STRATEGIES:
        runs = {(r["seed"]): (r["success"], r["step"]) for r in rows if r["strategy"] == strategy}
        found = [s for ok, s in runs.values() if ok]
        print(f"{strategy}: found {len(found)}/{len(runs)}, mean steps of the found "
              f"{np.mean(found) if found else float('nan'):.0f}")
        for lo, hi, n, med, q1, q3 in binned(rows, strategy):
            print(f"  tr(Σ) in [{lo:8.1f}, {hi:8.1f}): {n:6d} steps, sensor distance median {med:6.1f} "
                  f"(quartiles {q1:.1f}-{q3:.1f})")
    return rows


if __name__ == "__main__":
    main()
