"""Figures of hidden-Markov plume mapping (Farrell, Pang & Li 2003, Figs. 5–8) and of
searches in the filament plume.

Each map panel follows the paper's layout: the region's cells shaded in grey by the
map's value (darker = larger), a regular grid of arrows giving the flow at the time of
the map, the plume's filaments as a grey patchy trail, the corner coordinates written
in the corners, and a dashed rectangle marking the search area of interest.

Everything drawn of the plume comes from records the truth's side made
(:meth:`FilamentPlume.snapshot <reciprocity.worlds.filament.FilamentPlume.snapshot>`,
:func:`~reciprocity.worlds.filament_figures.farrell_record`, an episode's
:attr:`~reciprocity.episode.Episode.truth`), and every map from the belief's side
(:func:`~reciprocity.beliefs.farrell_maps.farrell_maps`, a strategy's report): this module
draws arrays and never sees a world.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from ..beliefs.farrell_maps import farrell_maps
from ..errors import SearchError
from ..models.hmm import CellGrid

__all__ = ["draw_map", "farrell_figures", "plot_search", "search_map_figure"]

#: The dashed search area of interest of the paper's figures, ``(x0, x1, y0, y1)``, m.
SEARCH_AREA = (10.0, 90.0, -40.0, 40.0)


def draw_map(ax, grid: CellGrid, values: np.ndarray | None, *, plume: dict | None = None,
             wind=None, cells=None, track=None, title: str = "", search_area=None) -> None:
    """One map panel in the paper's layout.

    Parameters
    ----------
    ax : matplotlib Axes
    grid : CellGrid
    values : ndarray (N,) or None
        The map (grey scale, normalised to its maximum).
    plume : dict, optional
        A plume snapshot (:meth:`~reciprocity.worlds.filament.FilamentPlume.snapshot`):
        its ``filaments`` (centres, (n, 2), m) inside the region are drawn as grey discs
        growing with their puff σ (``radii``, (n,), m).
    wind : tuple of ndarray, optional
        ``(points, vectors)``, each (k, 2) (m, m/s), e.g. a snapshot's ``wind``: drawn as arrows.
    cells : array of int, optional
        A cell path, drawn as dark rectangles (MLOP, MLDP).
    track : ndarray (k, 2), optional
        The vehicle's path (arrows along it), m.
    title : str
    search_area : tuple, optional
        ``(x0, x1, y0, y1)`` of the dashed rectangle, m.
    """
    x0, x1, y0, y1 = grid.region
    if values is not None:
        v = np.asarray(values, dtype=float).reshape(grid.n, grid.m)
        v = v / v.max() if v.max() > 0 else v
        ax.imshow(v, origin="lower", extent=(x0, x1, y0, y1), cmap="Greys", vmin=0, vmax=1.15,
                  interpolation="nearest", aspect="equal")
    if plume is not None:
        c, r = plume["filaments"], plume["radii"]
        inside = (c[:, 0] > x0) & (c[:, 0] < x1) & (c[:, 1] > y0) & (c[:, 1] < y1)
        ax.scatter(c[inside, 0], c[inside, 1], s=(3 * r[inside]) ** 2 * 4, c="0.45", alpha=0.35, linewidths=0)
    if cells is not None:
        lx, ly = grid.L
        cen = grid.centres()[np.asarray(cells)]
        for k, p in enumerate(cen):
            shade = 0.15 + 0.6 * k / max(len(cen) - 1, 1)
            ax.add_patch(Rectangle((p[0] - lx / 2, p[1] - ly / 2), lx, ly, color=str(shade), alpha=0.9))
    if wind is not None:
        pts, u = wind
        ax.quiver(pts[:, 0], pts[:, 1], u[:, 0], u[:, 1], angles="xy", scale_units="xy", scale=0.25,
                  width=0.003, color="0.2")
    if track is not None and len(track) > 1:
        t = np.asarray(track)
        step = max(1, len(t) // 40)
        d = np.diff(t[::step], axis=0)
        ax.quiver(t[:-1:step][:len(d), 0], t[:-1:step][:len(d), 1], d[:, 0], d[:, 1], angles="xy",
                  scale_units="xy", scale=1, width=0.005, color="k")
    if search_area is not None:
        a0, a1, b0, b1 = search_area
        ax.plot([a0, a1, a1, a0, a0], [b0, b0, b1, b1, b0], "k--", lw=0.8)
    for (x, y, ha, va) in ((x0, y0, "left", "bottom"), (x1, y0, "right", "bottom"),
                           (x0, y1, "left", "top"), (x1, y1, "right", "top")):
        ax.text(x, y, f"({x:g},{y:g})", ha=ha, va=va, fontsize=6)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=8)


def farrell_figures(record: dict, out) -> list[Path]:
    """The paper's Figs. 5–8 from one record: the plume map α(65, 0) for a source in
    the true source's cell (Fig. 5), the map β̄_k for one detection in C_k after a
    vehicle path from the top of the region (Fig. 6), and, under the uniform flow of
    eq. (18) (1 m/s along x for t ≤ 30 s, then along y), the most likely odour path
    from C_488 (paper numbering) at t = 0 to C_388 at t = 44 s (Fig. 7) and the
    25-step most likely detection path between C_388 and C_471 at t = 48 s (Fig. 8).

    Parameters
    ----------
    record : dict
        The simulated plumes and what the vehicle measured
        (:func:`reciprocity.worlds.filament_figures.farrell_record`); the maps are
        :func:`reciprocity.beliefs.farrell_maps.farrell_maps` of it.
    out : str or Path
        Folder (created) for ``farrell_fig5_8.png`` (the four panels).

    Returns
    -------
    list of Path
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    maps = farrell_maps(record)
    grid, src = maps["grid"], maps["source_cell"]
    fig = Figure(figsize=(10, 10))
    axes = fig.subplots(2, 2)
    area = SEARCH_AREA
    plume = record["plume"]
    draw_map(axes[0, 0], grid, maps["alpha"], plume=plume, wind=plume["wind"], search_area=area,
             title=f"Fig. 5: plume map α(65, 0), source in C{grid.to_paper(src)}")
    if maps["detect"] is not None:
        t_d, k_d, beta_d = maps["detect"]
        snap = record["detection"][1]
        draw_map(axes[0, 1], grid, beta_d, plume=snap, wind=snap["wind"], search_area=area,
                 track=record["track"][:(t_d + 1) * record["readings"]],
                 title=f"Fig. 6: β̄ for a detection in C{grid.to_paper(k_d)} at t = {t_d + 1} s")
    else:
        axes[0, 1].set_title("Fig. 6: no detection on this path", fontsize=8)
    snap44, snap48 = record["uniform"][44], record["uniform"][48]
    draw_map(axes[1, 0], grid, None, plume=snap44, wind=snap44["wind"], cells=maps["mlop"], search_area=area,
             title="Fig. 7: most likely odour path C488(0) → C388(44)")
    draw_map(axes[1, 1], grid, maps["uniform_alpha"], plume=snap48, wind=snap48["wind"], cells=maps["mldp"],
             search_area=area, title="Fig. 8: 25-step most likely detection path C388 → C471 (t = 48 s)")
    fig.tight_layout()
    path = out / "farrell_fig5_8.png"
    fig.savefig(path, dpi=110)
    return [path]


