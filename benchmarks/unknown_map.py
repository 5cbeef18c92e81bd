"""Known map against unknown map (issue 23, part 1): the reciprocity search on the point
observer, told the true walls or only the outer boundary (with a 64-beam, 40 cm, 0.5 cm
lidar), on the same (source, start, noise) pairs.

Each seed index draws the pair exactly as a campaign with ``random_source: true`` does
(:func:`reciprocity.campaign.worker.world_draw`: source >= 8 cm from the walls, start
>= 5 cm, uniform heading, from the campaign seed 2026), so the known and unknown runs of
an index meet the same world. Episodes run one after the other in this process.

    python benchmarks/unknown_map.py --seeds 25 --out benchmarks/unknown_map/runs.csv
    python benchmarks/unknown_map.py --seeds 25 --modes unknown-flat unknown-onesided --out benchmarks/unknown_map/runs.csv
    python benchmarks/unknown_map.py --table benchmarks/unknown_map/runs.csv

The point observer moves along free paths of the true walls: it never touches a wall, so
its contacts are 0 by construction (the car's are the open question).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ARENAS = ["paper", "maze", "deep_u", str(HERE / "unknown_map" / "pillars.yaml"),
          str(HERE / "unknown_map" / "two_rooms.yaml"), str(HERE / "unknown_map" / "baffles.yaml")]
#: Modes: the world overrides, and the likelihood's allowance for the unseen map
#: (:mod:`reciprocity.strategies.mapping`: UNSEEN_MODEL_ERROR, MAPPED_MODEL_ERROR,
#: UNSEEN_SHORTFALL): ``unknown`` widens it both ways, ``unknown-flat`` not at all (what
#: widening costs), ``unknown-onesided`` also lets readings fall short of the open model.
MODES = {"known": ({}, (0.3, 0.05, 0.0)), "unknown": ({"map": "unknown"}, (0.3, 0.05, 0.0)),
         "unknown-flat": ({"map": "unknown"}, (0.0, 0.0, 0.0)),
         "unknown-onesided": ({"map": "unknown"}, (0.3, 0.05, 0.8))}
CAMPAIGN_SEED = 2026
FIELDS = ["arena", "mode", "index", "seed", "success", "converged", "stop", "n_measurements", "path_length",
          "error", "source_reachable", "wall_time_s", "remeshes"]


def run(arenas: list[str], modes: list[str], seeds: int, out: Path, params: dict) -> None:
    from reciprocity.campaign.spec import episode_seed
    from reciprocity.campaign.worker import world_draw
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import load_scenario
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    from reciprocity.strategies import mapping as keeper
    done = set()
    if out.exists():
        with out.open() as f:
            done = {(r["arena"], r["mode"], int(r["index"])) for r in csv.DictReader(f)}
    new = not out.exists()
    with out.open("a", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        if new:
            w.writeheader()
        for i in range(seeds):
            for name in arenas:
                sc = load_scenario(name)
                seed = episode_seed(CAMPAIGN_SEED, i)
                pair = world_draw(sc, seed)
                for mode in modes:
                    label = Path(name).stem
                    if (label, mode, i) in done:
                        continue
                    world, allowance = MODES[mode]
                    keeper.UNSEEN_MODEL_ERROR, keeper.MAPPED_MODEL_ERROR, keeper.UNSEEN_SHORTFALL = allowance
                    env = SearchEnv(sc, world={**pair, **world})
                    agent = StrategyAgent(STRATEGIES["reciprocity"], dict(params))
                    t0 = time.perf_counter()
                    s = rollout(env, agent, seed).summary
                    mapping = getattr(agent.strategy, "mapping", None)
                    w.writerow(dict(arena=label, mode=mode, index=i, seed=seed, success=s["success"],
                                    converged=s["converged"], stop=s["stop"], n_measurements=s["n_measurements"],
                                    path_length=round(s["path_length"], 2),
                                    error=None if s["error"] is None else round(s["error"], 3),
                                    source_reachable=s["source_reachable"],
                                    wall_time_s=round(time.perf_counter() - t0, 2),
                                    remeshes=0 if mapping is None else mapping.revision))
                    f.flush()
                    print(f"{label:10s} {mode:8s} {i:3d} success={s['success']} n={s['n_measurements']} "
                          f"err={s['error'] if s['error'] is None else round(s['error'], 2)} stop={s['stop']}",
                          file=sys.stderr)


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score 95 % interval of a proportion k / n."""
    if n == 0:
        return (math.nan, math.nan)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def median_ci(x: np.ndarray, z: float = 1.96) -> tuple[float, float, float]:
    """Median and its distribution-free 95 % interval (order statistics of the binomial)."""
    x = np.sort(np.asarray(x, dtype=float))
    n = len(x)
    if n == 0:
        return (math.nan,) * 3
    lo = int(max(0, math.floor(n / 2 - z * math.sqrt(n) / 2)))
    hi = int(min(n - 1, math.ceil(n / 2 + z * math.sqrt(n) / 2)))
    return float(np.median(x)), float(x[lo]), float(x[hi])


def table(path: Path) -> str:
    with path.open() as f:
        rows = list(csv.DictReader(f))
    arenas = list(dict.fromkeys(r["arena"] for r in rows))
    lines = ["| arena | map | runs | success (95 % CI) | median readings (95 % CI) | median path cm | "
             "readings ratio to known | median error cm | contacts |", "|---|---|---|---|---|---|---|---|---|"]
    for group in arenas + ["all"]:
        med = {}
        for mode in MODES:
            rs = [r for r in rows if r["mode"] == mode and (group == "all" or r["arena"] == group)]
            if not rs:
                continue
            k = sum(r["success"] == "True" for r in rs)
            lo, hi = wilson(k, len(rs))
            m, mlo, mhi = median_ci([int(r["n_measurements"]) for r in rs])
            med[mode] = m
            path = float(np.median([float(r["path_length"]) for r in rs]))
            err = float(np.median([float(r["error"]) for r in rs if r["error"] not in ("", "None")]))
            ratio = f"{m / med['known']:.2f}" if mode != "known" and "known" in med else ""
            lines.append(f"| {group} | {mode} | {len(rs)} | {100 * k / len(rs):.0f} % ({100 * lo:.0f}-{100 * hi:.0f}) | "
                         f"{m:g} ({mlo:g}-{mhi:g}) | {path:.0f} | {ratio} | {err:.2f} | 0 |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=20, help="pairs per arena (default 20)")
    ap.add_argument("--arenas", nargs="*", default=ARENAS)
    ap.add_argument("--modes", nargs="*", default=["known", "unknown"], choices=list(MODES))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a strategy parameter (a number), e.g. --set h=2")
    ap.add_argument("--out", type=Path, default=HERE / "unknown_map" / "runs.csv")
    ap.add_argument("--table", type=Path, help="only print the table of this CSV")
    args = ap.parse_args(argv)
    if args.table:
        print(table(args.table))
        return 0
    params = {k: float(v) for k, v in (s.split("=", 1) for s in args.set)}
    run(args.arenas, args.modes, args.seeds, args.out, params)
    print(table(args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
