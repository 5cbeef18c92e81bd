"""The keys of several true sources, shared by every world kind: ``sources`` (replacing
``source``), ``strengths`` (one per source) and ``max_sources`` (the task's public bound).

Each kind checks where a source may lie (an arena's free region, a plume's area, a
lattice's transient nodes) through the ``place`` callable it passes; the rest (how many,
distinct, consistent with ``source``, one strength each, the bound) is checked here, with
one ``error:`` line naming the key, the value and what is allowed.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import SearchError
from ..outcome import MAX_SOURCES
from ..validation import number, whole

__all__ = ["source_list", "source_strengths", "source_clearance", "MAX_SOURCE_CLEARANCE"]

#: Largest ``source_clearance`` (cm).
MAX_SOURCE_CLEARANCE = 1000.0


def source_list(params: dict, place: Callable, *, prefix: str = "", what: str = "points",
                single: str = "strength") -> list | None:
    """The ``sources`` key of `params` as a list of distinct places, or None.

    Parameters
    ----------
    params : dict
        The world's parameters as given.
    place : callable
        ``place(value, key)``: one source as the kind stores it (a point, a node index),
        raising SearchError naming `key` when it is not a valid place.
    prefix : str
        Put before every key in messages (e.g. ``"plume "``).
    what : str
        What a source is, in messages (``"points"``, ``"lattice nodes"``).
    single : str
        The key a single source's strength takes, in messages.

    Raises
    ------
    SearchError
        ``strengths`` without ``sources``; not a list of 1 to MAX_SOURCES; a place that
        is invalid or repeats an earlier one; a ``source`` that is not the first.
    """
    sources = params.get("sources")
    if sources is None:
        if params.get("strengths") is not None:
            raise SearchError(f"{prefix}strengths {params['strengths']!r} needs sources: [[x, y], ...] (one per "
                              f"source); a single source takes {single}")
        return None
    if not isinstance(sources, (list, tuple)) or not 1 <= len(sources) <= MAX_SOURCES:
        raise SearchError(f"{prefix}sources must be a list of 1 to {MAX_SOURCES} {what} [[x, y], ...]; "
                          f"got {sources!r}")
    places = [place(q, f"{prefix}sources[{i}]") for i, q in enumerate(sources)]
    for i, q in enumerate(places):
        if any(np.array_equal(q, o) for o in places[:i]):
            raise SearchError(f"{prefix}sources[{i}] {sources[i]!r} repeats an earlier source; sources must be "
                              "distinct")
    one = params.get("source")
    if one is not None:
        try:
            same = np.array_equal(place(one, f"{prefix}source"), places[0])
        except SearchError:
            same = False
        if not same:
            raise SearchError(f"{prefix}source {one!r} is not the first of sources {sources!r}; give either source "
                              "(one source) or sources (several), not both")
    return places


def source_strengths(params: dict, sources: list | None, default: float, strength: Callable, *,
                     prefix: str = "", each: str = "strength") -> dict:
    """``sources``, ``strengths`` and ``max_sources`` checked: the world's parameters.

    Parameters
    ----------
    params : dict
        The world's parameters as given.
    sources : list or None
        :func:`source_list`'s result.
    default : float
        Every source's strength when ``strengths`` is not given (the nominal one).
    strength : callable
        ``strength(value, key) -> float``: one strength checked (its bounds are the kind's).
    prefix : str
        Put before every key in messages.
    each : str
        What one strength is, in messages (``"release rate"``).

    Returns
    -------
    dict
        ``sources`` and ``strengths`` (None for a single source) and ``max_sources``,
        kept as given (None: the world's default, 1 for one source and MAX_SOURCES for
        several, so that replacing one source by several keeps the default).
    """
    given = params.get("max_sources")
    bound = None if given is None else whole(given, f"{prefix}max_sources", 1, MAX_SOURCES)
    if sources is None:
        return {"sources": None, "strengths": None, "max_sources": bound}
    values = params.get("strengths")
    if values is None:
        values = [default] * len(sources)
    elif not isinstance(values, (list, tuple)) or len(values) != len(sources):
        raise SearchError(f"{prefix}strengths must give one {each} per source ({len(sources)}); got {values!r}")
    values = [strength(c, f"{prefix}strengths[{i}]") for i, c in enumerate(values)]
    if bound is not None and bound < len(sources):
        raise SearchError(f"{prefix}max_sources ({bound}) is less than the number of sources ({len(sources)}); "
                          f"give max_sources from {len(sources)} to {MAX_SOURCES}")
    return {"sources": sources, "strengths": values, "max_sources": bound}


def source_clearance(params: dict, arena) -> float:
    """The ``source_clearance`` key of an arena world: the task's public statement that
    every true source lies at least this far (cm) from the walls. Not given, it is the
    arena's own (a generated arena's source was drawn 8 cm off the walls; a source the
    scenario replaces drops it), else 0: anywhere in the free region. A strategy may take
    it as its prior; the true sources must keep it.

    Parameters
    ----------
    params : dict
        The world's parameters as given.
    arena : arenas.Arena
        The scenario's arena, with its source (or the first of several) and the
        clearance it states.

    Returns
    -------
    float
        The clearance, cm.

    Raises
    ------
    SearchError
        Not a number in ``[0, MAX_SOURCE_CLEARANCE]``, or a true source nearer the walls.
    """
    clearance = number(params.get("source_clearance", arena.source_clearance), "source_clearance", 0.0,
                       MAX_SOURCE_CLEARANCE, unit="cm")
    if clearance > 0:
        given = params.get("sources")
        pts = np.array(given if given is not None else [arena.source], dtype=float).reshape(-1, 2)
        gap = arena.wall_distance(pts)
        if gap.min() < clearance - 1e-9:
            i = int(np.argmin(gap))
            key = f"sources[{i}]" if given is not None else "source"
            raise SearchError(f"source_clearance of {clearance:g} cm: {key} ({pts[i, 0]:g}, {pts[i, 1]:g}) lies "
                              f"{gap[i]:.3g} cm from the walls; give source_clearance <= {gap.min():.3g} cm or "
                              "move the source")
    return clearance
