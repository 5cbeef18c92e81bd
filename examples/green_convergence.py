"""Observed convergence of the FEM Green's function on a disk, against the closed form.

    python examples/green_convergence.py [--out out/examples]
"""

import argparse
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import arenas
import reciprocity as r


def max_error_away(solver, z, rmin, n=4000):
    """Largest |G_h - G| over random points at least `rmin` from `z` (inside the mesh)."""
    pts = np.random.default_rng(0).uniform(-1, 1, (n, 2))
    pts = pts[(np.hypot(*pts.T) < 1 - solver.h) & (np.hypot(*(pts - z).T) >= rmin)]
    return np.max(np.abs(solver.green(z)(pts) - r.disk_green(pts, z)))


def main(out_dir="out/examples") -> dict:
    """Write ``green_convergence.png``; return the observed order for P1 and P2."""
    disk = arenas.Arena.disk((0, 0), 1.0)
    z = np.array([0.3, 0.2])
    hs = np.array([0.1, 0.05, 0.025])
    fig = Figure(figsize=(5, 4), layout="constrained")
    ax = fig.add_subplot()
    orders = {}
    for order in (1, 2):
        errs = [max_error_away(r.GreenSolver(disk, h=h, order=order), z, 0.25) for h in hs]
        orders[order] = np.polyfit(np.log(hs), np.log(errs), 1)[0]
        ax.loglog(hs, errs, "o-", label=f"P{order}: order {orders[order]:.2f}")
    ax.set_xlabel("mesh size h")
    ax.set_ylabel("max |G_h - G|, |x - z| >= 0.25")
    ax.legend()
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    fig.savefig(Path(out_dir) / "green_convergence.png", dpi=120)
    print("observed orders (max norm away from the source):",
          ", ".join(f"P{k} {v:.2f}" for k, v in orders.items()))
    return orders


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/examples", help="output folder (created)")
    main(ap.parse_args().out)
