"""Figures in the style of Landa et al.: imaging steps (Fig. 4) and gradient runs (Fig. 5)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.tri import Triangulation

from arenas import Arena, Floor

from ..episode import Episode
from ..fem.green import Field
from ..beliefs.imaging import ImagingMap

__all__ = ["draw_arena", "imaging_steps_figure", "count_steps_figure", "doubling_steps", "gradient_run_figure",
           "field_figure", "sources_figure"]


def draw_arena(ax, arena: Arena, *, obstacle_color: str = "0.25", wall_color: str = "k") -> None:
    """Draw the arena's walls and filled obstacles on `ax` (cm, equal aspect)."""
    b = np.vstack([arena.boundary, arena.boundary[:1]])
    ax.plot(b[:, 0], b[:, 1], color=wall_color, lw=1.5)
    for o in arena.obstacles:
        ax.fill(o[:, 0], o[:, 1], color=obstacle_color, zorder=3)
    (x0, x1), (y0, y1) = arena.bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")


def _route(trace) -> np.ndarray:
    """The way travelled over the given trace records, shape (n, 2)."""
    return np.vstack([np.asarray(r["route"]) for r in trace])


def _replans(trace) -> np.ndarray:
    """Positions where a car re-planned its path over the given records, shape (n, 2)."""
    pts = [np.asarray(p, dtype=float)[:2] for r in trace for p in r.get("replans", ())]
    return np.array(pts).reshape(-1, 2)


def _triangulation(imaging: ImagingMap) -> Triangulation:
    """The solver's own triangulation (one per mesh); P2 maps need the split one."""
    if imaging.solver.order == 1:
        return imaging.solver.triangulation
    return Triangulation(imaging.nodes[:, 0], imaging.nodes[:, 1], imaging.triangles)


