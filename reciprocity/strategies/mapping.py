"""What a strategy does with a map it has to discover: the component it owns for
``map: unknown``.

:class:`MapKeeper` holds the occupancy grid (:class:`~reciprocity.spaces.occupancy.OccupancyGrid`)
built from the platform's range scans and answers the strategy's four questions:

- *on which domain is the field computed?* :attr:`MapKeeper.arena`, the outer boundary
  with the believed obstacles, unknown space free (optimistic). It is the same object
  until the believed obstacles change, so the solver cached on it
  (:func:`~reciprocity.models.green.cached_solver`) and its factorization are reused
  while the map stays the same, and rebuilt only when it changes;
- *how far is the model from the truth?* :meth:`MapKeeper.model_error`: the relative
  error of a predicted reading grows with the share of the arena not yet seen (walls
  there are missing from the model), so that readings do not rule out sources the
  unseen walls would explain;
- *where may the observer go, and when should it explore?* Observation points only in
  seen-free space (:meth:`MapKeeper.admissible`); when most of the belief lies in unseen
  space, the frontier point (a seen-free point next to unseen space) with the most
  belief mass within reach, discounted by the path to it (:meth:`MapKeeper.frontier_point`):
  the reciprocity strategy surveys it (:class:`~reciprocity.intents.Survey`: the scan
  there tells about the map, with no reading) where the platform takes surveys, and reads
  there otherwise;
- *which targets has the platform refused?* :meth:`MapKeeper.refuse` remembers them
  across the believed maps (each re-mesh rebuilds the reachable set) until the walls near
  one lose enough area to open a way to it (:meth:`MapKeeper.refused`).
"""

from __future__ import annotations

import copy
from typing import Callable

import numpy as np

from arenas import Arena

from ..errors import SearchError
from ..beliefs.imaging import ImagingMap
from ..observations import Observation, scans_of
from ..spaces.occupancy import MIN_CHANGE_CM2, OccupancyGrid

__all__ = ["MapKeeper", "ShortfallImaging", "UNSEEN_MODEL_ERROR", "MAPPED_MODEL_ERROR", "UNSEEN_SHORTFALL",
           "FRONTIER_SHARE", "SURVEY_SHARE", "FRONTIER_DISCOUNT", "REOPEN_CM2"]

#: Relative model error added per unit share of the arena not yet seen (the whole arena
#: unseen: 0.3, a reading may be 30 % off the model's prediction).
UNSEEN_MODEL_ERROR = 0.3
#: Relative model error of a map seen everywhere: believed walls sit up to about a cell
#: (1 cm) off the true ones, and their far sides are unseen.
MAPPED_MODEL_ERROR = 0.05
#: Relative shortfall of a reading below the optimistic model's prediction allowed per unit
#: share of the arena not yet seen (:class:`ShortfallImaging`); 0: the symmetric widening
#: alone.
UNSEEN_SHORTFALL = 0.0
#: Explore (go to the frontier) when at least this share of the belief lies in unseen space.
FRONTIER_SHARE = 0.5
#: The same when the frontier is surveyed (scanned without a reading). Kept at
#: FRONTIER_SHARE: a lower share rescued some draws that spent their readings in seen space
#: but cost readings and path on the others (``benchmarks/likelihood_terms.md``).
SURVEY_SHARE = FRONTIER_SHARE
#: Path length (cm) over which a frontier point's score falls by a factor e.
FRONTIER_DISCOUNT = 100.0
#: A refused target is tried again once the believed walls within the lidar's range of it
#: have lost this much of the area they held at the refusal (cm²): walls that appear can
#: only shut a target out further, walls that go (noisy hits seen through, a gap seen
#: from nearer) may open the way that was shut. Opening a gap the platform could not pass
#: takes a strip through a believed wall (three cells thick) two or more cells wide; a
#: noisy cell that comes and goes is mostly hidden by its neighbours' dilation: twice
#: MIN_CHANGE_CM2, the change that makes a new believed map.
REOPEN_CM2 = 2.0 * MIN_CHANGE_CM2


