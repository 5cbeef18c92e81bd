"""Algorithm 1 of Landa et al.: reciprocity-based source discovery, assembled from the
parts of :mod:`reciprocity.strategies.imaging_search`."""

from __future__ import annotations

import numpy as np

from ..beliefs.imaging import ImagingMap
from ..fem.green import GreenSolver
from ..intents import Measure, Survey
from ..outcome import StopReason
from .base import SearchContext, Status, Strategy
from .imaging_search.meshing import BeliefMesh
from .imaging_search.next_point import RULES, axis_point, mass_within_reach, survey_point
from .imaging_search.presets import DEFAULTS, PARTS, PRESETS, assemble, settings
from .imaging_search.several import MORE_TOL
from .imaging_search.stop_rule import likely_out_of_reach, out_of_reach

__all__ = ["ReciprocityStrategy", "RULES", "PRESETS", "DEFAULTS", "axis_point", "mass_within_reach"]

#: The keys of :meth:`ReciprocityStrategy.params`, in the order the episode records them.
PARAM_ORDER = ("preset", "rule", "reach", "eps", "area_tol", "extent_tol", "tail_tol", "d", "credible_radius",
               "credible_mass", "sigma", "sigma_used", "max_steps", "clearance", "combine", "strength",
               "strength_range", "max_sources", "more_tol", "survey_travel", "survey_reach", "model_error",
               "strength_error", "position_error", "survey", "model_error_used", "source_clearance",
               "source_clearance_used", "h")
#: What the strategy reads as its own from its parts: each part's settings (``s.eps``,
#: ``s.rule``, ``s.sigma``, ...) and the mesh's state (``s.space``, ``s.solver``, ...).
DELEGATED = {**{key: {"next_point": "next_point_rule"}.get(part, part) for part in ("reachability", "next_point",
             "stop_rule", "likelihood", "several") for key in PARTS[part] if key != "max_steps"},
             **dict.fromkeys(("h", "solver", "space", "mapping", "clearance_used", "source_clearance", "survey",
                              "n_surveys"), "mesh"),
             "reading_sigma": "likelihood", "reading_bias": "likelihood", "book": "several", "estimates_sd": "several"}