def imaging_steps_figure(episode: Episode, imaging: ImagingMap, arena: Arena, *,
                         eps: float, steps=None, ncols: int = 4,
                         within_reach: np.ndarray | None = None) -> Figure:
    """One panel per step of a reciprocity search, as in the paper's Fig. 4.

    Background: ``P_M`` after the step; black: the newest level set ``{v_k = I_k}``;
    white: the boundary of ``{P_M >= eps}``; red circles: measurement points; blue
    line: the path (the car's true path on the testbed); small blue circles: where the
    car re-planned its path; black cross: the next point; magenta diamond: the estimate;
    green star: the true source.

    Parameters
    ----------
    episode : Episode
        The run (its trace gives the path and next points).
    imaging : ImagingMap
        The strategy's imaging map at the end of the run.
    arena : Arena
        For the walls.
    eps : float
        Region threshold.
    steps : sequence of int, optional
        Steps to draw (1-based); default: the first two and the last two.
    ncols : int
        Panels per row.
    within_reach : ndarray of bool, optional
        At the nodes of `imaging`: what the search could still reach at its end
        (``ReciprocityStrategy.within_reach``), outlined dashed in the last panel with
        the belief mass outside it, when some node lies outside.
    """
    n = imaging.n
    if within_reach is not None and len(within_reach) != len(imaging.nodes):
        within_reach = None                              # another mesh than the map's
    if steps is None:
        steps = sorted({1, min(2, n), max(1, n - 1), n})
    steps = [k for k in steps if 1 <= k <= n]
    rows = int(np.ceil(len(steps) / ncols))
    cols = min(ncols, len(steps))
    fig = Figure(figsize=(3.6 * cols, 3.5 * rows), layout="constrained")
    tri = _triangulation(imaging)
    src = np.atleast_2d(np.asarray(episode.summary.get("sources") or episode.summary["source"], dtype=float))
    for i, k in enumerate(steps):
        ax = fig.add_subplot(rows, cols, i + 1)
        sub = imaging.first(k)
        P = sub.values()
        tpc = ax.tripcolor(tri, P, shading="gouraud", cmap="jet", vmin=0, vmax=1, rasterized=True)
        draw_arena(ax, arena)
        for line in sub.level_set(-1):
            ax.plot(line[:, 0], line[:, 1], "k-", lw=1.2)
        for line in sub.region_boundary(eps):
            ax.plot(line[:, 0], line[:, 1], "w-", lw=1.5)
        path = _route(episode.trace[:k])
        ax.plot(path[:, 0], path[:, 1], "-", color="tab:blue", lw=1.2)
        replans = _replans(episode.trace[:k])
        ax.plot(replans[:, 0], replans[:, 1], "o", mfc="none", mec="tab:blue", ms=4, mew=1)
        ax.plot(sub.points[:, 0], sub.points[:, 1], "o", mfc="none", mec="red", ms=7, mew=1.5)
        nxt = episode.trace[k - 1].get("next")
        if nxt is not None:
            ax.plot(*nxt, "kx", ms=9, mew=2)
        est = sub.estimate()
        found = episode.trace[k - 1].get("estimates")          # a search for several sources
        shown = np.atleast_2d(found) if found else est[None]
        ax.plot(shown[:, 0], shown[:, 1], "D", color="magenta", mec="k", ms=7, ls="")
        ax.plot(src[:, 0], src[:, 1], "*", color="lime", mec="k", ms=11, ls="")
        outside = ""
        if within_reach is not None and k == steps[-1] and not within_reach.all():
            ax.tricontour(tri, within_reach.astype(float), levels=[0.5], colors="k",
                          linestyles="--", linewidths=1.4)
            w = sub.weights()
            outside = f"\n{1.0 - w[within_reach].sum():.0%} of the belief out of reach"
        area = sub.area(eps)
        what = f"{len(found)} found" if found else f"est. ({est[0]:.1f}, {est[1]:.1f})"
        ax.set_title(f"step {k}: area {area:.0f} cm², {what}{outside}", fontsize=9)
        ax.set_xlabel("x (cm)", fontsize=8)
        ax.set_ylabel("y (cm)", fontsize=8)
    fig.colorbar(tpc, ax=fig.axes, shrink=0.8, label="imaging function $P_M$")
    shown = "every step" if len(steps) == n else f"steps {', '.join(map(str, steps))} of {n}"
    fig.suptitle(f"reciprocity search: {shown} ({n} measurements); region $P_M \\geq$ {eps:g}", fontsize=10)
    handles = [
        Line2D([], [], marker="*", ls="", color="lime", mec="k", ms=11, label="true source"),
        Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=7, label="estimate"),
        Line2D([], [], marker="x", ls="", color="k", ms=9, mew=2, label="next observation point"),
        Line2D([], [], marker="o", ls="", mfc="none", mec="red", ms=7, mew=1.5, label="observation points"),
        Line2D([], [], color="k", lw=1.2, label="newest level set $v_k = I_k$"),
        Line2D([], [], color="w", lw=1.5, label=f"region $P_M \\geq$ {eps:g}"),
        Line2D([], [], color="tab:blue", lw=1.2, label="path"),
    ]
    if within_reach is not None and not within_reach.all():
        handles.append(Line2D([], [], color="k", ls="--", lw=1.4, label="within reach (last step)"))
    if len(_replans(episode.trace)):
        handles.append(Line2D([], [], marker="o", ls="", mfc="none", mec="tab:blue", ms=4,
                              label="re-plans (car)"))
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=8, facecolor="0.85")
    return fig


def doubling_steps(n: int) -> list[int]:
    """Steps 1, 2, 4, 8, ... and the last, `n` (1-based)."""
    return sorted({2 ** i for i in range(int(np.log2(max(n, 1))) + 1)} | {n})


def streamlines(ax, wind, arena: Arena) -> None:
    """The wind's streamlines, faint, over the arena's bounding box (NaN in the walls)."""
    (x0, x1), (y0, y1) = arena.bounds
    x, y = np.linspace(x0, x1, 120), np.linspace(y0, y1, 120)
    xx, yy = np.meshgrid(x, y)
    u = np.asarray(wind(np.column_stack([xx.ravel(), yy.ravel()]))).reshape(len(y), len(x), 2)
    lines = ax.streamplot(x, y, np.ma.masked_invalid(u[..., 0]), np.ma.masked_invalid(u[..., 1]), color="0.5",
                          density=1.0, linewidth=0.6, arrowsize=0.7, zorder=2)
    lines.lines.set_alpha(0.6)
    lines.arrows.set_alpha(0.6)


