"""The overhead camera: renders the car's ArUco tag and measures its pose.

The testbed of Landa et al. (section V) tracks the micro-car with an overhead camera
reading an identification tag on top of the car. Here the camera is orthographic and
looks straight down over the arena's bounding box. The car is drawn as a dark
rectangle carrying a white-bordered ArUco marker whose "up" edge points along the
car's heading; :meth:`OverheadCamera.observe` renders a noisy frame and measures the
pose with OpenCV's :class:`cv2.aruco.ArucoDetector`.

Rendering is exact area sampling: the car sprite is built once from the marker's
module grid with analytic pixel coverage, and each frame only warps it
(``warpAffine``) into the pixels around the car. With a predicted position, the tag is
searched for first in a small square around it, then in the tracking window, then in
the full frame, so a tracked observation costs a fraction of a millisecond.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.special import ndtri

from .errors import ArenaError
from .frames import pixel_to_world, world_to_pixel
from .geometry import Arena

__all__ = ["FOCUS_MARGIN", "Observation", "OverheadCamera"]

#: Grey levels of the default floor, the obstacles and the car body.
FLOOR_GREY, OBSTACLE_GREY, CAR_GREY = 150, 60, 35

#: How far (cm) the tag may be from the predicted position and still be found by the
#: first, smallest search around it.
FOCUS_MARGIN = 1.5

_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, eq=False)
class Observation:
    """One camera measurement of the car.

    Attributes
    ----------
    pose : ndarray, shape (3,)
        Estimated ``(x, y, theta)``: tag centre in cm, heading in radians in [0, 2 pi).
    corners : ndarray, shape (4, 2)
        Detected marker corners in full-frame pixels ``(col, row)``, in the marker's
        own order (top-left, top-right, bottom-right, bottom-left, the top edge at the
        car's front).
    time : float or None
        Time of the frame, s, when the caller gave one.
    """

    pose: np.ndarray
    corners: np.ndarray
    time: float | None = None


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _affine(transform) -> np.ndarray:
    """The 3 x 3 matrix of an affine map of the plane given as a function of (n, 2) points."""
    o, ex, ey = transform([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    return np.array([[*(ex - o), 0.0], [*(ey - o), 0.0], [*o, 1.0]]).T


def _coverage(edges_lo: np.ndarray, edges_hi: np.ndarray, n: int) -> np.ndarray:
    """Fraction of each of `n` unit pixels ``[j, j + 1)`` covered by each interval
    ``[lo, hi)``: shape (len(lo), n)."""
    j = np.arange(n, dtype=float)
    lo, hi = np.asarray(edges_lo, float)[:, None], np.asarray(edges_hi, float)[:, None]
    return np.clip(np.minimum(j + 1, hi) - np.maximum(j, lo), 0.0, 1.0)


class OverheadCamera:
    """An orthographic camera over the arena that finds the car's ArUco tag.

    Parameters
    ----------
    arena : Arena
        The arena; the camera covers ``arena.bounds``.
    background : ndarray, optional
        uint8 grey image of the floor (any resolution, row 0 at the top, covering the
        arena bounds), resized once to the camera resolution. Default: a plain
        mid-grey floor with the obstacles drawn dark.
    px_per_cm : float
        Resolution, pixels per cm.
    rate : float
        Frame rate, Hz. :meth:`observe` does not enforce it; the caller takes one
        observation every ``1 / rate`` s (:attr:`period`).
    tag_size : float
        Side of the marker's black square, cm. A white border surrounds it.
    tag_id : int
        Marker id in `dictionary`.
    dictionary : str
        Name of an OpenCV predefined ArUco dictionary (``cv2.aruco.DICT_*``).
    pixel_noise : float
        Standard deviation of the Gaussian noise added to each pixel, grey levels.
    car_length, car_width : float
        Size of the car body drawn around the tag, cm.
    window : float
        Side of the square tracking window searched around a predicted position, cm.

    Attributes
    ----------
    shape : tuple of int
        Frame shape ``(rows, cols)``.
    cm_per_px : float
        Pixel side, cm.
    origin : tuple of float
        World coordinates (cm) of the frame's lower-left corner.
    period : float
        ``1 / rate``, s.
    background : ndarray of uint8, shape `shape`
        The floor as the camera sees it, without the car.

    Notes
    -----
    The detector uses contour corner refinement (line fits to the marker's edges),
    accepts only candidates with about the tag's perimeter and, when the marker's
    modules are at least 3 px wide, a single adaptive-threshold window about the
    tag's size. The tag is sharp and the camera has no lens distortion or motion blur.
    Below 3 px per module detection becomes unreliable; keep
    ``tag_size * px_per_cm >= 3 * (marker bits + 2)``. The pose error and the share of
    poses found, measured: ``docs/testbed.md`` (*The camera, the car and the sensor*).

    Examples
    --------
    >>> import numpy as np, arenas
    >>> cam = arenas.OverheadCamera(arenas.load("paper"))
    >>> obs = cam.observe((70.0, 30.0, 1.0), np.random.default_rng(0), near=(71.0, 29.0))
    >>> bool(np.hypot(*(obs.pose[:2] - [70.0, 30.0])) < 0.3)
    True
    """

    def __init__(self, arena: Arena, background: np.ndarray | None = None, *,
                 px_per_cm: float = 8.0, rate: float = 30.0, tag_size: float = 3.0,
                 tag_id: int = 7, dictionary: str = "DICT_4X4_50", pixel_noise: float = 4.0,
                 car_length: float = 7.0, car_width: float = 3.8, window: float = 16.0) -> None:
        if not isinstance(arena, Arena):
            raise ArenaError(f"OverheadCamera needs an arenas.Arena; got {type(arena).__name__}")
        for name, value in [("px_per_cm", px_per_cm), ("rate", rate), ("tag_size", tag_size),
                            ("car_length", car_length), ("car_width", car_width),
                            ("window", window)]:
            if not (_is_number(value) and math.isfinite(value) and value > 0):
                raise ArenaError(f"{name} must be a positive finite number; got {value!r}")
        if not (_is_number(pixel_noise) and math.isfinite(pixel_noise) and pixel_noise >= 0):
            raise ArenaError(f"pixel_noise must be a finite std >= 0 (grey levels); got {pixel_noise!r}")
        if not isinstance(dictionary, str) or not dictionary.startswith("DICT_") \
                or not hasattr(cv2.aruco, dictionary):
            raise ArenaError(f"unknown ArUco dictionary {dictionary!r}; use a cv2.aruco name such "
                             "as 'DICT_4X4_50' or 'DICT_6X6_250'")
        self.arena = arena
        self.px_per_cm = float(px_per_cm)
        self.cm_per_px = 1.0 / self.px_per_cm
        self.rate = float(rate)
        self.period = 1.0 / self.rate
        self.tag_size, self.tag_id, self.dictionary = float(tag_size), int(tag_id), dictionary
        self.pixel_noise = float(pixel_noise)
        self.car_length, self.car_width, self.window = float(car_length), float(car_width), float(window)

        self._dict = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, dictionary))
        n_ids = self._dict.bytesList.shape[0]
        if not 0 <= self.tag_id < n_ids:
            raise ArenaError(f"tag_id must be in 0..{n_ids - 1} for {dictionary}; got {tag_id!r}")
        self._detectors: dict[int, cv2.aruco.ArucoDetector] = {}

        (x0, x1), (y0, y1) = arena.bounds
        self.origin = (x0, y0)
        self.shape = (math.ceil((y1 - y0) * self.px_per_cm - 1e-6),
                      math.ceil((x1 - x0) * self.px_per_cm - 1e-6))
        self.background = self._background(background)
        self._background_f32 = self.background.astype(np.float32)
        self._sprite, self._alpha = self._car_sprite()
        # world <-> pixel are affine: their matrices come from arenas.frames, the one
        # place that defines the convention, so the per-frame work stays in small products
        self._world_to_px = _affine(self.to_pixel)
        self._px_to_world = _affine(self.to_world)
        # Gaussian pixel noise by inverse-CDF lookup of 16-bit uniforms: 3x faster than
        # rng.standard_normal, exact to a 2^-16 quantile (tails cut at 4.3 sigma)
        self._noise = (self.pixel_noise * ndtri((np.arange(65536) + 0.5) / 65536)).astype(np.float32)
        rows, cols = self._alpha.shape
        # sprite pixel (col, row) -> car frame (u forward, w left), cm; see _car_sprite
        self._sprite_to_car = np.array([[0.0, -1.0, rows / 2 - 0.5], [-1.0, 0.0, cols / 2 - 0.5],
                                        [0.0, 0.0, self.px_per_cm]]) / self.px_per_cm
        self._sprite_box = np.array([[-0.5, -0.5, 1.0], [cols - 0.5, -0.5, 1.0],
                                     [-0.5, rows - 0.5, 1.0], [cols - 0.5, rows - 0.5, 1.0]]).T
        self._focus = min(self.window, math.sqrt(2) * self.tag_size + 2 * FOCUS_MARGIN)

    # ------------------------------------------------------------------ frames
    def to_pixel(self, points) -> np.ndarray:
        """World points (cm), shape (n, 2), to frame pixels ``(col, row)`` (via
        :func:`arenas.frames.world_to_pixel`)."""
        return world_to_pixel(points, self.cm_per_px, self.shape[0], self.origin)

    def to_world(self, pixels) -> np.ndarray:
        """Frame pixels ``(col, row)``, shape (n, 2), to world points in cm (via
        :func:`arenas.frames.pixel_to_world`)."""
        return pixel_to_world(pixels, self.cm_per_px, self.shape[0], self.origin)

    def _background(self, background) -> np.ndarray:
        rows, cols = self.shape
        if background is None:
            img = np.full(self.shape, FLOOR_GREY, np.uint8)
            polys = [np.round(self.to_pixel(o) * 16).astype(np.int32) for o in self.arena.obstacles]
            if polys:
                cv2.fillPoly(img, polys, OBSTACLE_GREY, lineType=cv2.LINE_AA, shift=4)
            return img
        img = np.asarray(background)
        if img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] in (3, 4) and img.size:
            img = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY if img.shape[2] == 3 else cv2.COLOR_BGRA2GRAY)
        if img.ndim != 2 or img.size == 0 or img.dtype != np.uint8:
            raise ArenaError(f"background must be a non-empty uint8 grey image (rows, cols); got "
                             f"dtype {img.dtype} shape {img.shape} (convert with .astype(np.uint8))")
        shrink = img.shape[0] > rows or img.shape[1] > cols
        return cv2.resize(img, (cols, rows), interpolation=cv2.INTER_AREA if shrink else cv2.INTER_LINEAR)

    def _car_sprite(self) -> tuple[np.ndarray, np.ndarray]:
        """The car seen from above with its front up: the grey level premultiplied by
        coverage, and the coverage, each (rows, cols) float32 (OpenCV warps one
        channel much faster than two).

        Sprite pixel ``(col, row)`` (centre) is the car-frame point
        ``w = (cols / 2 - col - 0.5) / s`` to the left, ``u = (rows / 2 - row - 0.5) / s``
        forward, ``s = px_per_cm``.
        """
        s = self.px_per_cm
        modules = self._dict.markerSize + 2
        margin = max((min(self.car_width, self.car_length) - self.tag_size) / 2,
                     0.5 * self.tag_size / modules)
        half_w = max(self.car_width, self.tag_size + 2 * margin) / 2
        half_l = max(self.car_length, self.tag_size + 2 * margin) / 2
        cols, rows = 2 * math.ceil(half_w * s) + 2, 2 * math.ceil(half_l * s) + 2
        cc, rc = cols / 2, rows / 2

        def box(half_x: float, half_y: float) -> np.ndarray:
            return (_coverage([rc - half_y * s], [rc + half_y * s], rows).T
                    @ _coverage([cc - half_x * s], [cc + half_x * s], cols))

        body = box(self.car_width / 2, self.car_length / 2)
        white = box(self.tag_size / 2 + margin, self.tag_size / 2 + margin)
        alpha = np.maximum(body, white)
        grey = CAR_GREY * body * (1 - white) + 255.0 * white
        # the marker's module grid, area-sampled exactly: M[i, j] spread over pixels
        marker = cv2.aruco.generateImageMarker(self._dict, self.tag_id, modules, borderBits=1)
        side = self.tag_size * s
        lo = np.arange(modules) * side / modules
        by_row = _coverage(rc - side / 2 + lo, rc - side / 2 + lo + side / modules, rows)
        by_col = _coverage(cc - side / 2 + lo, cc - side / 2 + lo + side / modules, cols)
        tag = by_row.T @ np.ones((modules, modules)) @ by_col
        grey = grey * (1 - tag) + by_row.T @ marker.astype(float) @ by_col
        return grey.astype(np.float32), alpha.astype(np.float32)

    def _sprite_to_frame(self, pose) -> np.ndarray:
        """Affine map (2, 3), C-contiguous for OpenCV, from sprite pixels to frame pixels
        for a car at `pose`."""
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)
        car_to_world = np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])
        return (self._world_to_px @ car_to_world @ self._sprite_to_car)[:2].copy()

    # ------------------------------------------------------------------ rendering
    def _window_box(self, center, side: float | None = None) -> tuple[int, int, int, int]:
        """Pixel box ``(col0, row0, col1, row1)`` of the square of `side` cm (default the
        tracking window) around `center` (cm), clipped to the frame (possibly empty)."""
        n = max(1, round((self.window if side is None else side) * self.px_per_cm))
        m = self._world_to_px
        col = m[0, 0] * center[0] + m[0, 1] * center[1] + m[0, 2]
        row = m[1, 0] * center[0] + m[1, 1] * center[1] + m[1, 2]
        c0, r0 = math.floor(col + 0.5 - n / 2), math.floor(row + 0.5 - n / 2)
        rows, cols = self.shape
        return max(c0, 0), max(r0, 0), min(c0 + n, cols), min(r0 + n, rows)

    def _render_box(self, pose, box, rng: np.random.Generator | None) -> np.ndarray:
        """The pixels ``box = (col0, row0, col1, row1)`` of a frame with the car at `pose`."""
        c0, r0, c1, r1 = box
        out = self._background_f32[r0:r1, c0:c1].copy()
        m = self._sprite_to_frame(pose)
        cols, rows = (m @ self._sprite_box).tolist()
        bc0, br0 = max(math.floor(min(cols)) - 1, c0), max(math.floor(min(rows)) - 1, r0)
        bc1, br1 = min(math.ceil(max(cols)) + 2, c1), min(math.ceil(max(rows)) + 2, r1)
        if bc1 > bc0 and br1 > br0:  # only the pixels the car can touch are warped
            m[:, 2] -= (bc0, br0)
            size = (bc1 - bc0, br1 - br0)
            roi = out[br0 - r0:br1 - r0, bc0 - c0:bc1 - c0]
            roi *= 1.0 - cv2.warpAffine(self._alpha, m, size, flags=cv2.INTER_LINEAR)
            roi += cv2.warpAffine(self._sprite, m, size, flags=cv2.INTER_LINEAR)
        if rng is not None and self.pixel_noise > 0:
            out += self._noise[rng.integers(0, 65536, out.shape, dtype=np.uint16)]
        np.clip(out, 0, 255, out=out)
        return np.rint(out, out=out).astype(np.uint8)

    def render(self, pose, window: tuple | None = None,
               rng: np.random.Generator | None = None) -> np.ndarray:
        """A grey frame with the car at `pose`.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Car pose ``(x, y, theta)``: cm, cm, radians.
        window : tuple (x, y), optional
            Render only the square tracking window of side :attr:`window` cm around this
            point (cm), clipped to the frame (it can be smaller near the edges, or
            empty outside the frame).
        rng : numpy.random.Generator, optional
            Draws the Gaussian pixel noise (std :attr:`pixel_noise`); None renders the
            noise-free image.

        Returns
        -------
        ndarray of uint8, shape (rows, cols)
            The frame (row 0 at the top) or the window crop.
        """
        p = self._pose(pose)
        box = (0, 0, self.shape[1], self.shape[0]) if window is None else self._window_box(
            self._point(window, "window"))
        return self._render_box(p, box, rng)

    def frame(self, pose, trail=None, overlay=None) -> np.ndarray:
        """A noise-free colour frame for videos and figures.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Car pose ``(x, y, theta)``.
        trail : array_like, shape (n, 2), optional
            World points (cm) drawn as a red polyline, e.g. the path driven so far.
        overlay : ndarray, optional
            uint8 grey or BGR image covering the arena bounds (any resolution, row 0
            at the top), e.g. an imaging map, blended half-and-half over the floor.

        Returns
        -------
        ndarray of uint8, shape (rows, cols, 3)
            BGR image.
        """
        bgr = cv2.cvtColor(self._render_box(self._pose(pose), (0, 0, self.shape[1], self.shape[0]),
                                            None), cv2.COLOR_GRAY2BGR)
        if overlay is not None:
            over = np.asarray(overlay)
            if over.dtype != np.uint8 or over.ndim not in (2, 3) or over.size == 0:
                raise ArenaError(f"overlay must be a uint8 grey or BGR image; got dtype "
                                 f"{over.dtype} shape {over.shape}")
            if over.ndim == 2:
                over = cv2.cvtColor(over, cv2.COLOR_GRAY2BGR)
            over = cv2.resize(over[:, :, :3], (self.shape[1], self.shape[0]),
                              interpolation=cv2.INTER_LINEAR)
            bgr = cv2.addWeighted(bgr, 0.5, over, 0.5, 0.0)
        if trail is not None:
            pts = np.asarray(trail, dtype=float).reshape(-1, 2)
            if len(pts) >= 2:
                px = np.round(self.to_pixel(pts) * 16).astype(np.int32)
                cv2.polylines(bgr, [px], False, (0, 0, 255), 2, cv2.LINE_AA, shift=4)
        return bgr

    # ------------------------------------------------------------------ measuring
    def _detector(self, size: int) -> cv2.aruco.ArucoDetector:
        """The ArUco detector tuned for this tag in images whose larger side is `size` px."""
        if size not in self._detectors:
            params = cv2.aruco.DetectorParameters()
            # contour refinement fits lines to the marker edges: unbiased headings
            # (sub-pixel corner refinement gave a ~1 degree orientation-dependent bias)
            params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_CONTOUR
            tag_px = self.tag_size * self.px_per_cm
            if tag_px >= 3 * (self._dict.markerSize + 2):
                # modules of >= 3 px: one thresholding pass with a window about the tag's
                # size finds it as reliably as OpenCV's three, in a third of the time
                win = 2 * max(1, round(0.35 * tag_px)) + 1
                params.adaptiveThreshWinSizeMin = params.adaptiveThreshWinSizeMax = win
            # the threshold offset stays above the pixel noise (the tag's contrast is
            # ~200 grey levels), and candidates must have about the tag's perimeter (the
            # limits are relative to the image size): noise specks and floor contours
            # are dropped before the costly identification, 5-10x faster in a window
            params.adaptiveThreshConstant = max(7.0, 3.5 * self.pixel_noise)
            params.minMarkerPerimeterRate = 0.5 * 4 * tag_px / size
            params.maxMarkerPerimeterRate = 2.0 * 4 * tag_px / size
            self._detectors[size] = cv2.aruco.ArucoDetector(self._dict, params)
        return self._detectors[size]

    def _detect(self, image: np.ndarray, offset) -> np.ndarray | None:
        if image.size == 0:
            return None
        corners, ids, _ = self._detector(max(image.shape)).detectMarkers(image)
        if ids is None:
            return None
        for c, i in zip(corners, ids.ravel()):
            if i == self.tag_id:
                return c.reshape(4, 2).astype(float) + offset
        return None

    def pose_from_corners(self, corners) -> np.ndarray:
        """Car pose ``(x, y, theta)`` from marker corners in full-frame pixels.

        The position is the mean of the four corners (the tag centre). The heading
        averages the front direction (bottom edge to top edge) and the right direction
        (left edge to right edge) turned a quarter to the left, all in world
        coordinates (:func:`arenas.frames.pixel_to_world`).
        """
        (a, b, tx), (c, d, ty) = self._px_to_world[:2].tolist()
        (x0, y0), (x1, y1), (x2, y2), (x3, y3) = [
            (a * u + b * v + tx, c * u + d * v + ty)
            for u, v in np.asarray(corners, dtype=float).reshape(4, 2).tolist()]
        front = (x0 + x1 - x2 - x3, y0 + y1 - y2 - y3)
        right = (x1 + x2 - x0 - x3, y1 + y2 - y0 - y3)
        heading = math.atan2(front[1] + right[0], front[0] - right[1]) % _TWO_PI
        return np.array([(x0 + x1 + x2 + x3) / 4, (y0 + y1 + y2 + y3) / 4, heading])

    def observe(self, pose, rng: np.random.Generator, near=None, *,
                time: float | None = None) -> Observation | None:
        """Take a noisy frame of the car at `pose` and measure its pose from the tag.

        Parameters
        ----------
        pose : array_like, shape (3,)
            True car pose ``(x, y, theta)``.
        rng : numpy.random.Generator
            Draws the pixel noise.
        near : array_like (x, y), optional
            Predicted position (cm). The tag is searched for in a small square around
            it (side: the tag's diagonal plus 2 x :data:`FOCUS_MARGIN` cm), then in the
            tracking window of side :attr:`window` cm, then in the full frame; each
            retry renders a new noisy frame. Without `near`, the full frame (slow: its
            time against tracking is in ``docs/testbed.md``).
        time : float, optional
            Time stamp copied into the observation, s.

        Returns
        -------
        Observation or None
            None when the tag is not found (e.g. outside the frame); the controller
            then dead-reckons.
        """
        if not isinstance(rng, np.random.Generator):
            raise ArenaError(f"rng must be a numpy.random.Generator; got {type(rng).__name__}")
        p = self._pose(pose)
        corners = None
        if near is not None:
            center = self._point(near, "near")
            for side in (self._focus, self.window):
                box = self._window_box(center, side)
                corners = self._detect(self._render_box(p, box, rng), box[:2])
                if corners is not None or side >= self.window:
                    break
        if corners is None:
            corners = self._detect(self._render_box(p, (0, 0, self.shape[1], self.shape[0]), rng),
                                   (0, 0))
        if corners is None:
            return None
        return Observation(self.pose_from_corners(corners), corners,
                           None if time is None else float(time))

    # ------------------------------------------------------------------ validation
    @staticmethod
    def _pose(pose) -> tuple[float, float, float]:
        p = np.asarray(pose, dtype=float).ravel()
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ArenaError(f"pose must be three finite numbers (x cm, y cm, theta rad); got {pose!r}")
        return float(p[0]), float(p[1]), float(p[2])

    @staticmethod
    def _point(point, name: str) -> np.ndarray:
        p = np.asarray(point, dtype=float).ravel()
        if p.shape not in [(2,), (3,)] or not np.all(np.isfinite(p)):
            raise ArenaError(f"{name} must be a finite point (x, y) in cm; got {point!r}")
        return p[:2]
