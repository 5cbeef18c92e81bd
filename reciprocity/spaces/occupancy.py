"""The believed map of an arena whose obstacles are unknown: an occupancy grid.

A log-odds occupancy grid (Thrun, Burgard & Fox, *Probabilistic Robotics*, ch. 9) over
the bounding box of the known outer boundary, updated from range scans: the cells inside
a scan's visibility polygon (the fan through the measured ranges) are seen free, the
cell of each beam's hit is seen occupied. From it come the seen region, the frontier
(seen-free cells next to unseen ones) and the believed arena: the outer boundary with
the believed obstacles, for the PDE. A platform that knows where its body has been
(:meth:`OccupancyGrid.sweep`) keeps those cells free for certain; one that must pass a gap
the believed walls close may look at the scanned arena (:meth:`OccupancyGrid.scanned_arena`):
the hit cells as walls, without the believed arena's dilation.

Unknown space is **free** in the believed arena (optimistic): a wall is in the model only
once a beam has hit it. The field is then computed as if the unseen part were open;
the likelihood is widened for what that costs (:mod:`reciprocity.strategies.mapping`),
and observation points are chosen in seen-free space only.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.errors import GEOSException
from shapely.geometry import Polygon
from shapely.ops import unary_union

from arenas import Arena, ArenaError

from ..errors import SearchError

__all__ = ["OccupancyGrid", "L_FREE", "L_OCCUPIED", "L_MAX", "MIN_CHANGE_CM2", "MAX_BELIEVED_VERTICES"]

#: Log-odds added to a cell seen free by one scan (a free beam through it).
L_FREE = -0.4
#: Log-odds added to the cell of a hit (one beam ending on a wall there).
L_OCCUPIED = 1.2
#: Log-odds are clipped to ``±L_MAX``: a wall seen many times can still be cleared.
L_MAX = 4.0
#: A cell is believed occupied above this log-odds (probability 0.6): one hit is enough,
#: one hit outweighed by two free beams through the cell is not.
L_THRESHOLD = 0.4
#: Believed obstacles change only when they differ from the current ones by more than
#: this area (cm²): a single noisy cell does not re-mesh the model.
MIN_CHANGE_CM2 = 4.0
#: Hits within this many cells of the known outer boundary are the boundary itself.
BOUNDARY_CELLS = 1.5
#: Cells within this many cells of a place the observer scanned from are never believed
#: walls (it stood there): its readings stay inside the believed free region.
VISITED_CELLS = 2.5
#: Most vertices of the believed obstacles together: the traced walls are simplified
#: (tolerance doubled from 0.3 cell up to MAX_SIMPLIFY_CELLS cells) until they fit, so a
#: believed arena meshes like a user's arena of that size, whatever the grid shows.
MAX_BELIEVED_VERTICES = 1500
#: Largest simplification tolerance, cells; walls still over the budget beyond it are
#: refused (the believed arena stays what it was).
MAX_SIMPLIFY_CELLS = 4.0
#: Free slivers narrower than this many cells (between believed walls, or a wall and the
#: boundary) are closed before meshing: no observer passes them, and a mesh would need
#: triangles that small there.
SLIVER_CELLS = 0.5

#: Neighbouring beams whose ends lie more than this many cells apart in range see past a
#: wall's corner: the space between them is taken as free only up to the nearer end.
SILHOUETTE_CELLS = 2.0


class OccupancyGrid:
    """Log-odds occupancy over the box of a known outer boundary, updated from scans.

    Parameters
    ----------
    arena : Arena
        What is known: the outer boundary and any obstacles already told (a partial map),
        cm. Its obstacles stay obstacles whatever the scans say.
    cell : float
        Cell side, cm (about the lidar's range noise or finer makes walls one or two
        cells thick).

    Attributes
    ----------
    logodds : ndarray, shape (ny, nx)
        Log-odds of occupancy; row ``i`` is ``y = y0 + (i + 1/2) cell``, column ``j`` is
        ``x = x0 + (j + 1/2) cell`` (world frame, y up: not an image).
    seen : ndarray of bool, shape (ny, nx)
        Cells inside a scan's visibility polygon or holding a hit.
    inside : ndarray of bool, shape (ny, nx)
        Cells whose centre lies inside the outer boundary.
    visited : ndarray of bool, shape (ny, nx)
        Cells free for certain: within VISITED_CELLS of a place a scan was taken from,
        or under a body that was there (:meth:`sweep`). Never walls of a believed map.
    revision : int
        Incremented each time :meth:`believed_arena` changes.

    Examples
    --------
    >>> import arenas
    >>> grid = OccupancyGrid(arenas.Arena.from_polygons([[0, 0], [40, 0], [40, 40], [0, 40]]))
    >>> angles = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    >>> hit = np.zeros(32, dtype=bool)
    >>> ranges = np.full(32, 10.0)
    >>> grid.update((20.0, 20.0), angles, ranges, hit, 10.0)
    >>> bool(grid.seen_at([[20.0, 25.0]])[0]), bool(grid.seen_at([[20.0, 35.0]])[0])
    (True, False)
    """

    def __init__(self, arena: Arena, cell: float = 1.0):
        if not np.isfinite(cell) or cell <= 0:
            raise SearchError(f"occupancy cell must be a positive number of cm; got {cell!r}")
        self.known = arena.without_scenario()
        self.cell = float(cell)
        (x0, x1), (y0, y1) = self.known.bounds
        self.origin = np.array([x0, y0])
        self.nx, self.ny = int(np.ceil((x1 - x0) / cell)), int(np.ceil((y1 - y0) / cell))
        self.logodds = np.zeros((self.ny, self.nx))
        self.seen = np.zeros((self.ny, self.nx), dtype=bool)
        self.visited = np.zeros((self.ny, self.nx), dtype=bool)
        centres = self.centres()
        outer = Arena.from_polygons(self.known.boundary)
        self.inside = outer.contains(centres.reshape(-1, 2)).reshape(self.ny, self.nx)
        self._near_boundary = (outer.wall_distance(centres.reshape(-1, 2)) < BOUNDARY_CELLS * cell
                               ).reshape(self.ny, self.nx)
        told = self.known.contains(centres.reshape(-1, 2)).reshape(self.ny, self.nx)
        self._told = self.inside & ~told
        told = unary_union([Polygon(o) for o in self.known.obstacles])
        #: per kind of map ("believed", "scanned"): the arena now and the obstacles it was made of
        self._maps = {"believed": (self.known, told), "scanned": (self.known, told)}
        self.revision = 0

    # ------------------------------------------------------------------ grid
    def centres(self) -> np.ndarray:
        """Cell centres, shape (ny, nx, 2), cm."""
        x = self.origin[0] + (np.arange(self.nx) + 0.5) * self.cell
        y = self.origin[1] + (np.arange(self.ny) + 0.5) * self.cell
        return np.stack(np.meshgrid(x, y), axis=-1)

    def index(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Row, column and in-grid mask of each point (m, 2)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        ij = np.floor((p - self.origin) / self.cell).astype(int)
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < self.nx) & (ij[:, 1] >= 0) & (ij[:, 1] < self.ny)
        return np.clip(ij[:, 1], 0, self.ny - 1), np.clip(ij[:, 0], 0, self.nx - 1), ok

    @property
    def occupied(self) -> np.ndarray:
        """Cells believed occupied (log-odds above threshold, or told), shape (ny, nx)."""
        return (self.inside & (self.logodds > L_THRESHOLD)) | self._told

    @property
    def free(self) -> np.ndarray:
        """Cells seen and believed free, shape (ny, nx)."""
        return self.seen & self.inside & ~self.occupied

    @property
    def seen_fraction(self) -> float:
        """Share of the cells inside the boundary that have been seen."""
        return float((self.seen & self.inside).sum() / max(self.inside.sum(), 1))

    def seen_at(self, points) -> np.ndarray:
        """Whether each point (m, 2) lies in a seen cell."""
        r, c, ok = self.index(points)
        return ok & self.seen[r, c]

    def free_at(self, points) -> np.ndarray:
        """Whether each point (m, 2) lies in a seen-free cell."""
        r, c, ok = self.index(points)
        return ok & self.free[r, c]

    def frontier(self) -> np.ndarray:
        """Seen-free cells with an unseen neighbour inside the boundary (4-neighbours),
        shape (ny, nx), leaving out cells within two cells of a believed wall or the
        boundary: the unseen cells there are the wall's inside, not open space."""
        from scipy import ndimage
        unseen = self.inside & ~self.seen
        near = np.zeros_like(unseen)
        near[1:] |= unseen[:-1]
        near[:-1] |= unseen[1:]
        near[:, 1:] |= unseen[:, :-1]
        near[:, :-1] |= unseen[:, 1:]
        walls = ndimage.binary_dilation(np.pad(self.occupied | ~self.inside, 2, constant_values=True),
                                        np.ones((5, 5), dtype=bool))[2:-2, 2:-2]
        return self.free & near & ~walls

    # ------------------------------------------------------------------ update
    def update(self, position, angles: np.ndarray, ranges: np.ndarray, hit: np.ndarray,
               max_range: float) -> None:
        """Take in one scan from `position` (cm).

        Parameters
        ----------
        position : array_like, shape (2,)
            Where the scan was taken, cm.
        angles : ndarray, shape (n,)
            Beam directions, radians (world frame).
        ranges : ndarray, shape (n,)
            Measured ranges, cm.
        hit : ndarray of bool, shape (n,)
            Beams that ended on a wall.
        max_range : float
            The sensor's range, cm (beams without a hit read it).

        Notes
        -----
        The free part is the visibility polygon through the beam ends, each end drawn
        half a cell short of a hit (so the wall's own cell is hardly cleared), filled with
        :func:`skimage.draw.polygon`: with 64 beams at 40 cm neighbouring ends lie 4 cm
        apart, and tracing the beams alone would leave unseen slivers between them.
        Where neighbouring beams end more than SILHOUETTE_CELLS apart (one passes the
        corner of a wall the other hits), the space between them is free only up to the
        nearer end (:func:`visibility_outline`): a chord from the hit out to the far end
        would cut through the wall behind the corner and clear its cells.
        """
        from skimage.draw import polygon
        p = np.asarray(position, dtype=float)[:2]
        angles, ranges = np.asarray(angles, dtype=float), np.asarray(ranges, dtype=float)
        hit = np.asarray(hit, dtype=bool)
        d = np.column_stack([np.cos(angles), np.sin(angles)])
        reach = np.where(hit, np.maximum(ranges - 0.5 * self.cell, 0.0), ranges)
        ends = visibility_outline(p, d, reach, hit, SILHOUETTE_CELLS * self.cell)
        fx, fy = (ends - self.origin).T / self.cell - 0.5   # fractional cell coordinates
        rr, cc = polygon(fy, fx, shape=self.logodds.shape)
        own_r, own_c, own_ok = self.index(p[None])
        near = np.sum((self.centres() - p) ** 2, axis=-1) <= (VISITED_CELLS * self.cell) ** 2
        self.visited |= near & self.inside
        free = np.zeros(self.logodds.shape, dtype=bool)
        free[rr, cc] = True
        if own_ok[0]:
            free[own_r[0], own_c[0]] = True
        self.logodds[free] += L_FREE
        self.seen |= free
        if hit.any():
            r, c, ok = self.index(p + ranges[hit, None] * d[hit])
            r, c = r[ok], c[ok]
            self.seen[r, c] = True
            keep = ~self._near_boundary[r, c]               # the known boundary itself
            cells = np.unique(np.column_stack([r[keep], c[keep]]), axis=0)
            if len(cells):
                self.logodds[cells[:, 0], cells[:, 1]] += L_OCCUPIED - L_FREE * free[cells[:, 0], cells[:, 1]]
                self.seen[cells[:, 0], cells[:, 1]] = True
        np.clip(self.logodds, -L_MAX, L_MAX, out=self.logodds)

    def sweep(self, bodies) -> None:
        """Keep the cells under bodies that have been there free for certain.

        Parameters
        ----------
        bodies : sequence of array_like, each shape (k, 2)
            Polygons an observer's body covered (e.g. a car's footprint at each pose it
            drove through), cm.

        Notes
        -----
        A cell counts as covered when its centre lies inside a body. The cells join
        :attr:`visited`: they are seen, and never walls of the believed or scanned arena
        (a body stood there), whatever a noisy hit or the dilation of a wall beside them
        says. The walls next to a corridor the observer drove stay where they were seen.
        """
        from skimage.draw import polygon
        mask = np.zeros(self.logodds.shape, dtype=bool)
        for body in bodies:
            fx, fy = (np.asarray(body, dtype=float)[:, :2] - self.origin).T / self.cell - 0.5
            rr, cc = polygon(fy, fx, shape=mask.shape)
            mask[rr, cc] = True
        mask &= self.inside
        self.visited |= mask
        self.seen |= mask

    # ------------------------------------------------------------------ believed map
    def obstacle_mask(self, dilate: bool = True) -> np.ndarray:
        """Cells the believed arena treats as walls, shape (ny, nx).

        Parameters
        ----------
        dilate : bool
            True (the believed arena): the occupied cells dilated by one cell (a wall
            seen from one side is at least three cells thick). False (the scanned arena):
            the occupied cells as they are.

        Returns
        -------
        ndarray of bool, shape (ny, nx)
            Those walls with the gaps of up to about two cells between them or the
            boundary closed (no model of a slit the beams cannot resolve; without the
            dilation, the holes of up to about four cells between the hits of a wall
            seen from afar, and not to the boundary), less the :attr:`visited` cells, and with any pocket of free cells they
            cut off from the largest free part filled (the free region of an arena is
            connected).
        """
        from scipy import ndimage
        occ = ndimage.binary_dilation(self.occupied, np.ones((3, 3), dtype=bool)) if dilate else self.occupied
        # undilated walls are closed among themselves only: cells a few cm from the
        # boundary, joined to it, would touch it at points no valid arena has
        blocked = np.pad(occ | ~self.inside if dilate else occ, 3, constant_values=dilate)
        disk = np.add.outer(np.arange(-2, 3) ** 2, np.arange(-2, 3) ** 2) <= 4
        closed = ndimage.binary_closing(blocked, disk)[3:-3, 3:-3]
        # only gaps next to a believed wall are closed (not the boundary's own corners)
        blocked = (occ | (closed & ndimage.binary_dilation(occ, disk))) & ~self.visited
        free = self.inside & ~blocked
        label, n = ndimage.label(free)
        if n > 1:
            sizes = np.bincount(label.ravel())[1:]
            free = label == 1 + int(np.argmax(sizes))
        return self.inside & ~free

    def believed_geometry(self, dilate: bool = True):
        """The believed obstacles (of :meth:`obstacle_mask` with `dilate`) as one shapely
        geometry (cm), cut to the boundary and simplified to at most
        MAX_BELIEVED_VERTICES vertices; None when they do not fit."""
        from skimage.measure import find_contours
        mask = np.pad(self.obstacle_mask(dilate), 1, constant_values=False)
        polys = []
        for c in find_contours(mask.astype(float), 0.5):
            xy = self.origin + (c[:, ::-1] - 1 + 0.5) * self.cell   # (row, col) -> (x, y)
            if len(xy) >= 4:
                poly = Polygon(xy).buffer(0)
                if poly.area > self.cell ** 2:
                    polys.append(poly)
        if not polys:
            return Polygon()
        # the contours of holes come out too: a hole lies inside an outer contour
        polys.sort(key=lambda g: -g.area)
        geom = Polygon()
        for g in polys:
            geom = geom.difference(g) if geom.contains(g) else geom.union(g)
        told = unary_union([Polygon(o) for o in self.known.obstacles])
        return _within_budget(geom.union(told).intersection(Polygon(self.known.boundary)), self.cell)

    def believed_arena(self) -> Arena:
        """The outer boundary with the believed obstacles, unknown space free.

        The same object (and so the same cached solver) is returned until the believed
        obstacles change by more than MIN_CHANGE_CM2; :attr:`revision` counts changes.
        A geometry that is not a valid arena (obstacles pinching the free region to a
        point) keeps the previous arena.
        """
        arena, changed = self._follow("believed", self.believed_geometry())
        self.revision += changed
        return arena

    def scanned_arena(self) -> Arena:
        """The outer boundary with the scanned obstacles: the occupied cells, not dilated
        (:meth:`obstacle_mask` with ``dilate=False``), unknown space free.

        Walls a cell thinner on each side than in :meth:`believed_arena`: the map to try
        a path on before a target the believed walls shut out is given up (their dilation
        narrows every gap by two cells or more, and closes gaps of twice a platform's
        clearance plus two cells). Only holes of up to about four cells are closed: those
        between the hits of a wall seen from afar (beams a few cm apart), which no
        platform of a clearance above one cell passes. Kept, like the believed arena,
        until the obstacles change by more than MIN_CHANGE_CM2.
        """
        return self._follow("scanned", self.believed_geometry(dilate=False))[0]

    def _follow(self, kind: str, geom) -> tuple[Arena, bool]:
        """The arena of map `kind` after its obstacles became `geom`, and whether it changed."""
        arena, current = self._maps[kind]
        if geom is None or geom.symmetric_difference(current).area <= MIN_CHANGE_CM2:
            return arena, False
        for closing in (0.0, 0.5 * self.cell, self.cell):
            new = self._arena_of(geom, closing)
            if new is not None:
                self._maps[kind] = (new, geom)
                return new, True
        return arena, False

    def _arena_of(self, geom, closing: float) -> Arena | None:
        """The arena whose obstacles are `geom` closed by `closing` cm (joins obstacles
        that touch at a point), with the free region reduced to its largest part; None
        when that is still not a valid arena."""
        outer = Polygon(self.known.boundary)
        if closing > 0:
            geom = geom.buffer(closing, join_style="mitre").buffer(-closing, join_style="mitre")
        free = outer.difference(geom).buffer(0)
        sliver = 0.5 * SLIVER_CELLS * self.cell
        free = free.buffer(-sliver, join_style="mitre").buffer(sliver, join_style="mitre").intersection(outer)
        if free.is_empty or free.area <= 0:
            return None
        free = max(getattr(free, "geoms", [free]), key=lambda g: g.area)
        blocked = outer.difference(Polygon(free.exterior))
        blocked = unary_union([blocked, *(Polygon(h) for h in free.interiors)])
        parts = [g for g in getattr(blocked, "geoms", [blocked]) if g.geom_type == "Polygon" and g.area > 0.5 * self.cell ** 2]
        try:
            return Arena.from_polygons(self.known.boundary, [np.asarray(g.exterior.coords)[:-1] for g in parts],
                                       name=self.known.name, strength=self.known.strength).without_scenario()
        except (ArenaError, GEOSException):
            return None