def count_steps_figure(episode: Episode, posterior, triangulation: Triangulation, arena: Arena, *,
                       wind=None, steps=None, ncols: int = 4, floor: float = 1e-3, zoom_below: float = 4.0,
                       zoom: float = 20.0) -> Figure:
    """One panel per step of a search on hit counts (``reciprocity-wind``): the posterior
    over the source after the step's readings.

    Background: the posterior density over the source, relative to its peak, on a log
    scale down to `floor`; faint white: the wind's streamlines; dots: the readings so far
    (white: hits, area growing with the count; grey: none), the newest ringed in black;
    thin blue line: the path; magenta diamond: the estimate; red star: the true source.
    A panel whose posterior is narrower than `zoom_below` (standard deviation, cm) shows
    only `zoom` cm either side of the estimate.

    Parameters
    ----------
    episode : Episode
        The run (its trace gives the readings and the path).
    posterior : CountPosterior
        The strategy's belief at the end (:meth:`~reciprocity.beliefs.counts.CountPosterior.first`
        gives each step's).
    triangulation : Triangulation
        The mesh of the posterior's nodes.
    arena : Arena
        For the walls.
    wind : callable, optional
        The wind at points (n, 2) -> (n, 2), cm/s: its streamlines are drawn.
    steps : sequence of int, optional
        Steps to draw (1-based); default :func:`doubling_steps`.
    """
    from matplotlib.colors import LogNorm
    n = posterior.n
    steps = [k for k in (steps or doubling_steps(n)) if 1 <= k <= n]
    rows, cols = int(np.ceil(len(steps) / ncols)), min(ncols, len(steps))
    fig = Figure(figsize=(3.6 * cols, 3.7 * rows + 0.6), layout="constrained")
    src = np.asarray(episode.summary["source"], dtype=float)
    points = np.vstack([r["points"] for r in episode.trace])
    counts = np.concatenate([r["readings"] for r in episode.trace])
    norm = LogNorm(floor, 1.0)
    for i, k in enumerate(steps):
        ax = fig.add_subplot(rows, cols, i + 1)
        sub = posterior.first(k)
        density = sub.weights() / sub.areas
        tpc = ax.tripcolor(triangulation, np.clip(density / density.max(), floor, 1.0), shading="gouraud",
                           cmap="viridis", norm=norm, rasterized=True)
        draw_arena(ax, arena)
        if wind is not None:
            streamlines(ax, wind, arena)
        path = _route(episode.trace[:k])
        ax.plot(path[:, 0], path[:, 1], "-", color="tab:blue", lw=0.8, alpha=0.8, zorder=4)
        hit = counts[:k] > 0
        ax.scatter(points[:k][hit, 0], points[:k][hit, 1], s=12 + 6 * np.sqrt(counts[:k][hit]), c="w",
                   edgecolors="k", linewidths=0.6, zorder=5)
        ax.scatter(points[:k][~hit, 0], points[:k][~hit, 1], s=10, c="0.55", edgecolors="k", linewidths=0.5,
                   zorder=5)
        ax.plot(*points[k - 1], "o", mfc="none", mec="k", ms=9, mew=1.4, zorder=6)
        est = sub.estimate()
        ax.plot(*est, "D", color="magenta", mec="k", ms=7, zorder=7)
        ax.plot(*src, "*", color=(1.0, 0.0, 0.0), mec="k", ms=13, zorder=8)
        w = sub.weights()
        spread = np.sqrt(w @ np.sum((sub.nodes - w @ sub.nodes) ** 2, axis=1))
        zoomed = spread < zoom_below
        if zoomed:
            ax.set_xlim(est[0] - zoom, est[0] + zoom)
            ax.set_ylim(est[1] - zoom, est[1] + zoom)
        ax.set_title(f"reading {k}: {counts[k - 1]:.0f} hit{'' if counts[k - 1] == 1 else 's'}, "
                     f"est. ({est[0]:.0f}, {est[1]:.0f})"
                     + (f"\nzoom: posterior sd {spread:.1f} cm" if zoomed else ""), fontsize=9)
        ax.set_xlabel("x (cm)", fontsize=8)
        ax.set_ylabel("y (cm)", fontsize=8)
    fig.colorbar(tpc, ax=fig.axes, shrink=0.8, label="posterior density / its peak")
    s = episode.summary
    fig.suptitle(f"reciprocity in wind: the posterior after readings {', '.join(map(str, steps))} "
                 f"of {n}; error {s['error']:.1f} cm, {s['stop_reason'].split(':')[0]}", fontsize=10)
    handles = [
        Line2D([], [], marker="*", ls="", color=(1.0, 0.0, 0.0), mec="k", ms=12, label="true source"),
        Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=7, label="estimate"),
        Line2D([], [], marker="o", ls="", color="w", mec="k", ms=6, label="reading with hits (size: count)"),
        Line2D([], [], marker="o", ls="", color="0.55", mec="k", ms=4, label="reading without hits"),
        Line2D([], [], marker="o", ls="", mfc="none", mec="k", ms=9, mew=1.4, label="newest reading"),
        Line2D([], [], color="tab:blue", lw=0.8, label="path"),
    ]
    if wind is not None:
        handles.append(Line2D([], [], color="0.6", lw=0.8, label="wind streamlines (true)"))
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=8, facecolor="0.85")
    return fig


