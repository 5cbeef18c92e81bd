"""The ``filament`` world kind of scenario files: parameters, world, walker platform."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from ..errors import SearchError
from ..scenarios import WorldKind, check_keys, register_world
from .filament import FilamentParams, FilamentWorld

__all__ = ["FILAMENT", "FILAMENT_KEYS", "filament_params", "source_cell"]

#: Parameters of a ``filament`` scenario (besides the common keys).
FILAMENT_KEYS = tuple(f.name for f in fields(FilamentParams)) + ("cells", "speed")

_POSITIVE = ("release_rate", "puff_mass", "puff_sigma0", "threshold", "sampling_rate", "wind_tau",
             "wind_scale")
_NON_NEGATIVE = ("puff_diffusivity", "centre_diffusivity", "wind_sigma", "spinup")


def _number(name, value, *, positive: bool) -> float:
    ok = not isinstance(value, bool) and isinstance(value, (int, float)) and np.isfinite(value)
    if not ok or (value <= 0 if positive else value < 0):
        what = "a positive" if positive else "a non-negative"
        raise SearchError(f"{name} must be {what} number; got {value!r}")
    return float(value)


def _pair(name, value) -> tuple:
    a = np.asarray(value, dtype=float) if isinstance(value, (list, tuple)) else None
    if a is None or a.shape != (2,) or not np.all(np.isfinite(a)):
        raise SearchError(f"{name} must be [x, y] (two numbers); got {value!r}")
    return tuple(float(v) for v in a)


def _check(params: dict) -> dict:
    check_keys(params, FILAMENT_KEYS, "filament world parameter")
    out = dict(params)
    d = FilamentParams()
    for k in _POSITIVE:
        out[k] = _number(k, params.get(k, getattr(d, k)), positive=True)
    for k in _NON_NEGATIVE:
        out[k] = _number(k, params.get(k, getattr(d, k)), positive=False)
    region = params.get("region", d.region)
    r = np.asarray(region, dtype=float) if isinstance(region, (list, tuple)) else None
    if r is None or r.shape != (4,) or not np.all(np.isfinite(r)) or r[1] <= r[0] or r[3] <= r[2]:
        raise SearchError(f"region must be [x_min, x_max, y_min, y_max] with x_min < x_max, "
                          f"y_min < y_max (m); got {region!r}")
    out["region"] = tuple(float(v) for v in r)
    out["source"] = _pair("source", params.get("source", d.source))
    sx, sy = out["source"]
    if not (r[0] < sx < r[1] and r[2] < sy < r[3]):
        raise SearchError(f"source {list(out['source'])} lies outside the region "
                          f"x in [{r[0]:g}, {r[1]:g}], y in [{r[2]:g}, {r[3]:g}]")
    out["wind_mean"] = _pair("wind_mean", params.get("wind_mean", d.wind_mean))
    modes = params.get("wind_modes", d.wind_modes)
    if isinstance(modes, bool) or not isinstance(modes, int) or not 0 <= modes <= 4:
        raise SearchError(f"wind_modes must be a whole number from 0 to 4; got {modes!r}")
    cells = params.get("cells", (40, 25))
    if (not isinstance(cells, (list, tuple)) or len(cells) != 2
            or any(isinstance(c, bool) or not isinstance(c, int) or c < 1 for c in cells)):
        raise SearchError(f"cells must be [m, n], two positive whole numbers (cells along x, y); got {cells!r}")
    out["cells"] = (int(cells[0]), int(cells[1]))
    out["speed"] = _number("speed", params.get("speed", 1.0), positive=True)
    return out


def filament_params(params: dict) -> FilamentParams:
    """The :class:`FilamentParams` of validated scenario parameters."""
    return FilamentParams(**{k: params[k] for k in (f.name for f in fields(FilamentParams)) if k in params})


def _build(params: dict, rng: np.random.Generator) -> FilamentWorld:
    return FilamentWorld(filament_params(params), cells=params["cells"], speed=params["speed"])


def source_cell(region, cells, point) -> int:
    """Index ``i + j m`` (0-based) of the cell of `point` in the region's ``m × n`` cells."""
    x0, x1, y0, y1 = region
    m, n = cells
    i = min(int((point[0] - x0) / (x1 - x0) * m), m - 1)
    j = min(int((point[1] - y0) / (y1 - y0) * n), n - 1)
    return i + j * m


def _default_start(world: FilamentWorld, rng: np.random.Generator) -> np.ndarray:
    """A uniformly random start in the region, at least 10 m from the source."""
    x0, x1, y0, y1 = world.p.region
    while True:
        p = rng.uniform([x0, y0], [x1, y1])
        if np.hypot(*(p - world.source)) >= 10.0:
            return np.array([p[0], p[1], 0.0])


def _walker(world: FilamentWorld, scenario, options: dict):
    from ..platforms.walker import WalkerPlatform
    unknown = set(options)
    if unknown:
        raise SearchError(f"unknown walker option(s) {', '.join(sorted(unknown))}; the filament walker takes none")
    if scenario is not None and scenario.starts is not None:
        k = source_cell(world.p.region, world.cells, world.source)
        for s in scenario.starts:
            if not world.contains(s[None, :2])[0]:
                raise SearchError(f"start ({s[0]:g}, {s[1]:g}) lies outside the region {list(world.p.region)}")
            if source_cell(world.p.region, world.cells, s[:2]) == k:
                raise SearchError(f"start ({s[0]:g}, {s[1]:g}) lies in the source's cell; start elsewhere")
    dt = 1.0 / world.p.sampling_rate
    return WalkerPlatform(None, max_step=world.speed * dt, dt=dt)


FILAMENT = register_world(WorldKind("filament", _check, _build, {"walker": _walker}, _default_start))
