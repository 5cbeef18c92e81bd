"""MP4 video of a car search episode: the floor, the car and its path, and the imaging map.

Each frame shows, at one simulated time, the testbed floor seen from above (the car at
its true pose, its path so far, the measurements, re-plans, collisions, the true source
and the next target; on an unknown map, the walls the car plans on at that time) and, for strategies with an imaging map, ``P`` after the latest
completed measurement. The static layers are drawn once; everything that accumulates
(path, measurements, re-plans, collisions) is drawn once onto a persistent canvas as the
episode's clock passes it, so a frame costs one copy plus the car and a few markers.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from matplotlib.tri import Triangulation
from tqdm import tqdm

from arenas import Arena, pixel_to_world, world_to_pixel
from arenas.car import CarSpec, car_footprint

from ..episode import Episode
from ..errors import SearchError

__all__ = ["write_video", "encode_mp4"]

#: Colours, BGR.
COLORS = {
    "reciprocity_path": (200, 70, 0), "gradient_path": (0, 160, 0), "plan": (235, 190, 120),
    "wall": (0, 0, 0), "obstacle": (70, 70, 70), "outside": (40, 40, 40),
    "measurement": (0, 0, 230), "replan": (255, 190, 60), "collision": (0, 140, 255),
    "source": (0, 190, 0), "target": (0, 0, 0), "camera": (255, 255, 0),
    "car": (0, 215, 255), "car_edge": (0, 0, 0), "estimate": (255, 0, 255),
    "header": (30, 30, 30), "text": (240, 240, 240), "imaging_wall": (255, 255, 255),
    "imaging_point": (255, 255, 255),
    "believed": (190, 40, 150), "scanned": (150, 150, 0),
}

#: Opacity of the fill of the walls a car plans on (unknown map) over the floor.
MAP_ALPHA = 0.45

#: Fractional bits of the pixel coordinates handed to OpenCV (sub-pixel drawing).
SHIFT = 4

#: Gap between the two panels, pixels.
GAP_PX = 4


@dataclass
class _Timeline:
    """Everything a frame needs from the trace, as time-sorted arrays (s, cm)."""

    times: np.ndarray          # (n,) camera frame times
    true: np.ndarray           # (n, 3) true poses, heading unwrapped
    estimated: np.ndarray      # (n, 3) camera estimates
    travelled: np.ndarray      # (n,) cm driven up to each camera frame
    meas_time: np.ndarray      # (m,)
    meas_point: np.ndarray     # (m, 2)
    meas_signal: np.ndarray    # (m,) bool: a signal reading (one imaging update)
    replan_time: np.ndarray    # (r,)
    replan_point: np.ndarray   # (r, 2)
    plans: list                # (start s, end s, (p, 2) polyline)
    coll_time: np.ndarray      # (c,)
    coll_point: np.ndarray     # (c, 2)
    done_time: np.ndarray      # (k,) end of each record
    estimates: list            # estimate in force after each record, or None
    nexts: list                # next target after each record, or None
    end: float                 # end of the last record
    maps: list                 # (time s, kind, [(k, 2) polygons]): walls the car plans on from then

    def pose(self, t: float) -> np.ndarray:
        """The true pose at `t`, interpolated between camera frames."""
        return np.array([np.interp(t, self.times, self.true[:, i]) for i in range(3)])


def _array(values, cols: int) -> np.ndarray:
    """`values` (array, list, JSON nulls) as a float array of shape (n, cols)."""
    if values is None or len(values) == 0:
        return np.empty((0, cols))
    return np.asarray(values, dtype=float).reshape(-1, cols)


def _items(record: dict, key: str) -> list:
    """The entries of a record's list (or array) `key`; none when missing or null."""
    value = record.get(key)
    return [] if value is None else list(value)


def _optional_point(value):
    """A point ``(x, y)`` as an array, or None for a missing or non-finite one."""
    if value is None:
        return None
    p = np.asarray(value, dtype=float).ravel()[:2]
    return p if p.shape == (2,) and np.all(np.isfinite(p)) else None


