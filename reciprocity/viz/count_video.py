"""MP4 video of a search on hit counts in a ``flow`` world (reciprocity in wind, infotaxis,
surge-cast, gradient), drawn from the episode's record alone.

Left: the true mean concentration (log scale) under the wind's streamlines, with the
observer moving along its path and its readings. Right, when the strategy recorded a
posterior over the source (``belief["posterior"]``): that posterior after the latest
reading. Each reading takes ``move_frames`` frames of travel from the last point read (the
posterior of the readings before it) and ``hold_frames`` frames at the point (the posterior
with it). The static layers are drawn once per reading; the moving ones are blitted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.tri import Triangulation
from tqdm import tqdm

from arenas import Arena

from ..episode import Episode
from ..errors import SearchError
from .figures import draw_arena, streamlines
from .video import encode_mp4

__all__ = ["write_count_video"]

#: The posterior and the concentration are drawn relative to their peak down to this share.
FLOOR = 1e-3
#: A posterior narrower than this (standard deviation, cm) is shown ZOOM cm either side of
#: its estimate.
ZOOM_BELOW, ZOOM = 4.0, 20.0


def _readings(episode: Episode) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """Points read (n, 2), counts (n,) and the route travelled to each point (n arrays)."""
    if not episode.trace or "readings" not in episode.trace[0]:
        raise SearchError("the episode's trace holds no readings: run it with figures=True on a flow world")
    points = np.vstack([np.asarray(r["points"], dtype=float)[:, :2] for r in episode.trace])
    counts = np.concatenate([np.asarray(r["readings"], dtype=float) for r in episode.trace])
    routes = [np.asarray(r["route"], dtype=float)[:, :2] for r in episode.trace]
    return points, counts, routes


def _along(route: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """Points at the given fractions of a polyline's length (m, 2)."""
    if len(route) < 2:
        return np.repeat(route[-1:], len(fractions), axis=0)
    seg = np.hypot(*np.diff(route, axis=0).T)
    cum = np.r_[0.0, np.cumsum(seg)]
    if cum[-1] <= 0:
        return np.repeat(route[-1:], len(fractions), axis=0)
    s = fractions * cum[-1]
    return np.column_stack([np.interp(s, cum, route[:, 0]), np.interp(s, cum, route[:, 1])])


def _concentration(ax, field, arena: Arena, px: int = 240):
    """The true mean concentration relative to its peak in the free space, log scale."""
    (x0, x1), (y0, y1) = arena.bounds
    x, y = np.linspace(x0, x1, px), np.linspace(y0, y1, max(2, int(px * (y1 - y0) / (x1 - x0))))
    xx, yy = np.meshgrid(x, y)
    pts = np.column_stack([xx.ravel(), yy.ravel()])
    inside = np.asarray(arena.contains(pts), dtype=bool)
    c = np.full(len(pts), np.nan)
    c[inside] = np.maximum(np.asarray(field(pts[inside]), dtype=float), 0.0)
    peak = np.nanmax(c) if np.isfinite(c).any() and np.nanmax(c) > 0 else 1.0
    img = np.clip(c / peak, FLOOR, 1.0).reshape(len(y), len(x))
    return ax.imshow(np.ma.masked_invalid(img), origin="lower", extent=(x0, x1, y0, y1), cmap="magma",
                     norm=LogNorm(FLOOR, 1.0), interpolation="bilinear", zorder=1)