def _vertices(geom) -> int:
    return int(shapely.get_num_coordinates(geom))


def _within_budget(geom, cell: float):
    """`geom` simplified to at most MAX_BELIEVED_VERTICES vertices (tolerance 0.3 cell,
    doubled up to MAX_SIMPLIFY_CELLS cells; then its smallest parts left out, as unseen
    space is free), or None when its largest part alone does not fit."""
    tol = 0.3 * cell
    out = geom.simplify(tol)
    while _vertices(out) > MAX_BELIEVED_VERTICES and tol < MAX_SIMPLIFY_CELLS * cell:
        tol *= 2.0
        out = geom.simplify(tol)
    if _vertices(out) <= MAX_BELIEVED_VERTICES:
        return out
    kept, n = [], 0
    for part in sorted(getattr(out, "geoms", [out]), key=lambda g: -g.area):
        if n + _vertices(part) > MAX_BELIEVED_VERTICES:
            break
        kept.append(part)
        n += _vertices(part)
    return unary_union(kept) if kept else None


def visibility_outline(position: np.ndarray, directions: np.ndarray, reach: np.ndarray, hit: np.ndarray,
                       jump: float) -> np.ndarray:
    """The outline of the space a scan saw free: the beam ends in beam order, with the
    wedge between two neighbouring beams cut back to the nearer end where the farther one
    has passed the corner of the wall the nearer one hit.

    Parameters
    ----------
    position : numpy.ndarray, shape (2,)
        Where the scan was taken, cm.
    directions : numpy.ndarray, shape (n, 2)
        Unit directions of the beams, in scan order (the last beam neighbours the first).
    reach : numpy.ndarray, shape (n,)
        How far along each beam the space is free, cm.
    hit : numpy.ndarray, shape (n,)
        Beams that ended on a wall.
    jump : float
        Reaches of neighbouring beams that differ by at most this much (cm) are joined by a
        straight chord; so is a farther end within this distance of the wall the nearer
        beam hit (the line through its end and its other neighbour's, both hits).

    Returns
    -------
    numpy.ndarray, shape (m, 2)
        Polygon vertices, cm: each beam's end, in beam order; where the wedge to the
        previous (next) beam is cut back and this beam is the farther one, preceded
        (followed) by the point on it at the nearer beam's reach.

    Notes
    -----
    Where a beam passes a wall's corner and its neighbour hits the wall just before it,
    the chord between their ends runs behind the corner, through the wall: a grid filled
    inside that chord clears the wall's cells there, scan after scan, until the corner is
    gone from the map. Between two such beams nothing beyond the nearer end is known to be
    free. A wall seen at a grazing angle also gives neighbouring reaches far apart, but its
    chords run along the wall and are kept.
    """
    p = np.asarray(position, dtype=float)[:2]
    ends = p + reach[:, None] * directions
    nxt = np.roll(reach, -1)
    cut = np.abs(reach - nxt) > jump                   # the wedge between beam i and i + 1
    near_first = reach <= nxt
    # the nearer beam of each wedge, its other neighbour, and the farther beam
    idx = np.arange(len(reach))
    near = np.where(near_first, idx, (idx + 1) % len(reach))
    other = np.where(near_first, (idx - 1) % len(reach), (idx + 2) % len(reach))
    far = np.where(near_first, (idx + 1) % len(reach), idx)
    along = ends[near] - ends[other]
    size = np.hypot(along[:, 0], along[:, 1])
    off = ends[far] - ends[near]
    gap = np.abs(along[:, 0] * off[:, 1] - along[:, 1] * off[:, 0]) / np.where(size > 0, size, 1.0)
    same_wall = hit[near] & hit[other] & (size > 0) & (gap <= jump)
    cut &= ~same_wall
    inner = np.minimum(reach, nxt)
    # the cut point lies on the farther beam (on the nearer one it is the beam's own end)
    before = np.roll(cut, 1) & (reach > np.roll(reach, 1))
    after = cut & (reach > nxt)
    radii = np.column_stack([np.where(before, np.roll(inner, 1), np.nan), reach, np.where(after, inner, np.nan)])
    pts = p + radii[:, :, None] * directions[:, None, :]
    pts = pts.reshape(-1, 2)
    return pts[np.isfinite(pts[:, 0])]
