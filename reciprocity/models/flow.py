"""A gas source in wind among walls: the physics shared by the ``flow`` world and its strategies.

A source at ``x_s`` releases ``q`` particles per second; they diffuse (``D``, cm²/s), are
carried by a potential-flow wind through the arena (entering on the inflow segments of
the outer boundary at ``speed`` cm/s, leaving on the outflow ones) and decay with
lifetime ``τ`` (s). The mean concentration is ``q c(z; x_s)`` with ``c`` the Green's
function of :class:`~reciprocity.fem.AdvectionSolver`. A detector at ``z`` counts
particles at the mean rate ``k q c(z; x_s)`` (``k``, cm²/s, the detector's capture rate:
for an absorbing disk of radius ``a`` it is about ``2 pi D / ln(λ/a)``, the factor of the
plume papers' ``R / ln(λ/a)``), so over a dwell ``Δt`` the count is Poisson with mean
``k q c(z; x_s) Δt``.

The truth (:mod:`reciprocity.worlds.flow`) and a strategy's model each build their own
solver with :func:`build_flow_solver`, each on its own mesh, with its own parameters (the
truth's may differ on purpose: mismatch) and in its own cache.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from arenas import Arena
from arenas.memo import sized_cache

from ..fem import AdvectionSolver, WindField

__all__ = ["FlowParams", "build_flow_solver", "flow_solver", "segments_tuple"]

#: Bytes of a strategy's advection solvers (with their winds) kept per process.
FLOW_CACHE_BYTES = 300 * 2**20


def segments_tuple(segments) -> tuple:
    """Segments ``[[[x0, y0], [x1, y1]], ...]`` as nested tuples of floats (hashable)."""
    return tuple(tuple(tuple(float(v) for v in p) for p in s) for s in np.asarray(segments, dtype=float))


@dataclass(frozen=True)
class FlowParams:
    """The physics of a ``flow`` scenario, as the truth has it or as a strategy is told.

    Attributes
    ----------
    inflow, outflow : tuple of ((x0, y0), (x1, y1))
        Segments of the outer boundary where the wind enters and leaves, cm.
    speed : float
        Inflow speed, cm/s.
    D : float
        Diffusivity, cm²/s.
    tau : float
        Lifetime, s.
    walls : {"impermeable", "absorbing"}
        Wall condition of the concentration.
    strength : float
        Release rate ``q`` of the source, particles/s.
    detector : float
        Capture rate ``k`` of the detector, cm²/s: counts per second per unit
        concentration (particles/cm²).
    """

    inflow: tuple
    outflow: tuple
    speed: float
    D: float
    tau: float
    walls: str = "impermeable"
    strength: float = 100.0
    detector: float = 1.0

    def as_dict(self) -> dict:
        out = asdict(self)
        out["inflow"] = [[list(p) for p in s] for s in self.inflow]
        out["outflow"] = [[list(p) for p in s] for s in self.outflow]
        return out

    def peclet(self, length: float) -> float:
        """Global Péclet number ``speed · length / D`` over `length` cm."""
        return self.speed * float(length) / self.D


def build_flow_solver(arena: Arena, params: FlowParams, h: float) -> AdvectionSolver:
    """The factorized advection solver of `params` on `arena` (its geometry) at mesh size
    `h` cm, on the mesh of its potential-flow wind. Not cached: the truth keeps its own
    (:func:`reciprocity.worlds.flow.truth_solver`), strategies theirs (:func:`flow_solver`),
    so that neither evicts the other.

    Raises
    ------
    ReciprocityError
        A segment runs along an obstacle attached to the boundary (seen on the mesh).
    """
    wind = WindField.potential(arena, list(params.inflow), list(params.outflow), speed=params.speed, h=float(h))
    return AdvectionSolver(arena, wind, D=params.D, tau=params.tau, h=float(h), walls=params.walls).factorize()


@sized_cache(FLOW_CACHE_BYTES, maxsize=8)
def flow_solver(arena: Arena, params: FlowParams, h: float) -> AdvectionSolver:
    """:func:`build_flow_solver` for a strategy's model, kept per process (pass
    ``arena.without_scenario()``): episodes on one arena factorize it once."""
    return build_flow_solver(arena, params, h)