def gradient_run_figure(episode: Episode, field: Field | None, arena: Arena,
                        gradients=(), *, floor: Floor | None = None) -> Figure:
    """A gradient-ascent run over the grey-scale signal, as in the paper's Fig. 5.

    Grey background: the painted floor when `floor` is given, else the signal clipped to
    0-255 (lighter = stronger); green: the path; magenta circles: signal measurements;
    red circles and arrows: where gradients were estimated, and their directions; blue
    circles: where a car re-planned; green star: the true source.
    """
    fig = Figure(figsize=(6, 5.4), layout="constrained")
    ax = fig.add_subplot()
    (x0, x1), (y0, y1) = arena.bounds
    if floor is not None:
        floor.plot(ax)
    else:
        x, y, u = field.on_grid(1.0)
        ax.set_facecolor("0.25")  # cells inside obstacles are NaN: show them as obstacles
        ax.imshow(np.clip(u, 0, 255), origin="lower", extent=[x0, x1, y0, y1], cmap="gray",
                  vmin=0, vmax=255, interpolation="nearest")
    draw_arena(ax, arena)
    path = _route(episode.trace)
    ax.plot(path[:, 0], path[:, 1], "-", color="limegreen", lw=1.5)
    sig = np.array([np.atleast_2d(r["points"])[-1] for r in episode.trace if r["kind"] == "signal"])
    ax.plot(sig[:, 0], sig[:, 1], "o", mfc="none", mec="magenta", ms=7, mew=1.5)
    replans = _replans(episode.trace)
    ax.plot(replans[:, 0], replans[:, 1], "o", mfc="none", mec="tab:blue", ms=4, mew=1)
    if len(gradients):
        at = np.array([p for p, _ in gradients]).reshape(-1, 2)
        ax.plot(at[:, 0], at[:, 1], "o", mfc="none", mec="red", ms=7, mew=1.5)
    for p, g in gradients:
        g = np.asarray(g)
        u_ = 8.0 * g / max(np.hypot(*g), 1e-12)
        ax.annotate("", xy=(p[0] + u_[0], p[1] + u_[1]), xytext=p,
                    arrowprops=dict(arrowstyle="->", color="red", lw=1.5))
    ax.plot(*episode.summary["source"], "*", color="lime", mec="k", ms=12)
    if episode.summary["estimate"] is not None:
        ax.plot(*episode.summary["estimate"], "D", color="magenta", mec="k", ms=7)
    s = episode.summary
    n_grad = sum(r["kind"] == "gradient" for r in episode.trace)
    extra = s["n_samples"] - s["n_measurements"]
    ax.set_title(f"gradient ascent: {s['n_measurements']} signal + {n_grad} gradients × 2 extra "
                 f"= {s['n_measurements'] + extra} samples", fontsize=9)
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    handles = [
        Line2D([], [], marker="*", ls="", color="lime", mec="k", ms=12, label="true source"),
        Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=7, label="estimate"),
        Line2D([], [], color="limegreen", lw=1.5, label="path"),
        Line2D([], [], marker="o", ls="", mfc="none", mec="magenta", ms=7, mew=1.5, label="signal readings"),
        Line2D([], [], marker=r"$\rightarrow$", ls="", color="red", ms=12, label="gradient estimates"),
    ]
    if len(replans):
        handles.append(Line2D([], [], marker="o", ls="", mfc="none", mec="tab:blue", ms=4, label="re-plans"))
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
    return fig