def write_count_video(path, episode: Episode, arena: Arena, *, fps: int = 8, move_frames: int = 3,
                      hold_frames: int = 3, dpi: int = 90, progress: bool = False) -> Path:
    """Write an MP4 video of a search on hit counts.

    Parameters
    ----------
    path : str or Path
        Output file; must end in ``.mp4``. Parent folders are created.
    episode : Episode
        A ``flow`` episode run with ``figures=True``: its trace gives the readings and the
        path; ``truth["field"]`` and ``truth["wind"]`` the left panel;
        ``belief["posterior"]`` and ``belief["triangulation"]``, when present, the right.
    arena : Arena
        The arena's walls.
    fps : int
        Frames per second, 1 to 60.
    move_frames, hold_frames : int
        Frames of travel to each reading (1 to 30), and frames at it (1 to 30).
    dpi : int
        Pixels per inch of the frames (40 to 200).
    progress : bool
        Show a progress bar.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    SearchError
        On a path that does not end in ``.mp4`` or cannot be written, bad frame counts, or
        an episode without readings.
    """
    path = Path(path)
    if path.suffix.lower() != ".mp4":
        raise SearchError(f"video path {str(path)!r} must end in .mp4")
    for key, value, lo, hi in (("fps", fps, 1, 60), ("move_frames", move_frames, 1, 30),
                               ("hold_frames", hold_frames, 1, 30), ("dpi", dpi, 40, 200)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
            raise SearchError(f"{key} must be an integer from {lo} to {hi}, got {value!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    points, counts, routes = _readings(episode)
    truth, belief = episode.truth or {}, episode.belief or {}
    posterior, tri = belief.get("posterior"), belief.get("triangulation")
    source = np.asarray(episode.summary["source"], dtype=float).reshape(-1, 2)
    two = posterior is not None and tri is not None
    fig = Figure(figsize=(11.0 if two else 6.0, 5.4), dpi=dpi, layout="constrained")
    axes = fig.subplots(1, 2 if two else 1, squeeze=False)[0]
    left = axes[0]
    if truth.get("field") is not None:
        _concentration(left, truth["field"], arena)
    draw_arena(left, arena)
    if truth.get("wind") is not None:
        streamlines(left, truth["wind"], arena)
    left.set_title("true mean concentration (log, relative to its peak) and wind", fontsize=9)
    mesh = None
    if two:
        right = axes[1]
        tri = tri if isinstance(tri, Triangulation) else Triangulation(*np.asarray(tri).T)
        mesh = right.tripcolor(tri, np.full(len(posterior.nodes), FLOOR), shading="gouraud", cmap="viridis",
                               norm=LogNorm(FLOOR, 1.0), rasterized=True, zorder=1)
        draw_arena(right, arena)
        right.set_title("posterior over the source (relative to its peak;\n"
                        f"{2 * ZOOM:g} cm wide once narrower than {ZOOM_BELOW:g} cm)", fontsize=9)
    moving = []
    for ax in axes:
        moving.append(dict(
            path=ax.plot([], [], "-", color="tab:cyan", lw=1.0, zorder=4, animated=True)[0],
            hits=ax.scatter([], [], s=[], c="w", edgecolors="k", linewidths=0.6, zorder=5, animated=True),
            none=ax.scatter([], [], s=10, c="0.55", edgecolors="k", linewidths=0.5, zorder=5, animated=True),
            me=ax.plot([], [], "o", color="tab:cyan", mec="k", ms=8, zorder=7, animated=True)[0],
            est=ax.plot([], [], "D", color="magenta", mec="k", ms=7, zorder=7, animated=True)[0],
            source=ax.plot(source[:, 0], source[:, 1], "*", color=(1.0, 0.0, 0.0), mec="k", ms=13, zorder=8,
                           animated=True)[0]))
    header = fig.suptitle(" ", fontsize=10, animated=True)
    fig.legend(handles=[
        Line2D([], [], marker="*", ls="", color=(1.0, 0.0, 0.0), mec="k", ms=12, label="true source"),
        Line2D([], [], marker="D", ls="", color="magenta", mec="k", ms=7, label="estimate"),
        Line2D([], [], marker="o", ls="", color="w", mec="k", ms=6, label="reading with hits (size: count)"),
        Line2D([], [], marker="o", ls="", color="0.55", mec="k", ms=4, label="reading without hits"),
        Line2D([], [], marker="o", ls="", color="tab:cyan", mec="k", ms=7, label="observer and path")],
        loc="outside lower center", ncols=5 if two else 3, fontsize=8)
    canvas = FigureCanvasAgg(fig)
    estimates = [r.get("estimate") for r in episode.trace]
    strategy, n = episode.summary["strategy"], len(points)
    state = {}

    def redraw(read: int) -> None:
        """Draw the static layers, with the posterior after `read` readings, and keep them."""
        if mesh is not None:
            (x0, x1), (y0, y1) = arena.bounds
            if read:
                sub = posterior.first(read)
                w = sub.weights()
                density = w / posterior.areas
                spread = float(np.sqrt(w @ np.sum((posterior.nodes - w @ posterior.nodes) ** 2, axis=1)))
                if spread < ZOOM_BELOW:               # a narrow posterior: look closer
                    cx, cy = sub.estimate()
                    (x0, x1), (y0, y1) = (cx - ZOOM, cx + ZOOM), (cy - ZOOM, cy + ZOOM)
            else:
                density = np.ones(len(posterior.nodes))
            mesh.set_array(np.clip(density / max(density.max(), 1e-300), FLOOR, 1.0))
            mesh.axes.set_xlim(x0, x1)
            mesh.axes.set_ylim(y0, y1)
        canvas.draw()
        state["background"] = canvas.copy_from_bbox(fig.bbox)

    def frame(here: np.ndarray, travelled: np.ndarray, read: int, title: str) -> np.ndarray:
        """One frame: the static layers kept, then the observer `here`, its path and the
        first `read` readings."""
        canvas.restore_region(state["background"])
        hit = counts[:read] > 0
        est = estimates[read - 1] if read else None
        for art in moving:
            art["path"].set_data(travelled[:, 0], travelled[:, 1])
            art["hits"].set_offsets(points[:read][hit].reshape(-1, 2))
            art["hits"].set_sizes(12 + 6 * np.sqrt(counts[:read][hit]))
            art["none"].set_offsets(points[:read][~hit].reshape(-1, 2))
            art["me"].set_data([here[0]], [here[1]])
            art["est"].set_data(*(([est[0]], [est[1]]) if est is not None else ([], [])))
            for a in art.values():
                a.axes.draw_artist(a)
        header.set_text(title)
        fig.draw_artist(header)
        return np.ascontiguousarray(np.asarray(canvas.buffer_rgba())[:, :, 2::-1])   # BGR

    def frames():
        travelled = [routes[0][:1]]
        for k in tqdm(range(n), desc="video", unit="reading", disable=not progress, leave=False):
            redraw(k)
            for f in range(1, move_frames + 1):
                along = _along(routes[k], np.linspace(0.0, f / move_frames, 2 + 4 * f))
                yield frame(along[-1], np.vstack(travelled + [along]), k,
                            f"{strategy}: travelling to reading {k + 1} of {n}")
            travelled.append(routes[k])
            redraw(k + 1)
            e = estimates[k]
            off = "" if e is None else f"; estimate {np.hypot(*(np.asarray(e, dtype=float) - source[0])):.1f} cm off"
            for _ in range(hold_frames):
                yield frame(points[k], np.vstack(travelled), k + 1,
                            f"{strategy}: reading {k + 1} of {n}, {counts[k]:.0f} "
                            f"hit{'' if counts[k] == 1 else 's'}{off}")

    canvas.draw()
    width, height = canvas.get_width_height()
    encode_mp4(path, frames(), (width, height), fps)
    return path