def _timeline(trace) -> _Timeline:
    """Collect and time-sort what the video draws from a car episode's trace records."""
    times, true, est = [], [], []
    meas, replans, plans, colls, maps = [], [], [], [], []
    done, estimates, nexts = [], [], []
    estimate = nxt = None
    clock = 0.0
    for rec in trace:
        t = np.asarray(_items(rec, "times"), dtype=float).ravel()
        p = _array(rec.get("true_poses"), 3)
        e = _array(rec.get("estimated_poses"), 3)
        if len(p) != len(t):
            raise SearchError(f"trace record {rec.get('step')} has {len(t)} times but "
                              f"{len(p)} true poses; the trace is corrupt")
        e = e if len(e) == len(t) else p
        start = t[0] if len(t) else clock
        for m in _items(rec, "measurements"):
            meas.append((float(m["time"]), *np.asarray(m["point"], float)[:2],
                         rec.get("kind") == "signal"))
        # a re-plan happens at a camera estimate of this record: take that frame's time
        r_times = []
        for q in _array([r[:2] for r in _items(rec, "replans")], 2):
            d = np.hypot(*(e[:, :2] - q).T)
            i = int(np.argmin(np.where(np.isfinite(d), d, np.inf))) if len(d) else -1
            r_times.append(t[i] if i >= 0 else start)
            replans.append((r_times[-1], *q))
        for c in _items(rec, "collisions"):
            colls.append((float(c["time"]), float(c["x"]), float(c["y"])))
        for m in _items(rec, "maps"):
            maps.append((float(m["time"]), str(m.get("walls", "believed")),
                         [_array(o, 2) for o in _items(m, "obstacles")]))
        clock = max([clock, *t, *(m[0] for m in meas)])
        ends = r_times[1:] + [clock]
        for t0, t1, line in zip(r_times, ends, _items(rec, "plans")):
            plans.append((t0, t1, _array(line, 2)))
        times.append(t)
        true.append(p)
        est.append(e)
        if "estimate" in rec:  # unreachable records leave the estimate as it was
            estimate = _optional_point(rec["estimate"])
        nxt = _optional_point(rec.get("next"))
        done.append(clock)
        estimates.append(estimate)
        nexts.append(nxt)
    t, p, e = np.concatenate(times), np.vstack(true), np.vstack(est)
    if len(t) == 0:
        raise SearchError(
            "the episode has no car trace (no true_poses in any record): a video needs a "
            "car episode; run with platform 'car' (reciprocity run --platform car)")
    order = np.argsort(t, kind="stable")
    t, p, e = t[order], p[order], e[order]
    p[:, 2] = np.unwrap(p[:, 2])
    travelled = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p[:, :2], axis=0).T))])
    m = np.array(sorted(meas, key=lambda r: r[0]), dtype=float).reshape(-1, 4)
    r = np.array(sorted(replans, key=lambda r: r[0]), dtype=float).reshape(-1, 3)
    c = np.array(sorted(colls, key=lambda r: r[0]), dtype=float).reshape(-1, 3)
    return _Timeline(t, p, e, travelled, m[:, 0], m[:, 1:3], m[:, 3].astype(bool),
                     r[:, 0], r[:, 1:3], plans, c[:, 0], c[:, 1:3], np.asarray(done),
                     estimates, nexts, float(clock), sorted(maps, key=lambda m: m[0]))


