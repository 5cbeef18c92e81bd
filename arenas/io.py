"""Arena files (YAML) and the built-in arenas.

File format (all lengths in cm, the start heading in degrees)::

    name: paper                      # optional, defaults to the file stem
    boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]
    # or, instead of boundary, a circular domain:
    # disk: {center: [70, 70], radius: 70}
    obstacles:                       # optional list of simple polygons
      - [[20, 20], [40, 20], [40, 26], [20, 26]]
    source: [70.21, 70.21]           # optional true source position
    strength: 850                    # optional source strength c in (0, 1e6] (default 850)
    start: [128, 12, 135]            # optional start: x, y[, heading in degrees]
    source_clearance: 8              # optional: the source lies at least this far (cm) from the walls

Coordinates lie within ±1e5 cm, a disk radius in (0, 1e5] cm; an arena has at most 1000
obstacles and 20000 obstacle vertices. Files are read by the strict loader of :mod:`arenas.files`: safe YAML (no Python objects),
at most 1 MB of UTF-8 text, no duplicate keys, aliases capped.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import yaml

from .errors import ArenaError
from .files import load_yaml
from .families import PREFIX, from_mapping, from_text
from .geometry import DEFAULT_STRENGTH, MAX_COORD_CM, MAX_STRENGTH, Arena
from .poses import pose_from_degrees, pose_to_degrees

__all__ = ["load", "save", "builtin_names", "from_dict", "to_dict", "DEFAULT_STRENGTH"]

_KEYS = {"name", "boundary", "disk", "obstacles", "source", "strength", "start", "description",
         "source_clearance"}


def builtin_names() -> list[str]:
    """Names of the built-in arenas, sorted."""
    files = resources.files("arenas") / "data"
    return sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".yaml"))


def builtin_description(name: str) -> str:
    """The one-line ``description`` of a built-in arena."""
    data = _read_yaml(resources.files("arenas") / "data" / f"{name}.yaml", name)
    return str(data.get("description", ""))


def load(name_or_path) -> Arena:
    """Load a built-in arena by name, or an arena YAML file by path (an arena file, or a
    ROS ``map_server`` map, recognised by its keys: see :mod:`arenas.ros_map`).

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A name from :func:`builtin_names` (e.g. ``"paper"``), a generated arena
        ``generate:FAMILY[:SEED[:KEY=VALUE,...]]`` (:func:`arenas.families.from_text`), or
        a path to a YAML file (an arena file or a ROS map).

    Returns
    -------
    Arena

    Raises
    ------
    ArenaError
        Unknown name, unreadable or malformed file, or invalid geometry.

    Examples
    --------
    >>> import arenas
    >>> arenas.load("empty").area
    19600.0
    """
    text = str(name_or_path)
    if text.startswith(PREFIX):
        return from_text(text)
    if text in builtin_names():
        src = resources.files("arenas") / "data" / f"{text}.yaml"
        default_name = text
    else:
        src = Path(text)
        if not src.exists():
            raise ArenaError(
                f"no built-in arena or file named {text!r}; built-ins are "
                f"{', '.join(builtin_names())} (or give the path of a YAML arena file)")
        default_name = src.stem
    data = _read_yaml(src, text)
    if "image" in data and "resolution" in data:     # a ROS map_server map (ros_map.is_ros_map)
        from .ros_map import from_ros_map            # OpenCV, imported where a map is read
        if not isinstance(src, Path):
            raise ArenaError(f"built-in arena {text!r} cannot be a ROS map")
        return from_ros_map(data, src.parent, where=f"ROS map {text!r}", name=default_name)
    data.setdefault("name", default_name)
    return from_dict(data, where=text)


def _read_yaml(src, label: str) -> dict:
    data = load_yaml(src, f"arena file {label!r}")
    if not isinstance(data, dict):
        raise ArenaError(f"arena file {label!r} must hold a mapping with a 'boundary' or "
                         f"'disk' key; got {type(data).__name__}")
    return data


def _number(value, key: str, where: str, lo: float = -MAX_COORD_CM, hi: float = MAX_COORD_CM) -> float:
    """`value` as a float in ``[lo, hi]`` (coordinates by default), else ArenaError."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi:
        raise ArenaError(f"{where}: {key!r} must be a number in [{lo:g}, {hi:g}]; got {value!r}")
    return float(value)


