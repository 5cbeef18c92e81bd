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

__all__ = ["draw_links", "lattice_figure", "search_figure", "SearchSnapshot", "snapshot", "posterior_figure",
           "true_path", "lattice_episode_figures"]


def draw_links(ax, lattice, present=None, *, color="k", lw=1.0, alpha=1.0, missing_color=None):
    """Draw the links of `lattice` (a record: ``points``, ``links``, ``present``, ``radius``,
    as :meth:`LatticeWorld.figure_record <reciprocity.worlds.lattice.LatticeWorld.figure_record>`
    gives it) where `present` (default the record's); missing links dotted in
    `missing_color` when given."""
    pres = np.asarray(lattice["present"] if present is None else present, dtype=bool)
    seg = np.asarray(lattice["points"])[np.asarray(lattice["links"])]
    ax.add_collection(LineCollection(seg[pres], colors=color, linewidths=lw, alpha=alpha))
    if missing_color is not None:
        ax.add_collection(LineCollection(seg[~pres], colors=missing_color, linewidths=0.6,
                                         linestyles=":", alpha=0.6))
    r = lattice["radius"]
    ax.add_patch(plt.Circle((0, 0), r, fill=False, color="0.5", lw=0.8, ls="--"))
    ax.set_xlim(-r - 1.5, r + 1.5)
    ax.set_ylim(-r - 1.5, r + 1.5)
    ax.set_aspect("equal")


