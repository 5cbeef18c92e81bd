"""Arena geometry: an outer boundary with impassable obstacles, in cm."""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass, field
from numbers import Real
from functools import cached_property
from typing import Iterable

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon
from shapely.ops import unary_union
from shapely.validation import explain_validity

from .errors import ArenaError

__all__ = ["Arena", "as_points", "check_strength", "DEFAULT_STRENGTH", "MAX_COORD_CM", "MAX_STRENGTH",
           "MAX_VERTICES"]

#: Default source strength ``c``: puts the built-in arenas' signal on a 0-255 scale.
DEFAULT_STRENGTH = 850.0

#: Smallest admissible side of an arena or obstacle bounding box, cm.
MIN_SIZE_CM = 1e-3
#: Largest absolute coordinate of any point of an arena, cm (1 km: far beyond any testbed,
#: and far from where areas and distances overflow).
MAX_COORD_CM = 1e5
#: Largest source strength ``c`` (the built-in arenas use 850).
MAX_STRENGTH = 1e6
#: Most vertices of one polygon, and of all polygons of an arena together.
MAX_VERTICES = 20_000


def as_points(points, name: str = "points") -> np.ndarray:
    """Return `points` as a float array of shape (n, 2), or raise ArenaError.

    A single point ``(x, y)`` becomes shape (1, 2).
    """
    try:
        arr = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArenaError(f"{name} must be numbers of shape (n, 2); got {points!r}") from exc
    if arr.ndim == 1 and arr.shape[0] == 2:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ArenaError(f"{name} must have shape (n, 2) (x, y in cm); got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ArenaError(f"{name} contains NaN or infinite coordinates; give finite numbers in cm")
    if arr.size and np.abs(arr).max() > MAX_COORD_CM:
        raise ArenaError(f"{name} must lie within ±{MAX_COORD_CM:g} cm of the origin; got a coordinate "
                         f"of {np.abs(arr).max():g}")
    return arr


def _check_size(obstacles: list) -> None:
    """Refuse arenas whose obstacles have more than :data:`MAX_VERTICES` vertices together."""
    n = sum(len(o) for o in obstacles)
    if n > MAX_VERTICES:
        raise ArenaError(f"the obstacles have {n} vertices together; at most {MAX_VERTICES} are allowed")


def _polygon(vertices, what: str) -> np.ndarray:
    """Validate one simple polygon and return its vertices, (n, 2), counter-clockwise."""
    v = as_points(vertices, what)
    if len(v) > MAX_VERTICES:
        raise ArenaError(f"{what} has {len(v)} vertices; at most {MAX_VERTICES} are allowed")
    if len(v) > 1 and np.allclose(v[0], v[-1]):
        v = v[:-1]  # a repeated closing vertex is accepted and dropped
    if len(v) < 3:
        raise ArenaError(f"{what} needs at least 3 vertices; got {len(v)}")
    span = v.max(axis=0) - v.min(axis=0)
    if np.any(span < MIN_SIZE_CM):
        raise ArenaError(f"{what} is degenerate: its extent is {span[0]:.3g} x {span[1]:.3g} cm")
    ring = LinearRing(v)
    if not ring.is_simple:
        raise ArenaError(
            f"{what} intersects itself ({explain_validity(Polygon(v))}); "
            "list its vertices in order around the outline without crossing edges")
    if not ring.is_ccw:
        v = v[::-1].copy()
    return v


#: Geometries kept by :meth:`Arena.without_scenario`, least recently used dropped first
#: (believed arenas of an unknown map are new at every change; unbounded, a long
#: campaign kept every one).
GEOMETRY_CACHE_SIZE = 64
_GEOMETRY: OrderedDict = OrderedDict()


def _geometry_only(arena: "Arena") -> "Arena":
    key = (arena.name, arena.boundary.tobytes(), tuple(o.tobytes() for o in arena.obstacles),
           arena.circle)
    if key not in _GEOMETRY:
        _GEOMETRY[key] = Arena(arena.boundary, arena.obstacles, arena.name, None,
                               DEFAULT_STRENGTH, None, arena.circle)
        while len(_GEOMETRY) > GEOMETRY_CACHE_SIZE:
            _GEOMETRY.popitem(last=False)
    _GEOMETRY.move_to_end(key)
    return _GEOMETRY[key]


def check_strength(value, what: str = "strength") -> float:
    """`value` as a source strength c in (0, :data:`MAX_STRENGTH`] (ArenaError naming
    `what` otherwise): the one check of a strength given with an arena's scenario or on
    the command line (``--strength``)."""
    ok = isinstance(value, Real) and not isinstance(value, bool) and 0 < float(value) <= MAX_STRENGTH
    if not ok:
        raise ArenaError(f"{what} must be a number in (0, {MAX_STRENGTH:g}]; got {value!r}")
    return float(value)


@dataclass(frozen=True, eq=False)
class Arena:
    """A 2-D arena: the domain ``D`` minus impassable obstacles ``Omega``.

    Build one with :meth:`from_polygons`, :meth:`disk` or :func:`arenas.load`.

    Attributes
    ----------
    boundary : ndarray, shape (n, 2)
        Outer boundary polygon, counter-clockwise, in cm (for a disk, a fine polygon
        through points of the circle; the exact circle is in :attr:`circle`).
    obstacles : list of ndarray, shape (m, 2)
        Obstacle polygons, counter-clockwise, in cm. Non-convex allowed.
    name : str
        Name of the arena.
    source : ndarray, shape (2,), or None
        True source position (cm) when the arena file gives one.
    strength : float
        Source strength ``c`` of ``-Δu = c δ(x - S)`` (signal units times cm^0).
    start : ndarray, shape (3,), or None
        Start pose ``(x, y, heading)``: cm, cm, radians.
    circle : tuple (cx, cy, r) or None
        For :meth:`disk` arenas, the exact circle (cm).
    source_clearance : float
        How far (cm) from every wall the source was drawn at least, when the arena says so
        (a generated arena: :data:`arenas.families.CLEARANCE`); 0 says nothing. A public
        statement about where sources lie, which a search may take as its prior.
    """

    boundary: np.ndarray
    obstacles: list = field(default_factory=list)
    name: str = "arena"
    source: np.ndarray | None = None
    strength: float = DEFAULT_STRENGTH
    start: np.ndarray | None = None
    circle: tuple | None = None
    source_clearance: float = 0.0

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_polygons(cls, boundary, obstacles: Iterable = (), *, name: str = "arena",
                      source=None, strength: float = DEFAULT_STRENGTH, start=None) -> "Arena":
        """Build and validate an arena from polygons.

        Parameters
        ----------
        boundary : array_like, shape (n, 2)
            Outer boundary, a simple polygon in cm.
        obstacles : iterable of array_like, shape (m, 2)
            Obstacles, simple polygons in cm, inside the boundary. They may touch the
            boundary along an edge (a wall attached to the outer wall) but not overlap
            each other or pinch the free region to a point.
        name : str
            Arena name.
        source : array_like, shape (2,), optional
            True source position, cm. Must lie in the free region.
        strength : float
            Source strength ``c > 0``.
        start : array_like, shape (2,) or (3,), optional
            Start ``(x, y)`` or pose ``(x, y, heading)`` in cm, cm, radians.

        Raises
        ------
        ArenaError
            If any polygon, pose or parameter is invalid; the message says how to fix it.
        """
        b = _polygon(boundary, "the arena boundary")
        obs = [_polygon(o, f"obstacle {i}") for i, o in enumerate(obstacles)]
        _check_size(obs)
        arena = cls(b, obs, str(name), None, 1.0, None, None)
        arena._check_obstacles()
        return arena.with_scenario(source=source, strength=strength, start=start)

    @classmethod
    def disk(cls, center=(0.0, 0.0), radius: float = 1.0, obstacles: Iterable = (), *,
             name: str = "disk", source=None, strength: float = DEFAULT_STRENGTH, start=None,
             n_boundary: int = 512) -> "Arena":
        """A circular domain of `radius` (cm) around `center`, for analytic checks.

        The Green's function of a disk has a closed form (see
        :func:`reciprocity.fem.exact.disk_green`); meshes of this arena put their boundary
        nodes on the exact circle.
        """
        c = as_points(center, "disk center")[0]
        r = float(radius) if isinstance(radius, Real) and not isinstance(radius, bool) else math.nan
        if not MIN_SIZE_CM < r <= MAX_COORD_CM:
            raise ArenaError(f"disk radius must be a number in ({MIN_SIZE_CM:g}, {MAX_COORD_CM:g}] cm; "
                             f"got {radius!r}")
        if int(n_boundary) < 16:
            raise ArenaError(f"n_boundary must be at least 16; got {n_boundary}")
        a = np.linspace(0.0, 2 * np.pi, int(n_boundary), endpoint=False)
        b = c + r * np.column_stack([np.cos(a), np.sin(a)])
        obs = [_polygon(o, f"obstacle {i}") for i, o in enumerate(obstacles)]
        _check_size(obs)
        arena = cls(b, obs, str(name), None, 1.0, None, (float(c[0]), float(c[1]), r))
        arena._check_obstacles()
        return arena.with_scenario(source=source, strength=strength, start=start)

    def with_scenario(self, *, source=None, strength: float | None = None,
                      start=None, source_clearance: float | None = None) -> "Arena":
        """Return a copy with a different true source, strength, start pose and/or
        source clearance (cm).

        Arguments left as None keep the current value (the source and start are
        validated to lie in the free region), except that a new source drops the
        clearance the old one was drawn with unless `source_clearance` is given; a source
        nearer the walls than its clearance is refused.
        """
        src = self.source if source is None else self._check_point(source, "the source")
        clear = (self.source_clearance if source is None else 0.0) if source_clearance is None \
            else source_clearance
        if isinstance(clear, bool) or not isinstance(clear, Real) or not 0 <= float(clear) <= MAX_COORD_CM:
            raise ArenaError(f"source_clearance must be a distance in [0, {MAX_COORD_CM:g}] cm; got {clear!r}")
        clear = float(clear)
        if clear > 0 and src is not None and self.wall_distance(src)[0] < clear - 1e-9:
            raise ArenaError(f"the source ({src[0]:g}, {src[1]:g}) lies {self.wall_distance(src)[0]:.3g} cm "
                             f"from the walls, nearer than its source_clearance of {clear:g} cm")
        c = self.strength if strength is None else check_strength(strength)
        st = self.start
        if start is not None:
            s = np.asarray(start, dtype=float).ravel()
            if s.shape not in [(2,), (3,)] or not np.all(np.isfinite(s)):
                raise ArenaError(f"the start must be (x, y) or (x, y, heading); got {start!r}")
            self._check_point(s[:2], "the start")
            heading = float(s[2]) % (2 * np.pi) if s.shape == (3,) else 0.0
            st = np.array([s[0], s[1], heading])
        return Arena(self.boundary, self.obstacles, self.name, src, c, st, self.circle, clear)

    def without_scenario(self) -> "Arena":
        """The geometry alone (no source, start; default strength), cached per arena.

        Solvers are keyed on this, so episodes with different sources share one
        factorization."""
        return _geometry_only(self)

    # ------------------------------------------------------------------ validation
    def _check_obstacles(self) -> None:
        outer = Polygon(self.boundary)
        polys = [Polygon(o) for o in self.obstacles]
        for i, p in enumerate(polys):
            if not outer.buffer(1e-9).contains(p):
                raise ArenaError(
                    f"obstacle {i} is not inside the arena boundary (it reaches "
                    f"{p.difference(outer).area:.3g} cm^2 outside); move or clip it")
        pinch = ("pinches the free region to a point; leave a gap or let them share an "
                 "edge")
        for i, p in enumerate(polys):
            touch = p.intersection(outer.exterior)
            if not touch.is_empty and touch.length == 0:
                raise ArenaError(f"obstacle {i} touches the boundary at a single point, which {pinch}")
        for i in range(len(polys)):
            for j in range(i + 1, len(polys)):
                inter = polys[i].intersection(polys[j])
                if inter.area > 1e-9:
                    raise ArenaError(
                        f"obstacles {i} and {j} overlap ({inter.area:.3g} cm^2); "
                        "merge them into one polygon or separate them")
                if not inter.is_empty and inter.length == 0:
                    raise ArenaError(f"obstacles {i} and {j} touch at a single point, which {pinch}")
        free = self.free_region
        if free.is_empty or free.area <= MIN_SIZE_CM ** 2:
            raise ArenaError("the obstacles cover the whole arena: there is no free region")
        if free.geom_type != "Polygon":
            n = len(getattr(free, "geoms", []))
            raise ArenaError(
                f"the free region is split into {n} disconnected parts; open a passage "
                "between them or remove the enclosed part (fill it as an obstacle)")
        if not free.is_valid:
            raise ArenaError(f"the free region is invalid ({explain_validity(free)}): an "
                             f"obstacle {pinch}")

    def _check_point(self, point, what: str) -> np.ndarray:
        p = as_points(point, what)[0]
        if not self.contains(p)[0]:
            where = "inside an obstacle" if self._in_outer(p) else "outside the arena"
            raise ArenaError(
                f"{what} ({p[0]:.4g}, {p[1]:.4g}) cm is {where}; choose a point in the "
                "free region")
        return p

    def _in_outer(self, p) -> bool:
        return bool(shapely.contains_xy(Polygon(self.boundary), p[0], p[1]))

    # ------------------------------------------------------------------ queries
    @cached_property
    def free_region(self):
        """The free region ``D \\ Omega`` as a shapely geometry."""
        outer = Polygon(self.boundary)
        if not self.obstacles:
            return outer
        return outer.difference(unary_union([Polygon(o) for o in self.obstacles]))

    @property
    def area(self) -> float:
        """Area of the free region, cm^2."""
        return float(self.free_region.area)

    @property
    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """Bounding box ``((x0, x1), (y0, y1))`` of the boundary, cm."""
        lo, hi = self.boundary.min(axis=0), self.boundary.max(axis=0)
        return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))

    def contains(self, points, clearance: float = 0.0) -> np.ndarray:
        """Whether points lie in the free region, at least `clearance` cm from any wall.

        Parameters
        ----------
        points : array_like, shape (n, 2) or (2,)
            Points in cm.
        clearance : float
            Minimum distance (cm) to the boundary and to every obstacle.

        Returns
        -------
        ndarray of bool, shape (n,)
        """
        pts = as_points(points)
        inside = shapely.contains_xy(self._prepared_free, pts[:, 0], pts[:, 1])
        if clearance > 0:
            inside &= self.wall_distance(pts) >= clearance
        return inside

    def wall_distance(self, points) -> np.ndarray:
        """Distance (cm) from each point to the nearest wall (boundary or obstacle edge)."""
        pts = as_points(points)
        return shapely.distance(self._walls, shapely.points(pts))

    @cached_property
    def _prepared_free(self):
        geom = self.free_region
        shapely.prepare(geom)
        return geom

    @cached_property
    def _walls(self):
        walls = self.free_region.boundary
        shapely.prepare(walls)
        return walls

    def random_free_points(self, n: int, rng: np.random.Generator,
                           clearance: float = 0.0) -> np.ndarray:
        """Draw `n` points uniformly from the free region at `clearance` cm from walls.

        Parameters
        ----------
        n : int
            Number of points.
        rng : numpy.random.Generator
            Source of randomness (no global state is used).
        clearance : float
            Minimum wall distance, cm.
        """
        (x0, x1), (y0, y1) = self.bounds
        out = np.empty((0, 2))
        for _ in range(1000):
            cand = np.column_stack([rng.uniform(x0, x1, 4 * n + 16), rng.uniform(y0, y1, 4 * n + 16)])
            out = np.vstack([out, cand[self.contains(cand, clearance)]])
            if len(out) >= n:
                return out[:n]
        raise ArenaError(f"could not find {n} free points at clearance {clearance} cm; "
                         "reduce the clearance")

    def __repr__(self) -> str:
        return (f"Arena(name={self.name!r}, boundary={len(self.boundary)} vertices, "
                f"obstacles={len(self.obstacles)}, free area={self.area:.1f} cm^2)")