class MapKeeper:
    """The believed map of a strategy told only part of the walls.

    Parameters
    ----------
    arena : Arena
        What the strategy is told: the outer boundary and any known obstacles, cm.
    lidar : dict
        The range sensor's nominal parameters ``{beams, range, noise}`` (cm).
    cell : float
        Occupancy cell side, cm.

    Attributes
    ----------
    grid : OccupancyGrid
        The occupancy grid.
    arena : Arena
        The believed arena (geometry only), the same object while the map is unchanged.
    """

    def __init__(self, arena: Arena, lidar: dict, cell: float = 1.0):
        if not lidar or "range" not in lidar:
            raise SearchError("an unknown map needs a range sensor: give lidar: {beams, range, noise}")
        self.grid = OccupancyGrid(arena, cell)
        self.lidar = dict(lidar)
        self.arena = self.grid.believed_arena()
        self._visited = np.empty((0, 2))
        self._refused: list[tuple[np.ndarray, float, np.ndarray]] = []

    @classmethod
    def from_nominal(cls, nominal) -> "MapKeeper | None":
        """A keeper when the task says the map is unknown (``map: "unknown"``), else None."""
        if nominal.get("map") != "unknown":
            return None
        return cls(nominal["arena"], nominal.get("lidar") or {})

    @property
    def revision(self) -> int:
        """How many times the believed obstacles changed."""
        return self.grid.revision

    def update(self, observations: list[Observation]) -> bool:
        """Take in the scans among `observations`; True when the believed arena changed
        (the strategy then re-meshes). A new arena that leaves out a place the observer
        scanned from (so a reading taken there) is not taken: the map keeps the last one."""
        for o in scans_of(observations):
            d = o.data
            self.grid.update(o.position, np.asarray(d["angles"]), np.asarray(d["ranges"]),
                             np.asarray(d["hit"], dtype=bool), float(d["max_range"]))
            self._visited = np.vstack([self._visited, o.position])
        new = self.grid.believed_arena()
        if new is not self.arena and len(self._visited) and not new.contains(self._visited).all():
            new = self.arena
        changed = new is not self.arena
        self.arena = new
        return changed

    def refuse(self, point, radius: float) -> float:
        """Remember that the platform refused a target at `point` (cm), and return the
        radius (cm) of the neighbourhood to keep out of the reachable set of this and
        every later believed map (until :meth:`refused` lets it go).

        `radius` at first; a target refused within twice the radius of an earlier refusal
        in force gets twice that one's radius, up to half the lidar's range: refusals
        that cluster mark a region the platform cannot enter (behind a gap too narrow for
        it), which point-by-point refusals would spend the search's refusals on.
        """
        p = np.asarray(point, dtype=float)[:2]
        r = float(radius)
        for q, rq, _ in self._refused:
            if np.hypot(*(p - q)) <= 2.0 * rq:
                r = max(r, 2.0 * rq)
        r = min(r, max(float(radius), 0.5 * float(self.lidar["range"])))
        self._refused.append((p, r, np.flatnonzero(self._walls_near(p))))
        return r

    def refused(self) -> list[tuple[np.ndarray, float]]:
        """The refused targets still in force, ``(point (2,), radius)``, cm; a target
        whose nearby believed walls (within the lidar's range) lost REOPEN_CM2 of their
        area since its refusal is forgotten (it may have become reachable)."""
        if not self._refused:
            return []
        walls = self.grid.obstacle_mask().ravel()
        cell2 = self.grid.cell ** 2
        self._refused = [(p, r, cells) for p, r, cells in self._refused
                         if (~walls[cells]).sum() * cell2 < REOPEN_CM2]
        return [(p, r) for p, r, _ in self._refused]

    def _walls_near(self, point: np.ndarray) -> np.ndarray:
        """Mask (ny, nx) of the believed walls within the lidar's range of `point`."""
        near = np.sum((self.grid.centres() - point) ** 2, axis=-1) <= float(self.lidar["range"]) ** 2
        return self.grid.obstacle_mask() & near

    def model_error(self, base: float = 0.0) -> float:
        """Relative error of the model's predicted readings on the believed map: `base`
        (the model's own, known walls) and the believed walls' ``MAPPED_MODEL_ERROR +
        UNSEEN_MODEL_ERROR x unseen share``, added in quadrature."""
        unseen = 1.0 - self.grid.seen_fraction
        return float(np.hypot(base, MAPPED_MODEL_ERROR + UNSEEN_MODEL_ERROR * unseen))

    def shortfall(self) -> float:
        """How far below the optimistic prediction a reading may fall (relative):
        ``UNSEEN_SHORTFALL x unseen share``."""
        return float(UNSEEN_SHORTFALL * (1.0 - self.grid.seen_fraction))

    def imaging(self, imaging: ImagingMap) -> "ShortfallImaging":
        """`imaging` as a :class:`ShortfallImaging` with the shortfall of the map now."""
        return ShortfallImaging.of(imaging, self.shortfall())

    def admissible(self, points: np.ndarray) -> np.ndarray:
        """Mask of `points` (n, 2) in seen-free space (where the observer may measure)."""
        return self.grid.free_at(points)

    def unseen_share(self, points: np.ndarray, weights: np.ndarray) -> float:
        """Share of the belief (`weights` at `points`) that lies in unseen space."""
        w = np.asarray(weights, dtype=float)
        total = w.sum()
        return 0.0 if total <= 0 else float(w[~self.grid.seen_at(points)].sum() / total)

    def frontier_point(self, space, weights: np.ndarray, allowed: np.ndarray, here,
                       mass_near: Callable[[np.ndarray], np.ndarray],
                       share: float = FRONTIER_SHARE) -> np.ndarray | None:
        """The frontier point to explore, or None when the belief lies mostly in seen
        space (less than `share` unseen) or no frontier point is allowed.

        Parameters
        ----------
        space : reciprocity.spaces.MeshSpace
            The believed mesh (its nodes are the candidates).
        weights : ndarray, shape (n,)
            Belief mass at the nodes.
        allowed : ndarray of bool, shape (n,)
            Nodes the strategy may measure at.
        here : array_like, shape (2,)
            The observer's position, cm.
        mass_near : callable
            ``mass_near(points (m, 2)) -> (m,)``: the belief mass within sensing reach of
            each point.
        share : float
            Explore only while at least this share of the belief is unseen
            (FRONTIER_SHARE when the frontier point is read at, SURVEY_SHARE when it is
            surveyed).

        Returns
        -------
        ndarray, shape (2,) or None
            The node maximising ``mass_near(y) exp(-path(y) / FRONTIER_DISCOUNT)`` among
            allowed nodes within a cell of the frontier, ``path`` along the believed mesh.
        """
        pts = space.points
        if self.unseen_share(pts, weights) < share:
            return None
        from scipy import ndimage
        near = ndimage.binary_dilation(self.grid.frontier(), np.ones((3, 3), dtype=bool))
        r, c, ok = self.grid.index(pts)
        cand = np.flatnonzero(allowed & ok & near[r, c])
        if cand.size == 0:
            return None
        path = _path_lengths(space, here)[cand]
        score = mass_near(pts[cand]) * np.exp(-path / FRONTIER_DISCOUNT)
        return pts[cand[int(np.argmax(score))]].copy()


