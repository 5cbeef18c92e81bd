"""Figures of a search on an unknown map: the true walls against the believed ones, the
seen region, the frontier and the imaging on the believed mesh, step by step."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from arenas import Arena

from ..episode import Episode
from .figures import draw_arena

__all__ = ["mapping_steps_figure"]


def mapping_steps_figure(episode: Episode, true_arena: Arena, *, steps=None, ncols: int = 4) -> Figure:
    """One panel per step of a search on an unknown map.

    Background: the imaging function ``P_M`` on the believed mesh after the step; grey
    fill: the believed obstacles (what the model solves around); red outline: the true
    obstacles (never shown to the strategy); hatched dark veil: space not yet seen by the
    lidar (free in the model: optimistic); cyan dots: the frontier (seen-free cells next to
    unseen ones); red circles: observation points; blue line: the path; black cross: the
    next point; magenta diamond: the estimate; green star: the true source.

    Parameters
    ----------
    episode : Episode
        The run (``map: unknown``, with ``figures=True``): its trace, and the believed map
        after a few steps, ``belief["map_steps"]``
        (:func:`reciprocity.strategies.map_steps.with_map_steps`).
    true_arena : Arena
        The true walls (the world's, for the figure only).
    steps : sequence of int, optional
        Steps (1-based) among those recorded; default: all of them (1, 2, the middle one,
        the last).
    ncols : int
        Panels per row.
    """
    n = len(episode.trace)
    snaps = {snap["step"]: snap for snap in episode.belief["map_steps"]}
    steps = sorted(snaps) if steps is None else [k for k in steps if k in snaps]
    rows = int(np.ceil(len(steps) / ncols))
    cols = min(ncols, len(steps))
    fig = Figure(figsize=(3.8 * cols, 3.7 * rows + 0.6), layout="constrained")
    src = np.asarray(episode.summary["source"])
    veil = ListedColormap([(0, 0, 0, 0), (0.1, 0.1, 0.1, 0.55)])
    tpc = None
    for i, k in enumerate(steps):
        ax = fig.add_subplot(rows, cols, i + 1)
        snap = snaps[k]
        im = snap["imaging"]
        tpc = ax.tripcolor(im.solver.triangulation, im.values(), shading="gouraud", cmap="jet", vmin=0, vmax=1,
                           rasterized=True)
        draw_arena(ax, snap["arena"], obstacle_color="0.55")
        for o in true_arena.obstacles:
            c = np.vstack([o, o[:1]])
            ax.plot(c[:, 0], c[:, 1], "-", color="red", lw=1.0, zorder=4)
        (x0, x1), (y0, y1) = snap["bounds"]
        ax.imshow(snap["unseen"], origin="lower", extent=snap["extent"], cmap=veil,
                  vmin=0, vmax=1, zorder=2, interpolation="nearest")
        front = snap["frontier"]
        ax.plot(front[:, 0], front[:, 1], ".", color="cyan", ms=1.5, zorder=5)
        path = np.vstack([np.asarray(r["route"]) for r in episode.trace[:k]])
        ax.plot(path[:, 0], path[:, 1], "-", color="tab:blue", lw=1.2, zorder=6)
        ax.plot(im.points[:, 0], im.points[:, 1], "o", mfc="none", mec="red", ms=6, mew=1.3, zorder=6)
        nxt = episode.trace[k - 1].get("next")
        if nxt is not None:
            ax.plot(*nxt, "kx", ms=8, mew=2, zorder=7)
        est = im.estimate()
        ax.plot(*est, "D", color="magenta", mec="k", ms=6, zorder=7)
        ax.plot(*src, "*", color="lime", mec="k", ms=10, zorder=7)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_title(f"step {k}: seen {100 * snap['seen_fraction']:.0f} %, map rev. {snap['revision']}, "
                     f"model error {100 * im.model_error:.0f} %", fontsize=8)
        ax.tick_params(labelsize=7)
    fig.colorbar(tpc, ax=fig.axes, shrink=0.8, label="imaging function $P_M$ (believed mesh)")
    fig.suptitle(f"reciprocity search on an unknown map ({n} steps, {episode.summary['n_measurements']} "
                 f"readings): believed against true walls", fontsize=10)
    handles = [
        Patch(color="0.55", label="believed obstacles"),
        Line2D([], [], color="red", lw=1.0, label="true obstacles (hidden from the strategy)"),
        Patch(color=(0.1, 0.1, 0.1, 0.55), label="not yet seen (free in the model)"),
        Line2D([], [], marker=".", ls="", color="cyan", label="frontier"),
        Line2D([], [], marker="*", ls="", color="lime", mec="k", ms=10, label="true source"),
        Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=6, label="estimate"),
        Line2D([], [], marker="o", ls="", mfc="none", mec="red", ms=6, label="observation points"),
        Line2D([], [], marker="x", ls="", color="k", ms=8, mew=2, label="next point"),
        Line2D([], [], color="tab:blue", lw=1.2, label="path"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=5, fontsize=7, facecolor="0.85")
    return fig
