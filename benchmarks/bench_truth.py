"""Error and cost of the Poisson world's truth: its own discretisation against a fine reference.

    python benchmarks/bench_truth.py [--arenas paper maze] [--ref-h 0.35]

For each arena, the true signal ``u = c G(., S)`` of its source is computed on a reference
(P2 at ``--ref-h``) and on candidate truths: the former truth (P1 at 0.7 x a strategy's
1 cm), the current one (:data:`reciprocity.worlds.poisson.TRUTH_H`, P2) and neighbours.
At 400 random free points at least 5 cm from the source and 3 cm from the walls it prints
the largest and mean absolute error (signal units), the largest relative to ``max |u|``,
the unknowns and the build + solve time, with the ratio of each error to the sensor's
noise (12 signal units on the built-in arenas). Results: benchmarks/truth_discretisation.md.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import arenas
from reciprocity.fem.green import GreenSolver
from reciprocity.worlds.poisson import TRUTH_GRADING, TRUTH_H, TRUTH_ORDER

NOISE = 12.0


def true_signal(arena, h: float, order: int, points: np.ndarray):
    """Values of the arena's true field at `points` and (unknowns, seconds)."""
    clock = time.perf_counter()
    solver = GreenSolver(arena.without_scenario(), h=h, order=order,
                         grading=TRUTH_GRADING if order == 2 else None)
    values = solver.field(arena.source, arena.strength)(points)
    return values, solver.n_unknowns, time.perf_counter() - clock


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arenas", nargs="+", default=["paper", "maze"])
    ap.add_argument("--ref-h", type=float, default=0.35, help="reference P2 mesh size, cm")
    args = ap.parse_args(argv)
    candidates = [(0.7, 1, "former truth (P1, 0.7 x 1 cm)"), (1.0, 1, "a strategy's model at h = 1"),
                  (1.0, 2, ""), (TRUTH_H, TRUTH_ORDER, "the truth (TRUTH_H, TRUTH_ORDER)"), (2.0, 2, "")]
    print("| arena | discretisation | unknowns | time (s) | max err | mean err | max err / max u | max err / noise | |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in args.arenas:
        arena = arenas.load(name)
        pts = arena.random_free_points(400, np.random.default_rng(0), clearance=3.0)
        pts = pts[np.hypot(*(pts - arena.source).T) > 5]
        ref, n_ref, t_ref = true_signal(arena, args.ref_h, 2, pts)
        print(f"| {name} | P2, h = {args.ref_h:g} (reference) | {n_ref} | {t_ref:.2f} | – | – | – | – | |")
        for h, order, label in candidates:
            v, n, t = true_signal(arena, h, order, pts)
            err = np.abs(v - ref)
            print(f"| {name} | P{order}, h = {h:g} | {n} | {t:.2f} | {err.max():.3g} | {err.mean():.3g} | "
                  f"{err.max() / np.abs(ref).max():.2e} | {err.max() / NOISE:.1e} | {label} |")


if __name__ == "__main__":
    main()
