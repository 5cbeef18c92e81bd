"""Value function and optimal car paths in the `paper` arena (Landa et al., section IV).

Solves φ(x, y, θ) for the arena's source as target, draws the slice at the
start heading with the optimal paths from the arena's start pose and a few
random poses, and prints how well each path length agrees with φ(start).

Run: ``python examples/planner_paths.py [OUT_DIR] [--fine]`` (``--fine``:
1 cm and 72 headings, the testbed planner's resolution).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import arenas  # noqa: E402
from hjplanner import solve  # noqa: E402


def main(out_dir: str | Path = ".", *, h: float = 2.0, ntheta: int = 36, rho: float = 12.0,
         clearance: float = 3.0, n_paths: int = 5, seed: int = 0) -> float:
    """Write ``planner_paths.png`` into ``out_dir``; return the largest |length - φ(start)| / φ(start).

    Raises RuntimeError if a path does not reach the target.

    Parameters
    ----------
    out_dir : str or Path
        Output directory (created if missing).
    h, ntheta, rho, clearance : float, int, float, float
        Grid spacing (cm), headings, turning radius (cm), obstacle inflation (cm).
    n_paths : int
        Random start poses in addition to the arena's start.
    seed : int
        Seed of the random start poses.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    arena = arenas.load("paper")
    vf = solve(arena, tuple(arena.source), rho, h, ntheta, clearance=clearance)
    rng = np.random.default_rng(seed)
    starts = [np.asarray(arena.start, dtype=float)]
    while len(starts) < n_paths + 1:
        pose = rng.uniform([5, 5, 0], [135, 135, 2 * np.pi])
        if np.isfinite(vf(*pose)):
            starts.append(pose)
    fig, ax = plt.subplots(figsize=(7, 6))
    vf.plot_slice(starts[0][2], ax=ax)
    worst, all_reached = 0.0, True
    print(f"{'start (x, y, deg)':>24} {'phi(start)':>10} {'length':>8} {'reached':>8}")
    for pose in starts:
        path = vf.path(pose)
        ax.plot(path.xy[:, 0], path.xy[:, 1], "-", color="w", lw=1.5)
        ax.plot(*pose[:2], "o", color="w", ms=4)
        driven = path.length + float(np.hypot(*(path.xy[-1] - vf.target)))
        worst = max(worst, abs(driven - path.value_start) / path.value_start)
        all_reached &= path.reached
        print(f"({pose[0]:6.1f}, {pose[1]:6.1f}, {np.degrees(pose[2]):5.0f}) {path.value_start:10.1f} "
              f"{driven:8.1f} {str(path.reached):>8}")
    ax.set_title(f"φ at θ = {np.degrees(starts[0][2]):.0f}° and optimal paths (ρ = {rho:g} cm)")
    fig.savefig(out_dir / "planner_paths.png", dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(f"largest relative length - φ gap: {worst:.3f}; wrote {out_dir / 'planner_paths.png'}")
    if not all_reached:
        raise RuntimeError("a path did not reach the target")
    return worst


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    fine = dict(h=1.0, ntheta=72) if "--fine" in sys.argv else {}
    main(args[0] if args else ".", **fine)
