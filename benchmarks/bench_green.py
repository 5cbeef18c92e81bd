"""Speed of the reciprocity core: factorization, adjoint solves, full Algorithm-1 steps.

    python benchmarks/bench_green.py [--arena paper]

Prints, for a range of mesh sizes, the number of unknowns, the mesh + assembly +
factorization time (the mesh column times the mesh cache when the mesh is already in it,
``RECIPROCITY_CACHE=off`` to time meshing itself), the time per adjoint solve (one back-substitution), and the time of
a full Algorithm-1 step (solve + imaging update + region area + estimate + next point),
with the scaling exponent against the number of unknowns.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import arenas
import reciprocity as r


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def step_time(solver: r.GreenSolver, arena, repeat: int = 5) -> float:
    """Mean time of Algorithm-1 steps after a few warm-up measurements."""
    s = r.ReciprocityStrategy(solver=solver)
    s.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=arena.strength),
                            np.array([[*arena.start[:2], 0.0]]), np.random.default_rng(0)))
    u = solver.field(arena.source, arena.strength)
    rng = np.random.default_rng(1)
    pts = arena.random_free_points(2 + repeat, rng, clearance=5.0)

    def observe(p, noise):
        obs = r.Observation(p, u(p[None])[0] + noise * rng.standard_normal())
        s.observe([obs], r.Measure(p))

    for p in pts[:2]:
        observe(p, 0.0)
    t = time.perf_counter()
    for p in pts[2:]:
        observe(p, 12.0)
    return (time.perf_counter() - t) / repeat


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arena", default="paper")
    ap.add_argument("--hs", default="2,1.4,1,0.7")
    args = ap.parse_args(argv)
    arena = arenas.load(args.arena)
    z = arena.random_free_points(20, np.random.default_rng(0), clearance=3.0)
    print(f"arena {args.arena!r}, P1 elements")
    print(f"{'h cm':>5} {'unknowns':>9} {'setup s':>8} {'mesh s':>7} {'assemble s':>10} "
          f"{'factor s':>9} {'solve ms':>9} {'step ms':>8} {'locate 1e5 pts ms':>18}")
    rows = []
    for h in map(float, args.hs.split(",")):
        t = time.perf_counter()
        solver = r.GreenSolver(arena, h=h).factorize()
        setup = time.perf_counter() - t
        solve = best_of(lambda: solver.solve(solver.point_sources(z[0])), 7)
        step = step_time(solver, arena)
        pts = np.random.default_rng(2).uniform(0, 140, (100_000, 2))
        locate = best_of(lambda: solver.locate(pts), 3)
        rows.append((solver.n_unknowns, setup, solve, step))
        tm = solver.timings
        print(f"{h:>5.2f} {solver.n_unknowns:>9d} {setup:>8.2f} {tm['mesh']:>7.2f} {tm['assemble']:>10.2f} "
              f"{tm['factorize']:>9.2f} {solve * 1e3:>9.2f} {step * 1e3:>8.1f} "
              f"{locate * 1e3:>18.1f}")
    n = np.log([r_[0] for r_ in rows])
    for k, name in [(1, "setup"), (2, "solve"), (3, "step")]:
        slope = np.polyfit(n, np.log([r_[k] for r_ in rows]), 1)[0]
        print(f"{name} time ~ unknowns^{slope:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