class ShortfallImaging(ImagingMap):
    """An imaging map on an optimistic believed map: readings may fall short of the model.

    Walls absorb (the field vanishes on them), so a wall the map does not hold yet can
    only lower the signal: with the true free region inside the believed one, the true
    Green's function is at most the believed one (domain monotonicity of the Dirichlet
    Green's function). A reading *below* the prediction ``v_k(x)`` is then scored with
    the variance ``sigma^2/2 + ((model_error + shortfall) v_k)^2``, one *above* it with
    ``sigma^2/2 + (model_error v_k)^2``: a split normal (its normalisation ``2 /
    (sqrt(2 pi) (s_below + s_above))`` counts, as it differs from node to node). A source
    behind walls not yet seen is not ruled out by readings the open model over-predicts.
    With ``shortfall = 0`` (or a shared offset) it is :class:`~reciprocity.beliefs.imaging.ImagingMap`.

    Attributes
    ----------
    shortfall : float
        Relative shortfall allowed below the prediction (a fraction of ``v_k``).
    """

    shortfall: float = 0.0

    @classmethod
    def of(cls, imaging: ImagingMap, shortfall: float) -> "ShortfallImaging":
        """`imaging` (its readings and parameters) with `shortfall`: a copy sharing its
        adjoint solves (use it in place of `imaging`)."""
        if not np.isfinite(shortfall) or shortfall < 0:
            raise SearchError(f"shortfall must be a fraction >= 0; got {shortfall!r}")
        out = copy.copy(imaging)
        out.__class__ = cls
        out.shortfall = float(shortfall)
        out._clear()
        return out

    def _correlated_misfit(self, r: np.ndarray) -> np.ndarray:
        if self.shortfall <= 0 or self.offset_sd > 0:
            return super()._correlated_misfit(r)
        s2 = self.sigma ** 2 / 2.0
        v = self.model()
        extra = self.position_variance()
        extra = 0.0 if extra is None else extra
        above = s2 + (self.model_error * v) ** 2 + extra
        below = s2 + ((self.model_error + self.shortfall) * v) ** 2 + extra
        e = r * self.sigma                                           # v_k - I_k, signal units
        d = np.where(e > 0, below, above)
        norm = np.sum(np.log((np.sqrt(below) + np.sqrt(above)) / (2.0 * np.sqrt(s2))), axis=1)
        return 0.5 * np.sum(e * e / d, axis=1) + norm


def _path_lengths(space, here) -> np.ndarray:
    """Path length (cm) from the node nearest `here` to every node along the mesh's edges."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra
    i, j = space.edges
    n = len(space.points)
    graph = coo_matrix((np.hypot(*(space.points[i] - space.points[j]).T), (i, j)), shape=(n, n)).tocsr()
    return dijkstra(graph, directed=False, indices=space.nearest(here))
