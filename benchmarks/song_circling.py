"""What do the searches that fail at the paper's ±3° turns do? Song, He & Lei (2019), Table 1.

    nice -n 10 python benchmarks/song_circling.py --seeds 10 --sides 100,150 --out runs/circling

Each strategy of ``song2019-table1`` runs on ``song-<side>`` with the printed turns
(world ``max_turn: 3``) for `--seeds` seeds. Per run the script writes one CSV row from
the episode record: whether it found the source, its steps, the final estimate's error,
the walker's closest approach to the true source, and, over its last `--last` steps,

* ``near_estimate``: the share of those steps within `--radius` of the final estimate;
* ``at_max_turn``: the share of those steps that turned by the largest angle allowed;
* ``orbit_radius``: the mean distance from the walker to the centre of its last positions;
* ``orbit_to_source``: the distance from that centre to the true source.

A walker that turns 3° every unit step goes round a circle of radius
``1 / (2 sin 1.5°) ≈ 19.1``, against the found radius R_s = 3: one that keeps turning
at the limit about its estimate never enters R_s.

Rows are appended as runs end, and a rerun with the same ``--out`` resumes: it runs only
what ``circling.csv`` lacks, then prints from all the rows asked for; ``--minutes M``
starts no new run after M minutes and ``--max-steps N`` caps a run at N steps (default:
the scenario's). Results: ``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse

import numpy as np

from arguments import Parser, among, listed, number, whole
from resumable import resume, truth

from reciprocity.campaign.tables.song2019 import SONG_MAX_TURN, SONG_SCALES, SONG_TABLE1
from reciprocity.env import SearchEnv, rollout
from reciprocity.scenarios import MAX_STEPS, load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent

#: CSV columns, one row per run, and how each is read back.
TYPES = dict(strategy=str, side=int, seed=int, success=truth, steps=int, error=float, closest_approach=float,
             near_estimate=float, at_max_turn=float, orbit_radius=float, orbit_to_source=float)
COLUMNS = tuple(TYPES)


def circling(trace: list[dict], source, max_turn_deg: float, last: int, radius: float) -> dict:
    """The circling measures of one run's step records (see the module docstring).

    Parameters
    ----------
    trace : list of dict
        The episode's step records (``pose`` [x, y, heading rad], ``estimate``).
    source : array-like, shape (2,)
        The true source (the episode summary's, read after the run).
    max_turn_deg : float
        The largest turn per step, degrees.
    last : int
        How many final steps to measure.
    radius : float
        The radius about the final estimate that counts as near it (length unit).

    Returns
    -------
    dict
        ``closest_approach``, ``near_estimate``, ``at_max_turn``, ``orbit_radius``,
        ``orbit_to_source``.
    """
    pose = np.array([r["pose"] for r in trace], dtype=float)
    xy, heading = pose[:, :2], pose[:, 2]
    src = np.asarray(source, dtype=float)
    tail = slice(max(0, len(xy) - last), None)
    est = np.asarray(trace[-1]["estimate"], dtype=float)
    turn = np.abs((np.diff(heading[tail]) + np.pi) % (2 * np.pi) - np.pi)
    centre = xy[tail].mean(axis=0)
    return dict(
        closest_approach=float(np.min(np.hypot(*(xy - src).T))),
        near_estimate=float(np.mean(np.hypot(*(xy[tail] - est).T) <= radius)),
        at_max_turn=float(np.mean(turn >= np.radians(max_turn_deg) * (1 - 1e-6))) if len(turn) else 0.0,
        orbit_radius=float(np.mean(np.hypot(*(xy[tail] - centre).T))),
        orbit_to_source=float(np.hypot(*(centre - src))))


def run(strategy: str, side: int, seed: int, last: int, radius: float, max_steps: int | None = None) -> dict:
    """One run at the printed turns, capped at `max_steps` (None: the scenario's cap); its
    CSV row."""
    sc = load_scenario(f"song-{side}").with_world({"max_turn": SONG_MAX_TURN}).with_limits(max_steps=max_steps)
    episode = rollout(SearchEnv(sc), StrategyAgent(STRATEGIES[strategy], {}), seed)
    s = episode.summary
    row = dict(strategy=strategy, side=side, seed=seed, success=bool(s["success"]), steps=int(s["steps"]),
               error=float(s["error"]))
    row.update(circling(episode.trace, s["source"], SONG_MAX_TURN, last, radius))
    return row


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one)."""
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--seeds", type=whole(1), default=10, help="runs per strategy and side")
    ap.add_argument("--sides", type=listed(among(SONG_SCALES, int)), default=[100],
                    help=f"area sides, comma-separated, among {', '.join(map(str, SONG_SCALES))}")
    ap.add_argument("--strategies", type=listed(among(SONG_TABLE1)), default=list(SONG_TABLE1),
                    help="strategies of song2019-table1, comma-separated (default: all six)")
    ap.add_argument("--last", type=whole(1), default=500, help="final steps measured")
    ap.add_argument("--radius", type=number(0, low_open=True), default=25.0,
                    help="'near the estimate' radius (length unit)")
    ap.add_argument("--max-steps", type=whole(1, MAX_STEPS), default=None,
                    help="step cap of a run (default: the scenario's)")
    return ap.parse_resumable(argv, "runs/song_circling", "circling.csv", COLUMNS)


def main(argv=None) -> list[dict]:
    """Run what ``circling.csv`` does not hold yet, then print from all its rows of the
    seeds, sides and strategies asked for; those rows."""
    args = parse(argv)
    keys = [(strategy, side, seed) for seed in range(args.seeds) for side in args.sides
            for strategy in args.strategies]
    rows = resume(args.csv, TYPES, keys, lambda r: (r["strategy"], r["side"], r["seed"]),
                  lambda k: [run(*k, args.last, args.radius, args.max_steps)], args.minutes)
    summarise(rows)
    return rows


def summarise(rows: list[dict]) -> None:
    """Print, per strategy and side, the found runs and the failed runs' medians."""
    print(f"{'strategy':<18} {'side':>4} {'found':>7} {'failed: error':>14} {'closest':>8} "
          f"{'near est.':>9} {'max turn':>8} {'orbit r':>8} {'orbit-src':>9}")
    keys = sorted({(r["strategy"], r["side"]) for r in rows}, key=lambda k: (k[1], k[0]))
    for strategy, side in keys:
        mine = [r for r in rows if (r["strategy"], r["side"]) == (strategy, side)]
        bad = [r for r in mine if not r["success"]]
        med = {k: (np.median([r[k] for r in bad]) if bad else np.nan)
               for k in ("error", "closest_approach", "near_estimate", "at_max_turn", "orbit_radius",
                         "orbit_to_source")}
        print(f"{strategy:<18} {side:>4} {len(mine) - len(bad):>3}/{len(mine):<3} {med['error']:>14.2f} "
              f"{med['closest_approach']:>8.2f} {med['near_estimate']:>9.2f} {med['at_max_turn']:>8.2f} "
              f"{med['orbit_radius']:>8.2f} {med['orbit_to_source']:>9.2f}")


if __name__ == "__main__":
    main()
