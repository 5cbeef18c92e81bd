"""What can be measured of the maps of Farrell, Pang & Li (2003)'s Figs. 5–8 (belief), so
that ours can be set against what the paper's Sect. V and captions state.

A map (α of Fig. 5, β̄ of Fig. 6) is described in the frame of the flow that made it,
from a cell of reference (the source's cell, the detecting vehicle's cell): where its
maximum lies, its second moments and the widths holding 50 % and 90 % of its mass along
and across the flow, and how its crossflow spread changes with the distance downflow
(or upflow). A path (the MLOP of Fig. 7, the MLDP of Fig. 8) is described by its cells
in the paper's numbering, its ends, its moves and its length.

The paper numbers its cells ``k = i + (j - 1) m`` (1-based; ``i`` the column along x,
``j`` the row, counted from the top of the region: its C_64 is ``i = 24, j = 2`` at the
top edge, its source cell C_488 is ``i = 8, j = 13``); :func:`paper_ij` gives that pair.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..models.hmm import CellGrid, backtrack, detection_path, transition
from .farrell_maps import DETECTION_STEPS, ODOUR_END, ODOUR_SECONDS
from .hmm import plume_map

__all__ = ["BANDS", "MapShape", "PathSummary", "detection_path_cells", "farrell_measures", "map_shape",
           "odour_distribution", "paper_ij", "path_summary"]

#: Bands of distance from the reference cell (m) in which the crossflow spread is measured.
BANDS = (0.0, 15.0, 30.0, 45.0)


def paper_ij(number: int, grid: CellGrid) -> tuple[int, int]:
    """The paper's column and row ``(i, j)`` (1-based, rows from the top) of its cell
    ``C_number``: the inverse of ``number = i + (j - 1) m``."""
    return (int(number) - 1) % grid.m + 1, (int(number) - 1) // grid.m + 1


@dataclass(frozen=True)
class MapShape:
    """A map in the frame of a flow, from a reference cell; pairs are ``(along, across)``
    in m, along positive downflow, across positive to the flow's left.

    Attributes
    ----------
    peak : int
        The map's largest cell, paper numbering.
    peak_offset : tuple of float
        Its centre's offset from the reference cell's centre, m.
    runner_up : int
        The largest cell other than the reference cell, paper numbering.
    runner_up_offset : tuple of float
        Its offset, m.
    mean, sd : tuple of float
        The map's centre of mass (offset, m) and standard deviations (m).
    extent50, extent90 : tuple of float
        Widths of the central intervals holding 50 % and 90 % of the map's mass, m.
    band_sd_across : tuple of float
        Crossflow standard deviation (m) of the mass in each band of :data:`BANDS` of
        distance from the reference cell in the direction of `sense` (NaN if empty).
    band_mass : tuple of float
        The map's mass in each band (fractions of the whole).
    """

    peak: int
    peak_offset: tuple[float, float]
    runner_up: int
    runner_up_offset: tuple[float, float]
    mean: tuple[float, float]
    sd: tuple[float, float]
    extent50: tuple[float, float]
    extent90: tuple[float, float]
    band_sd_across: tuple[float, ...]
    band_mass: tuple[float, ...]


def _quantile_width(x: np.ndarray, w: np.ndarray, mass: float) -> float:
    """Width of the central interval of the weighted sample (`x`, `w`) holding `mass`."""
    order = np.argsort(x)
    cum = np.cumsum(w[order])
    lo, hi = np.searchsorted(cum, [(1 - mass) / 2, (1 + mass) / 2])
    return float(x[order][min(hi, len(x) - 1)] - x[order][lo])


def map_shape(values: np.ndarray, grid: CellGrid, origin: int, flow, *, sense: int = 1,
              bands: tuple[float, ...] = BANDS) -> MapShape:
    """Describe a map over the cells in the frame of `flow`, from cell `origin`.

    Parameters
    ----------
    values : ndarray (N,)
        The map (non-negative, any scale), in our cell order.
    grid : CellGrid
    origin : int
        The reference cell (our index): the source's for α, the vehicle's for β̄.
    flow : array_like (2,)
        The flow giving the frame, m/s (only its direction matters).
    sense : int
        +1 to band by distance downflow of `origin` (a plume map), -1 upflow (a source map).
    bands : tuple of float
        Band edges of that distance, m.

    Returns
    -------
    MapShape
    """
    u = np.asarray(flow, dtype=float)
    e = u / np.hypot(*u)
    d = grid.centres() - grid.centres()[origin]
    along, across = d @ e, d @ np.array([-e[1], e[0]])
    v = np.asarray(values, dtype=float)
    w = v / v.sum()
    peak = int(np.argmax(v))
    runner = int(np.argmax(np.where(np.arange(len(v)) == origin, -np.inf, v)))
    mean = (float(w @ along), float(w @ across))
    sd = (float(np.sqrt(w @ (along - mean[0]) ** 2)), float(np.sqrt(w @ (across - mean[1]) ** 2)))
    dist = sense * along
    band_sd, band_mass = [], []
    for lo, hi in zip(bands[:-1], bands[1:]):
        inside = (dist >= lo) & (dist < hi)
        m = w[inside].sum()
        band_mass.append(float(m))
        if m > 0:
            c = w[inside] @ across[inside] / m
            band_sd.append(float(np.sqrt(w[inside] @ (across[inside] - c) ** 2 / m)))
        else:
            band_sd.append(float("nan"))
    return MapShape(peak=grid.to_paper(peak), peak_offset=(float(along[peak]), float(across[peak])),
                    runner_up=grid.to_paper(runner), runner_up_offset=(float(along[runner]), float(across[runner])),
                    mean=mean, sd=sd,
                    extent50=(_quantile_width(along, w, 0.5), _quantile_width(across, w, 0.5)),
                    extent90=(_quantile_width(along, w, 0.9), _quantile_width(across, w, 0.9)),
                    band_sd_across=tuple(band_sd), band_mass=tuple(band_mass))


@dataclass(frozen=True)
class PathSummary:
    """A cell path, in time (MLOP) or step (MLDP) order.

    Attributes
    ----------
    cells : tuple of int
        Its cells, paper numbering.
    start, end : int
        Its first and last cells, paper numbering.
    steps : int
        Transitions along it (``len(cells) - 1``).
    distinct : int
        Distinct cells it visits.
    x_moves, y_moves : tuple of int
        The steps (1-based: step s goes from cell s - 1 to cell s) at which the column,
        resp. the row, changes.
    length : float
        Sum of the distances between successive cell centres, m.
    """

    cells: tuple[int, ...]
    start: int
    end: int
    steps: int
    distinct: int
    x_moves: tuple[int, ...]
    y_moves: tuple[int, ...]
    length: float


def path_summary(cells, grid: CellGrid) -> PathSummary:
    """Describe the path through our cells `cells` (int array).

    Parameters
    ----------
    cells : array_like of int
    grid : CellGrid

    Returns
    -------
    PathSummary
    """
    q = np.asarray(cells, dtype=np.int64)
    i, j = grid.ij(q)
    c = grid.centres()[q]
    paper = tuple(grid.to_paper(k) for k in q)
    return PathSummary(cells=paper, start=paper[0], end=paper[-1], steps=len(q) - 1, distinct=len(set(paper)),
                       x_moves=tuple(int(s) + 1 for s in np.flatnonzero(np.diff(i))),
                       y_moves=tuple(int(s) + 1 for s in np.flatnonzero(np.diff(j))),
                       length=float(np.hypot(*np.diff(c, axis=0).T).sum()))


def odour_distribution(grid: CellGrid, flows, start: int, dt: float = 1.0) -> np.ndarray:
    """Where odour in cell `start` at t = 0 is after the flows: ``e_start Ā(t_0) ⋯ Ā(t_{L-1})``
    (Appendix II), the probability of each cell (N,); the rest has left the region.

    Parameters
    ----------
    grid : CellGrid
    flows : array_like (L, 2)
        The flow of each period, m/s.
    start : int
        Our cell index.
    dt : float
        The period, s.

    Returns
    -------
    ndarray (N,)
    """
    p = np.eye(grid.N)[start]
    for u in flows:
        p = transition(grid, u, dt).right(p)
    return p


def detection_path_cells(alpha: np.ndarray, grid: CellGrid, start: int, steps: int, end: int | None = None
                         ) -> np.ndarray:
    """The `steps`-step most likely detection path on the plume map `alpha` from cell
    `start` to `end` (default: the best end cell), Sect. IV-C3; our indices, in step
    order."""
    log_mu, prev = detection_path(alpha, grid.neighbours(), start, steps)
    return backtrack(prev, int(np.argmax(log_mu[-1])) if end is None else int(end))


def farrell_measures(record: dict, maps: dict) -> dict:
    """The quantities of the paper's Figs. 5–8 measured on our maps.

    Parameters
    ----------
    record : dict
        The record the maps were made from
        (:func:`~reciprocity.worlds.filament_figures.farrell_record`): its per-second
        ``flow`` (m/s) and ``uniform_flow`` (m/s).
    maps : dict
        :func:`~reciprocity.beliefs.farrell_maps.farrell_maps` of it.

    Returns
    -------
    dict
        ``fig5``: :class:`MapShape` of α from the source's cell in the mean measured
        flow; ``fig6``: ``(t, cell, MapShape)`` of β̄ from the detecting cell in the
        mean flow measured until the detection (t in s, the cell in paper numbering),
        upflow bands, or None; ``fig7``: :class:`PathSummary` of the MLOP, and
        ``fig7_arrival``, ``(probability, rank, mode)``: the probability that odour in
        the source's cell at 0 s is in the path's end at 44 s (:func:`odour_distribution`),
        that cell's rank among all (1: the most probable) and the most probable cell
        (paper numbering); ``fig8``: the
        MLDP's :class:`PathSummary`, ``fig8_shared`` (cells it shares with the MLOP,
        paper numbering), ``fig8_free`` (the 25-step path from C_388 to its best end at
        48 s) and ``fig8_text`` (the 25-step path from C_388 to C_488 on α at 44 s, as
        Sect. V's prose words it).
    """
    grid, src = maps["grid"], maps["source_cell"]
    fig6 = None
    if maps["detect"] is not None:
        second, cell, beta = maps["detect"]
        fig6 = (second + 1, grid.to_paper(cell),
                map_shape(beta, grid, cell, np.mean(record["flow"][:second + 1], axis=0), sense=-1))
    uniform = record["uniform_flow"]
    odour_end = grid.from_paper(ODOUR_END)
    reach = odour_distribution(grid, uniform[:ODOUR_SECONDS], src)
    alpha44 = plume_map(np.eye(grid.N)[src], [transition(grid, u, 1.0) for u in uniform[:ODOUR_SECONDS]])
    mlop, mldp = path_summary(maps["mlop"], grid), path_summary(maps["mldp"], grid)
    return dict(
        fig5=map_shape(maps["alpha"], grid, src, np.mean(record["flow"], axis=0)),
        fig6=fig6,
        fig7=mlop,
        fig7_arrival=(float(reach[odour_end]), int((reach > reach[odour_end]).sum()) + 1,
                      grid.to_paper(int(np.argmax(reach)))),
        fig8=mldp,
        fig8_shared=tuple(sorted(set(mlop.cells) & set(mldp.cells))),
        fig8_free=path_summary(detection_path_cells(maps["uniform_alpha"], grid, odour_end, DETECTION_STEPS), grid),
        fig8_text=path_summary(detection_path_cells(alpha44, grid, odour_end, DETECTION_STEPS, src), grid),
    )