def _coords(value, key: str, where: str, shape_hint: str) -> np.ndarray:
    def flat(v):
        return v if isinstance(v, list) else [v]
    items = value if isinstance(value, list) else None
    if items is None:
        raise ArenaError(f"{where}: {key!r} must be a list {shape_hint}; got {value!r}")
    for v in (x for it in items for x in flat(it)):
        _number(v, key, where)
    try:
        return np.asarray(items, dtype=float)
    except ValueError as exc:
        raise ArenaError(f"{where}: {key!r} must be a list {shape_hint}; got {value!r}") from exc


def from_dict(data: dict, where: str = "arena") -> Arena:
    """Build an :class:`Arena` from the mapping of an arena file (see module doc), or a
    generated one from ``{generate: FAMILY, seed: N, KEY: VALUE, ...}``
    (:func:`arenas.generate`)."""
    if "generate" in data:
        return from_mapping(data, where)
    unknown = set(data) - _KEYS
    if unknown:
        raise ArenaError(f"{where}: unknown key(s) {sorted(unknown)}; allowed keys are "
                         f"{sorted(_KEYS)}")
    if ("boundary" in data) == ("disk" in data):
        raise ArenaError(f"{where}: give exactly one of 'boundary' (a polygon) or 'disk' "
                         "({center: [x, y], radius: r})")
    obstacles = data.get("obstacles") or []
    if not isinstance(obstacles, list):
        raise ArenaError(f"{where}: 'obstacles' must be a list of polygons; got {obstacles!r}")
    if len(obstacles) > 1000:
        raise ArenaError(f"{where}: 'obstacles' lists {len(obstacles)} polygons; at most 1000 are allowed")
    obstacles = [_coords(o, f"obstacles[{i}]", where, "of [x, y] vertices")
                 for i, o in enumerate(obstacles)]
    strength = data.get("strength", DEFAULT_STRENGTH)
    if isinstance(strength, bool) or not isinstance(strength, (int, float)) or not 0 < strength <= MAX_STRENGTH:
        raise ArenaError(f"{where}: 'strength' must be a number in (0, {MAX_STRENGTH:g}]; got {strength!r}")
    source = data.get("source")
    if source is not None:
        source = _coords(source, "source", where, "[x, y]")
        if source.shape != (2,):
            raise ArenaError(f"{where}: 'source' must be [x, y]; got {data['source']!r}")
    start = data.get("start")
    if start is not None:
        start = _coords(start, "start", where, "[x, y] or [x, y, heading_deg]")
        if start.shape not in [(2,), (3,)]:
            raise ArenaError(f"{where}: 'start' must be [x, y] or [x, y, heading_deg]; "
                             f"got {data['start']!r}")
        if start.shape == (3,):
            start = pose_from_degrees(start)
    name = str(data.get("name", "arena"))
    kw = dict(name=name, source=source, strength=strength, start=start)
    try:
        if "disk" in data:
            disk = data["disk"]
            if not isinstance(disk, dict) or set(disk) != {"center", "radius"}:
                raise ArenaError(f"{where}: 'disk' must be {{center: [x, y], radius: r}}; "
                                 f"got {disk!r}")
            center = _coords(disk["center"], "disk.center", where, "[x, y]")
            radius = _number(disk["radius"], "disk.radius", where, 0.0, MAX_COORD_CM)
            arena = Arena.disk(center, radius, obstacles, **kw)
            if "source_clearance" in data:
                arena = arena.with_scenario(source_clearance=data["source_clearance"])
            return arena
        boundary = _coords(data["boundary"], "boundary", where, "of [x, y] vertices")
        arena = Arena.from_polygons(boundary, obstacles, **kw)
        if "source_clearance" in data:
            arena = arena.with_scenario(source_clearance=data["source_clearance"])
        return arena
    except ArenaError as exc:
        if str(exc).startswith(where):
            raise
        raise ArenaError(f"{where}: {exc}") from None


def to_dict(arena: Arena) -> dict:
    """The arena-file mapping of `arena` (inverse of :func:`from_dict`)."""
    out: dict = {"name": arena.name}
    if arena.circle is not None:
        cx, cy, r = arena.circle
        out["disk"] = {"center": [cx, cy], "radius": r}
    else:
        out["boundary"] = arena.boundary.tolist()
    out["obstacles"] = [o.tolist() for o in arena.obstacles]
    if arena.source is not None:
        out["source"] = [float(v) for v in arena.source]
    out["strength"] = float(arena.strength)
    if arena.start is not None:
        out["start"] = pose_to_degrees(arena.start)
    if arena.source_clearance > 0:
        out["source_clearance"] = float(arena.source_clearance)
    return out


def save(arena: Arena, path) -> Path:
    """Write `arena` as a YAML arena file; return the path."""
    path = Path(path)
    path.write_text(yaml.safe_dump(to_dict(arena), sort_keys=False))
    return path
