"""Figures of the lattice search (Ristic et al. 2014, Figs. 2, 3 and 6).

:func:`lattice_figure` draws the lattice with its missing links and the mean
concentration; :func:`search_figure` the true path with particle clouds of the source
and of the searcher, and the estimated map, at a few steps of an episode.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

__all__ = ["draw_links", "lattice_figure", "search_figure", "SearchSnapshot", "snapshot", "posterior_figure"]


def draw_links(ax, space, present=None, *, color="k", lw=1.0, alpha=1.0, missing_color=None):
    """Draw the links of `space` where `present` (default ``space.present``); missing
    links dotted in `missing_color` when given."""
    pres = space.present if present is None else np.asarray(present, dtype=bool)
    seg = space.points[space.links]
    ax.add_collection(LineCollection(seg[pres], colors=color, linewidths=lw, alpha=alpha))
    if missing_color is not None:
        ax.add_collection(LineCollection(seg[~pres], colors=missing_color, linewidths=0.6,
                                         linestyles=":", alpha=0.6))
    r = space.radius
    ax.add_patch(plt.Circle((0, 0), r, fill=False, color="0.5", lw=0.8, ls="--"))
    ax.set_xlim(-r - 1.5, r + 1.5)
    ax.set_ylim(-r - 1.5, r + 1.5)
    ax.set_aspect("equal")


def lattice_figure(world, *, start=None, path=None):
    """The true lattice (missing links dotted) and the mean concentration ``A0·F``
    (the paper's Figs. 2 and 3). `path` (n, 2): the searcher's true path."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
    sp = world.space
    ax = axes[0]
    draw_links(ax, sp, missing_color="r")
    ax.plot(*world.source, "r*", ms=14, label="source")
    if start is not None:
        ax.plot(start[0], start[1], "bs", ms=8, label="start")
    if path is not None:
        p = np.asarray(path)
        ax.plot(p[:, 0], p[:, 1], "-o", color="tab:blue", ms=3, lw=1.5, alpha=0.8, label="true path")
    ax.set_title(f"lattice: {int((~sp.present).sum())} of {len(sp.links)} links missing (dotted)")
    ax.legend(loc="lower left", fontsize=8)
    ax = axes[1]
    lam = world.lam
    sc = ax.scatter(sp.points[:, 0], sp.points[:, 1], c=np.log10(np.maximum(lam, 1e-3)), s=55, marker="s",
                    cmap="Greys", vmin=-3, vmax=np.log10(max(lam.max(), 1e-3)))
    draw_links(ax, sp, color="tab:blue", lw=0.5, alpha=0.5)
    ax.plot(*world.source, "r*", ms=12)
    fig.colorbar(sc, ax=ax, label="log10 mean count λ = A0·F")
    ax.set_title(f"mean concentration, A0 = {world.strength:g}")
    fig.tight_layout()
    return fig


class SearchSnapshot:
    """Copies of what :func:`search_figure` draws at one step."""

    def __init__(self, step, belief, true_position, path):
        self.step = int(step)
        self.source = belief.source.copy()
        self.nodes = belief.space.points[belief.node].copy()
        self.links = belief.link_probability().copy()
        self.true_position = np.asarray(true_position, dtype=float).copy()
        self.path = np.asarray(path, dtype=float).copy()


def snapshot(step, strategy, platform, path) -> SearchSnapshot:
    """A snapshot of `strategy`'s belief and `platform`'s true position."""
    return SearchSnapshot(step, strategy.belief, platform.true_position, path)


def search_figure(world, snapshots, *, threshold: float = 0.6):
    """One panel per snapshot: links believed to exist (probability > `threshold`, the
    paper's Fig. 6b), source particles, searcher particles, true path."""
    n = len(snapshots)
    fig, axes = plt.subplots(1, n, figsize=(4.6 * n, 4.8), squeeze=False)
    for ax, s in zip(axes[0], snapshots):
        draw_links(ax, world.space, color="0.85", lw=0.6)
        draw_links(ax, world.space, s.links > threshold, color="k", lw=1.0)
        ax.plot(s.source[:, 0], s.source[:, 1], ".", color="tab:orange", ms=1.5, alpha=0.4)
        jit = np.random.default_rng(0).normal(0, 0.08, s.nodes.shape)
        ax.plot(*(s.nodes + jit).T, ".", color="tab:green", ms=2, alpha=0.4)
        ax.plot(s.path[:, 0], s.path[:, 1], "-", color="tab:blue", lw=1.3)
        ax.plot(*s.true_position, "bo", ms=7, mfc="none", mew=2)
        ax.plot(*world.source, "r*", ms=13)
        ax.set_title(f"step {s.step}: source (orange), searcher (green)", fontsize=9)
    fig.tight_layout()
    return fig


def posterior_figure(world, strategy, path=None):
    """The source posterior of ``lattice-reciprocity`` over the nodes (log10, the
    discrete-adjoint likelihood), on the lattice the strategy models, with the true
    source and `path` (n, 2), the searcher's true path."""
    sp = world.space
    fig, ax = plt.subplots(figsize=(5.6, 5.2))
    draw_links(ax, sp, color="0.6", lw=0.6)
    post = np.asarray(strategy.post)
    sc = ax.scatter(sp.points[:, 0], sp.points[:, 1], c=np.log10(np.maximum(post, 1e-6)), s=28, marker="s",
                    cmap="viridis", vmin=-6, vmax=0)
    if path is not None:
        p = np.asarray(path)
        ax.plot(p[:, 0], p[:, 1], "-", color="tab:red", lw=1.4, alpha=0.8)
    ax.plot(*world.source, "r*", ms=14)
    fig.colorbar(sc, ax=ax, label="log10 posterior of the source node")
    ax.set_title(f"lattice-reciprocity ({strategy.mode} map), {len(strategy.history)} readings", fontsize=9)
    fig.tight_layout()
    return fig
