"""Cost of an adjoint in wind: advection-diffusion-decay beside the Poisson adjoint, same mesh.

    python benchmarks/bench_advection.py [--arena paper] [--h 1.0] [--repeat 7]

Prints the set-up times (potential-flow wind, assembly, LU factorization) of
:class:`~reciprocity.fem.AdvectionSolver` and of the :class:`~reciprocity.GreenSolver`
the toolkit uses today, then the time of one adjoint solve followed by its evaluation at
every candidate source of a 1 cm raster (what a search does once per reading), best of
`--repeat`, and their ratio (the aim: at most 2).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import arenas
import reciprocity as r
from reciprocity.fem import AdvectionSolver, WindField

#: Wind through the arena: in on the left wall, out on the right one, cm and cm/s.
INFLOW, OUTFLOW, SPEED = [((0.0, 10.0), (0.0, 130.0))], [((140.0, 10.0), (140.0, 130.0))], 5.0
#: Diffusivity (cm²/s) and lifetime (s) of the substance.
D, TAU = 1.0, 60.0


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main(argv=None) -> float:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arena", default="paper")
    ap.add_argument("--h", type=float, default=1.0, help="mesh size, cm")
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args(argv)
    arena = arenas.load(args.arena)
    z = arena.random_free_points(args.repeat, np.random.default_rng(0), clearance=3.0)

    t = time.perf_counter()
    green = r.GreenSolver(arena, h=args.h).factorize()
    green_setup = time.perf_counter() - t
    t = time.perf_counter()
    wind = WindField.potential(arena, INFLOW, OUTFLOW, speed=SPEED, h=args.h)
    wind_s = time.perf_counter() - t
    t = time.perf_counter()
    adv = AdvectionSolver(arena, wind, D=D, tau=TAU, walls="impermeable").factorize()
    adv_setup = time.perf_counter() - t
    green.green(z[0]).on_grid(1.0)          # the candidates' probe matrices, built once per solver
    adv.adjoint(z[0]).on_grid(1.0)

    it = iter(range(10**9))
    poisson = best_of(lambda: green.green(z[next(it) % len(z)]).on_grid(1.0), args.repeat)
    advection = best_of(lambda: adv.adjoint(z[next(it) % len(z)]).on_grid(1.0), args.repeat)
    solve_only = best_of(lambda: adv.adjoints(z[:1]), args.repeat), best_of(lambda: green.greens(z[:1]), args.repeat)

    gt, at = green.timings, adv.timings
    print(f"arena {args.arena!r}, h = {args.h} cm, P1; wind {SPEED} cm/s, D = {D} cm²/s, tau = {TAU} s, "
          f"max cell Péclet {wind.peclet(args.h, D):.1f}")
    print(f"{'':28} {'unknowns':>9} {'setup s':>8} {'assemble s':>10} {'factor s':>9} {'solve ms':>9} "
          f"{'solve+eval ms':>14}")
    print(f"{'Poisson (GreenSolver)':28} {green.n_unknowns:>9d} {green_setup:>8.2f} {gt['assemble']:>10.2f} "
          f"{gt['factorize']:>9.2f} {solve_only[1] * 1e3:>9.1f} {poisson * 1e3:>14.1f}")
    print(f"{'advection (AdvectionSolver)':28} {adv.n_unknowns:>9d} {adv_setup:>8.2f} {at['assemble']:>10.2f} "
          f"{at['factorize']:>9.2f} {solve_only[0] * 1e3:>9.1f} {advection * 1e3:>14.1f}")
    print(f"potential-flow wind (P{wind.solver.order}, {wind.solver.n_unknowns} unknowns): {wind_s:.2f} s")
    ratio = advection / poisson
    print(f"adjoint solve + evaluation on a 1 cm raster: advection / Poisson = {ratio:.2f}")
    return ratio


if __name__ == "__main__":
    main()
