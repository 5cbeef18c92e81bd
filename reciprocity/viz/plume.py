"""Figures of plume searches: the mean-rate field, a search with its hits and particle
clouds, entropy and free energy against time, and multi-searcher runs with their messages.

Each figure is drawn from records alone: the truth's (an episode's
:attr:`~reciprocity.episode.Episode.truth`, :meth:`PlumeWorld.figure_record
<reciprocity.worlds.plume.PlumeWorld.figure_record>`: the true mean hits per step, the
bounds, the source) and the strategy's (:attr:`~reciprocity.episode.Episode.belief`: its
``particles``). Run the episodes with ``figures=True``; ``examples/plume_figures.py``
runs and draws the set.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..episode import Episode
from ..errors import SearchError

__all__ = ["rate_field_figure", "search_figure", "voi_figure"]


def _truth(episode: Episode) -> dict:
    """The episode's record of a plume's truth; refused when it was run without figures."""
    if "mean_hits" not in episode.truth:
        raise SearchError("a plume figure is drawn from the episode's record: run the episode with figures=True")
    return episode.truth


def _rate_image(ax, truth: dict):
    (x0, x1), (y0, y1) = truth["bounds"]
    r = truth["mean_hits"]
    im = ax.imshow(np.log10(np.maximum(r, 1e-6)), origin="lower", extent=(x0, x1, y0, y1),
                   cmap="viridis", vmin=-4, vmax=max(-3, float(np.log10(r.max()))), aspect="equal")
    ax.plot(*truth["source"], "r*", ms=14, mec="w", label="source")
    return im


def rate_field_figure(episode: Episode, *, title: str = "") -> Figure:
    """The true mean number of hits per step, log10, with the source.

    Parameters
    ----------
    episode : Episode
        A plume episode run with ``figures=True``: its :attr:`~reciprocity.episode.Episode.truth`
        holds ``mean_hits``, ``bounds``, ``source`` and ``form``.
    title : str
        Default: the rate's form.

    Returns
    -------
    Figure
    """
    truth = _truth(episode)
    fig = Figure(figsize=(6, 5))
    ax = fig.subplots()
    im = _rate_image(ax, truth)
    fig.colorbar(im, ax=ax, label="log10 mean hits per step")
    ax.set_title(title or f"mean hit rate ({truth['form']} form)")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="lower left")
    return fig


def _path(trace, agent=0):
    pts = [r["route"][-1] for r in trace if r["agent"] == agent and len(r["route"])]
    hits = [(r["points"][0], r["readings"][0]) for r in trace
            if r["agent"] == agent and len(r["readings"]) and r["readings"][0] > 0]
    return np.array(pts).reshape(-1, 2), hits


def search_figure(episode: Episode, *, title: str = "") -> Figure:
    """Trajectory with hits over the rate field, particle clouds at four steps, and
    entropy / free energy against time.

    Parameters
    ----------
    episode : Episode
        A plume episode run with ``figures=True``: the truth's record, and the strategy's
        particle clouds (``belief["particles"]``: none, no cloud is drawn).
    title : str
        Default: the strategy, its steps and its stop.

    Returns
    -------
    Figure
    """
    truth = _truth(episode)
    trace = episode.trace
    fig = Figure(figsize=(13, 8), layout="constrained")
    axes = fig.subplot_mosaic([["path", "c0", "c1"], ["curves", "c2", "c3"]])
    ax = axes["path"]
    _rate_image(ax, truth)
    path, hits = _path(trace)
    start = np.asarray(episode.summary["start"][:2])
    ax.plot(*np.vstack([start, path]).T, "w-", lw=1)
    if hits:
        h = np.array([p for p, _ in hits])
        ax.scatter(h[:, 0], h[:, 1], s=12 + 8 * np.array([v for _, v in hits]), c="r", label="hits", zorder=3)
    ax.plot(*start, "ws", ms=7, label="start")
    ax.set_title(title or f"{episode.summary['strategy']}: {episode.summary['steps']} steps, "
                 f"{episode.summary['stop']}")
    ax.legend(loc="lower left", fontsize=7)
    snaps = episode.belief.get("particles", [])
    picks = [snaps[int(i)] for i in np.linspace(0, len(snaps) - 1, 4).round()] if snaps else []
    (x0, x1), (y0, y1) = truth["bounds"]
    for k, key in enumerate(["c0", "c1", "c2", "c3"]):
        a = axes[key]
        if k >= len(picks):
            a.axis("off")
            continue
        step, x, w = picks[k]
        a.scatter(x[:, 0], x[:, 1], s=2 + 60 * w / max(w.max(), 1e-300), c="k", alpha=0.6)
        upto = path[:step] if step > 0 else path[:0]
        a.plot(*np.vstack([start, upto]).T, "b-", lw=0.8)
        a.plot(*truth["source"], "r*", ms=10)
        est = w @ x
        a.plot(*est, "m+", ms=12, mew=2)
        a.set_xlim(x0, x1)
        a.set_ylim(y0, y1)
        a.set_aspect("equal")
        a.set_title(f"particles at step {step}", fontsize=9)
    a = axes["curves"]
    ent = np.array([r.get("entropy", np.nan) for r in trace])
    fe = np.array([r.get("free_energy", np.nan) for r in trace])
    t = np.arange(1, len(trace) + 1)
    a.plot(t, ent, "b-", label="entropy S (nats)")
    a.set_xlabel("step")
    a.set_ylabel("entropy (nats)", color="b")
    a2 = a.twinx()
    a2.semilogy(t, np.maximum(fe, 1e-3), "r-", label="free energy F (eq. 8)")
    a2.set_ylabel("free energy", color="r")
    a.set_title("entropy and free energy")
    return fig


def voi_figure(episodes: dict) -> Figure:
    """Trajectories of every searcher for each run of `episodes` (label -> Episode, each
    run with ``figures=True``) over its true rate field, and the message timeline
    (cumulative messages against time).

    Parameters
    ----------
    episodes : dict
        Label -> Episode.

    Returns
    -------
    Figure
    """
    fig = Figure(figsize=(5 * (len(episodes) + 1), 5), layout="constrained")
    axes = fig.subplots(1, len(episodes) + 1)
    colors = ["w", "orange", "cyan", "magenta"]
    for ax, (label, ep) in zip(axes, episodes.items()):
        _rate_image(ax, _truth(ep))
        trace = ep.trace
        starts = np.atleast_2d(ep.summary.get("starts", [ep.summary["start"]]))
        for k in range(len(starts)):
            path, hits = _path(trace, k)
            ax.plot(*np.vstack([starts[k][:2], path]).T, "-", color=colors[k % 4], lw=1, label=f"searcher {k}")
            if hits:
                h = np.array([p for p, _ in hits])
                ax.scatter(h[:, 0], h[:, 1], s=14, c="r", zorder=3)
        ax.set_title(f"{label}: {ep.summary['steps']} steps, {ep.summary.get('messages', 0)} messages",
                     fontsize=9)
        ax.legend(loc="lower right", fontsize=7)
    ax = axes[-1]
    for label, ep in episodes.items():
        times = np.sort([m.time for m in ep.messages.messages])
        ax.step(np.concatenate([[0], times]), np.arange(len(times) + 1), where="post", label=label)
    ax.set_xlabel("time (steps)")
    ax.set_ylabel("messages sent (cumulative)")
    ax.set_title("message timeline")
    ax.legend()
    return fig
