"""The ``filament`` world kind of scenario files: parameters, world, walker platform."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from ..errors import SearchError
from ..scenarios import WorldKind, check_keys, register_world
from ..validation import MAX_COORD, Bound, point, starts_in_box, whole
from ..worlds.filament import FilamentParams, FilamentWorld

__all__ = ["FILAMENT", "FILAMENT_KEYS", "filament_params", "source_cell"]

#: Parameters of a ``filament`` scenario (besides the common keys).
FILAMENT_KEYS = tuple(f.name for f in fields(FilamentParams)) + ("cells", "speed")

#: Bounds of the numeric parameters (SI units: m, s, m/s): within them one episode stays
#: within seconds per simulated minute and a few hundred MB.
BOUNDS = {
    "release_rate": Bound(1e-6, 1000, unit="puffs/s"), "puff_mass": Bound(1e-9, 1e6),
    "puff_sigma0": Bound(1e-6, 100, unit="m"), "threshold": Bound(1e-12, 1e6),
    "sampling_rate": Bound(1e-3, 100, unit="Hz"), "wind_tau": Bound(1e-3, 1e4, unit="s"),
    "wind_scale": Bound(1e-3, 1e5, unit="m"), "puff_diffusivity": Bound(0, 100, unit="m²/s"),
    "centre_diffusivity": Bound(0, 100, unit="m²/s"), "wind_sigma": Bound(0, 100, unit="m/s"),
    "spinup": Bound(0, 3600, unit="s"), "speed": Bound(1e-6, 100, unit="m/s"),
}
#: Most steps of the spin-up (spinup × sampling_rate) and most puffs it releases.
MAX_SPINUP_STEPS, MAX_PUFFS = 100_000, 1_000_000
#: Most cells of the source map (the hidden-Markov map's transitions are cells × cells).
MAX_MAP_CELLS = 10_000
#: A default start keeps this far from the source, m.
START_DISTANCE = 10.0


def _pair(name, value, bound: float) -> tuple:
    return tuple(float(v) for v in point(value, name, bound=bound))


def _check(params: dict) -> dict:
    check_keys(params, FILAMENT_KEYS, "filament world parameter")
    out = dict(params)
    d = FilamentParams()
    for k, b in BOUNDS.items():
        out[k] = float(b.check(params.get(k, getattr(d, k, 1.0)), k))
    if out["spinup"] * out["sampling_rate"] > MAX_SPINUP_STEPS or out["spinup"] * out["release_rate"] > MAX_PUFFS:
        raise SearchError(f"spinup × sampling_rate must be at most {MAX_SPINUP_STEPS} steps and spinup × "
                          f"release_rate at most {MAX_PUFFS} puffs; got spinup {out['spinup']:g} s, sampling_rate "
                          f"{out['sampling_rate']:g} Hz, release_rate {out['release_rate']:g}/s")
    region = params.get("region", d.region)
    r = point(region, "region", size=4, bound=MAX_COORD) if isinstance(region, (list, tuple)) else None
    if r is None or r[1] <= r[0] or r[3] <= r[2]:
        raise SearchError(f"region must be [x_min, x_max, y_min, y_max] with x_min < x_max, "
                          f"y_min < y_max (m); got {region!r}")
    out["region"] = tuple(float(v) for v in r)
    out["source"] = _pair("source", params.get("source", d.source), MAX_COORD)
    sx, sy = out["source"]
    if not (r[0] < sx < r[1] and r[2] < sy < r[3]):
        raise SearchError(f"source {list(out['source'])} lies outside the region "
                          f"x in [{r[0]:g}, {r[1]:g}], y in [{r[2]:g}, {r[3]:g}]")
    out["wind_mean"] = _pair("wind_mean", params.get("wind_mean", d.wind_mean), 100.0)
    out["wind_modes"] = whole(params.get("wind_modes", d.wind_modes), "wind_modes", 0, 4)
    cells = params.get("cells", (40, 25))
    if (not isinstance(cells, (list, tuple)) or len(cells) != 2
            or any(isinstance(c, bool) or not isinstance(c, int) or c < 1 for c in cells)
            or cells[0] * cells[1] > MAX_MAP_CELLS):
        raise SearchError(f"cells must be [m, n], two positive whole numbers (cells along x, y) with "
                          f"m × n <= {MAX_MAP_CELLS}; got {cells!r}")
    out["cells"] = (int(cells[0]), int(cells[1]))
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
    far = max(np.hypot(cx - world.source[0], cy - world.source[1]) for cx in (x0, x1) for cy in (y0, y1))
    for _ in range(100_000 if far >= START_DISTANCE else 0):  # a tiny region has no room: no endless loop
        p = rng.uniform([x0, y0], [x1, y1])
        if np.hypot(*(p - world.source)) >= START_DISTANCE:
            return np.array([p[0], p[1], 0.0])
    raise SearchError(f"no start found {START_DISTANCE:g} m from the source in region {list(world.p.region)}; "
                      "give start: [x, y]")


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


def _check_start(params: dict, starts: np.ndarray) -> None:
    starts_in_box(starts, params["region"], "region")


FILAMENT = register_world(WorldKind("filament", _check, _build, {"walker": _walker}, _default_start,
                                    _check_start))