class _Canvas:
    """World (cm) to sub-pixel OpenCV coordinates for one panel, and the drawing sizes."""

    def __init__(self, arena: Arena, px_per_cm: float):
        (x0, x1), (y0, y1) = arena.bounds
        self.origin = (x0, y0)
        self.cm_per_px = 1.0 / px_per_cm
        self.width = max(2, round((x1 - x0) * px_per_cm))
        self.height = max(2, round((y1 - y0) * px_per_cm))
        self.px_per_cm = px_per_cm
        self.line = max(1, round(0.4 * px_per_cm))

    def pixels(self, points) -> np.ndarray:
        """Fractional pixels ``(col, row)`` of world points, shape (n, 2)."""
        return world_to_pixel(points, self.cm_per_px, self.height, self.origin)

    def fixed(self, points) -> np.ndarray:
        """Pixels as OpenCV's fixed-point ints (`SHIFT` fractional bits), shape (n, 2)."""
        return np.round(self.pixels(points) * (1 << SHIFT)).astype(np.int32)

    def whole(self, point) -> tuple[int, int]:
        """The nearest whole pixel of one world point (for markers)."""
        col, row = np.round(self.pixels(point)[0]).astype(int)
        return int(col), int(row)

    def size(self, cm: float, least: int = 2) -> int:
        """A length in cm as whole pixels, at least `least`."""
        return max(least, round(cm * self.px_per_cm))

    def polyline(self, img, points, color, thickness=None, closed=False) -> None:
        if len(points) > 1:
            cv2.polylines(img, [self.fixed(points)], closed, color,
                          thickness or self.line, cv2.LINE_AA, SHIFT)

    def circle(self, img, point, radius_cm: float, color, thickness=-1) -> None:
        r = round(max(radius_cm * self.px_per_cm, 1.5) * (1 << SHIFT))
        cv2.circle(img, tuple(int(v) for v in self.fixed(point)[0]), r, color, thickness,
                   cv2.LINE_AA, SHIFT)

    def marker(self, img, point, color, kind: int, size_cm: float, thickness=None) -> None:
        cv2.drawMarker(img, self.whole(point), color, kind, self.size(size_cm, 5),
                       thickness or self.line, cv2.LINE_AA)

    def outlines(self, img, arena: Arena, color) -> None:
        for ring in [arena.boundary, *arena.obstacles]:
            self.polyline(img, ring, color, closed=True)