class ReciprocityStrategy(Strategy):
    """Reciprocity search (Algorithm 1 of Landa et al.), assembled from parts: an
    :class:`~reciprocity.beliefs.imaging.ImagingMap` scored by a
    :class:`~.imaging_search.likelihood.Likelihood` (steps 9-11), a
    :class:`~.imaging_search.stop_rule.StopRule` (step 12), a
    :class:`~.imaging_search.next_point.NextPointRule` (step 13) within
    :class:`~.imaging_search.reachability.Reachability`, a
    :class:`~.imaging_search.meshing.BeliefMesh` and, for several sources,
    :class:`~.imaging_search.several.SeveralSources`. The method, the parts and the
    paper's preset: ``docs/reciprocity-search.md``.

    Parameters
    ----------
    preset : {None, "paper"}
        A named assembly (:data:`~.imaging_search.presets.PRESETS`); parameters given override it.
    rule, d, reach : {"axis", "reach", "nearest", "info", "lookahead"}, float, float
        Next-point rule, least separation of points read (cm), sensing reach (cm).
    combine : {"mean", "product"}
        The maps' combination: eq. (8), or the normalised likelihood.
    sigma : float or {"calibrated", "auto", "noise"}
        ``sigma`` of eq. (7), signal units, or the rule that sets it from the task.
    strength, strength_range : float or "arena" or None, "decade" or "fit" or (float, float)
        Source strength (signal units per unit Green's function; None: unknown), and an
        unknown one's log-uniform prior or per-point fit.
    model_error, strength_error : "estimate" or float, float
        Relative errors (fractions) of a predicted reading and of the stated strength.
    position_error : bool
        Score each reading with its variance over the sources a mesh node stands for
        (:class:`~reciprocity.beliefs.imaging.ImagingMap`'s `position_error`).
    eps, area_tol, max_steps : float, float, int or None
        The region ``{P_M >= eps}`` (``0 < eps < 1``); stop once its area is below
        `area_tol` (cm²), or after `max_steps` readings (default 30; 60 for several sources).
    extent_tol, tail_tol, credible_radius, credible_mass : float
        Further stop rules, cm (``inf`` for none): the region, and the nodes with ``P_M >=
        TAIL_EPS``, within this of the estimate; `credible_mass` (0 to 1) of the belief
        within `credible_radius` of it.
    clearance, source_clearance : float, "task" or float
        Distance (cm) from the walls of the points read, and of the possible sources (less
        one mesh size; ``"task"``: the task's).
    h, solver : float, GreenSolver or None
        Mesh size (cm) of the solver built when none is given; a prebuilt P1 solver.
    survey : bool
        On an unknown map, explore by scans without reading where the platform can.
    max_sources, more_tol : int or None, float
        Sources there may be (default the task's), found one at a time; stop once one more
        is less probable than `more_tol`.
    survey_travel, survey_reach : float or None, "reach" or float
        Several sources: discount length (cm) of a survey point's distance; seek one more
        within reach or within this distance (cm).

    Examples
    --------
    >>> s = ReciprocityStrategy(preset="paper", sigma=17.0)
    >>> s.rule, s.combine, s.sigma, s.extent_tol, s.tail_tol
    ('nearest', 'mean', 17.0, inf, inf)
    """

    name = "reciprocity"
    senses = ("scan",)

    def __init__(self, *, preset: str | None = None, rule: str | None = None,
                 combine: str | None = None, sigma=None, eps: float | None = None,
                 area_tol: float | None = None, extent_tol: float | None = None,
                 d: float | None = None, reach: float | None = None,
                 tail_tol: float | None = None, credible_radius: float | None = None,
                 credible_mass: float | None = None, max_steps: int | None = None,
                 clearance: float = 3.0, strength="arena", strength_range="decade",
                 h: float = 1.0, solver: GreenSolver | None = None, max_sources: int | None = None,
                 more_tol: float = MORE_TOL, survey_travel: float | None = None,
                 survey_reach: float | str = "reach", model_error: float | str = "estimate",
                 strength_error: float = 0.0, survey: bool = True, source_clearance: float | str = "task",
                 position_error: bool = True):
        super().__init__()
        p = settings(preset, dict(rule=rule, combine=combine, sigma=sigma, eps=eps, area_tol=area_tol,
                                  extent_tol=extent_tol, d=d, reach=reach, tail_tol=tail_tol,
                                  credible_radius=credible_radius, credible_mass=credible_mass))
        self.mesh = BeliefMesh(h=h, solver=solver, source_clearance=source_clearance, survey=survey)
        self.likelihood, self.combine, self.next_point_rule, self.stop_rule, self.reachability, self.several = \
            assemble(dict(p, max_steps=max_steps, clearance=clearance, strength=strength,
                          strength_range=strength_range, model_error=model_error, strength_error=strength_error,
                          position_error=position_error,
                          max_sources=max_sources, more_tol=more_tol, survey_travel=survey_travel,
                          survey_reach=survey_reach))
        self.preset, self.max_steps = preset, self.stop_rule.cap(several=False)

    def __getattr__(self, name: str):
        if (part := self.__dict__.get(DELEGATED.get(name, ""))) is None:   # a part's setting or state
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        return getattr(part, name)

    def params(self) -> dict:
        p = dict(preset=self.preset, sigma_used=getattr(self, "sigma_used", None), max_steps=self.max_steps,
                 combine=self.combine, clearance=self.clearance, model_error_used=getattr(self, "_model_error", None),
                 **self.likelihood.params(), **self.next_point_rule.params(), **self.stop_rule.params(),
                 **self.several.params(getattr(self.several, "bound", None)), **self.mesh.params())
        return {k: p[k] for k in PARAM_ORDER}

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        self.notes.update(self.mesh.start(ctx))
        arena_strength, start = ctx.arena.strength, ctx.start[:2]
        b = self.likelihood.belief(self.solver, ctx.nominal, arena_strength, self.combine,
                                   None if self.mapping is None else self.mapping.model_error)
        self.sigma_used, self.error_terms, self._model_error = b.sigma, b.error_terms, b.model_error
        self.rng, self.imaging = ctx.rng, self.mesh.believed(b.imaging)
        self.reachability.start(self.space, self.solver, start)
        self._next, self._here = np.asarray(start, dtype=float), np.array(start, dtype=float)
        self.next_point_rule.start(self.space, self.solver, ctx.rng)
        strength = b.strength if b.strength is not None else ctx.nominal.get("strength", arena_strength)
        self.several.start(ctx.nominal, self.imaging, strength, self.space.wall_distance)
        self.max_steps = self.stop_rule.cap(several=self.several.bound > 1)
        self._check_reachable()

    def _remesh(self, position=None) -> None:
        """The believed walls changed: the readings, reachable set and rules on the new mesh."""
        raw = self.mesh.remesh(self.imaging if self.book is None else self.book.raw, self._model_error, self.notes)
        if raw is not None:
            self.imaging = raw if self.book is None else self.book.rebase(raw, self.space.wall_distance)
            self.reachability.rebuild(self.space, self.solver, self.mapping.refused())
            self.next_point_rule.start(self.space, self.solver)

    @property
    def estimates(self) -> np.ndarray | None:
        """Every source found (k, 2), cm, where the task allows several; else None."""
        return self.several.estimates

    @property
    def belief(self) -> ImagingMap:
        """The strategy's belief: its imaging map (a :class:`~reciprocity.beliefs.Belief`)."""
        return self.imaging

    def propose(self) -> Measure | Survey | None:
        return None if self.done else (Survey if self.mesh.survey_next else Measure)(self._next.copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        if isinstance(intent, Survey):        # scans, no reading: no step of the search
            self.notes["surveys"] = self.mesh.n_surveys + 1
            self._here = np.asarray(observations[0].position if observations else intent.point, dtype=float)
            if self.mesh.surveyed(observations, self._here):
                self._remesh(self._here)
            self._choose_next()
        else:
            self._here = np.asarray(observations[0].position, dtype=float)
            if self.mapping is not None and self.mapping.update(observations):
                self._remesh(observations[0].position)
            self.n_measurements, self.n_samples = self.n_measurements + 1, self.n_samples + 1
            if self.book is None:
                self.imaging.update(observations[0])                   # steps 9-11
            else:
                self.imaging = self.book.add(observations[0])
            self._judge()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def _judge(self) -> None:
        """Step 12 after a reading, then the step cap, the out-of-reach stop or step 13."""
        estimate, area, extent, converged = self.stop_rule.judge(self.imaging)
        self.status = Status(estimate, area, extra=dict(region_extent=extent))
        if self.book is not None:
            self.imaging, self.status, why, notes = self.several.settle(
                self.imaging, self.status, converged, self.stop_rule.converged, self._survey_support,
                self.space.cell_areas, self.mesh.unseen())
            self.notes.update(notes)
            if why is not None:
                self.stop(StopReason.CONVERGED, why)
        elif converged:
            self.stop(StopReason.CONVERGED, "region smaller than area_tol")
        if not self.done and self.n_measurements >= self.max_steps:
            note = self.stop_rule.modes_note(self.imaging, self.space.triangles)
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} measurements{note}")
        if self.done:
            return
        if self.book is None or not self.book.found:      # the first source: as the search for one
            self._check_reachable()
        elif not self.reachability.reachable.any():
            self.stop(StopReason.UNREACHABLE, "no observation point is reachable")
        if not self.done:
            self._choose_next()

    def region(self) -> np.ndarray:
        """Mask of the nodes in ``{P_M >= eps}`` (every node before the first reading)."""
        return self.stop_rule.region(self.imaging)

    def modes(self) -> list[tuple[float, np.ndarray]]:
        """The belief's separate modes, ``(mass, peak cm)``, heaviest first (:meth:`.StopRule.modes`)."""
        return self.stop_rule.modes(self.imaging, self.space.triangles)

    def _check_reachable(self) -> None:
        """Stop (UNREACHABLE) when nothing can be read or no possible source is within reach."""
        why, notes = out_of_reach(self.imaging, self.region(), self.within_reach, self.reachability.reachable,
                                  self.space.cell_areas, self.reach)
        self.notes.update(notes)
        if why is not None:
            self.stop(StopReason.UNREACHABLE, why)

    def figure_record(self) -> dict:
        """What the figures draw: ``imaging``, ``steps`` (every reading as one source's map),
        ``eps``; ``within_reach`` (one source) or ``residual`` (several); ``mapping`` (unknown map)."""
        record = dict(imaging=self.imaging, eps=self.eps)
        if self.book is None:
            record.update(steps=self.imaging, within_reach=self.within_reach())
        else:
            record.update(steps=self.book.raw, residual=self.book.active)
        if self.mapping is not None:
            record["mapping"] = dict(known=self.mapping.grid.known, lidar=self.mapping.lidar,
                                     cell=self.mapping.grid.cell, h=self.h, model_error=self._model_error)
        return record

    def within_reach(self) -> np.ndarray:
        """Mask of the nodes of ``imaging`` within reach (:meth:`.Reachability.near`)."""
        return self.reachability.near(self.imaging, self.sigma_used / np.sqrt(2.0)).copy()

    def _survey_support(self) -> np.ndarray:
        """Where one more source is sought (see `survey_reach`)."""
        return self.several.support(self.within_reach, self.reachability)

    def _choose_next(self) -> None:
        nxt = self.next_point()                                        # step 13
        if nxt is None and not self.done:
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
        self._next = self._next if nxt is None else nxt

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None:
            self.reachability.restrict(mask)
            self._check_reachable()

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Exclude the neighbourhood of an unreachable target and choose again."""
        if self._count_rejection(reason) or not len(self.imaging.points):
            return None if self.done else super().reject(intent, point, reason, agent)
        radius = max(0.5 * self.d, self.solver.h)
        if self.mapping is not None:            # kept across the believed maps to come
            radius = self.mapping.refuse(point, radius)
        self.reachability.exclude(point, radius)
        self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def next_point(self) -> np.ndarray | None:
        """Step 13: the next observation point (cm), or None if none is admissible."""
        read = self.imaging.points if self.book is None else self.book.raw.points
        allowed = self.mesh.admissible(self.reachability.reachable & self.next_point_rule.separated(read))
        nxt = self.mesh.frontier(self.imaging, allowed, self._here, self.reach, self.max_steps)  # map unseen
        if nxt is not None:
            return nxt
        if self.book is not None and self.book.surveying:
            hidden = self.book.hidden(self._survey_support(), self.space.cell_areas, self.mesh.unseen())
            return survey_point(self.space, allowed, hidden, self.reach, self.survey_travel, read[-1])
        likely = self.next_point_rule.tests_reach and likely_out_of_reach(self.imaging, self.notes)
        nxt, undecided = self.next_point_rule.choose(self.imaging, allowed, self.sigma_used / np.sqrt(2.0),
                                                     self.within_reach() if likely else None)
        note = self.stop_rule.modes_note(self.imaging, self.space.triangles) if undecided else ""
        if note:
            self.stop(StopReason.GAVE_UP, f"no admissible point tells the modes apart{note}")
            return None
        return nxt
