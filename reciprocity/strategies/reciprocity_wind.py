"""Reciprocity in wind (issue 38): adjoint imaging of a gas source among walls from hit counts.

The ``flow`` world's readings are Poisson counts of mean ``k q c(z; x) Δt``, ``c`` the
steady advection-diffusion-decay Green's function of the arena's wind
(:mod:`reciprocity.models.flow`). Its adjoint (the wind reversed) turns one reading into
a statement about every candidate source: ``c(z; x) = v_z(x)`` with ``v_z`` the adjoint
field of the reading point (:meth:`~reciprocity.fem.AdvectionSolver.adjoint`, read at the
candidates through :meth:`~reciprocity.fem.AdvectionSolver.source_matrix`). So, as in
Algorithm 1 of Landa et al. with its Gaussian map replaced by the count likelihood:

- **model** (:class:`ArenaCounts`): one adjoint solve per reading gives the predicted
  mean count from a unit source at every node of the strategy's mesh; its own mesh
  (``h``), its own solver, built from what the task tells (the arena, the inflow and
  outflow, the speed, ``D``, ``τ``, the walls, the detector's capture rate);
- **belief** (:class:`~reciprocity.beliefs.counts.CountPosterior`): the Poisson
  likelihood of every count, over (node, release rate), the release rate integrated out
  over a log-uniform prior a decade either side of the stated one, as the Poisson
  search integrates out an unknown strength;
- **next point** (``rule="info"``, the default): the reachable node, at least ``d``
  (:data:`D_READ`) from every point read, whose count is expected to tell most about the
  source's node: the mutual information of the count with the node over ``samples``
  (node, release rate) pairs drawn from the posterior
  (:func:`~reciprocity.strategies.count_information.count_information`). By reciprocity one
  *forward* solve per sampled node gives its predicted count at every candidate at once
  (:meth:`ArenaCounts.from_sources`; kept for the rest of the search), so the rule sees the
  wind and the walls. The information is summed exactly at the ``shortlist`` candidates
  where the pairs' predicted counts differ most in units of their Poisson noise (the
  spread of ``2 sqrt(count)``). ``rule="axis"`` is the Poisson search's rule carried over
  unchanged (it takes any belief over mesh nodes): the node with the most belief within
  ``reach`` (:func:`~reciprocity.strategies.imaging_search.next_point.mass_within_reach`);
  once the belief is narrower than ``reach``, the node on its major axis beyond it
  (:func:`~reciprocity.strategies.imaging_search.next_point.axis_point`). It does not know
  the wind: an isotropic reach stands for the adjoint's footprint, which stretches upwind.
  On the benchmark draws the ``"info"`` rule needs fewer readings (``benchmarks/wind.md``).
- **stop**: the Poisson search's credible rule, CONVERGED once ``credible_mass`` of the
  belief lies within ``credible_radius`` of the estimate (the posterior mean near the
  most probable node); STEP_CAP after ``max_steps`` readings. The radius is 4 cm
  (:data:`CREDIBLE_RADIUS`), not the Poisson search's 3: counts near a wall leave the
  belief a few cm wide for many readings (``benchmarks/wind.md``).

``free-space-wind`` is the same search with the plume papers' model in the place of the
arena's (:class:`FreeSpaceCounts`): the free-space Green's function of a uniform wind
(the stated speed, blowing from the inflow toward the outflow), blind to the walls.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.base import credible_mass
from ..beliefs.counts import CountPosterior
from ..errors import SearchError
from ..fem.exact import free_space_advection_green
from ..intents import Measure
from ..models.flow import FlowParams, flow_solver, segments_tuple
from ..outcome import StopReason
from ..spaces import mesh_space
from ..validation import number, whole
from . import register
from .base import SearchContext, Status, Strategy
from .count_information import count_information, systematic_sample
from .imaging_search.next_point import axis_point, mass_within_reach

__all__ = ["ArenaCounts", "FreeSpaceCounts", "WindReciprocity", "TeamWindReciprocity", "FreeSpaceWind",
           "ReachableNodes", "ModelFreeWind", "told_wind_direction", "CREDIBLE_RADIUS"]

#: Default ``max_steps``: readings of one search.
MAX_STEPS = 80
#: Default ``d``, cm: half the Poisson search's 6 cm. A count tells little about where the
#: source is within a few cm unless it is read there again: with 6 cm between points read
#: the search stopped at its cap in 5 of 6 draws on ``paper-wind`` (the belief 2 cm wide),
#: with 3 cm it converged in all 6 (``benchmarks/wind.md``).
D_READ = 3.0
#: Background count rate of the likelihood, hits/s (see :class:`CountPosterior`).
BACKGROUND = 0.01
#: Default ``credible_radius``, cm: the stop once ``credible_mass`` of the belief lies this
#: close to the estimate, inside the 5 cm success radius. With the Poisson search's 3 cm,
#: 18 of 240 benchmark draws reached the 80-reading cap, 13 of them with the estimate
#: within 5 cm; with 4 cm, 7 (``benchmarks/wind.md``, measured on held-out draws too).
CREDIBLE_RADIUS = 4.0
#: The next-point rules of :class:`WindReciprocity`.
NEXT_POINT_RULES = ("info", "axis")
#: Largest ``source_clearance`` and ``clearance``, cm.
MAX_CLEARANCE = 100.0


def told_physics(nominal: dict) -> FlowParams:
    """The physics a ``flow`` task states (never the truth's)."""
    return FlowParams(segments_tuple(nominal["inflow"]), segments_tuple(nominal["outflow"]), float(nominal["speed"]),
                      float(nominal["D"]), float(nominal["tau"]), str(nominal["walls"]),
                      float(nominal["strength"]), float(nominal["detector"]))


def told_wind_direction(nominal: dict) -> np.ndarray:
    """Unit vector from the midpoint of the stated inflow segments to that of the outflow
    segments: the direction the wind blows as a ``flow`` task states it, blind to the walls."""
    mid_in = np.mean([np.mean(s, axis=0) for s in segments_tuple(nominal["inflow"])], axis=0)
    mid_out = np.mean([np.mean(s, axis=0) for s in segments_tuple(nominal["outflow"])], axis=0)
    along = mid_out - mid_in
    size = float(np.hypot(*along))
    if size == 0:
        raise SearchError("the inflow and outflow midpoints coincide: the stated wind has no direction")
    return along / size


class ArenaCounts:
    """Mean hits per second per unit release rate, from the arena's own wind and walls.

    Parameters
    ----------
    nominal : dict
        The ``flow`` task's description.
    h : float
        Mesh size of the model, cm.
    """

    def __init__(self, nominal: dict, h: float):
        geometry = nominal["arena"].without_scenario()
        self.physics = told_physics(nominal)
        self.solver = flow_solver(geometry, self.physics, h)
        self.space = mesh_space(geometry, h)
        if self.space.points.shape != self.solver.space.nodes.shape or \
                not np.allclose(self.space.points, self.solver.space.nodes, atol=1e-9):
            raise SearchError("the wind model's mesh differs from the search space's; give both the same h")
        # the source rows of every candidate, built once per search: adjoint dofs -> readings
        self._rows = self.solver.source_matrix(self.space.points)
        self._probe = None

    def rates(self, z: np.ndarray) -> np.ndarray:
        """``k c(z; x)`` at every node ``x`` of :attr:`space`: one adjoint solve (wind reversed)."""
        v = self.solver.adjoints(np.asarray(z, dtype=float)[None])[:, 0]
        return self.physics.detector * (self._rows @ v)

    def from_sources(self, nodes: np.ndarray) -> np.ndarray:
        """``k c(z; x)`` (n_nodes, m) at every node ``z`` of :attr:`space` from unit sources at the
        nodes ``x`` of index `nodes` (m,): one forward solve per source. Column ``j`` holds
        what :meth:`rates` gives at node ``nodes[j]`` for every reading node (reciprocity)."""
        if self._probe is None:
            self._probe, _ = self.solver.space.probe_matrix(self.space.points)
        u = self.solver.forwards(self.space.points[np.asarray(nodes, dtype=int)])
        return self.physics.detector * np.asarray(self._probe @ u)


class FreeSpaceCounts:
    """Mean hits per second per unit release rate in free space (the plume papers' model):
    a uniform wind of the stated speed from the inflow's midpoint toward the outflow's,
    no walls. The count at a candidate within ``h / 2`` of the reading is taken at
    ``h / 2`` upwind (the free-space function is singular there; a sensor has a size).

    Parameters
    ----------
    nominal : dict
        The ``flow`` task's description.
    h : float
        Mesh size of the candidate nodes, cm.
    """

    def __init__(self, nominal: dict, h: float):
        self.physics = p = told_physics(nominal)
        self.space = mesh_space(nominal["arena"].without_scenario(), h)
        self.wind = p.speed * told_wind_direction(nominal)
        self.near = 0.5 * h

    def rates(self, z: np.ndarray) -> np.ndarray:
        z = np.asarray(z, dtype=float)
        r = self.space.points - z
        d = np.hypot(r[:, 0], r[:, 1])
        upwind = -self.wind / np.hypot(*self.wind)
        direction = np.where(d[:, None] > 0, r / np.maximum(d, 1e-300)[:, None], upwind[None])
        x = np.where(d[:, None] < self.near, z + self.near * direction, self.space.points)
        # the reading at z from a source at x: the wind reversed, read from z
        c = free_space_advection_green(x, z, -self.wind, self.physics.D, self.physics.tau)
        return self.physics.detector * c

    def from_sources(self, nodes: np.ndarray) -> np.ndarray:
        """:meth:`rates` at every node as reading point, for the sources at nodes `nodes`
        (m,): shape (n_nodes, m), as :meth:`ArenaCounts.from_sources`."""
        return np.column_stack([self._column(self.space.points[j]) for j in np.asarray(nodes, dtype=int)]) \
            if len(nodes) else np.zeros((len(self.space.points), 0))

    def _column(self, x: np.ndarray) -> np.ndarray:
        """``rates(z)`` at source `x` for every node ``z``: the same points and singular cut
        as :meth:`rates`, with the function's translation invariance."""
        z = self.space.points
        r = x[None, :] - z
        d = np.hypot(r[:, 0], r[:, 1])
        upwind = -self.wind / np.hypot(*self.wind)
        direction = np.where(d[:, None] > 0, r / np.maximum(d, 1e-300)[:, None], upwind[None])
        xs = np.where(d[:, None] < self.near, z + self.near * direction, x[None, :])
        c = free_space_advection_green(xs - z, np.zeros(2), -self.wind, self.physics.D, self.physics.tau)
        return self.physics.detector * c


class ReachableNodes:
    """The nodes of :attr:`space` a search may read from (``_reachable``), narrowed by the
    platform's reach and by the targets it refused (a mixin of the ``flow`` searches)."""

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None:
            self._reachable &= mask

    def _refuse_around(self, point: np.ndarray, radius: float) -> bool:
        """Leave out the nodes within `radius` (cm) of a refused `point`; False when no
        node is left."""
        self._reachable &= ~self.space.around(point, radius)
        return bool(self._reachable.any())

    def _nearest(self, want: np.ndarray, here: np.ndarray) -> np.ndarray:
        """The reachable node nearest to `want` (cm), other than `here` when another exists
        (a node within half a mesh size of `here` is `here`)."""
        idx = np.flatnonzero(self._reachable)
        d = np.hypot(*(self.space.points[idx] - want).T)
        away = np.hypot(*(self.space.points[idx] - here).T) >= 0.5 * self.h
        if away.any():
            d = np.where(away, d, np.inf)
        return self.space.points[idx[int(np.argmin(d))]].copy()


class ModelFreeWind(ReachableNodes, Strategy):
    """What the model-free baselines on ``flow`` worlds share (``surge-cast-wind``,
    ``gradient-wind``): the nodes of a mesh of the arena they move between, the wind the
    task states, and the settings below (validated here).

    Parameters
    ----------
    step : float
        Length of a move, cm.
    hits : int
        Count that makes a reading a detection.
    declare : int
        Readings or stations in a row without a higher hit rate than the best that stop
        the search.
    max_steps : int
        Readings before the search stops at its cap.
    h : float
        Mesh size of the nodes it moves between, cm.
    clearance : float
        Points read keep this distance from the walls, cm.
    """

    worlds = ("flow",)
    agents = 1

    def __init__(self, *, step: float, hits: int, declare: int, max_steps: int, h: float, clearance: float):
        super().__init__()
        self.step = number(step, "step", 0.0, 1e3, lo_open=True, unit="cm")
        self.hits = whole(hits, "hits", 1, 10 ** 9)
        self.declare = whole(declare, "declare", 1, 100_000)
        self.max_steps = whole(max_steps, "max_steps", 1, 100_000)
        self.h = number(h, "h", 0.25, 20.0, unit="cm")
        self.clearance = number(clearance, "clearance", 0.0, 100.0, unit="cm")

    def start(self, ctx: SearchContext) -> None:
        """The mesh, the stated wind (``downwind``, a unit vector) and the nodes reachable
        from the start; stops UNREACHABLE when there are none."""
        self._reset_state()
        if ctx.world not in self.worlds:
            raise SearchError(f"strategy {self.name!r} applies to flow worlds; got {ctx.world!r}")
        self.space = mesh_space(ctx.nominal["arena"].without_scenario(), self.h)
        self.downwind = told_wind_direction(ctx.nominal)
        self._reachable = self.space.reachable_from(ctx.start[:2], self.clearance)

    def _check_reachable(self) -> None:
        if not self._reachable.any():
            self.stop(StopReason.UNREACHABLE, "no observation point is reachable")


@register
class WindReciprocity(ReachableNodes, Strategy):
    """Reciprocity in wind: one adjoint solve per reading, the count likelihood, the
    ``"info"`` next-point rule and the credible stop (see the module doc).

    Parameters
    ----------
    h : float
        Mesh size of the strategy's model and candidate nodes, cm.
    d : float
        Least distance between points read, cm.
    reach : float
        Kernel length of the next-point rule, cm.
    credible_radius : float
        Radius of the credible stop, cm.
    credible_mass : float
        Share of the belief within `credible_radius` that stops the search, in (0, 1).
    max_steps : int
        Readings before the search stops at its cap.
    clearance : float
        Points read keep this distance from the walls, cm.
    background : float
        Background count rate of the likelihood, hits/s.
    source_clearance : "task" or float
        The prior keeps every possible source at least this far (cm, less one mesh size)
        from the walls: ``"task"`` (default) takes the task's public ``source_clearance``
        (0, anywhere, when the task says nothing), as the Poisson search does.
    rule : {"info", "axis"}
        The next point: ``"info"`` (default), the admissible node whose count is expected
        to tell most about the source's node
        (:func:`~reciprocity.strategies.count_information.count_information`, over `samples`
        posterior pairs, scored exactly at the `shortlist` nodes where the pairs' predicted
        counts differ most in units of their Poisson noise); ``"axis"``, the Poisson
        search's rule (module doc).
    samples, shortlist : int
        Posterior (node, rate) pairs, and candidate nodes scored exactly, of the ``"info"`` rule.
    """

    name = "reciprocity-wind"
    worlds = ("flow",)
    agents = 1
    #: How a reading's mean counts are predicted from what the task tells.
    model = ArenaCounts

    def __init__(self, *, h: float = 2.0, d: float = D_READ, reach: float = 12.0,
                 credible_radius: float = CREDIBLE_RADIUS, credible_mass: float = 0.95, max_steps: int = MAX_STEPS,
                 clearance: float = 3.0, background: float = BACKGROUND, source_clearance: float | str = "task",
                 rule: str = "info", samples: int = 256, shortlist: int = 64):
        super().__init__()
        if rule not in NEXT_POINT_RULES:
            raise SearchError(f"rule must be one of {', '.join(NEXT_POINT_RULES)}; got {rule!r}")
        self.rule = rule
        self.samples = whole(samples, "samples", 8, 100_000)
        self.shortlist = whole(shortlist, "shortlist", 1, 100_000)
        self.h = number(h, "h", 0.25, 20.0, unit="cm")
        self.d = number(d, "d", 0.0, 1e3, lo_open=True, unit="cm")
        self.reach = number(reach, "reach", 0.0, 1e3, lo_open=True, unit="cm")
        self.credible_radius = number(credible_radius, "credible_radius", 0.0, 1e3, lo_open=True, unit="cm")
        self.credible_mass = number(credible_mass, "credible_mass", 0.0, 1.0, lo_open=True, hi_open=True)
        self.max_steps = whole(max_steps, "max_steps", 1, 100_000)
        self.clearance = number(clearance, "clearance", 0.0, 100.0, unit="cm")
        self.background = number(background, "background", 0.0, 1e6, lo_open=True, unit="hits/s")
        self.source_clearance = source_clearance if source_clearance == "task" else \
            number(source_clearance, "source_clearance", 0.0, MAX_CLEARANCE, unit="cm")

    def params(self) -> dict:
        return dict(h=self.h, d=self.d, reach=self.reach, credible_radius=self.credible_radius,
                    credible_mass=self.credible_mass, max_steps=self.max_steps, clearance=self.clearance,
                    background=self.background, source_clearance=self.source_clearance,
                    source_clearance_used=getattr(self, "clearance_used", None), rule=self.rule,
                    samples=self.samples, shortlist=self.shortlist)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        self._rng = ctx.rng
        self._dwell = 1.0
        self._columns: dict[int, np.ndarray] = {}       # the "info" rule's forward solves, by node
        if ctx.world not in self.worlds:
            raise SearchError(f"strategy {self.name!r} applies to flow worlds; got {ctx.world!r}")
        self.counts = self.model(ctx.nominal, self.h)
        self.space = self.counts.space
        q = float(ctx.nominal["strength"])
        self.belief = CountPosterior(self.space.points, self.space.cell_areas, (q / 10.0, q * 10.0),
                                     background=self.background)
        self._keep_off_walls(ctx.nominal)
        self._reachable = self.space.reachable_from(ctx.start[:2], self.clearance)
        self._far = np.ones(len(self.space.points), dtype=bool)
        self._next = np.asarray(ctx.start[:2], dtype=float).copy()
        if not self._reachable.any():
            self.stop(StopReason.UNREACHABLE, "no observation point is reachable")

    def _keep_off_walls(self, nominal: dict) -> None:
        """No prior mass nearer the walls than the source clearance in use, less one mesh
        size (a clearance that would leave no node leaves the prior as it is)."""
        self.clearance_used = float(nominal.get("source_clearance", 0.0)) \
            if self.source_clearance == "task" else float(self.source_clearance)
        if self.clearance_used > 0:
            allowed = self.space.wall_distance >= self.clearance_used - self.h
            if allowed.any():
                self.belief.restrict(allowed)

    def figure_record(self) -> dict:
        """``posterior``: the belief over (node, release rate), whose :meth:`~CountPosterior.first`
        gives each step's; ``triangulation``: its nodes' mesh; ``credible_radius``."""
        return dict(posterior=self.belief, triangulation=self.space.triangulation,
                    credible_radius=self.credible_radius)

    # -- protocol ------------------------------------------------------------------------
    def propose(self) -> Measure | None:
        return None if self.done else Measure(self._next.copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        self._take_reading(observations[0])
        if not self._credible_stop() and self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} readings")
        if not self.done:
            self._choose_next()

    def _take_reading(self, obs) -> np.ndarray:
        """Condition the belief on one count; returns where it was read (cm)."""
        z = np.asarray(obs.position, dtype=float)
        self._dwell = float(obs.dwell)
        self.belief.add(self.counts.rates(z), float(obs.value), float(obs.dwell))
        self.n_measurements += 1
        self.n_samples += 1
        self._far &= self.space.separated(z[None], self.d)
        return z

    def _credible_stop(self) -> bool:
        """The status from the belief; stop (CONVERGED, True) once ``credible_mass`` of it lies
        within ``credible_radius`` of the estimate."""
        estimate = self.belief.estimate(self.credible_radius)
        held = credible_mass(self.space.points, self.belief.weights(), estimate, self.credible_radius)
        self.status = Status(estimate, None, extra=dict(credible=held, entropy=self.belief.entropy()))
        if held >= self.credible_mass:
            self.stop(StopReason.CONVERGED, f"{held:.3f} of the belief within {self.credible_radius:g} cm "
                                            "of the estimate")
        return self.done

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Exclude the neighbourhood of an unreachable target and choose again."""
        if self._count_rejection(reason):
            return
        self._refuse_around(point, max(0.5 * self.d, self.h))
        self._choose_next()

    # -- the next point --------------------------------------------------------------------
    def _choose_next(self) -> None:
        allowed = self._reachable & self._far
        idx = np.flatnonzero(allowed)
        if idx.size == 0:
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
            return
        self._next = self._rule_point(idx)
        self.status.extra["next"] = self._next.tolist()

    def _rule_point(self, idx: np.ndarray) -> np.ndarray:
        """The next-point rule's point (cm) among the admissible nodes `idx`; where the
        ``"axis"`` rule has none, the node with the most belief within ``reach``."""
        w = self.belief.weights()
        if self.rule == "info":
            return np.asarray(self._info_point(idx), dtype=float).copy()
        allowed = np.zeros(len(w), dtype=bool)
        allowed[idx] = True
        nxt = axis_point(self.space, w, allowed, self.reach, self.d)
        if nxt is None:
            score = mass_within_reach(self.space.points[idx], self.space.points, w, self.reach)
            nxt = self.space.points[idx[int(np.argmax(score))]]
        return np.asarray(nxt, dtype=float).copy()

    def _info_point(self, idx: np.ndarray) -> np.ndarray:
        """The ``"info"`` rule's point among the admissible nodes `idx` (see the class doc)."""
        post = self.belief
        logw = np.where(post.allowed[:, None], post.loglik, -np.inf) + np.log(post.areas)[:, None]
        w = np.exp(logw - logw.max()).ravel()
        pick = systematic_sample(w / w.sum(), self.samples, self._rng)
        node, cell = np.divmod(pick, post.loglik.shape[1])
        fresh = [j for j in np.unique(node) if int(j) not in self._columns]
        if fresh:
            for j, column in zip(fresh, self.counts.from_sources(np.array(fresh)).T):
                self._columns[int(j)] = np.maximum(column, 0.0)
        used, slot = np.unique(node, return_inverse=True)
        per_unit = np.column_stack([self._columns[int(j)][idx] for j in used])[:, slot]   # (candidates, samples)
        mean = (per_unit * post.rates[cell][None, :] + self.background) * self._dwell
        # the shortlist: where the samples' counts differ most in units of Poisson noise
        # (2 sqrt(count) has unit variance)
        spread = np.std(2.0 * np.sqrt(mean), axis=1)
        short = np.argsort(spread)[::-1][:self.shortlist]
        info = count_information(mean[short], node)
        best = short[int(np.argmax(info))]
        self.status.extra["information"] = float(info.max())
        return self.space.points[idx[best]]


@register
class TeamWindReciprocity(WindReciprocity):
    """Reciprocity in wind for a team: every observer's counts update one shared belief (the
    multi-agent papers' full sharing), and each round every observer reads where the
    next-point rule puts it.

    The observers choose in turn, after the last count of a round: each takes the rule's
    point among the nodes reachable from where it stands, at least ``d`` from every point
    read and at least ``reach`` from the points its teammates chose this round (so that two
    observers do not read the same plume twice). ``max_steps`` counts rounds; the stop is
    the credible rule on the shared belief. Parameters as :class:`WindReciprocity`.
    """

    name = "team-reciprocity-wind"
    agents = None

    def start(self, ctx: SearchContext) -> None:
        super().start(ctx)
        starts = np.asarray(ctx.starts, dtype=float)[:, :2]
        self._reach_of = [self.space.reachable_from(p, self.clearance) for p in starts]
        self._reachable = np.logical_or.reduce(self._reach_of)
        self._nexts = starts.copy()
        self._waiting: set[int] = set()
        self.rounds = 0
        if not self._reachable.any():
            self.stop(StopReason.UNREACHABLE, "no observation point is reachable")

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None:
            self._reachable &= mask
            self._reach_of = [r & mask for r in self._reach_of]

    def propose(self) -> dict | None:
        if self.done:
            return None
        self._waiting = set(range(len(self._nexts)))
        return {a: Measure(p.copy()) for a, p in enumerate(self._nexts)}

    def observe(self, observations, intent, agent: int = 0) -> None:
        self._nexts[agent] = self._take_reading(observations[0])[:2]
        self._end_of_turn(agent)

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        if self._count_rejection(reason):
            return
        around = self.space.around(point, max(0.5 * self.d, self.h))
        self._reach_of[agent] &= ~around
        self._end_of_turn(agent)

    def _end_of_turn(self, agent: int) -> None:
        """After the last observer of a round: the stop, else every observer's next point."""
        self._waiting.discard(agent)
        if self._waiting or self.done:
            return
        self.rounds += 1
        if self._credible_stop():
            return
        if self.rounds >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} rounds")
            return
        chosen: list[np.ndarray] = []
        for a in range(len(self._nexts)):
            allowed = self._reach_of[a] & self._far
            for point in chosen:
                allowed &= ~self.space.around(point, self.reach)
            idx = np.flatnonzero(allowed)
            if idx.size == 0:
                idx = np.flatnonzero(self._reach_of[a] & self._far)
            if idx.size == 0:
                self.stop(StopReason.NO_TARGET, f"no admissible observation point left for observer {a}")
                return
            self._nexts[a] = self._rule_point(idx)[:2]
            chosen.append(self._nexts[a].copy())
        self.status.extra["next"] = self._nexts.tolist()


@register
class FreeSpaceWind(WindReciprocity):
    """:class:`WindReciprocity` with the free-space likelihood of a uniform wind, blind to
    the walls (the plume papers' model; see the module doc)."""

    name = "free-space-wind"
    model = FreeSpaceCounts
