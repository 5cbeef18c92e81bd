"""Plume searchers on shared seeds: mean steps with 95 % intervals, paired differences.

Every strategy meets the same seeds (same source draw, same hit noise stream where the
paths coincide), so the paired difference against a baseline has a tighter interval
than the two means. Steps are counted over all runs; runs that stop at ``max_steps``
count with their step cap (their share is printed as the found rate).

    nice python benchmarks/bench_plume_beyond.py --scenario otto-2d --seeds 1000 \
        --strategy infotaxis --strategy free-energy --strategy lookahead
    nice python benchmarks/bench_plume_beyond.py --scenario song-100 --world max_turn=30 \
        --seeds 100 --strategy free-energy --strategy lookahead --baseline free-energy

Each strategy is ``name`` or ``name:{json params}`` (``label=name:{...}`` to name it).
Results are cached per (scenario, world, strategy, params) in ``--out`` (JSON lines),
so re-running resumes.
"""

from __future__ import annotations

import argparse
import time
from multiprocessing import Pool
from pathlib import Path

import numpy as np

from plume_bench import cached_seeds, mean_ci, parse_strategy, parse_world


def _one(job):
    scenario, world, name, params, seed = job
    from reciprocity.api import run
    t0, c0 = time.time(), time.process_time()
    s = run(scenario, name, seed=seed, params=params, world=world).summary
    return dict(seed=seed, steps=int(s["steps"]), success=bool(s["success"]),
                cpu=time.process_time() - c0, wall=time.time() - t0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", required=True)
    ap.add_argument("--world", action="append", default=[], help="key=value (JSON value)")
    ap.add_argument("--strategy", action="append", required=True)
    ap.add_argument("--baseline", default=None, help="label of the paired baseline (default: first)")
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default="out/plume_beyond")
    a = ap.parse_args(argv)
    world = parse_world(a.world) or None
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    strategies = [parse_strategy(s) for s in a.strategy]
    seeds = list(range(a.first_seed, a.first_seed + a.seeds))
    results = {}
    with Pool(a.workers) as pool:
        for label, name, params in strategies:
            results[label] = cached_seeds(out, [a.scenario, world, name, params], seeds, _one,
                                          lambda s: (a.scenario, world, name, params, s), pool, chunksize=4)
    base = a.baseline or strategies[0][0]
    print(f"\n{a.scenario} world={world} seeds {seeds[0]}..{seeds[-1]} (n = {len(seeds)})")
    print("| strategy | mean steps ± 95 % | found % | mean steps found | Δ vs " + base + " (paired) ± 95 % | Δ % "
          "| Δ where both found ± 95 % | Δ % both found | median steps | CPU s/episode |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    b = np.array([r["steps"] for r in results[base]], float)
    bok = np.array([r["success"] for r in results[base]])
    for label, rs in results.items():
        st = np.array([r["steps"] for r in rs], float)
        ok = np.array([r["success"] for r in rs])
        m, h = mean_ci(st)
        d, dh = mean_ci(st - b)
        mf = st[ok].mean() if ok.any() else float("nan")
        cpu = np.mean([r["cpu"] for r in rs])
        both = ok & bok
        d2, d2h = mean_ci(st[both] - b[both]) if both.sum() > 1 else (float("nan"),) * 2
        print(f"| {label} | {m:.2f} ± {h:.2f} | {100 * ok.mean():.1f} | {mf:.2f} | {d:+.2f} ± {dh:.2f} | "
              f"{100 * d / b.mean():+.1f} | {d2:+.2f} ± {d2h:.2f} | {100 * d2 / b[both].mean():+.1f} | "
              f"{np.median(st):.0f} | {cpu:.3f} |")


if __name__ == "__main__":
    main()
