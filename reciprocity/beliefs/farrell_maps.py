"""The maps of Farrell, Pang & Li (2003)'s Figs. 5–8 (belief), from what a vehicle measured
and the flow it was told: the plume map of a source, a detection's source map, the most
likely odour path and the most likely detection path.

:func:`farrell_maps` takes the record :func:`reciprocity.worlds.filament_figures.farrell_record`
returns (its flows, detections and positions; it never reads the plume snapshots) and
returns arrays over the paper's cells; :func:`reciprocity.viz.hmm.farrell_figures` draws them.
"""

from __future__ import annotations

import numpy as np

from ..models.hmm import CellGrid, backtrack, transition, viterbi
from .hmm import HMMSourceMap, plume_map

__all__ = ["CELLS", "farrell_maps"]

#: The paper's map cells, along x and along y.
CELLS = (40, 25)
#: Cells in the paper's numbering: the source of Figs. 5, 7 and 8, the odour path's end
#: (Fig. 7) and the detection path's end (Fig. 8).
SOURCE_CELL, ODOUR_END, DETECTION_END = 488, 388, 471
#: The odour path ends at this second (Fig. 7); the detection path has this many steps (Fig. 8).
ODOUR_SECONDS, DETECTION_STEPS = 44, 25


def farrell_maps(record: dict) -> dict:
    """The maps and paths of the paper's Figs. 5–8.

    Parameters
    ----------
    record : dict
        :func:`~reciprocity.worlds.filament_figures.farrell_record`'s: ``region``,
        ``readings``, per second ``flow`` (m/s), ``hit`` and ``position`` (m), the
        ``detection`` second, and ``uniform_flow`` (m/s).

    Returns
    -------
    dict
        ``grid`` (the :class:`~reciprocity.models.hmm.CellGrid` of :data:`CELLS`),
        ``source_cell`` (0-based); ``alpha`` (Fig. 5: the plume map α of a source in
        ``source_cell`` after the vehicle's seconds, (N,)); ``detect`` (Fig. 6: ``(second,
        cell, β̄)`` at the record's detection, or None); ``mlop`` (Fig. 7: the most likely
        odour path's cells from ``source_cell`` at 0 s to C_388 at 44 s); ``uniform_alpha``
        and ``mldp`` (Fig. 8: the plume map at the end of the uniform flow, and the
        25-step most likely detection path C_388 → C_471).
    """
    grid = CellGrid(record["region"], *CELLS)
    src = grid.from_paper(SOURCE_CELL)
    return dict(grid=grid, source_cell=src, **_vehicle_maps(record, grid, src), **_uniform_paths(record, grid, src))


def _vehicle_maps(record: dict, grid: CellGrid, src: int) -> dict:
    """Figs. 5 and 6: the map follows each second's mean flow and detection."""
    belief = HMMSourceMap(grid, readings=record["readings"])
    ts, detect = [], None
    for second, (u, hit, pos) in enumerate(zip(record["flow"], record["hit"], record["position"])):
        ts.append(transition(grid, u, 1.0))
        belief.advance(u, hit, pos)
        if record["detection"] is not None and second == record["detection"][0]:
            k = int(grid.index(pos)[0])
            detect = (second, k, belief.beta(k))
    return dict(alpha=plume_map(np.eye(grid.N)[src], ts), detect=detect)


def _uniform_paths(record: dict, grid: CellGrid, src: int) -> dict:
    """Figs. 7 and 8: Viterbi over the first 44 s of the uniform flow, and Ψ advanced
    over all of it (no readings) for the detection path."""
    trs = [transition(grid, u, 1.0) for u in record["uniform_flow"]]
    _, psi = viterbi(np.eye(grid.N)[src], [t.bar() for t in trs[:ODOUR_SECONDS]])
    m = HMMSourceMap(grid, readings=1)
    m.pi = np.eye(grid.N)[src]
    for t in trs:
        t.superpose(m.psi, m.n + 1, m._buf)
        m.psi, m._buf = m._buf, m.psi
        m.n += 1
    return dict(mlop=backtrack(psi, grid.from_paper(ODOUR_END)), uniform_alpha=m.alpha(),
                mldp=m.mldp(grid.from_paper(ODOUR_END), DETECTION_STEPS, end=grid.from_paper(DETECTION_END)))