def search_map_figure(episode) -> Figure:
    """The vehicle's track over the final source map (the strategy's record
    ``belief["source_map"]``, e.g. ``hmm``'s) or over the plume alone, with the true
    source and the estimate, drawn from the episode's record.

    Parameters
    ----------
    episode : Episode
        A filament episode run with ``figures=True``: its :attr:`~reciprocity.episode.Episode.truth`
        holds the plume at the end, the region, the cells and the source.

    Returns
    -------
    Figure
    """
    truth = episode.truth
    if "plume" not in truth:
        raise SearchError("a filament figure is drawn from the episode's record: run the episode with figures=True")
    tr = episode.trace
    track = np.array([r["pose"][:2] for r in tr])
    hits = np.array([r["readings"][0] > 0 for r in tr])
    fig = Figure(figsize=(6, 6))
    ax = fig.subplots()
    grid = CellGrid(truth["region"], *truth["cells"])
    draw_map(ax, grid, episode.belief.get("source_map"), plume=truth["plume"], wind=truth["plume"]["wind"],
             title=f"{episode.summary['strategy']}: {episode.summary['stop_reason']}")
    ax.plot(track[:, 0], track[:, 1], "-", color="tab:blue", lw=1)
    ax.plot(track[hits, 0], track[hits, 1], ".", color="tab:red", ms=3)
    ax.plot(*truth["source"], "r*", ms=12)
    if episode.summary["estimate"] is not None:
        ax.plot(*episode.summary["estimate"], "gx", ms=10, mew=2)
    fig.tight_layout()
    return fig


def plot_search(episode, path) -> Path:
    """Write :func:`search_map_figure` of `episode` to the PNG `path` (100 dpi); return the path."""
    search_map_figure(episode).savefig(path, dpi=100)
    return Path(path)
