"""The mesh the reciprocity search's belief lives on, and how it follows the believed walls.

The candidate sources and observation points are the nodes of the solver's own P1 mesh
(:func:`candidate_space`). The prior keeps every possible source at least the source
clearance from the walls, less one mesh size (:func:`keep_off_walls`): a source a few mm
from an absorbing wall reads as almost nothing, so without it the belief keeps mass along
every wall until readings are taken next to each stretch.

**Unknown obstacles** (a task with ``map: "unknown"``: the strategy is told the outer
boundary, or a partial map, and reads the platform's range scans): a
:class:`~reciprocity.strategies.mapping.MapKeeper` turns the scans into an occupancy
grid; the field is computed on the believed arena (unknown space free: optimistic),
re-meshed only when the believed walls change (:func:`remesh`; the solver and its
factorization are reused otherwise) with every reading imaged again on the new mesh; the
model error grows with the share of the arena not yet seen; observation points lie in
seen-free space; and while most of the belief lies in unseen space the next point is the
frontier point that best serves it (:func:`frontier_point`, see
:mod:`reciprocity.strategies.mapping`), surveyed (scanned, with no reading) where the
platform takes surveys.
"""

from __future__ import annotations

import numpy as np

from arenas import ArenaError

from ...beliefs.imaging import ImagingMap
from ...errors import MeshError, SearchError
from ...fem.green import GreenSolver
from ...models.green import cached_solver
from ...spaces import MeshSpace, mesh_space
from ..mapping import FRONTIER_SHARE, SURVEY_SHARE, MapKeeper
from .next_point import mass_within_reach

__all__ = ["BeliefMesh", "candidate_space", "keep_off_walls", "remesh", "frontier_point", "SURVEY_CAP"]

#: Most surveys of a search, as a multiple of its `max_steps`.
SURVEY_CAP = 3


def candidate_space(geometry, solver: GreenSolver) -> MeshSpace:
    """The candidate points on `geometry`: the nodes of `solver`'s own P1 mesh."""
    space, nodes = mesh_space(geometry, solver.h), solver.nodes
    if solver.order != 1 or space.points.shape != nodes.shape or not np.allclose(space.points, nodes, atol=1e-9):
        raise SearchError("the reciprocity strategy needs a P1 solver (order=1) on the arena's mesh")
    return space


def keep_off_walls(imaging: ImagingMap, space: MeshSpace, clearance: float, margin: float) -> None:
    """Restrict the prior of `imaging` (on `space`'s nodes) to the nodes at least
    `clearance` less `margin` (cm: one mesh size, and on an unknown map one more cell of its
    grid, as believed walls reach that far into the free space) from the walls. A
    clearance that would leave no node leaves the prior as it is."""
    if not clearance > 0:
        return
    allowed = space.wall_distance >= clearance - margin
    if allowed.any():
        imaging.restrict(allowed)


def remesh(mapping: MapKeeper, h: float, notes: dict) -> tuple[MeshSpace, GreenSolver] | None:
    """The space and factorized solver on `mapping`'s believed arena at mesh size `h`
    (cm), or None when the re-mesh fails (a geometry Triangle cannot mesh, out of memory):
    then ``notes["remesh_failures"]`` counts it and ``notes["remesh_note"]`` says why, and
    the caller keeps its last good mesh."""
    geometry = mapping.arena
    try:
        # not the process-wide cache: a believed map is not met again, and eight stale
        # solvers of up to ~100 k nodes each held RSS near 2 GB
        space = MeshSpace(geometry, h)
        solver = GreenSolver(geometry, h=h, order=1, mesh=space).factorize()
    except (MeshError, ArenaError, MemoryError) as exc:
        notes["remesh_failures"] += 1
        notes["remesh_note"] = (f"re-mesh of believed map {mapping.revision} failed "
                                f"({str(exc)[:200]}); kept the last good mesh")
        return None
    return space, solver


def frontier_point(mapping: MapKeeper, space: MeshSpace, weights: np.ndarray, allowed: np.ndarray,
                   here: np.ndarray, reach: float, survey: bool) -> np.ndarray | None:
    """While most of the belief (`weights` at `space`'s nodes) lies in unseen space, the
    frontier point among the `allowed` nodes that best serves it, from `here` (cm), the
    belief's mass within `reach` (cm) scoring each; `survey` when it is to be surveyed
    (:data:`~reciprocity.strategies.mapping.SURVEY_SHARE`, else ``FRONTIER_SHARE``).
    None when the belief is mostly in seen space."""
    return mapping.frontier_point(space, weights, allowed, here,
                                  lambda y: mass_within_reach(y, space.points, weights, reach),
                                  share=SURVEY_SHARE if survey else FRONTIER_SHARE)


