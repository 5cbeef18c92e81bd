"""Wind through an arena and the plume of one source, at two Péclet numbers.

    python examples/wind_figure.py --out DIR [--h 2]

For the ``paper`` and ``maze`` arenas, with the wind coming in on the left wall and
leaving on the right one: the potential flow (streamlines over the speed), then the
steady (mean) concentration of one source with impermeable walls at a global Péclet
number ``U L / D`` of 20 (diffusion spreads the plume round obstacles) and 200 (a thin
plume that follows the streamlines). Writes ``wind_paper.png`` and ``wind_maze.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import arenas
from reciprocity.fem import AdvectionSolver, WindField

#: Inflow speed, cm/s; arena length for the Péclet number, cm; lifetime of the substance, s.
SPEED, LENGTH, TAU = 5.0, 140.0, 60.0
#: Global Péclet numbers U L / D of the two plumes.
PECLETS = (20.0, 200.0)
#: Per arena: inflow segments, outflow segments (cm) and the source (cm).
SETUPS = {
    "paper": ([((0.0, 10.0), (0.0, 130.0))], [((140.0, 10.0), (140.0, 130.0))], (56.0, 60.0)),
    "maze": ([((0.0, 4.0), (0.0, 28.0))], [((140.0, 112.0), (140.0, 136.0))], (30.0, 16.0)),
}
#: Concentrations below this share of the largest are drawn as the background colour.
FLOOR = 1e-4


def draw_walls(ax, arena, inflow, outflow) -> None:
    from matplotlib.patches import Polygon
    ax.add_patch(Polygon(arena.boundary, closed=True, fill=False, lw=1.5, color="k"))
    for ob in arena.obstacles:
        ax.add_patch(Polygon(ob, closed=True, color="0.55", lw=0))
    for (p0, p1), colour in [(s, "tab:green") for s in inflow] + [(s, "tab:orange") for s in outflow]:
        ax.plot([p0[0], p1[0]], [p0[1], p1[1]], color=colour, lw=5, solid_capstyle="butt")
    ax.set_aspect("equal")
    ax.set_xlim(-3, 143)
    ax.set_ylim(-3, 143)
    ax.set_xticks([])
    ax.set_yticks([])


def figure(name: str, h: float, out: Path) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    arena = arenas.load(name)
    inflow, outflow, source = SETUPS[name]
    wind = WindField.potential(arena, inflow, outflow, speed=SPEED, h=h)
    x = np.arange(0.5, 140.0, 1.0)
    xx, yy = np.meshgrid(x, x)
    u = wind(np.column_stack([xx.ravel(), yy.ravel()])).reshape(len(x), len(x), 2)
    speed = np.hypot(u[..., 0], u[..., 1])

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.4), constrained_layout=True)
    ax = axes[0]
    im = ax.imshow(np.ma.masked_invalid(speed), origin="lower", extent=(0, 140, 0, 140), cmap="Blues",
                   vmin=0, vmax=3 * SPEED)
    ax.streamplot(x, x, np.ma.masked_invalid(u[..., 0]), np.ma.masked_invalid(u[..., 1]), color="navy",
                  density=1.4, linewidth=0.7, arrowsize=0.8)
    draw_walls(ax, arena, inflow, outflow)
    fig.colorbar(im, ax=ax, shrink=0.8, label="wind speed, cm/s")
    ax.set_title(f"{name}: potential flow\n{SPEED:g} cm/s in (green), out (orange)")
    for ax, pe in zip(axes[1:], PECLETS):
        D = SPEED * LENGTH / pe
        solver = AdvectionSolver(arena, wind, D=D, tau=TAU, walls="impermeable")
        _, _, c = solver.forward(source).on_grid(1.0)
        top = np.nanmax(c)
        im = ax.imshow(np.ma.masked_invalid(np.clip(c, FLOOR * top, None)), origin="lower",
                       extent=(0, 140, 0, 140), cmap="viridis", norm=LogNorm(FLOOR * top, top))
        draw_walls(ax, arena, inflow, outflow)
        ax.plot(*source, marker="*", color=(1.0, 0.0, 0.0), ms=16, mec="k", mew=0.6)
        fig.colorbar(im, ax=ax, shrink=0.8, label="concentration per unit release, s/cm²")
        ax.set_title(f"Péclet U·L/D = {pe:g} (D = {D:.3g} cm²/s, τ = {TAU:g} s;\n"
                     f"cell Péclet at U: {wind.speed * solver.h / (2 * D):.2g})")
    path = out / f"wind_{name}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None) -> list[Path]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=".", help="folder for the PNG files")
    ap.add_argument("--h", type=float, default=2.0, help="mesh size, cm")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [figure(name, args.h, out) for name in SETUPS]
    for p in paths:
        print(p)
    return paths


if __name__ == "__main__":
    main()
