"""Value function and optimal car paths in the `paper` arena (Landa et al., section IV).

Solves φ(x, y, θ) of the car platform's planner (turning radius 15 cm,
1.5 cm grid, 48 headings, 4 cm clearance, reverse allowed) for a disk of
radius 2h around the arena's source, draws the slice at the start heading
with the optimal paths from the arena's start pose and a few random poses,
and prints how well each path length agrees with φ(start) and how close
each path comes to a wall (by the arena's own geometry).

Run: ``python examples/planner_paths.py [--out out/examples] [--fine]`` (``--fine``:
1 cm and 72 headings).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import arenas  # noqa: E402
from hjplanner import solve  # noqa: E402


def main(out_dir: str | Path = "out/examples", *, h: float = 1.5, ntheta: int = 48, rho: float = 15.0,
         clearance: float = 4.0, reverse: bool = True, n_paths: int = 5, seed: int = 0) -> tuple[float, float]:
    """Write ``planner_paths.png`` into ``out_dir``; return the largest gap and the smallest wall distance.

    The gap is ``max |length - φ(start)| / h`` over the paths (grid spacings);
    the wall distance (cm) is the smallest over all path samples.

    Parameters
    ----------
    out_dir : str or Path
        Output directory (created if missing).
    h, ntheta, rho, clearance : float, int, float, float
        Grid spacing (cm), headings, turning radius (cm), wall clearance (cm).
    reverse : bool
        Allow reverse driving.
    n_paths : int
        Random start poses in addition to the arena's start.
    seed : int
        Seed of the random start poses.

    Raises
    ------
    RuntimeError
        If a path does not reach the target.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    arena = arenas.load("paper")
    vf = solve(arena, tuple(arena.source), rho, h, ntheta, clearance=clearance, reverse=reverse, tol=2 * h)
    rng = np.random.default_rng(seed)
    starts = [np.asarray(arena.start, dtype=float)]
    while len(starts) < n_paths + 1:
        pose = rng.uniform([5, 5, 0], [135, 135, 2 * np.pi])
        if np.isfinite(vf(*pose)):
            starts.append(pose)
    fig, ax = plt.subplots(figsize=(7, 6))
    vf.plot_slice(starts[0][2], ax=ax)
    worst, nearest, all_reached = 0.0, np.inf, True
    print(f"{'start (x, y, deg)':>24} {'phi(start)':>10} {'length':>8} {'wall cm':>8} {'reached':>8}  controls")
    for pose in starts:
        path = vf.path(pose, ds=0.25)
        ax.plot(path.xy[:, 0], path.xy[:, 1], "-", color="w", lw=1.5)
        ax.plot(*pose[:2], "o", color="w", ms=4)
        worst = max(worst, abs(path.length - path.value_start) / h)
        wall = float(arena.wall_distance(path.xy).min())
        nearest = min(nearest, wall)
        all_reached &= path.reached
        controls = " ".join(f"{'-' if v < 0 else ''}{'RSL'[u + 1]}{s:.1f}" for u, v, s in path.segments)
        print(f"({pose[0]:6.1f}, {pose[1]:6.1f}, {np.degrees(pose[2]):5.0f}) {path.value_start:10.1f} "
              f"{path.length:8.1f} {wall:8.2f} {str(path.reached):>8}  {controls}")
    ax.set_title(f"φ at θ = {np.degrees(starts[0][2]):.0f}° and optimal paths (ρ = {rho:g} cm)")
    fig.savefig(out_dir / "planner_paths.png", dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(f"largest |length - φ(start)|: {worst:.2f} h; closest approach to a wall: {nearest:.2f} cm "
          f"(clearance {clearance:g} cm); wrote {out_dir / 'planner_paths.png'}")
    if not all_reached:
        raise RuntimeError("a path did not reach the target")
    return worst, nearest


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/examples", help="output folder (created)")
    ap.add_argument("--fine", action="store_true", help="1 cm and 72 headings")
    a = ap.parse_args()
    main(a.out, **(dict(h=1.0, ntheta=72) if a.fine else {}))