def sources_figure(episode: Episode, more: ImagingMap, arena: Arena) -> Figure:
    """The end of a search for several sources: every estimate with its uncertainty, the
    true sources, the path, and the map of one more source on the readings the estimates
    leave unexplained.

    Parameters
    ----------
    episode : Episode
        The run; its summary gives ``estimates``, ``estimates_sd`` and ``sources``.
    more : ImagingMap
        The residual map of one more source (``SourceBook.active`` at the end).
    arena : Arena
        For the walls.
    """
    s = episode.summary
    fig = Figure(figsize=(5.6, 4.6), layout="constrained")
    ax = fig.add_subplot()
    tpc = ax.tripcolor(_triangulation(more), more.values(), shading="gouraud", cmap="viridis", vmin=0, vmax=1,
                       rasterized=True)
    draw_arena(ax, arena)
    path = _route(episode.trace)
    ax.plot(path[:, 0], path[:, 1], "-", color="tab:blue", lw=1.0, alpha=0.8)
    pts = np.array([r["targets"] for r in episode.trace if r.get("targets") is not None]).reshape(-1, 2)
    ax.plot(pts[:, 0], pts[:, 1], "o", mfc="none", mec="red", ms=5, mew=1.2)
    true = np.atleast_2d(np.asarray(s.get("sources") or s["source"], dtype=float))
    ax.plot(true[:, 0], true[:, 1], "*", color="lime", mec="k", ms=13, ls="")
    est = np.asarray(s.get("estimates") or [], dtype=float).reshape(-1, 2)
    sd = s.get("estimates_sd") or [0.0] * len(est)
    for j, (p, r) in enumerate(zip(est, sd)):
        ax.plot(*p, "D", color="magenta", mec="k", ms=7)
        ax.add_patch(Circle(p, 2.0 * r, fill=False, ec="magenta", lw=1.2))
        ax.annotate(str(j + 1), p, xytext=(5, 5), textcoords="offset points", color="magenta", fontsize=9,
                    fontweight="bold")
    fig.colorbar(tpc, ax=ax, shrink=0.85, label="one more source: $P$ on the residual readings")
    right = "K right" if s.get("n_sources_right") else "K wrong"
    fig.suptitle(f"{len(est)} sources found of {len(true)} ({right}); {s['n_measurements']} readings", fontsize=10)
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    ax.set_aspect("equal")
    handles = [Line2D([], [], marker="*", ls="", color="lime", mec="k", ms=11, label="true sources"),
               Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=7, label="estimates (circle: 2 sd)"),
               Line2D([], [], marker="o", ls="", mfc="none", mec="red", ms=5, label="readings"),
               Line2D([], [], color="tab:blue", lw=1.0, label="path")]
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8, facecolor="0.85")
    return fig


def field_figure(field: Field, arena: Arena, *, title: str = "") -> Figure:
    """The signal as a grey-scale floor (lighter = stronger), clipped to 0-255."""
    fig = Figure(figsize=(6, 5.4), layout="constrained")
    ax = fig.add_subplot()
    x, y, u = field.on_grid(0.5)
    (x0, x1), (y0, y1) = arena.bounds
    ax.set_facecolor("0.25")
    im = ax.imshow(np.clip(u, 0, 255), origin="lower", extent=[x0, x1, y0, y1], cmap="gray",
                   vmin=0, vmax=255)
    draw_arena(ax, arena)
    fig.colorbar(im, ax=ax, label="signal")
    ax.set_title(title)
    return fig

