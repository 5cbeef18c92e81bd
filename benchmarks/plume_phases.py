"""Where a plume searcher's steps go: before the first hit, and after it, against a bound.

For each strategy and seed, the run is split at its first hit: steps to the first hit,
the searcher's distance to the source there (progress = start distance − that), and the
steps after it. The bound is a walker that knows the source and steers straight at it
within the scenario's turn limit (same start pose, step and stop radius): no searcher
can take fewer steps on average.

    nice python benchmarks/plume_phases.py --scenario song-100 --world max_turn=30 --seeds 100 \
        --strategy free-energy --strategy lookahead --strategy infotaxis --strategy space-aware-infotaxis

Strategies are ``name`` or ``name:{json params}``; a start heading among the ``--world``
overrides is in radians. Scenarios with a drawn source or a forced first hit (otto-2d)
have no fixed bound; the script refuses them. Runs are cached per seed in ``--out``.
"""

from __future__ import annotations

import argparse
from multiprocessing import Pool
from pathlib import Path

import numpy as np

from plume_bench import cached_seeds, mean_ci, parse_strategy, parse_world


def oracle_steps(start, heading_deg: float, source, *, step: float, max_turn_deg: float, radius: float,
                 cap: int = 100_000) -> int:
    """Steps of a walker that knows `source`: each step turns toward it by at most
    `max_turn_deg`, then moves `step`; stops within `radius` (the bound in the tables)."""
    p, s = np.asarray(start, float), np.asarray(source, float)
    h, lim = np.radians(heading_deg), np.radians(max_turn_deg)
    for n in range(cap):
        if np.hypot(*(p - s)) <= radius:
            return n
        want = np.arctan2(s[1] - p[1], s[0] - p[0])
        h += np.clip((want - h + np.pi) % (2 * np.pi) - np.pi, -lim, lim)
        p = p + step * np.array([np.cos(h), np.sin(h)])
    return cap


def _one(job):
    scenario, world, name, params, seed = job
    from reciprocity.api import run
    r = run(scenario, name, seed=seed, params=params, world=world)
    pos = np.array([rec.pose[:2] for rec in r.records])
    hits = np.array([rec.observations[0].value for rec in r.records])
    first = int(np.argmax(hits > 0)) + 1 if (hits > 0).any() else len(hits)
    return dict(seed=seed, steps=int(r.summary["steps"]), success=bool(r.summary["success"]),
                first=first, at_first=pos[first - 1].tolist())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", required=True)
    ap.add_argument("--world", action="append", default=[], help="key=value (JSON value)")
    ap.add_argument("--strategy", action="append", required=True)
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--out", default="out/plume_phases")
    a = ap.parse_args(argv)
    from reciprocity.scenarios import load_scenario
    world = parse_world(a.world)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    sc = load_scenario(a.scenario)
    w = dict(sc.params, **world)
    if isinstance(w.get("source"), str) or w.get("initial_hit") or sc.starts is None:
        ap.error(f"{a.scenario} draws its source, forces a first hit or has no fixed start: no fixed bound")
    src = np.array(w["source"], float)
    start = np.array(sc.with_world(world).starts[0], float)        # heading in radians
    heading = float(np.degrees(start[2]))
    bound = oracle_steps(start[:2], heading, src, step=float(w["step"]),
                         max_turn_deg=float(w["max_turn"]), radius=float(w["found_radius"]))
    d0 = float(np.hypot(*(start[:2] - src)))
    print(f"{a.scenario} world={world}: start {d0:.1f} from the source; bound (knows the source) {bound} steps")
    print("| strategy | mean steps (found) ± 95 % | found | over the bound | steps to 1st hit | progress by 1st hit "
          "| excess before | steps after 1st hit | excess after |")
    print("|---|---|---|---|---|---|---|---|---|")
    with Pool(a.workers) as pool:
        for text in a.strategy:
            _, name, params = parse_strategy(text)
            rs = cached_seeds(out, ["phases", a.scenario, world, name, params], range(a.seeds), _one,
                              lambda s: (a.scenario, world or None, name, params, s), pool)
            ok = np.array([r["success"] for r in rs])
            st = np.array([r["steps"] for r in rs], float)[ok]
            first = np.array([r["first"] for r in rs], float)[ok]
            dist = np.array([np.hypot(*(np.array(r["at_first"]) - src)) for r in rs])[ok]
            prog = d0 - dist
            after = st - first
            m, h = mean_ci(st)
            print(f"| {text} | {m:.1f} ± {h:.1f} | {ok.sum()}/{len(ok)} | {m - bound:+.1f} | {first.mean():.1f} | "
                  f"{prog.mean():.1f} | {(first - prog).mean():.1f} | {after.mean():.1f} | "
                  f"{(after - (dist - float(w['found_radius']))).mean():.1f} |", flush=True)


if __name__ == "__main__":
    main()
