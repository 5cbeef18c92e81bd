"""The ``flow`` world kind of scenario files: a gas source in wind among walls.

Parameters (``arena``, ``inflow`` and ``outflow`` required)::

    arena: paper                  # a built-in name, a file, or {generate: FAMILY, seed: N}
    source: [56, 60]              # the true source, cm (default: the arena's)
    inflow: [[[0, 10], [0, 130]]]     # segments of the outer boundary where the wind enters, cm
    outflow: [[[140, 10], [140, 130]]]  # ... and where it leaves
    speed: 1                      # inflow speed, cm/s
    D: 5                          # diffusivity, cm²/s
    tau: 60                       # lifetime of the substance, s
    walls: impermeable            # impermeable | absorbing
    strength: 100                 # release rate q, particles/s
    detector: 1                   # capture rate k of the detector, cm²/s (hits/s per particle/cm²)
    truth_h: 0.5                  # mesh size of the truth's own solver, cm
    mismatch: {wind_factor: 1.2}  # wind_factor, diffusivity_factor, tau_factor, strength_factor,
                                  # inflow, outflow (the true segments)

A reading is a Poisson count of mean ``k q c(z; x_s) dwell`` (:mod:`reciprocity.worlds.flow`);
the point observer reads for its ``dwell`` (platform option, default 1 s).
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from arenas import Arena, ArenaError

from ..errors import ReciprocityError, SearchError
from ..fem.advection import WALL_KINDS
from ..fem.wind import boundary_segments
from ..models.flow import FlowParams, segments_tuple
from ..scenarios import WorldKind, check_keys, register_world
from ..validation import Bound, point
from ..worlds.flow import TRUTH_H, FlowMismatch, FlowWorld
from .arena import check_start, default_start, scenario_arena
from .sources import source_clearance

__all__ = ["FLOW", "FLOW_KEYS", "params_of"]

#: Parameters of a ``flow`` scenario.
FLOW_KEYS = ("arena", "source", "inflow", "outflow", "speed", "D", "tau", "walls", "strength", "detector",
             "truth_h", "mismatch", "source_clearance")
#: Bounds of the numeric parameters (cm, s): the plume then stays longer than a tenth of a
#: millimetre and the counts countable.
BOUNDS = {
    "speed": Bound(0.0, 1e3, unit="cm/s", lo_open=True), "D": Bound(1e-3, 1e4, unit="cm²/s"),
    "tau": Bound(1e-3, 1e6, unit="s"), "strength": Bound(0.0, 1e9, unit="particles/s", lo_open=True),
    "detector": Bound(0.0, 1e6, unit="cm²/s", lo_open=True), "truth_h": Bound(0.1, 10.0, unit="cm"),
}
DEFAULTS = dict(speed=1.0, D=5.0, tau=60.0, strength=100.0, detector=1.0, truth_h=TRUTH_H)
#: Bounds of the mismatch factors.
FACTOR = Bound(1e-3, 1e3, lo_open=False)
#: Most triangles of the truth's mesh (its P1 advection operator and the P2 potential of
#: its wind are then a few hundred MB).
MAX_TRUTH_TRIANGLES = 600_000


def _arena(params: dict) -> Arena:
    try:
        arena = scenario_arena(params.get("arena"), "flow")
        source = params.get("source")
        if source is not None:
            source = point(source, "source")
        arena = arena.with_scenario(source=source)       # the release rate is the world's, not the arena's
    except ArenaError as exc:
        raise SearchError(str(exc)) from None
    if arena.source is None:
        raise SearchError(f"arena {arena.name!r} has no source: give source: [x, y]")
    return arena


def _segments(arena: Arena, inflow, outflow, where: str = "") -> tuple[tuple, tuple]:
    for key, value in (("inflow", inflow), ("outflow", outflow)):
        if value is None:
            raise SearchError(f"a flow scenario needs {where}{key}: a list of boundary segments "
                              "[[[x0, y0], [x1, y1]], ...] in cm")
    try:
        seg_in, seg_out = boundary_segments(arena, inflow, outflow)
    except ReciprocityError as exc:
        raise SearchError(f"{where}{exc}") from None
    return segments_tuple(seg_in), segments_tuple(seg_out)


def _mismatch(value, arena: Arena) -> FlowMismatch:
    if isinstance(value, FlowMismatch):
        return value
    if value is None:
        return FlowMismatch()
    names = [f.name for f in fields(FlowMismatch)]
    if not isinstance(value, dict):
        raise SearchError(f"flow mismatch must be a mapping of {', '.join(names)}; got {value!r}")
    check_keys(value, names, "flow mismatch option")
    out = {k: float(FACTOR.check(v, f"mismatch {k}")) for k, v in value.items() if k.endswith("_factor")}
    if "inflow" in value or "outflow" in value:
        # the true segments: both given, or one with the nominal other (checked together below)
        out["inflow"], out["outflow"] = value.get("inflow"), value.get("outflow")
    return FlowMismatch(**out)


def _check(params: dict) -> dict:
    check_keys(params, FLOW_KEYS, "flow world parameter")
    out = dict(params)
    arena = _arena(params)
    out["arena"] = arena
    out["source"] = arena.source.tolist()
    out["source_clearance"] = source_clearance(params, arena)
    for key, bound in BOUNDS.items():
        out[key] = float(bound.check(params.get(key, DEFAULTS[key]), key))
    walls = params.get("walls", "impermeable")
    if walls not in WALL_KINDS:
        raise SearchError(f"walls must be one of {', '.join(WALL_KINDS)}; got {walls!r}")
    out["walls"] = walls
    out["inflow"], out["outflow"] = _segments(arena, params.get("inflow"), params.get("outflow"))
    m = _mismatch(params.get("mismatch"), arena)
    if m.inflow is not None or m.outflow is not None:
        true_in, true_out = _segments(arena, m.inflow if m.inflow is not None else out["inflow"],
                                      m.outflow if m.outflow is not None else out["outflow"], "mismatch ")
        m = FlowMismatch(m.wind_factor, m.diffusivity_factor, m.tau_factor, m.strength_factor, true_in, true_out)
    out["mismatch"] = m
    h = out["truth_h"]
    triangles = arena.area / (0.3 * h * h)
    if triangles > MAX_TRUTH_TRIANGLES:
        least = (arena.area / (0.3 * MAX_TRUTH_TRIANGLES)) ** 0.5
        raise SearchError(f"truth_h of {h:g} cm would mesh arena {arena.name!r} with about {triangles:.2g} "
                          f"triangles (at most {MAX_TRUTH_TRIANGLES:.0e}); use truth_h >= {least:.3g} cm")
    return out


def params_of(params: dict) -> FlowParams:
    """The nominal physics of checked scenario parameters."""
    return FlowParams(params["inflow"], params["outflow"], params["speed"], params["D"], params["tau"],
                      params["walls"], params["strength"], params["detector"])


def _build(params: dict, rng: np.random.Generator) -> FlowWorld:
    return FlowWorld(params["arena"], params_of(params), mismatch=params["mismatch"], h=params["truth_h"],
                     source_clearance=params.get("source_clearance", 0.0))


def _point(world: FlowWorld, scenario, options: dict):
    from ..platforms.point import PointPlatform
    from ..spaces import mesh_space
    unknown = set(options) - {"dwell", "route_h"}
    if unknown:
        raise SearchError(f"unknown point-observer option(s) {', '.join(sorted(unknown))}; "
                          "choose from dwell, route_h")
    dwell = float(Bound(0.0, 1e4, unit="s", lo_open=True).check(options.get("dwell", 1.0), "dwell"))
    route_h = float(Bound(0.25, 20.0, unit="cm").check(options.get("route_h", 2.0), "route_h"))
    return PointPlatform(mesh_space(world.arena.without_scenario(), route_h), dwell=dwell)


FLOW = register_world(WorldKind("flow", _check, _build, {"point": _point}, default_start, check_start))
