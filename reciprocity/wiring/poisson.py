"""The ``poisson`` world kind of scenario files: parameters, world, platforms."""

from __future__ import annotations

import numpy as np

from arenas import Arena, ArenaError

from ..errors import SearchError
from ..scenarios import WorldKind, check_keys, register_world
from ..validation import number, point
from ..worlds.poisson import Mismatch, PoissonWorld, TRUTH_H, shifted_walls
from .arena import check_start, default_start, scenario_arena
from .sensing import believed_arena, check_lidar, check_map
from .sources import source_clearance, source_list, source_strengths

__all__ = ["POISSON", "POISSON_KEYS"]

#: Parameters of a ``poisson`` scenario.
POISSON_KEYS = ("arena", "source", "strength", "noise", "truth_h", "mismatch", "sources", "strengths",
                "max_sources", "map", "lidar", "source_clearance")
#: Largest sensor noise (standard deviation, signal units).
MAX_NOISE = 1e6
#: Most triangles of the truth's mesh (its quadratic elements then have about 2e6 unknowns,
#: a factorization of a few hundred MB).
MAX_TRUTH_TRIANGLES = 1_000_000


def _check(params: dict) -> dict:
    check_keys(params, POISSON_KEYS, "poisson world parameter")
    out = dict(params)
    try:
        arena = scenario_arena(params.get("arena"), "poisson")
        sources = source_list(params, point)
        source = params.get("source") if sources is None else sources[0]
        if source is not None:
            source = point(source, "source")
        arena = arena.with_scenario(source=source, strength=params.get("strength"))
    except ArenaError as exc:
        raise SearchError(str(exc)) from None
    if arena.source is None:
        raise SearchError(f"arena {arena.name!r} has no source: give source: [x, y]")
    out["arena"] = arena
    out["source"] = arena.source.tolist()
    out["strength"] = float(arena.strength)
    out.update(_several(params, sources, arena))
    out["source_clearance"] = source_clearance(params, arena)
    out["noise"] = number(params.get("noise", 12.0), "noise", 0.0, MAX_NOISE, unit="(signal units)")
    h = number(params.get("truth_h", TRUTH_H), "truth_h", 0.5, 10.0, unit="cm")
    triangles = arena.area / (0.65 * h * h)
    if triangles > MAX_TRUTH_TRIANGLES:
        least = (arena.area / (0.65 * MAX_TRUTH_TRIANGLES)) ** 0.5
        raise SearchError(f"truth_h of {h:g} cm would mesh arena {arena.name!r} with about {triangles:.2g} "
                          f"triangles (at most {MAX_TRUTH_TRIANGLES:.0e}); use truth_h >= {least:.3g} cm")
    out["truth_h"] = h
    m = params.get("mismatch") or {}
    if isinstance(m, Mismatch):
        m = m.__dict__
    if not isinstance(m, dict):
        raise SearchError(f"mismatch must be a mapping of options; got {m!r}")
    out["mismatch"] = Mismatch.from_dict(m)
    # the true walls must make a valid arena too (overlapping grown obstacles, a source
    # swallowed by one): refused here, before any episode, not in every episode
    shifted_walls(arena, out["mismatch"].wall_shift)
    out["map"] = check_map(params.get("map"))
    out["lidar"] = check_lidar(params.get("lidar"), out["map"])
    believed_arena(arena, out["map"])   # a partial map that does not fit is refused here
    return out


def _several(params: dict, sources: list | None, arena: Arena) -> dict:
    """``sources``, ``strengths`` and ``max_sources``, each source in `arena`'s free region
    and at least 1 cm from the others."""
    out = source_strengths(params, sources, float(arena.strength),
                           lambda c, key: number(c, key, 0.0, 1e9, lo_open=True), each="number")
    if sources is None:
        return out
    pts = np.array(sources, dtype=float)
    inside = arena.contains(pts)
    if not inside.all():
        i = int(np.argmin(inside))
        raise SearchError(f"sources[{i}] ({pts[i, 0]:g}, {pts[i, 1]:g}) cm is outside the free region of "
                          f"arena {arena.name!r} (outside the boundary or inside an obstacle)")
    gaps = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))[np.triu_indices(len(pts), 1)]
    if gaps.size and gaps.min() < 1.0:
        raise SearchError(f"two sources are {gaps.min():.3g} cm apart; sources must be at least 1 cm apart")
    out["sources"] = pts.tolist()
    return out


def _build(params: dict, rng: np.random.Generator) -> PoissonWorld:
    return PoissonWorld(params["arena"], noise=params["noise"], h=params["truth_h"],
                        mismatch=params["mismatch"], sources=params.get("sources"),
                        strengths=params.get("strengths"), max_sources=params.get("max_sources"),
                        believed=believed_arena(params["arena"], params.get("map", "known")),
                        lidar=params.get("lidar"), source_clearance=params.get("source_clearance", 0.0))


def _point(world: PoissonWorld, scenario, options: dict):
    from ..platforms.lidar import Lidar
    from ..platforms.point import PointPlatform
    from ..spaces import mesh_space
    unknown = set(options) - {"dwell", "route_h"}
    if unknown:
        raise SearchError(f"unknown point-observer option(s) {', '.join(sorted(unknown))}; "
                          "choose from dwell, route_h")
    space = mesh_space(world.true_arena.without_scenario(), float(options.get("route_h", world.h)))
    lidar = Lidar.from_dict(world.lidar) if world.lidar is not None else None
    return PointPlatform(space, dwell=float(options.get("dwell", 1.0)), lidar=lidar)


def _car(world: PoissonWorld, scenario, options: dict):
    from ..platforms.car import make_car_platform
    return make_car_platform(world, **options)


POISSON = register_world(WorldKind("poisson", _check, _build, {"point": _point, "car": _car},
                                   default_start, check_start))