def lattice_figure(truth: dict, *, start=None, path=None):
    """The true lattice (missing links dotted) and the mean concentration ``A0·F``
    (the paper's Figs. 2 and 3), from the environment's record of the truth
    (:attr:`Episode.truth <reciprocity.episode.Episode.truth>`: ``lattice``, ``source``,
    ``lam``, ``strength``). `path` (n, 2): the searcher's true path."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
    sp = truth["lattice"]
    present, points = np.asarray(sp["present"], dtype=bool), np.asarray(sp["points"])
    ax = axes[0]
    draw_links(ax, sp, missing_color="r")
    ax.plot(*truth["source"], "r*", ms=14, label="source")
    if start is not None:
        ax.plot(start[0], start[1], "bs", ms=8, label="start")
    if path is not None:
        p = np.asarray(path)
        ax.plot(p[:, 0], p[:, 1], "-o", color="tab:blue", ms=3, lw=1.5, alpha=0.8, label="true path")
    ax.set_title(f"lattice: {int((~present).sum())} of {len(sp['links'])} links missing (dotted)")
    ax.legend(loc="lower left", fontsize=8)
    ax = axes[1]
    lam = np.asarray(truth["lam"])
    sc = ax.scatter(points[:, 0], points[:, 1], c=np.log10(np.maximum(lam, 1e-3)), s=55, marker="s",
                    cmap="Greys", vmin=-3, vmax=np.log10(max(lam.max(), 1e-3)))
    draw_links(ax, sp, color="tab:blue", lw=0.5, alpha=0.5)
    ax.plot(*truth["source"], "r*", ms=12)
    fig.colorbar(sc, ax=ax, label="log10 mean count λ = A0·F")
    ax.set_title(f"mean concentration, A0 = {truth['strength']:g}")
    fig.tight_layout()
    return fig


class SearchSnapshot:
    """Copies of what :func:`search_figure` draws at one step."""

    def __init__(self, step, particles: dict, true_position, path):
        self.step = int(step)
        self.source = np.asarray(particles["source"], dtype=float).copy()
        self.nodes = np.asarray(particles["nodes"], dtype=float).copy()
        self.links = np.asarray(particles["links"], dtype=float).copy()
        self.true_position = np.asarray(true_position, dtype=float).copy()
        self.path = np.asarray(path, dtype=float).copy()


def snapshot(step, belief: dict, true_position, path) -> SearchSnapshot:
    """A snapshot of a lattice searcher's record of its belief (its ``figure_record()``,
    with ``lattice_particles``) beside its true position (the trace's route)."""
    return SearchSnapshot(step, belief["lattice_particles"], true_position, path)


def search_figure(truth: dict, snapshots, *, threshold: float = 0.6):
    """One panel per snapshot: links believed to exist (probability > `threshold`, the
    paper's Fig. 6b), source particles, searcher particles, true path; the truth as
    :func:`lattice_figure` takes it."""
    n = len(snapshots)
    sp = truth["lattice"]
    fig, axes = plt.subplots(1, n, figsize=(4.6 * n, 4.8), squeeze=False)
    for ax, s in zip(axes[0], snapshots):
        draw_links(ax, sp, color="0.85", lw=0.6)
        draw_links(ax, sp, s.links > threshold, color="k", lw=1.0)
        ax.plot(s.source[:, 0], s.source[:, 1], ".", color="tab:orange", ms=1.5, alpha=0.4)
        jit = np.random.default_rng(0).normal(0, 0.08, s.nodes.shape)
        ax.plot(*(s.nodes + jit).T, ".", color="tab:green", ms=2, alpha=0.4)
        ax.plot(s.path[:, 0], s.path[:, 1], "-", color="tab:blue", lw=1.3)
        ax.plot(*s.true_position, "bo", ms=7, mfc="none", mew=2)
        ax.plot(*truth["source"], "r*", ms=13)
        ax.set_title(f"step {s.step}: source (orange), searcher (green)", fontsize=9)
    fig.tight_layout()
    return fig


def posterior_figure(truth: dict, belief: dict, path=None):
    """The source posterior of ``lattice-reciprocity`` over the nodes (log10, the
    discrete-adjoint likelihood; its ``figure_record()``: ``lattice_posterior``,
    ``lattice_mode``, ``lattice_readings``), on the true lattice of `truth`, with the true
    source and `path` (n, 2), the searcher's true path."""
    sp = truth["lattice"]
    points = np.asarray(sp["points"])
    fig, ax = plt.subplots(figsize=(5.6, 5.2))
    draw_links(ax, sp, color="0.6", lw=0.6)
    post = np.asarray(belief["lattice_posterior"])
    sc = ax.scatter(points[:, 0], points[:, 1], c=np.log10(np.maximum(post, 1e-6)), s=28, marker="s",
                    cmap="viridis", vmin=-6, vmax=0)
    if path is not None:
        p = np.asarray(path)
        ax.plot(p[:, 0], p[:, 1], "-", color="tab:red", lw=1.4, alpha=0.8)
    ax.plot(*truth["source"], "r*", ms=14)
    fig.colorbar(sc, ax=ax, label="log10 posterior of the source node")
    ax.set_title(f"lattice-reciprocity ({belief['lattice_mode']} map), {belief['lattice_readings']} readings",
                 fontsize=9)
    fig.tight_layout()
    return fig


def true_path(episode) -> np.ndarray:
    """The searcher's true path (n, 2) from the episode's trace: the start, then where each
    step's route ended (the routes hold the true positions, slips included)."""
    path = []
    for rec in episode.records:
        if len(rec.route):
            if not path:
                path.append(np.asarray(rec.route[0], dtype=float)[:2].tolist())
            path.append(np.asarray(rec.route[-1], dtype=float)[:2].tolist())
    return np.array(path or [np.atleast_2d(episode.summary["start"])[0, :2].tolist()], dtype=float)


def lattice_episode_figures(episode):
    """The figures of a lattice episode run with ``figures=True``, from its record: the
    true lattice with the true path (``"lattice"``), and the searcher's final particle
    clouds (``"search"``, ``lattice_particles``) or source posterior (``"posterior"``,
    ``lattice_posterior``)."""
    truth, belief = episode.truth, episode.belief
    path = true_path(episode)
    start = np.atleast_2d(episode.summary["start"])[0]
    yield "lattice", lattice_figure(truth, start=start, path=path)
    if "lattice_particles" in belief:
        yield "search", search_figure(truth, [snapshot(episode.summary["steps"], belief, path[-1], path)])
    if "lattice_posterior" in belief:
        yield "posterior", posterior_figure(truth, belief, path)
