"""The bounds of every numeric strategy parameter, checked before a strategy is built.

A strategy's constructor checks what its method needs (a probability below one, a
positive step); this table adds what keeps one episode within memory and time (at most a
few GB, minutes): particle counts, grid resolutions, horizons and step caps. Lengths are
in the world's unit (cm for arenas). A parameter not listed is checked by its strategy.
"""

from __future__ import annotations

from ..outcome import MAX_SOURCES
from ..validation import Bound

__all__ = ["STRATEGY_BOUNDS"]

_STEPS = Bound(1, 100_000, integer=True)                     # a strategy's own step cap
_CLEARANCE = Bound(0, 50, unit="cm")
_STRENGTH = Bound(1e-6, 1e6, words=("arena",), none=True)
_MESH_H = Bound(0.2, 20, unit="cm")                            # ~0.5 M triangles at most on 140 cm
_PARTICLES = Bound(10, 100_000, integer=True)
_PLUME_BELIEF = dict(particles=_PARTICLES, resample_below=Bound(0, 1), mcmc_steps=Bound(0, 100, integer=True),
                     eta=Bound(0, 1))
_LATTICE_BELIEF = dict(n_particles=_PARTICLES, n_gain=Bound(1, 100_000, integer=True), eta0=Bound(1e-6, 1e6),
                       theta0=Bound(1e-6, 1e6), q0=Bound(0, 1), persistence=Bound(0, 1),
                       min_distance=Bound(1e-6, 1e3), loop_window=Bound(1, 10_000, integer=True),
                       loop_visits=Bound(1, 10_000, integer=True))

#: Strategy name -> parameter -> :class:`Bound`.
STRATEGY_BOUNDS: dict[str, dict[str, Bound]] = {
    "reciprocity": dict(eps=Bound(0, 1, none=True, lo_open=True, hi_open=True), area_tol=Bound(1e-3, 1e6, none=True, unit="cm²"),
                        extent_tol=Bound(1e-3, 1e4, none=True, unit="cm"), d=Bound(1e-3, 1e4, none=True, unit="cm"),
                        reach=Bound(0, 1e4, none=True, unit="cm"), tail_tol=Bound(0, 1, none=True),
                        sigma=Bound(1e-6, 1e6, words=("calibrated", "auto", "noise"), none=True),
                        max_steps=_STEPS, clearance=_CLEARANCE, strength=_STRENGTH, h=_MESH_H,
                        solver=Bound(python=True), max_sources=Bound(1, MAX_SOURCES, integer=True, none=True),
                        more_tol=Bound(0, 1, lo_open=True, hi_open=True),
                        survey_travel=Bound(1e-3, 1e4, none=True, unit="cm"),
                        survey_reach=Bound(1e-3, 1e4, words=("reach",), unit="cm")),
    "gradient": dict(i_min=Bound(0, 1e6), i_max=Bound(0, 1e6, none=True), stop_radius=Bound(0, 1e4, unit="cm"),
                     d=Bound(1e-3, 1e4, unit="cm"), delta=Bound(1e-3, 1e3, unit="cm"),
                     step_max=Bound(1e-3, 1e4, unit="cm"), kappa=Bound(0, 1e6), max_steps=_STEPS,
                     clearance=_CLEARANCE, strength=_STRENGTH, h=_MESH_H, space=Bound(python=True),
                     stall_steps=Bound(0, 100_000, integer=True), stall_radius=Bound(0, 1e4, unit="cm")),
    "random-walk": dict(n_steps=_STEPS, step=Bound(1e-3, 1e4, unit="cm"), clearance=_CLEARANCE),
    "rbpf": _LATTICE_BELIEF,
    "rbpf-infotaxis": _LATTICE_BELIEF,
    "lattice-reciprocity": dict(strength=Bound(1e-6, 1e6, none=True), eta0=Bound(1e-6, 1e6),
                                theta0=Bound(1e-6, 1e6), slip=Bound(0, 1, none=True), n_particles=_PARTICLES,
                                support=Bound(0, 1), n_maps=Bound(1, 1000, integer=True)),
    "infotaxis": _PLUME_BELIEF,
    "free-energy": dict(_PLUME_BELIEF, alpha=Bound(0, 1e6), beta=Bound(0, 1e6), gamma=Bound(0, 1e6),
                        area_exponent=Bound(0, 10, lo_open=False)),
    "mapless-infotaxis": dict(_PLUME_BELIEF, extent=Bound(0, 1e4), temperature=Bound(0, 1e6)),
    "entrotaxis": _PLUME_BELIEF,
    "space-aware-infotaxis": _PLUME_BELIEF,
    "voi": dict(_PLUME_BELIEF, threshold=Bound(0, 1e6)),
    "lookahead": dict(_PLUME_BELIEF, depth=Bound(1, 3, integer=True), kappa=Bound(0, 1e6), power=Bound(0.1, 100),
                      second_kmax=Bound(1, 100, integer=True)),
    "arena-infotaxis": dict(step=Bound(1e-3, 1e4, unit="cm"), spacing=Bound(0.5, 100, unit="cm"),
                            support=Bound(1, 10_000, integer=True), confidence=Bound(0, 1),
                            radius=Bound(1e-3, 1e4, unit="cm"), sigma=Bound(1e-6, 1e6, words=("auto",)),
                            h=_MESH_H, max_steps=_STEPS),
    "plume-reciprocity": dict(h=Bound(0.1, 100), reach=Bound(0, 1e4), d=Bound(1e-3, 1e4, none=True)),
    "hmm": dict(eps_d=Bound(0, 1), eps_c=Bound(0, 1), horizon=Bound(1, 1000, integer=True), radius=Bound(0, 1e4),
                stop_mass=Bound(0, 1), period=Bound(1e-3, 1e4), min_time=Bound(0, 1e6), approach=Bound(0, 1)),
    "surge-cast": dict(surge_time=Bound(1e-3, 1e4), cast_leg=Bound(1e-3, 1e4), declare_time=Bound(0, 1e6)),
    "detection-infotaxis": dict(resolution=Bound(0.05, 100), period=Bound(1e-3, 1e4), lookahead=Bound(0, 1e4),
                                n_headings=Bound(1, 360, integer=True), found=Bound(0, 1e4), radius=Bound(0, 1e4),
                                stop_mass=Bound(0, 1), min_time=Bound(0, 1e6), temper=Bound(0, 1e6),
                                wind_window=Bound(0, 1e6), min_gain=Bound(0, 1e6),
                                min_hits=Bound(0, 1e6, integer=True), memory=Bound(0, 1e6, none=True),
                                overshoot=Bound(0, 1e4)),
}