def _floor_panel(canvas: _Canvas, arena: Arena, floor_image: np.ndarray) -> np.ndarray:
    """The static left panel: the floor, outside and obstacles shaded, the walls."""
    img = np.asarray(floor_image)
    if img.ndim != 2 or img.dtype != np.uint8 or min(img.shape, default=0) < 1:
        raise SearchError(f"floor_image must be a non-empty 2-D uint8 grey image; got dtype "
                          f"{img.dtype}, shape {img.shape} (pass arenas.Floor.image)")
    grey = cv2.resize(img, (canvas.width, canvas.height), interpolation=cv2.INTER_AREA)
    panel = cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)
    inside = np.zeros(panel.shape[:2], np.uint8)
    cv2.fillPoly(inside, [canvas.fixed(arena.boundary)], 255, cv2.LINE_8, SHIFT)
    panel[inside == 0] = COLORS["outside"]
    for o in arena.obstacles:
        cv2.fillPoly(panel, [canvas.fixed(o)], COLORS["obstacle"], cv2.LINE_AA, SHIFT)
    canvas.outlines(panel, arena, COLORS["wall"])
    return panel


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z-component of the cross products of rows of (n, 2) arrays."""
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


class _ImagingRaster:
    """``P_k`` on the panel's pixel grid, as JET colours (black outside the mesh).

    The pixel centres are located in the mesh once; each ``P_k`` is then the barycentric
    combination of its nodal values, exactly what ``matplotlib.tri.LinearTriInterpolator``
    returns but without locating 10^5 points again for every k.
    """

    def __init__(self, imaging, canvas: _Canvas):
        self.imaging = imaging
        self.shape = (canvas.height, canvas.width)
        nodes = np.asarray(imaging.nodes, dtype=float)
        triangles = np.asarray(imaging.triangles, dtype=np.int64)
        rows, cols = np.mgrid[0:canvas.height, 0:canvas.width]
        xy = pixel_to_world(np.column_stack([cols.ravel(), rows.ravel()]), canvas.cm_per_px,
                            canvas.height, canvas.origin)
        tri = Triangulation(nodes[:, 0], nodes[:, 1], triangles)
        found = tri.get_trifinder()(xy[:, 0], xy[:, 1])
        self.inside = np.flatnonzero(found >= 0)
        self.vertices = triangles[found[self.inside]]
        a, b, c = (nodes[self.vertices[:, i]] for i in range(3))
        p = xy[self.inside]
        det = _cross(b - a, c - a)
        with np.errstate(divide="ignore", invalid="ignore"):  # degenerate triangles: NaN
            wb = _cross(p - a, c - a) / det
            wc = _cross(b - a, p - a) / det
        self.weights = np.column_stack([1.0 - wb - wc, wb, wc])
        self.available = getattr(imaging, "n", None)
        self._cache: dict[int, np.ndarray] = {}

    def colours(self, k: int) -> np.ndarray:
        """BGR image of ``P`` after `k` measurements (black everywhere when k = 0)."""
        if self.available is not None:
            k = min(k, int(self.available))
        if k not in self._cache:
            grey = np.zeros(self.shape[0] * self.shape[1], np.uint8)
            valid = np.zeros(grey.shape, bool)
            if k > 0:
                values = np.asarray(self.imaging.first(k).values(), dtype=float)
                P = np.einsum("ij,ij->i", values[self.vertices], self.weights)
                ok = np.isfinite(P)
                grey[self.inside[ok]] = np.round(np.clip(P[ok], 0.0, 1.0) * 255)
                valid[self.inside[ok]] = True
            img = cv2.applyColorMap(grey.reshape(self.shape), cv2.COLORMAP_JET)
            img[~valid.reshape(self.shape)] = 0
            self._cache[k] = img
        return self._cache[k]


@dataclass
class _Layout:
    """Where the header and the panels go in a frame (pixels); the frame size is even."""

    header: int
    left: tuple[int, int]
    right: tuple[int, int] | None
    size: tuple[int, int]       # (width, height)
    font_scale: float

    @classmethod
    def for_panels(cls, canvas: _Canvas, two: bool, sample_text: str) -> _Layout:
        width = 2 * canvas.width + GAP_PX if two else canvas.width
        (tw, _), _ = cv2.getTextSize(sample_text, cv2.FONT_HERSHEY_SIMPLEX, 1.0, 1)
        scale = float(np.clip((width - 12) / tw, 0.3, 0.55))
        (_, th), base = cv2.getTextSize(sample_text, cv2.FONT_HERSHEY_SIMPLEX, scale, 1)
        header = th + base + 10
        height = header + canvas.height
        size = (width + width % 2, height + height % 2)
        right = (header, canvas.width + GAP_PX) if two else None
        return cls(header, (header, 0), right, size, scale)


def _status_text(strategy: str, t: float, n_meas: int, path_cm: float) -> str:
    return f"{strategy}   t = {t:6.1f} s   measurements {n_meas:3d}   path {path_cm:5.0f} cm"


class _Renderer:
    """Draws frames in increasing simulated time, accumulating the path and the marks."""

    def __init__(self, line: _Timeline, arena: Arena, canvas: _Canvas, background: np.ndarray,
                 raster: _ImagingRaster | None, layout: _Layout, strategy: str, source):
        self.line, self.arena, self.canvas, self.raster = line, arena, canvas, raster
        self.layout, self.strategy, self.source = layout, strategy, source
        self.trail = background.copy()
        self.path_color = COLORS["gradient_path" if strategy == "gradient" else "reciprocity_path"]
        self.frame = np.zeros((layout.size[1], layout.size[0], 3), np.uint8)
        self.frame[:] = COLORS["header"]
        self.right_key = None
        self.drawn = {"pose": 0, "meas": 0, "replan": 0, "coll": 0}
        self.map_times = np.array([m[0] for m in line.maps], dtype=float)
        self.map_key, self.map_layer = -1, None

    # -- the persistent canvas -----------------------------------------------------------
    def _advance(self, t: float) -> None:
        """Draw onto the trail canvas whatever has happened up to `t`."""
        ln, cv, d = self.line, self.canvas, self.drawn
        n = int(np.searchsorted(ln.times, t, side="right"))
        if n > d["pose"]:
            cv.polyline(self.trail, ln.true[max(0, d["pose"] - 1):n, :2], self.path_color)
            d["pose"] = n
        n = int(np.searchsorted(ln.replan_time, t, side="right"))
        for q in ln.replan_point[d["replan"]:n]:
            cv.circle(self.trail, q, 1.0, COLORS["replan"], 1)
        d["replan"] = n
        n = int(np.searchsorted(ln.meas_time, t, side="right"))
        for q in ln.meas_point[d["meas"]:n]:
            cv.circle(self.trail, q, 1.4, COLORS["measurement"], cv.line)
        d["meas"] = n
        n = int(np.searchsorted(ln.coll_time, t, side="right"))
        for q in ln.coll_point[d["coll"]:n]:
            cv.marker(self.trail, q, COLORS["collision"], cv2.MARKER_TILTED_CROSS, 2.5)
        d["coll"] = n

    # -- one frame -----------------------------------------------------------------------
    def render(self, t: float) -> np.ndarray:
        ln, cv = self.line, self.canvas
        self._advance(t)
        done = int(np.searchsorted(ln.done_time, t, side="right")) - 1
        estimate = ln.estimates[done] if done >= 0 else None
        nxt = ln.nexts[done] if done >= 0 else None
        r0, c0 = self.layout.left
        left = self.frame[r0:r0 + cv.height, c0:c0 + cv.width]
        left[:] = self.trail
        self._walls(left, t)
        pose = ln.pose(t)
        last = self.drawn["pose"]
        if last:
            cv.polyline(left, np.vstack([ln.true[last - 1, :2], pose[:2]]), self.path_color)
        for t0, t1, plan in ln.plans:
            if t0 <= t < t1:
                cv.polyline(left, plan, COLORS["plan"], 1)
        self._markers(left, estimate)
        if nxt is not None:
            cv.marker(left, nxt, COLORS["target"], cv2.MARKER_CROSS, 4.0)
        if last and np.all(np.isfinite(ln.estimated[last - 1, :2])):
            cv.marker(left, ln.estimated[last - 1, :2], COLORS["camera"], cv2.MARKER_CROSS, 2.5, 1)
        self._car(left, pose)
        if self.raster is not None:
            k = int(ln.meas_signal[:self.drawn["meas"]].sum())
            self._right(k, done, estimate)
        self._header(t)
        return self.frame

    def _walls(self, img, t: float) -> None:
        """The walls the car plans on at `t` (unknown map): filled, half transparent, and
        outlined, in the colour of their kind (believed or scanned)."""
        i = int(np.searchsorted(self.map_times, t, side="right")) - 1
        if i < 0:
            return
        if i != self.map_key:
            _, kind, polygons = self.line.maps[i]
            mask = np.zeros(img.shape[:2], np.uint8)
            edges = np.zeros(img.shape[:2], np.uint8)
            rings = [self.canvas.fixed(o) for o in polygons if len(o) > 2]
            if rings:
                cv2.fillPoly(mask, rings, 255, cv2.LINE_8, SHIFT)
                cv2.polylines(edges, rings, True, 255, self.canvas.line, cv2.LINE_8, SHIFT)
            self.map_key, self.map_layer = i, (mask > 0, edges > 0, np.array(COLORS[kind], float))
        fill, edge, color = self.map_layer
        img[fill] = np.round((1 - MAP_ALPHA) * img[fill] + MAP_ALPHA * color).astype(np.uint8)
        img[edge] = color.astype(np.uint8)

    def _car(self, img, pose) -> None:
        cv, spec = self.canvas, CarSpec()
        body = cv.fixed(car_footprint(pose, spec.length, spec.width))
        cv2.fillPoly(img, [body], COLORS["car"], cv2.LINE_AA, SHIFT)
        cv2.polylines(img, [body], True, COLORS["car_edge"], 1, cv2.LINE_AA, SHIFT)
        front = pose[:2] + 0.5 * spec.length * np.array([np.cos(pose[2]), np.sin(pose[2])])
        cv.polyline(img, np.vstack([pose[:2], front]), COLORS["car_edge"], 1)
        cv.circle(img, front, 0.5, COLORS["car_edge"])

    def _right(self, k: int, done: int, estimate) -> None:
        """Redraw the imaging panel when a measurement or an estimate has arrived."""
        if (k, done) == self.right_key:
            return
        self.right_key = (k, done)
        cv, ln = self.canvas, self.line
        r0, c0 = self.layout.right
        right = self.frame[r0:r0 + cv.height, c0:c0 + cv.width]
        right[:] = self.raster.colours(k)
        cv.outlines(right, self.arena, COLORS["imaging_wall"])
        for q in ln.meas_point[ln.meas_signal][:k]:
            cv.circle(right, q, 1.4, COLORS["imaging_point"], cv.line)
        self._markers(right, estimate)

    def _markers(self, img, estimate) -> None:
        """The true source and the estimate, on top of the path and the measurements."""
        if self.source is not None:
            self.canvas.marker(img, self.source, COLORS["source"], cv2.MARKER_STAR, 4.0)
        if estimate is not None:
            self.canvas.marker(img, estimate, COLORS["estimate"], cv2.MARKER_DIAMOND, 4.0)

    def _header(self, t: float) -> None:
        ln, lay = self.line, self.layout
        self.frame[:lay.header] = COLORS["header"]
        text = _status_text(self.strategy, t, self.drawn["meas"],
                            float(np.interp(t, ln.times, ln.travelled)))
        cv2.putText(self.frame, text, (6, lay.header - 6), cv2.FONT_HERSHEY_SIMPLEX,
                    lay.font_scale, COLORS["text"], 1, cv2.LINE_AA)


def _frame_times(end: float, fps: int, speedup: float) -> np.ndarray:
    """Simulated times of the frames: every ``speedup / fps`` s up to `end`, then `end`
    held for one second of video."""
    dt = speedup / fps
    n = int(np.floor(end / dt + 1e-9)) + 1
    return np.concatenate([np.arange(n) * dt, np.full(fps, end)])


def write_video(path, episode: Episode, arena: Arena, floor_image: np.ndarray, *, imaging=None,
                fps: int = 20, speedup: float = 4.0, px_per_cm: float = 4.0,
                progress: bool = False) -> Path:
    """Write an MP4 video of a car search episode.

    Left: the floor seen from above with the car (true pose, 7 x 3.8 cm, heading mark),
    its true path so far (blue; green for the gradient strategy), on an unknown map the
    walls the car plans on at that time (purple for its believed walls, olive while it
    drives on its scanned walls; the true ones stay dark grey), the current planned
    path (light), the camera's estimate of the car (cyan cross), measurement points (red
    circles), re-plans (small light-blue rings), collisions (orange crosses), the true
    source (green star), the strategy's estimate (magenta diamond) and its next target
    (black cross). Right, when `imaging` is given: ``P`` after the latest completed
    signal measurement (JET colours, black off the mesh) with the measurement points
    (white), the estimate and the source. A header line gives the strategy, simulated
    time, measurements taken and path driven.

    Parameters
    ----------
    path : str or Path
        Output file; must end in ``.mp4``. Parent folders are created.
    episode : Episode
        A car episode: its trace records carry ``times``, ``true_poses`` and so on
        (see :class:`reciprocity.platforms.car.CarPlatform`), and on an unknown map
        ``maps``: ``{time, walls, obstacles}`` each time the walls the car plans on
        change. Records may hold lists instead of arrays (a trace read back from JSON).
    arena : Arena
        The arena of the episode (walls, obstacles and bounds).
    floor_image : ndarray of uint8, shape (H, W)
        The floor, row 0 at the top, covering ``arena.bounds`` at any resolution
        (e.g. ``arenas.Floor.image``).
    imaging : object, optional
        The strategy's :class:`~reciprocity.beliefs.imaging.ImagingMap`, or anything with
        ``nodes`` (N, 2) cm, ``triangles`` (M, 3) and ``first(k).values()`` (N,) in
        [0, 1]. Adds the right panel.
    fps : int
        Frames per second of the video.
    speedup : float
        Simulated seconds per second of video.
    px_per_cm : float
        Resolution of each panel.
    progress : bool
        Show a tqdm progress bar.

    Returns
    -------
    Path
        `path`.

    Raises
    ------
    SearchError
        If `path` does not end in ``.mp4``, the episode has no car trace (e.g. a
        point-observer episode), an argument is invalid, or the video cannot be written.

    Notes
    -----
    Frames are taken at simulated times ``0, speedup/fps, 2 speedup/fps, ...`` up to the
    end of the last trace record; the final state is then held for one second, so a
    video has ``floor(T fps / speedup) + 1 + fps`` frames for an episode of ``T`` s.
    Poses are interpolated linearly between camera frames.

    Examples
    --------
    >>> from reciprocity.viz.video import write_video
    >>> write_video("run.mp4", episode, arena, episode.truth["floor"].image,   # doctest: +SKIP
    ...             imaging=episode.belief.get("imaging"))
    """
    path = Path(path)
    if path.suffix.lower() != ".mp4":
        raise SearchError(f"the video path must end in .mp4; got {str(path)!r}")
    if int(fps) != fps or fps < 1:
        raise SearchError(f"fps must be a positive whole number; got {fps!r}")
    for name, val in (("speedup", speedup), ("px_per_cm", px_per_cm)):
        if not np.isfinite(val) or val <= 0:
            raise SearchError(f"{name} must be a positive number; got {val!r}")
    fps = int(fps)
    line = _timeline(episode.trace)
    source = _optional_point(episode.summary.get("source"))
    strategy = str(episode.summary.get("strategy", "search"))
    canvas = _Canvas(arena, float(px_per_cm))
    background = _floor_panel(canvas, arena, floor_image)
    raster = None if imaging is None else _ImagingRaster(imaging, canvas)
    sample = _status_text(strategy, line.end, len(line.meas_time), line.travelled[-1])
    layout = _Layout.for_panels(canvas, raster is not None, sample)
    renderer = _Renderer(line, arena, canvas, background, raster, layout, strategy, source)
    times = _frame_times(line.end, fps, float(speedup))

    path.parent.mkdir(parents=True, exist_ok=True)
    frames = (renderer.render(float(t)) for t in tqdm(times, desc="video", unit="frame",
                                                       disable=not progress, leave=False))
    encode_mp4(path, frames, layout.size, fps)
    return path


def encode_mp4(path: Path, frames, size: tuple[int, int], fps: int) -> None:
    """Write BGR frames as H.264 (yuv420p, which browsers play) through the ffmpeg that
    imageio-ffmpeg ships; OpenCV's MPEG-4 Part 2 writer when that is not available."""
    try:
        import imageio_ffmpeg
        imageio_ffmpeg.get_ffmpeg_exe()
    except (ImportError, RuntimeError):
        imageio_ffmpeg = None
    if path.is_dir() or not os.access(path.parent, os.W_OK):
        raise SearchError(f"cannot open {str(path)!r} for writing a video: it is a folder, or its "
                          "folder is not writable")
    if imageio_ffmpeg is not None:
        w, h = size
        even = (w + w % 2, h + h % 2)  # yuv420p needs even sides
        writer = imageio_ffmpeg.write_frames(str(path), even, fps=fps, codec="libx264",
                                             pix_fmt_out="yuv420p", quality=7, macro_block_size=1,
                                             output_params=["-movflags", "+faststart"])
        writer.send(None)
        try:
            for frame in frames:
                rgb = np.ascontiguousarray(frame[:, :, ::-1])
                if rgb.shape[:2] != (even[1], even[0]):
                    rgb = np.pad(rgb, ((0, even[1] - h), (0, even[0] - w), (0, 0)), mode="edge")
                writer.send(rgb)
        except OSError as exc:
            raise SearchError(f"cannot write the video {str(path)!r}: {str(exc).splitlines()[0]}") from None
        finally:
            writer.close()
        return
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, size)
    if not writer.isOpened():
        raise SearchError(f"cannot open {str(path)!r} for writing an mp4v video: check the "
                          "folder is writable and OpenCV was built with an MP4 encoder")
    try:
        for frame in frames:
            writer.write(frame)
    finally:
        writer.release()
