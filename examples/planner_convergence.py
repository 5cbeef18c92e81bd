"""Observed order of the HJ planner against the exact Dubins distance.

    python examples/planner_convergence.py [--out out/examples] [--quick]

The reference set-up of ``tests/hjplanner/test_hj_solver.py``: the square [-1, 1]², turning
radius ρ = 0.3, a point target at the origin with a free final heading, whose exact
distance is :func:`hjplanner.point_distance`. The grid spacing h and the heading step
Δθ are refined together (the error cannot drop below about ρΔθ) and the exact initial
layer is held at a fixed radius, so the refinement measures the scheme alone. Writes
``planner_convergence.png`` (mean |φ_h - φ| over random poses whose exact distance is
below 0.95, against h, with the fitted order) and returns the observed order.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from hjplanner import SolverOptions, point_distance, solve

RHO = 0.3
SQUARE = ((-1.0, 1.0), (-1.0, 1.0))


def mean_errors(hs, nthetas, n_poses: int = 3000, seed: int = 3) -> list[float]:
    """Mean |φ_h - exact| for each (h, ntheta)."""
    rng = np.random.default_rng(seed)
    poses = rng.uniform([-1, -1, 0], [1, 1, 2 * np.pi], (6 * n_poses, 3))
    exact = point_distance(*poses.T, RHO)
    keep = exact < 0.95
    poses, exact = poses[keep][:n_poses], exact[keep][:n_poses]
    errors = []
    for h, ntheta in zip(hs, nthetas):
        vf = solve(SQUARE, (0.0, 0.0), RHO, h, ntheta, options=SolverOptions(exact_radius=0.35))
        errors.append(float(np.abs(vf(*poses.T) - exact).mean()))
    return errors


def main(argv=None) -> float:
    """Write ``planner_convergence.png``; return the observed order."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/examples", help="output folder (created)")
    ap.add_argument("--quick", action="store_true", help="the two coarser grids only (tests)")
    a = ap.parse_args(argv)
    hs, nthetas = ([0.04, 0.02], [32, 64]) if a.quick else ([0.04, 0.02, 0.01], [32, 64, 128])
    errors = mean_errors(hs, nthetas)
    order = float(np.polyfit(np.log(hs), np.log(errors), 1)[0])
    fig = Figure(figsize=(5, 4), layout="constrained")
    ax = fig.add_subplot()
    ax.loglog(hs, errors, "o-", label=f"HJ planner: order {order:.2f}")
    ax.loglog(hs, errors[0] * (np.array(hs) / hs[0]), "k:", label="order 1")
    ax.set_xlabel("grid spacing h (Δθ refined with it)")
    ax.set_ylabel("mean |φ_h - exact Dubins distance|")
    ax.set_title(f"point target, ρ = {RHO}")
    ax.legend()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "planner_convergence.png", dpi=100)
    print(f"mean errors {', '.join(f'{e:.4f}' for e in errors)}; observed order {order:.2f}")
    return order


if __name__ == "__main__":
    main()
