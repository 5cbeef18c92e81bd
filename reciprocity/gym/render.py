"""Frames of a Gymnasium episode: the arena (or lattice, or area), the path so far and the
agent's belief, as an RGB array. Nothing of the truth is drawn: a frame may be a learning
agent's observation."""

from __future__ import annotations

import numpy as np

__all__ = ["frame", "belief_points"]


def belief_points(agent):
    """``(support (n, 2), weights (n,))`` of the agent's belief, or None when it has none
    (an outside policy)."""
    strategy = getattr(agent, "strategy", None)
    belief = getattr(strategy, "belief", None)
    try:
        if belief is not None and hasattr(belief, "weights"):
            return np.asarray(belief.support(), dtype=float), np.asarray(belief.weights(), dtype=float)
        if strategy is not None and hasattr(strategy, "cells") and hasattr(strategy, "weights"):
            return np.asarray(strategy.cells, dtype=float), np.asarray(strategy.weights(), dtype=float)
    except (AttributeError, TypeError, ValueError):      # a belief not started yet
        return None
    return None


def frame(env, size_px: int = 480) -> np.ndarray:
    """An RGB frame (H, W, 3) of `env` (a :class:`~reciprocity.gym.SearchGymEnv`) now."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(size_px / 100, size_px / 100), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes([0.02, 0.02, 0.96, 0.96])
    lo, hi = env.face.bounds()
    nominal = env.face.nominal
    arena = nominal.get("arena")
    if arena is not None:
        ax.fill(*np.asarray(arena.boundary).T, color="0.97", ec="k", lw=1, zorder=0)
    else:
        ax.add_patch(matplotlib.patches.Rectangle(lo, *(hi - lo), fc="0.97", ec="k", lw=1, zorder=0))
    space = nominal.get("space")
    if space is not None and nominal.get("radius") is not None:          # the lattice's nodes
        ax.plot(*np.asarray(space.points).T, ".", color="0.8", ms=2, zorder=1)
    belief = belief_points(env.agent)
    if belief is not None:
        pts, w = belief
        top = w.max() if w.size and w.max() > 0 else 1.0
        keep = w >= 1e-3 * top
        ax.scatter(pts[keep, 0], pts[keep, 1], c=w[keep] / top, s=8, cmap="magma_r", vmin=0, vmax=1, lw=0,
                   zorder=2)
    if arena is not None:
        for o in arena.obstacles:
            ax.fill(*np.asarray(o).T, color="0.35", zorder=3)
    if env.run is not None and env.run.records:
        route = np.vstack([np.asarray(r.route).reshape(-1, 2) for r in env.run.records])
        ax.plot(route[:, 0], route[:, 1], "-", color="tab:blue", lw=1.2, zorder=4)
    ax.plot(*env.face.position, "o", color="tab:blue", ms=6, zorder=5)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    return np.ascontiguousarray(rgba[..., :3])