class BeliefMesh:
    """The solver and candidate points of a search, the prior's source clearance, and on
    an unknown map the believed walls they follow (see the module's text).

    Parameters
    ----------
    h : float
        Mesh size (cm) of the solver built by :meth:`start` when none is given.
    solver : GreenSolver, optional
        A prebuilt P1 solver for the arena (kept while the arena is the same).
    source_clearance : "task" or float
        Possible sources lie at least this far (cm, less one mesh size) from the walls;
        ``"task"``: the task's public ``source_clearance`` (0 when it says nothing).
    survey : bool
        On an unknown map, explore by survey (scan, no reading) where the platform takes
        it, at most :data:`SURVEY_CAP` times the step cap.

    Attributes
    ----------
    mapping : MapKeeper or None
        The believed map of an unknown-map task; None when the map is known.
    space : MeshSpace
        The candidate points, on the solver's mesh.
    clearance_used : float
        The source clearance in use, cm.
    survey_next : bool
        The next point is to be surveyed, not read.
    """

    def __init__(self, *, h: float = 1.0, solver: GreenSolver | None = None, source_clearance: float | str = "task",
                 survey: bool = True):
        if not np.isfinite(h) or h <= 0:
            raise SearchError(f"h must be a positive number; got {h!r}")
        if not isinstance(survey, bool):
            raise SearchError(f"survey must be true or false; got {survey!r}")
        if source_clearance != "task" and (isinstance(source_clearance, (bool, str))
                                           or not isinstance(source_clearance, (int, float))
                                           or not 0 <= source_clearance < np.inf):
            raise SearchError(f"source_clearance must be 'task' or a distance >= 0 cm; got {source_clearance!r}")
        self.h, self.solver, self.survey = float(h), solver, survey
        self.source_clearance = source_clearance if source_clearance == "task" else float(source_clearance)

    def start(self, ctx) -> dict:
        """The believed map, solver and candidate points for the task of `ctx` (a
        :class:`~reciprocity.strategies.base.SearchContext`); the episode's notes to start
        with (an unknown map's re-mesh failures and surveys)."""
        self.mapping = MapKeeper.from_nominal(ctx.nominal)            # map: unknown (issue 23)
        geometry = ctx.arena.without_scenario() if self.mapping is None else self.mapping.arena
        if self.solver is None or self.solver.arena.without_scenario() is not geometry:
            self.solver = cached_solver(geometry, self.h)
        self.space = candidate_space(geometry, self.solver)
        self.clearance_used = float(ctx.nominal.get("source_clearance", 0.0)) \
            if self.source_clearance == "task" else self.source_clearance
        self.n_surveys, self.survey_next, self._no_survey = 0, False, np.zeros(0, dtype=bool)
        self._can_survey = self.survey and "survey" in ctx.intents
        return {} if self.mapping is None else dict(remesh_failures=0, surveys=0)

    def believed(self, imaging: ImagingMap) -> ImagingMap:
        """`imaging` as the believed map scores it (unchanged when the map is known),
        its prior kept off the walls."""
        if self.mapping is not None:
            imaging = self.mapping.imaging(imaging)
        margin = self.solver.h + (self.mapping.grid.cell if self.mapping is not None else 0.0)
        keep_off_walls(imaging, self.space, self.clearance_used, margin)
        return imaging

    def remesh(self, base: ImagingMap, model_error: float, notes: dict) -> ImagingMap | None:
        """After the believed walls changed: the solver and space on the new believed
        arena, and the readings of `base` imaged on it with the model error of the map now
        (`model_error` before the unseen share); None, the last good mesh kept, when the
        re-mesh fails (:func:`remesh`)."""
        made = remesh(self.mapping, self.h, notes)
        if made is None:
            return None
        self.space, self.solver = made
        error = self.mapping.model_error(model_error) if base.combine == "product" \
            and base.strength_range is None else base.model_error
        return self.believed(base.on(self.solver, model_error=error))

    def unseen(self) -> np.ndarray | None:
        """With an unknown map, the nodes its range sensor has not seen yet; else None."""
        return None if self.mapping is None else ~self.mapping.grid.seen_at(self.space.points)

    def admissible(self, allowed: np.ndarray) -> np.ndarray:
        """`allowed` narrowed to the nodes the believed map lets a point be at."""
        return allowed if self.mapping is None else allowed & self.mapping.admissible(self.space.points)

    def frontier(self, imaging: ImagingMap, allowed: np.ndarray, here: np.ndarray, reach: float,
                 max_steps: int) -> np.ndarray | None:
        """On an unknown map while most of the belief `imaging` lies unseen, the frontier
        point among the `allowed` nodes (:func:`frontier_point`): surveyed, from `here`
        (cm), where the platform takes surveys and fewer than SURVEY_CAP times `max_steps`
        were taken, else read, from the last point read; else None. Sets
        :attr:`survey_next`."""
        self.survey_next = False
        if self.mapping is None:
            return None
        survey = self._can_survey and self.n_surveys < SURVEY_CAP * max_steps
        if survey and len(self._no_survey) != len(self.space.points):
            self._no_survey = np.zeros(len(self.space.points), dtype=bool)
        nxt = frontier_point(self.mapping, self.space, imaging.weights(), allowed & ~self._no_survey if survey
                             else allowed, here if survey else imaging.points[-1], reach, survey)
        self.survey_next = nxt is not None and survey
        return nxt

    def surveyed(self, observations, here: np.ndarray) -> bool:
        """After a survey at `here` (cm): take in its scans; whether the believed walls
        changed (then re-mesh). A survey that showed nothing new rules its neighbourhood
        out of later surveys."""
        self.n_surveys += 1
        if self.mapping.update(observations):
            return True
        if len(self._no_survey) == len(self.space.points):
            self._no_survey |= self.space.around(here, self.mapping.lidar["range"] / 2.0)
        return False

    def params(self) -> dict:
        """The settings, as :meth:`ReciprocityStrategy.params` reports them."""
        return dict(survey=self.survey, source_clearance=self.source_clearance,
                    source_clearance_used=getattr(self, "clearance_used", None),
                    h=self.h if self.solver is None else self.solver.h)
