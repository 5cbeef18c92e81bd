"""The ``map`` and ``lidar`` keys of a ``poisson`` scenario: what the strategy is told of
the walls, and the range sensor that shows it the rest.

``map: known`` (the default) tells the strategy the true walls, as before. ``map:
unknown`` tells it the outer boundary only; ``map: {known: FILE}`` tells it the boundary
and the obstacles of the arena file FILE (a partial map). Either gives the platform a
range sensor: ``lidar: {beams, range, noise}`` (cm), or, when the scenario names none,
:data:`~reciprocity.platforms.lidar.LIDAR_DEFAULTS` (64 beams, 40 cm, 0.5 cm noise):
without a sensor an unknown map would stay unknown.
"""

from __future__ import annotations

import arenas
from arenas import Arena, ArenaError

from ..errors import SearchError
from ..platforms.lidar import LIDAR_DEFAULTS, Lidar

__all__ = ["check_map", "check_lidar", "believed_arena", "MAP_FORMS"]

#: The forms of the ``map`` key, for messages.
MAP_FORMS = "known, unknown or {known: FILE} (a partial arena file)"


def check_map(value) -> str | dict:
    """The ``map`` key, checked: ``"known"``, ``"unknown"`` or ``{"known": Arena}`` (the
    partial map loaded and validated).

    Raises
    ------
    SearchError
        Any other value, or a partial map file that is missing or invalid.
    """
    if value is None or value in ("known", "unknown"):
        return value or "known"
    if isinstance(value, dict) and set(value) == {"known"}:
        part = value["known"]
        if isinstance(part, Arena):
            return {"known": part}
        if not isinstance(part, str):
            raise SearchError(f"map: known must name an arena file (a partial map); got {part!r}")
        try:
            return {"known": arenas.load(part)}
        except ArenaError as exc:
            raise SearchError(f"map: known {part!r}: {exc}") from None
    raise SearchError(f"map must be one of {MAP_FORMS}; got {value!r}")


def check_lidar(value, map_: str | dict) -> dict | None:
    """The ``lidar`` key, checked: ``{beams, range, noise}`` or None (no sensor). An
    unknown or partial map without one gets :data:`LIDAR_DEFAULTS`.

    Raises
    ------
    SearchError
        Not a mapping, an unknown key, or a value out of bounds (``beams`` a whole number
        >= 4, ``range`` > 0 cm, ``noise`` >= 0 cm).
    """
    if value is None:
        return None if map_ == "known" else dict(LIDAR_DEFAULTS)
    if isinstance(value, Lidar):
        return value.nominal()
    if not isinstance(value, dict):
        raise SearchError(f"lidar must be a mapping {{beams: N, range: CM, noise: CM}}; got {value!r}")
    unknown = set(value) - set(LIDAR_DEFAULTS)
    if unknown:
        raise SearchError(f"unknown lidar key(s) {', '.join(sorted(map(str, unknown)))}; choose from "
                          f"{', '.join(LIDAR_DEFAULTS)}")
    return Lidar.from_dict(value).nominal()


def believed_arena(arena: Arena, map_: str | dict) -> Arena | None:
    """The walls the strategy is told for `map_`: None (the true walls: ``known``), the
    boundary alone (``unknown``), or the boundary with the partial map's obstacles.

    Raises
    ------
    SearchError
        The partial map's obstacles do not fit in `arena`'s boundary.
    """
    if map_ == "known":
        return None
    obstacles = [] if map_ == "unknown" else map_["known"].obstacles
    try:
        return Arena.from_polygons(arena.boundary, obstacles, name=arena.name, strength=arena.strength)
    except ArenaError as exc:
        raise SearchError(f"map: the partial map does not fit arena {arena.name!r}: {exc}") from None
