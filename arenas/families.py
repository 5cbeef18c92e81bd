"""Generated arenas: families of random arenas, deterministic per (family, seed, size).

:func:`generate` draws one arena of a family from ``numpy.random.default_rng(seed)``;
:data:`FAMILIES` names the families. Every arena is valid by construction (the
:class:`~arenas.geometry.Arena` checks pass), its free region is one piece, and it is
reachable by the car: every door, gap and corridor is at least :data:`MIN_GAP` cm wide,
so the free region shrunk by ``MIN_GAP / 2`` cm (the car keeps 4 cm from the walls) is
still one piece, and the source and the start lie in it. Each arena carries a source and
a start pose drawn at least :data:`CLEARANCE` cm from every wall, so it runs as it is.

Difficulty is set by size keywords, each bounded (see :func:`generate`); the defaults
give arenas of the built-in ``paper`` arena's size (140 x 140 cm), so an episode costs
about the same. A text form, ``generate:FAMILY[:SEED[:KEY=VALUE,...]]``, is read by
:func:`from_text` (and by :func:`arenas.load`, hence ``reciprocity run --arena``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Integral, Real
from typing import Callable

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box
from shapely.ops import unary_union

from .errors import ArenaError
from .geometry import Arena

__all__ = ["FAMILIES", "MIN_GAP", "CLEARANCE", "MAX_GENERATED_VERTICES", "generate", "from_text",
           "size_keys", "PREFIX"]

#: Narrowest door, gap or corridor of any generated arena, cm (twice the car's 4 cm
#: clearance plus its 3.8 cm width and a margin: the car drives through every one).
MIN_GAP = 16.0
#: Least distance of the drawn source and start from every wall, cm.
CLEARANCE = 8.0
#: Most vertices of a generated arena's obstacles together.
MAX_GENERATED_VERTICES = 4000
#: Largest seed (``numpy.random.default_rng`` takes any non-negative integer; this keeps
#: names and files short).
MAX_SEED = 2 ** 63 - 1
#: The text form's prefix (:func:`from_text`).
PREFIX = "generate:"


@dataclass(frozen=True)
class _Knob:
    """One size keyword: its default, bounds and meaning."""

    default: float
    lo: float
    hi: float
    integer: bool = False
    doc: str = ""

    def allowed(self) -> str:
        kind = "an integer" if self.integer else "a number"
        return f"{kind} in [{self.lo:g}, {self.hi:g}]"


_SIDE = dict(width=_Knob(140.0, 60.0, 300.0, doc="outer width, cm"),
             height=_Knob(140.0, 60.0, 300.0, doc="outer height, cm"),
             wall=_Knob(6.0, 1.0, 20.0, doc="wall thickness, cm"))

#: The size keywords of each family (name -> _Knob).
_KNOBS: dict[str, dict[str, _Knob]] = {
    "rooms": {**_SIDE, "cols": _Knob(3, 1, 8, True, "rooms across"),
              "rows": _Knob(3, 1, 8, True, "rooms up"),
              "door": _Knob(22.0, MIN_GAP, 100.0, doc="door width, cm"),
              "loops": _Knob(0.25, 0.0, 1.0, doc="share of the walls not on the spanning tree that get a door too")},
    "spiral": {**_SIDE, "wall": _Knob(4.0, 1.0, 20.0, doc="wall thickness, cm"),
               "turns": _Knob(2, 1, 6, True, "full turns of the spiral wall")},
    "ring": {"radius": _Knob(70.0, 30.0, 150.0, doc="radius of the round arena, cm"),
             "wall": _Knob(4.0, 1.0, 20.0, doc="wall thickness, cm"),
             "rings": _Knob(2, 1, 6, True, "concentric C walls"),
             "gap": _Knob(22.0, MIN_GAP, 100.0, doc="opening of each C wall (chord), cm")},
    "pillars": {"width": _SIDE["width"], "height": _SIDE["height"], "pillars": _Knob(6, 0, 80, True, "pillars"),
                "pillar": _Knob(10.0, 2.0, 30.0, doc="pillar size, cm"),
                "notch": _Knob(0.4, 0.0, 0.6, doc="share of width and height cut from one corner "
                               "(an L-shaped hall); 0: a rectangle")},
    "maze": {**_SIDE, "wall": _Knob(4.0, 1.0, 20.0, doc="wall thickness, cm"),
             "cols": _Knob(4, 2, 12, True, "cells across"),
             "rows": _Knob(4, 2, 12, True, "cells up"),
             "loops": _Knob(0.0, 0.0, 1.0, doc="share of the remaining inner walls removed "
                            "(0: a perfect maze, one way between two cells)")},
    "office": {**_SIDE, "offices": _Knob(3, 1, 8, True, "offices on each side of the corridor"),
               "corridor": _Knob(24.0, MIN_GAP, 100.0, doc="corridor width, cm"),
               "door": _Knob(20.0, MIN_GAP, 100.0, doc="door width, cm")},
}

#: The families :func:`generate` draws from.
FAMILIES: tuple[str, ...] = tuple(_KNOBS)


def size_keys(family: str) -> dict[str, tuple[float, float, float, str]]:
    """The size keywords of `family`: name -> (default, low, high, meaning); lengths in cm."""
    return {k: (v.default, v.lo, v.hi, v.doc) for k, v in _knobs(family).items()}


def _knobs(family) -> dict[str, _Knob]:
    if not isinstance(family, str) or family not in _KNOBS:
        raise ArenaError(f"family: unknown arena family {family!r}; choose one of {', '.join(FAMILIES)}")
    return _KNOBS[family]


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, Integral) or not 0 <= int(seed) <= MAX_SEED:
        raise ArenaError(f"seed: must be an integer in [0, 2**63 - 1]; got {seed!r}")
    return int(seed)


def _sizes(family: str, size: dict) -> dict[str, float]:
    knobs = _knobs(family)
    unknown = sorted(set(size) - set(knobs))
    if unknown:
        raise ArenaError(f"{unknown[0]}: not a size key of the {family!r} family; allowed keys are "
                         f"{', '.join(knobs)}")
    out = {}
    for key, knob in knobs.items():
        value = size.get(key, knob.default)
        ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)) \
            and knob.lo <= float(value) <= knob.hi and (not knob.integer or float(value).is_integer())
        if not ok:
            raise ArenaError(f"{key}: {family!r} arenas take {knob.allowed()} ({knob.doc}); got {value!r}")
        out[key] = int(value) if knob.integer else float(value)
    return out


def _refuse(family: str, key: str, value, why: str) -> ArenaError:
    return ArenaError(f"{key}: {family!r} arenas cannot have {key}={value:g} with these sizes: {why}")


# ---------------------------------------------------------------------------- families
def _rect_walls(walls: list, holes: list, outer: Polygon) -> list[np.ndarray]:
    """Obstacles: the union of wall polygons minus door polygons, clipped to `outer`."""
    solid = unary_union(walls).difference(unary_union(holes)) if holes else unary_union(walls)
    solid = solid.intersection(outer)
    parts = getattr(solid, "geoms", [solid])
    return [np.asarray(p.exterior.coords)[:-1] for p in parts if p.geom_type == "Polygon" and p.area > 1e-6]


def _grid_lines(n: int, length: float) -> np.ndarray:
    return np.linspace(0.0, length, n + 1)


def _door(rng, lo: float, hi: float, door: float, margin: float) -> tuple[float, float]:
    """A door of width `door` at a random place on the span [lo, hi], `margin` from its ends."""
    c = rng.uniform(lo + margin + door / 2, hi - margin - door / 2)
    return c - door / 2, c + door / 2


def _rooms(rng, s: dict) -> tuple[np.ndarray, list]:
    w, h, t, door = s["width"], s["height"], s["wall"], s["door"]
    cols, rows = s["cols"], s["rows"]
    xs, ys = _grid_lines(cols, w), _grid_lines(rows, h)
    span = min(w / cols, h / rows) - t
    if span < door + 2 * t:
        key, n = ("cols", cols) if w / cols <= h / rows else ("rows", rows)
        raise _refuse("rooms", key, n, f"a room side of {span:.3g} cm leaves no room for a {door:g} cm door "
                      "and its frame; use fewer rooms, a narrower door or a larger arena")
    walls = [box(x - t / 2, 0, x + t / 2, h) for x in xs[1:-1]] + [box(0, y - t / 2, w, y + t / 2) for y in ys[1:-1]]
    # the walls between neighbouring rooms, a door in those of a random spanning tree and in a share of the rest
    edges = [((i, j), (i + 1, j)) for i in range(cols - 1) for j in range(rows)] + \
            [((i, j), (i, j + 1)) for i in range(cols) for j in range(rows - 1)]
    order = rng.permutation(len(edges))
    parent = {(i, j): (i, j) for i in range(cols) for j in range(rows)}

    def root(a):
        while parent[a] != a:
            a = parent[a]
        return a
    holes = []
    extra = rng.random(len(edges)) < s["loops"]
    for k in order:
        a, b = edges[k]
        ra, rb = root(a), root(b)
        if ra == rb and not extra[k]:
            continue
        parent[ra] = rb
        (i, j), (i2, j2) = a, b
        if i2 > i:          # a wall at x = xs[i + 1] between y = ys[j] and ys[j + 1]
            y0, y1 = _door(rng, ys[j], ys[j + 1], door, t)
            holes.append(box(xs[i + 1] - t, y0, xs[i + 1] + t, y1))
        else:
            x0, x1 = _door(rng, xs[i], xs[i + 1], door, t)
            holes.append(box(x0, ys[j + 1] - t, x1, ys[j + 1] + t))
    outer = box(0, 0, w, h)
    return np.asarray(outer.exterior.coords)[:-1], _rect_walls(walls, holes, outer)


def _spiral(rng, s: dict) -> tuple[np.ndarray, list]:
    w, h, t, turns = s["width"], s["height"], s["wall"], s["turns"]
    p = min(w, h) / (2 * turns + 2)           # pitch: corridor plus wall
    if p - t < MIN_GAP:
        most = max(int(min(w, h) / (MIN_GAP + t) / 2 - 1), 0)
        raise _refuse("spiral", "turns", turns, f"its corridors would be {p - t:.3g} cm wide, under the "
                      f"{MIN_GAP:g} cm minimum; at most {most} turns fit (or enlarge the arena, thin the wall)")
    corner = int(rng.integers(4))             # which outer wall the spiral hangs from
    pts = [(p, 0.0)]
    for i in range(turns):
        lo, top, right, bottom = (i + 1) * p, h - (i + 1) * p, w - (i + 1) * p, (i + 1) * p
        pts += [(lo, top), (right, top), (right, bottom), (lo + p, bottom)]
    wall = LineString(pts).buffer(t / 2, cap_style="flat", join_style="mitre")
    wall = unary_union([wall, box(p - t / 2, 0, p + t / 2, t)])     # the foot meets the outer wall flush
    wall = _turn(wall, corner, w, h)
    outer = box(0, 0, w, h)
    return np.asarray(outer.exterior.coords)[:-1], _rect_walls([wall], [], outer)


def _turn(geom, k: int, w: float, h: float):
    """`geom` turned by ``k`` quarter turns about the centre of the w x h box (square boxes),
    or mirrored (others), so that the seed varies which wall a spiral hangs from."""
    if w == h:
        return shapely.affinity.rotate(geom, 90 * k, origin=(w / 2, h / 2))
    xf = -1 if k & 1 else 1
    yf = -1 if k & 2 else 1
    return shapely.affinity.scale(geom, xf, yf, origin=(w / 2, h / 2))


def _ring(rng, s: dict) -> tuple[np.ndarray, list]:
    r, t, n, gap = s["radius"], s["wall"], s["rings"], s["gap"]
    pitch = r / (n + 1)
    if pitch - t < MIN_GAP:
        most = max(int(r / (MIN_GAP + t)) - 1, 0)
        raise _refuse("ring", "rings", n, f"the passages between rings would be {pitch - t:.3g} cm wide, under "
                      f"the {MIN_GAP:g} cm minimum; at most {most} rings fit (or enlarge the radius, thin the wall)")
    if gap >= 2 * (pitch - t / 2):
        raise _refuse("ring", "gap", gap, f"the innermost C wall (radius {pitch:.3g} cm) is too small for it; "
                      f"use a gap under {2 * (pitch - t / 2):.3g} cm")
    obstacles = []
    for i in range(n):
        rad = (i + 1) * pitch
        half = math.asin(gap / (2 * (rad - t / 2)))        # the chord at the inner face is `gap`
        a0 = rng.uniform(0, 2 * math.pi)
        sweep = 2 * math.pi - 2 * half
        m = max(int(math.degrees(sweep) / 4), 8)            # a vertex every 4 degrees or so
        a = a0 + half + np.linspace(0.0, sweep, m + 1)
        ring = np.concatenate([np.column_stack([(rad + t / 2) * np.cos(a), (rad + t / 2) * np.sin(a)]),
                               np.column_stack([(rad - t / 2) * np.cos(a[::-1]), (rad - t / 2) * np.sin(a[::-1])])])
        obstacles.append(ring + r)
    return None, obstacles


def _pillars(rng, s: dict) -> tuple[np.ndarray, list]:
    w, h, size, n = s["width"], s["height"], s["pillar"], s["pillars"]
    cut = s["notch"]
    cx, cy = w * (1 - cut), h * (1 - cut)
    if cut > 0 and min(w - cx, h - cy, cx, cy) < MIN_GAP:
        raise _refuse("pillars", "notch", cut, "the cut corner leaves an arm under the "
                      f"{MIN_GAP:g} cm minimum; choose a notch of 0 or one that leaves both arms wider")
    outer = box(0, 0, w, h) if cut == 0 else Polygon([(0, 0), (w, 0), (w, cy), (cx, cy), (cx, h), (0, h)])
    outer = _turn(outer, int(rng.integers(4)), w, h)
    room = outer.buffer(-MIN_GAP)             # pillar centres keep MIN_GAP + size / 2 from the walls
    placed: list = []
    x0, y0, x1, y1 = room.bounds if not room.is_empty else (0, 0, 0, 0)
    for _ in range(100 * n + 200 if not room.is_empty else 0):
        if len(placed) == n:
            break
        c = rng.uniform((x0, y0), (x1, y1))
        poly = shapely.affinity.rotate(box(*(c - size / 2), *(c + size / 2)), rng.uniform(0, 90),
                                       origin=tuple(c))
        if room.contains(poly) and all(poly.distance(q) >= MIN_GAP for q in placed):
            placed.append(poly)
    if len(placed) < n:
        raise _refuse("pillars", "pillars", n, f"only {len(placed)} pillars of {size:g} cm fit {MIN_GAP:g} cm "
                      "apart and from the walls; use fewer or smaller pillars or a larger hall")
    return np.asarray(shapely.geometry.polygon.orient(outer).exterior.coords)[:-1], \
        [np.asarray(q.exterior.coords)[:-1] for q in placed]


def _maze(rng, s: dict) -> tuple[np.ndarray, list]:
    w, h, t, cols, rows = s["width"], s["height"], s["wall"], s["cols"], s["rows"]
    if min(w / cols, h / rows) - t < MIN_GAP:
        key, n = ("cols", cols) if w / cols <= h / rows else ("rows", rows)
        raise _refuse("maze", key, n, f"its corridors would be {min(w / cols, h / rows) - t:.3g} cm wide, under "
                      f"the {MIN_GAP:g} cm minimum; use fewer cells, a thinner wall or a larger arena")
    xs, ys = _grid_lines(cols, w), _grid_lines(rows, h)
    # a perfect maze by a random depth-first walk over the cells; walls[(a, b)] stands between cells a, b
    walls = {((i, j), (i + 1, j)) for i in range(cols - 1) for j in range(rows)} | \
            {((i, j), (i, j + 1)) for i in range(cols) for j in range(rows - 1)}
    seen, stack = {(0, 0)}, [(0, 0)]
    while stack:
        i, j = stack[-1]
        nxt = [(a, b) for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
               if 0 <= a < cols and 0 <= b < rows and (a, b) not in seen]
        if not nxt:
            stack.pop()
            continue
        c = nxt[int(rng.integers(len(nxt)))]
        walls.discard(tuple(sorted([(i, j), c])))
        seen.add(c)
        stack.append(c)
    left = sorted(walls)
    keep = rng.random(len(left)) >= s["loops"]
    rects = []
    for ((i, j), (i2, j2)), k in zip(left, keep):
        if not k:
            continue
        if i2 > i:
            rects.append(box(xs[i + 1] - t / 2, ys[j] - t / 2, xs[i + 1] + t / 2, ys[j + 1] + t / 2))
        else:
            rects.append(box(xs[i] - t / 2, ys[j + 1] - t / 2, xs[i + 1] + t / 2, ys[j + 1] + t / 2))
    outer = box(0, 0, w, h)
    return np.asarray(outer.exterior.coords)[:-1], _rect_walls(rects, [], outer) if rects else []


def _office(rng, s: dict) -> tuple[np.ndarray, list]:
    w, h, t, n, c, door = s["width"], s["height"], s["wall"], s["offices"], s["corridor"], s["door"]
    vertical = bool(rng.integers(2))          # the corridor runs across (x) or up (y)
    length, depth = (h, w) if vertical else (w, h)
    office = length / n - t
    side = (depth - c) / 2 - t
    if office < door + 2 * t or side < MIN_GAP:
        key, val = ("offices", n) if office < door + 2 * t else ("corridor", c)
        raise _refuse("office", key, val, f"offices of {office:.3g} x {side:.3g} cm leave no room for a "
                      f"{door:g} cm door or a {MIN_GAP:g} cm passage; use fewer offices, a narrower "
                      "corridor or door, or a larger arena")
    mid = rng.uniform(depth / 2 - 0.15 * side, depth / 2 + 0.15 * side)   # the corridor's centre line
    lo_wall, hi_wall = mid - c / 2 - t / 2, mid + c / 2 + t / 2
    widths = rng.uniform(0.8, 1.2, n)                      # office widths vary by +-20 %
    widths = widths / widths.sum() * length
    if widths.min() - t < door + 2 * t:
        widths = np.full(n, length / n)
    xs = np.concatenate([[0.0], np.cumsum(widths)])
    walls = [box(0, lo_wall - t / 2, length, lo_wall + t / 2), box(0, hi_wall - t / 2, length, hi_wall + t / 2)]
    walls += [box(x - t / 2, 0, x + t / 2, lo_wall) for x in xs[1:-1]]
    walls += [box(x - t / 2, hi_wall, x + t / 2, depth) for x in xs[1:-1]]
    holes = []
    for k in range(n):
        for y in (lo_wall, hi_wall):
            d0, d1 = _door(rng, xs[k], xs[k + 1], door, t)
            holes.append(box(d0, y - t, d1, y + t))
    outer = box(0, 0, length, depth)
    obstacles = _rect_walls(walls, holes, outer)
    if vertical:                              # swap x and y: the corridor runs up
        obstacles = [o[:, ::-1].copy() for o in obstacles]
    return np.asarray(box(0, 0, w, h).exterior.coords)[:-1], obstacles


_BUILD: dict[str, Callable] = {"rooms": _rooms, "spiral": _spiral, "ring": _ring, "pillars": _pillars,
                               "maze": _maze, "office": _office}


# ---------------------------------------------------------------------------- the door
def generate(family: str, seed: int, **size) -> Arena:
    """Draw an arena of `family`, deterministic per (family, seed, size).

    Parameters
    ----------
    family : str
        One of :data:`FAMILIES`:

        ``rooms``
            A grid of ``cols`` x ``rows`` rooms; a door of width ``door`` (cm) in the
            walls of a random spanning tree of the rooms (every room reachable, one way
            between two rooms), and in a share ``loops`` of the other walls.
        ``spiral``
            A square spiral wall of ``turns`` full turns hanging from one outer wall; its
            corridor is ``min(width, height) / (2 turns + 2) - wall`` wide.
        ``ring``
            A round arena of ``radius`` (cm) with ``rings`` concentric C walls, each open
            by a chord of ``gap`` (cm) at a random angle.
        ``pillars``
            A hall, L-shaped when ``notch > 0`` (that share of width and height cut from
            one corner), with ``pillars`` square pillars of side ``pillar`` (cm) at random
            places and angles, at least :data:`MIN_GAP` cm apart and from the walls
            (random trials, a bounded number: a count that does not fit is refused).
        ``maze``
            A maze of ``cols`` x ``rows`` cells by a random depth-first walk (a perfect
            maze), with a share ``loops`` of its inner walls removed.
        ``office``
            An office floor: a corridor of width ``corridor`` (cm) through the middle,
            across or up, with ``offices`` offices on each side, each with a door of
            width ``door`` (cm) to the corridor.
    seed : int
        Seed of ``numpy.random.default_rng``, from 0 to 2**63 - 1.
    **size
        The family's size keywords (:func:`size_keys` lists them with their bounds):
        ``width``, ``height`` (cm, 140 by default; ``radius`` for rings), ``wall``
        (thickness, cm), and the family's own above. Lengths in cm.

    Returns
    -------
    Arena
        Named ``FAMILY-SEED`` (with the size keys given, e.g. ``rooms-3-cols4``), with a
        source and a start pose (uniform heading) drawn at least :data:`CLEARANCE` cm
        from the walls, the start at least 0.35 of the diagonal from the source when
        possible.

    Raises
    ------
    ArenaError
        Unknown family, a seed that is not an integer in [0, 2**63 - 1], an unknown size
        key, or a value out of its bounds or that does not fit the others (too many
        rooms for the width, ...); the message names the key, the value and what is
        allowed.

    Notes
    -----
    Difficulty grows with the number of rooms, cells, turns, rings and pillars (longer
    detours, more walls between the start and the source), with narrower doors, gaps
    and corridors (down to :data:`MIN_GAP`), and, for ``rooms`` and ``maze``, with fewer
    ``loops`` (one way only). Every door, gap and corridor is at least :data:`MIN_GAP`
    cm wide: the free region shrunk by ``MIN_GAP / 2`` cm is one piece and holds the
    source and the start, so the car (4 cm clearance) reaches every place the source
    may be.

    Examples
    --------
    >>> import arenas
    >>> a = arenas.generate("rooms", 3)
    >>> a.name, a.bounds
    ('rooms-3', ((0.0, 140.0), (0.0, 140.0)))
    >>> bool(a.contains(a.source, clearance=8.0)[0]), a.source_clearance
    (True, 8.0)
    """
    knobs = _knobs(family)
    seed = _check_seed(seed)
    s = _sizes(family, size)
    rng = np.random.default_rng(seed)
    boundary, obstacles = _BUILD[family](rng, s)
    n = sum(len(o) for o in obstacles)
    if n > MAX_GENERATED_VERTICES:      # unreachable within the bounds above; a guard for new families
        raise ArenaError(f"{family}: {n} obstacle vertices, more than {MAX_GENERATED_VERTICES}; use smaller sizes")
    tag = "".join(f"-{k}{_short(s[k])}" for k in knobs if k in size)
    name = f"{family}-{seed}{tag}"
    if boundary is None:
        arena = Arena.disk((s["radius"], s["radius"]), s["radius"], obstacles, name=name, n_boundary=256)
    else:
        arena = Arena.from_polygons(boundary, obstacles, name=name)
    _check_reachable(arena, family)
    source, start = _source_and_start(arena, rng)
    return arena.with_scenario(source=source, start=start, source_clearance=CLEARANCE)


def _short(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def _core(arena: Arena):
    """The free region shrunk by ``MIN_GAP / 2`` (a hair less, for rounding)."""
    return arena.free_region.buffer(-(MIN_GAP / 2 - 0.01), quad_segs=4)


def _check_reachable(arena: Arena, family: str) -> None:
    core = _core(arena)
    if core.geom_type != "Polygon":     # a guard: the constructions above keep every gap >= MIN_GAP
        raise ArenaError(f"{family}: a gap under {MIN_GAP:g} cm in {arena.name!r}; use smaller sizes")


def _source_and_start(arena: Arena, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    source = arena.random_free_points(1, rng, clearance=CLEARANCE)[0]
    cand = arena.random_free_points(32, rng, clearance=CLEARANCE)
    (x0, x1), (y0, y1) = arena.bounds
    far = np.hypot(*(cand - source).T) >= 0.35 * math.hypot(x1 - x0, y1 - y0)
    xy = cand[int(np.argmax(far))] if far.any() else cand[int(np.argmax(np.hypot(*(cand - source).T)))]
    return source, np.array([xy[0], xy[1], rng.uniform(0.0, 2 * math.pi)])


def from_text(text: str) -> Arena:
    """The arena of ``generate:FAMILY[:SEED[:KEY=VALUE,...]]`` (seed 0 by default).

    Examples: ``generate:rooms:3``, ``generate:maze:7:cols=6,rows=6``.

    Raises
    ------
    ArenaError
        A malformed text, or what :func:`generate` refuses.
    """
    parts = str(text).removeprefix(PREFIX).split(":")
    if len(parts) > 3 or not parts[0]:
        raise ArenaError(f"arena {text!r}: write generate:FAMILY[:SEED[:KEY=VALUE,...]] with FAMILY one of "
                         f"{', '.join(FAMILIES)}")
    family = parts[0]
    _knobs(family)
    seed = _int_text(parts[1], "seed", text) if len(parts) > 1 else 0
    size = {}
    for item in (parts[2].split(",") if len(parts) > 2 and parts[2] else []):
        key, eq, value = item.partition("=")
        if not eq:
            raise ArenaError(f"arena {text!r}: size {item!r} must be KEY=VALUE with KEY one of "
                             f"{', '.join(_knobs(family))}")
        size[key.strip()] = _number_text(value)
    return generate(family, seed, **size)


def _int_text(value: str, key: str, text: str) -> int:
    try:
        return int(value)
    except ValueError:
        raise ArenaError(f"{key}: must be an integer in [0, 2**63 - 1]; got {value!r} in {text!r}") from None


def _number_text(value: str):
    try:
        v = float(value)
    except ValueError:
        v = value                       # generate() names the key and its bounds
    return int(v) if isinstance(v, float) and v.is_integer() else v


def from_mapping(spec: dict, where: str = "arena") -> Arena:
    """The arena of a file's ``{generate: FAMILY, seed: N, KEY: VALUE, ...}`` (seed 0 by default)."""
    spec = dict(spec)
    family = spec.pop("generate")
    seed = spec.pop("seed", 0)
    try:
        return generate(family, seed, **{str(k): v for k, v in spec.items()})
    except ArenaError as exc:
        raise ArenaError(f"{where}: {exc}") from None
