"""The flow world (truth): a gas source in wind among walls, read as intermittent hits.

The mean concentration of the true source is the steady advection-diffusion-decay field
of :mod:`reciprocity.models.flow` (a potential-flow wind through the arena, walls
impermeable or absorbing), solved on the truth's own mesh (``truth_h``, finer than a
strategy's by default: no inverse crime of the mesh), with the truth's own parameters.
A reading over a dwell ``Δt`` at ``z`` is a Poisson count of mean
``k q c(z; x_s) Δt`` (the detector's capture rate ``k``, the release rate ``q``).

:class:`FlowMismatch` makes the truth differ from what a strategy is told: the wind's
speed, its inflow and outflow segments (its direction through the arena), the
diffusivity, the lifetime and the release rate.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from arenas import Arena
from arenas.memo import sized_cache

from ..errors import SearchError
from ..fem.green import Field
from ..models.flow import FlowParams, build_flow_solver
from .base import Reading, World

__all__ = ["FlowWorld", "FlowMismatch", "TRUTH_H", "truth_solver"]

#: Mesh size of the truth (cm): half the mesh size of the command line's default model (1 cm).
TRUTH_H = 0.5
#: Bytes of truth solvers kept per process (the paper arena at 0.5 cm: 93 000 unknowns).
TRUTH_CACHE_BYTES = 400 * 2**20


@sized_cache(TRUTH_CACHE_BYTES, maxsize=4)
def truth_solver(arena: Arena, params: FlowParams, h: float):
    """The truth's own advection solver of `arena` (its geometry) with the true `params`
    at mesh size `h` cm, kept for the truth alone (no strategy ever holds it)."""
    return build_flow_solver(arena, params, h)


@dataclass(frozen=True)
class FlowMismatch:
    """How the true flow differs from the nominal one (defaults: no mismatch).

    Attributes
    ----------
    wind_factor, diffusivity_factor, tau_factor, strength_factor : float
        True inflow speed, ``D``, ``τ`` and release rate as multiples of the nominal ones.
    inflow, outflow : tuple or None
        The true inflow and outflow segments (cm) when they differ from the nominal ones
        (the wind blows another way through the arena); None: as told.
    """

    wind_factor: float = 1.0
    diffusivity_factor: float = 1.0
    tau_factor: float = 1.0
    strength_factor: float = 1.0
    inflow: tuple | None = None
    outflow: tuple | None = None

    @property
    def none(self) -> bool:
        return self == FlowMismatch()

    def apply(self, p: FlowParams) -> FlowParams:
        """The true parameters of nominal `p`."""
        return replace(p, speed=p.speed * self.wind_factor, D=p.D * self.diffusivity_factor,
                       tau=p.tau * self.tau_factor, strength=p.strength * self.strength_factor,
                       inflow=p.inflow if self.inflow is None else self.inflow,
                       outflow=p.outflow if self.outflow is None else self.outflow)

    def as_dict(self) -> dict:
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        for key in ("inflow", "outflow"):
            if out[key] is not None:
                out[key] = [[list(p) for p in s] for s in out[key]]
        return out


class FlowWorld(World):
    """Truth of a ``flow`` scenario: Poisson hits of the mean concentration of the true source.

    Parameters
    ----------
    arena : Arena
        The arena with its true source (cm); its walls are the true ones and the told ones.
    params : FlowParams
        The nominal physics (what a strategy is told).
    mismatch : FlowMismatch, optional
        How the truth departs from `params`.
    h : float
        Mesh size of the truth's solver, cm.
    success_radius : float
        A converged estimate within this distance (cm) succeeds.
    source_clearance : float
        The task's public statement that the source lies at least this far (cm) from the
        walls, told to the strategy (0: anywhere).
    """

    kind = "flow"

    def __init__(self, arena: Arena, params: FlowParams, *, mismatch: FlowMismatch | None = None,
                 h: float = TRUTH_H, success_radius: float = 5.0, source_clearance: float = 0.0):
        if arena.source is None:
            raise SearchError(f"arena {arena.name!r} has no true source: give source: [x, y]")
        self.arena = arena
        #: the walls the observer meets (the flow world tells the strategy the true walls)
        self.true_arena = arena
        self.params = params
        self.mismatch = mismatch or FlowMismatch()
        self.truth = self.mismatch.apply(params)
        self.source = np.asarray(arena.source, dtype=float)
        self.strength = float(self.truth.strength)
        self.h = float(h)
        self.source_clearance = float(source_clearance)
        self.success_radius = float(success_radius)
        self._field: Field | None = None

    @property
    def field(self) -> Field:
        """The true mean concentration ``q c(·; x_s)`` (particles/cm², a field at any points, cm)."""
        if self._field is None:
            solver = truth_solver(self.arena.without_scenario(), self.truth, self.h)
            c = solver.forward(self.source)
            self._field = Field(c.solver, self.truth.strength * c.dofs, "mean concentration")
        return self._field

    def figure_record(self) -> dict:
        """``wind``: the true wind (a :class:`~reciprocity.fem.WindField`); ``field``: the
        true mean concentration; ``true_arena``: the walls."""
        wind = truth_solver(self.arena.without_scenario(), self.truth, self.h).wind
        return dict(wind=wind, field=self.field, true_arena=self.true_arena)

    def mean_count(self, points, dwell: float) -> np.ndarray:
        """Mean hits over `dwell` s at `points` (n, 2) cm: ``k q c Δt`` (stabilised P1
        fields dip slightly below zero far upwind: read as zero)."""
        c = self.field(np.atleast_2d(np.asarray(points, dtype=float)))
        return self.truth.detector * np.maximum(c, 0.0) * float(dwell)

    def read(self, position, *, time: float = 0.0, dwell: float = 1.0, rng: np.random.Generator,
             observer: int = 0) -> Reading:
        mu = float(self.mean_count(np.asarray(position, dtype=float)[None, :2], dwell)[0])
        if not np.isfinite(mu):
            raise SearchError(f"position ({position[0]:.4g}, {position[1]:.4g}) is not in the free region")
        return Reading(float(rng.poisson(mu)), False, "hits")

    def contains(self, points) -> np.ndarray:
        return self.arena.contains(np.atleast_2d(np.asarray(points, dtype=float)))

    def nominal(self) -> dict:
        p = self.params
        return self._nominal_sources(dict(arena=replace(self.arena, source=None), inflow=p.inflow,
                                          outflow=p.outflow, speed=p.speed, D=p.D, tau=p.tau, walls=p.walls,
                                          strength=p.strength, detector=p.detector))

    def describe(self) -> dict:
        return dict(flow=self.params.as_dict(), truth_h=self.h, mismatch=self.mismatch.as_dict())
