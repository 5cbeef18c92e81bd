"""The painted testbed floor: the signal ``u`` as grey levels, lighter = stronger.

The testbed floor of Landa et al. (section V) is coloured with grey scales according to
the solution of the forward problem, the lightest grey for the strongest signal, and the
obstacles are drawn as light-grey contours (their Fig. 1). :func:`render_floor` paints
such a floor from any field; a :class:`Floor` is the resulting image with its scale, and
the :class:`GreyMapping` that turns signal into grey and back.

Images have row 0 at the top; every conversion to and from world coordinates (cm, y up)
goes through :func:`arenas.frames.world_to_pixel` / :func:`arenas.frames.pixel_to_world`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import cv2
import numpy as np

from .errors import ArenaError
from .frames import pixel_to_world, world_to_pixel
from .geometry import Arena, as_points
from .memo import sized_cache

__all__ = ["FLOOR_FORMAT", "Floor", "GreyMapping", "render_floor"]

#: Tag written into a floor's sidecar JSON, checked on load.
FLOOR_FORMAT = "arenas.floor/1"


@dataclass(frozen=True)
class GreyMapping:
    """Signal ``u`` -> painted grey level (0 black .. 255 white), lighter = stronger.

    ``grey = g_min + (g_max - g_min) * u / u_max``, clipped to ``[g_min, 255]``
    (``u <= 0`` gives ``g_min``). `g_max` is the top of the sensor's working range
    (grey 185, Fig. 3 of Landa et al.): signal above `u_max` is painted lighter still,
    but the sensor cannot tell those greys apart (saturation).

    Parameters
    ----------
    u_max : float
        Signal painted at grey `g_max` (signal units), > 0.
    g_min : float
        Grey of zero (or negative, or missing) signal; also the colour of everything
        outside the free region. Default 40: dark, but on the sensor's sloped part.
    g_max : float
        Grey of signal `u_max`; at most 255.

    Examples
    --------
    >>> m = GreyMapping(u_max=100.0)
    >>> m.grey([0.0, 50.0, 100.0, 1e9]).tolist()
    [40.0, 112.5, 185.0, 255.0]
    >>> float(m.signal(112.5))
    50.0
    """

    u_max: float
    g_min: float = 40.0
    g_max: float = 185.0

    def __post_init__(self):
        for name in ("u_max", "g_min", "g_max"):
            object.__setattr__(self, name, float(getattr(self, name)))
        if not math.isfinite(self.u_max) or self.u_max <= 0:
            raise ArenaError(f"GreyMapping.u_max must be a positive finite signal; got {self.u_max!r}"
                             " (use GreyMapping.for_values to pick it from the field)")
        if not (0.0 <= self.g_min < self.g_max <= 255.0):
            raise ArenaError(f"GreyMapping needs 0 <= g_min < g_max <= 255; got g_min={self.g_min}, "
                             f"g_max={self.g_max}")

    @property
    def slope(self) -> float:
        """Grey levels per unit of signal on the working range."""
        return (self.g_max - self.g_min) / self.u_max

    def grey(self, u) -> np.ndarray:
        """Float grey levels of signal values `u` (any shape); NaN gives `g_min`."""
        u = np.asarray(u, dtype=float)
        g = self.g_min + self.slope * np.where(np.isnan(u), 0.0, u)
        return np.clip(g, self.g_min, 255.0)

    def signal(self, grey) -> np.ndarray:
        """Signal of grey levels (any shape): exact inverse of :meth:`grey` on [g_min, 255].

        Greys below `g_min` give 0; greys above `g_max` give signals above `u_max`
        (which the sensor cannot see: see :class:`arenas.sensor.Calibration`).
        NaN stays NaN.
        """
        g = np.asarray(grey, dtype=float)
        return (np.clip(g, self.g_min, 255.0) - self.g_min) / self.slope

    @classmethod
    def for_values(cls, values, saturated_fraction: float = 1e-3, **kw) -> GreyMapping:
        """The mapping whose `u_max` is the ``1 - saturated_fraction`` quantile of `values`.

        So a small disk around the source (that fraction of the painted area) is
        saturated and everything else lies in the sensor's working range.

        Parameters
        ----------
        values : array_like
            Signal samples, e.g. the field at every free pixel; NaNs are ignored.
        saturated_fraction : float
            Fraction of the values painted above `g_max`, in [0, 1).
        **kw
            ``g_min``, ``g_max`` passed to the constructor.
        """
        if not 0.0 <= saturated_fraction < 1.0:
            raise ArenaError(f"saturated_fraction must be in [0, 1); got {saturated_fraction!r}")
        v = np.asarray(values, dtype=float).ravel()
        v = v[np.isfinite(v)]
        if v.size == 0:
            raise ArenaError("GreyMapping.for_values got no finite values: the field is NaN "
                             "everywhere (is it defined on this arena's free region?)")
        u_max = float(np.quantile(v, 1.0 - saturated_fraction))
        if u_max <= 0:
            raise ArenaError(f"the signal's {1 - saturated_fraction:.4g} quantile is {u_max:.4g} "
                             "<= 0: there is no positive signal to paint; check the field's sign "
                             "and strength")
        return cls(u_max, **kw)


def _disk_offsets(radius_px: float) -> np.ndarray:
    """Equal-area sample offsets (pixels), shape (k, 2), filling a disk (Vogel spiral).

    About four samples per pixel of disk area, so the bilinear averages resolve the
    painted pixels; a disk below a pixel gets a few samples, radius 0 just its centre.
    """
    k = int(min(512, max(1, math.ceil(4 * math.pi * radius_px ** 2))))
    if k == 1:
        return np.zeros((1, 2))
    i = np.arange(k) + 0.5
    r = radius_px * np.sqrt(i / k)
    a = i * math.pi * (3.0 - math.sqrt(5.0))  # golden angle
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


@dataclass(frozen=True, eq=False)
class Floor:
    """A painted floor: a grey image with its scale and signal mapping.

    Build one with :func:`render_floor` or :meth:`Floor.load`.

    Attributes
    ----------
    image : ndarray of uint8, shape (H, W)
        Grey levels, row 0 at the top (the world's high y).
    px_per_cm : float
        Pixels per cm (the testbed at 1 px/mm has 10 px/cm).
    origin : tuple of float
        World ``(x, y)``, cm, of the image's lower-left corner.
    mapping : GreyMapping
        How the signal was painted.
    arena_name : str
        Name of the arena the floor was painted for.
    """

    image: np.ndarray
    px_per_cm: float
    origin: tuple[float, float]
    mapping: GreyMapping
    arena_name: str = "arena"

    def __post_init__(self):
        img = np.asarray(self.image)
        if img.ndim != 2 or img.dtype != np.uint8 or min(img.shape, default=0) < 1:
            raise ArenaError(f"a floor image must be a non-empty 2-D uint8 grey array; got "
                             f"dtype {img.dtype}, shape {img.shape}")
        ppc = float(self.px_per_cm)
        if not math.isfinite(ppc) or ppc <= 0:
            raise ArenaError(f"px_per_cm must be a positive number of pixels per cm; got "
                             f"{self.px_per_cm!r}")
        origin = tuple(float(c) for c in np.asarray(self.origin, dtype=float).ravel())
        if len(origin) != 2 or not all(map(math.isfinite, origin)):
            raise ArenaError(f"origin must be the finite world (x, y) cm of the image's lower-left "
                             f"corner; got {self.origin!r}")
        if not isinstance(self.mapping, GreyMapping):
            raise ArenaError(f"mapping must be a GreyMapping; got {type(self.mapping).__name__}")
        img = np.array(img, order="C")  # a private copy, read-only: a Floor is a value
        img.flags.writeable = False
        object.__setattr__(self, "image", img)
        object.__setattr__(self, "px_per_cm", ppc)
        object.__setattr__(self, "origin", origin)
        object.__setattr__(self, "arena_name", str(self.arena_name))

    # ------------------------------------------------------------------ geometry
    @property
    def cm_per_px(self) -> float:
        """Side of one pixel, cm."""
        return 1.0 / self.px_per_cm

    @property
    def shape(self) -> tuple[int, int]:
        """Image shape ``(H, W)``, pixels."""
        return self.image.shape

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """World rectangle ``(x0, x1, y0, y1)``, cm, covered by the image."""
        h, w = self.image.shape
        x0, y0 = self.origin
        return x0, x0 + w * self.cm_per_px, y0, y0 + h * self.cm_per_px

    def to_pixel(self, points) -> np.ndarray:
        """Fractional pixel ``(col, row)``, shape (n, 2), of world points (n, 2) cm."""
        return world_to_pixel(points, self.cm_per_px, self.image.shape[0], self.origin)

    def to_world(self, pixels) -> np.ndarray:
        """World points (n, 2) cm of pixel ``(col, row)`` positions (n, 2)."""
        return pixel_to_world(pixels, self.cm_per_px, self.image.shape[0], self.origin)

    # ------------------------------------------------------------------ sampling
    def _bilinear(self, pix: np.ndarray) -> np.ndarray:
        """Bilinear grey at fractional pixels (col, row); NaN outside the image rectangle.

        Pixel centres sit at integer indices; between the outermost centres and the
        image edge the edge pixel's value is used.
        """
        h, w = self.image.shape
        col, row = pix[..., 0], pix[..., 1]
        off = ~((col >= -0.5) & (col <= w - 0.5) & (row >= -0.5) & (row <= h - 0.5))
        # snap round-off (1e-9 px) so a pixel centre gives exactly that pixel's grey
        c = np.clip(np.round(np.where(off, 0.0, col), 9), 0.0, w - 1.0)
        r = np.clip(np.round(np.where(off, 0.0, row), 9), 0.0, h - 1.0)
        c0 = np.minimum(np.floor(c).astype(np.intp), max(w - 2, 0))
        r0 = np.minimum(np.floor(r).astype(np.intp), max(h - 2, 0))
        c1, r1 = np.minimum(c0 + 1, w - 1), np.minimum(r0 + 1, h - 1)
        fc, fr = c - c0, r - r0
        img = self.image
        top = img[r0, c0] * (1 - fc) + img[r0, c1] * fc
        bottom = img[r1, c0] * (1 - fc) + img[r1, c1] * fc
        g = top * (1 - fr) + bottom * fr
        g[off] = np.nan
        return g

    def grey_at(self, points) -> np.ndarray:
        """Bilinear grey level at world points.

        Parameters
        ----------
        points : array_like, shape (n, 2) or (2,)
            World points, cm.

        Returns
        -------
        ndarray of float, shape (n,)
            Grey levels 0..255; NaN for points off the image.
        """
        return self._bilinear(self.to_pixel(as_points(points)))

    def signal_at(self, points) -> np.ndarray:
        """The painted signal at world points (n, 2) cm: ``mapping.signal(grey_at)``."""
        return self.mapping.signal(self.grey_at(points))

    def spot_grey(self, centres, radius: float) -> np.ndarray:
        """Mean grey over a disk of `radius` cm around each centre.

        A fixed set of equal-area sample offsets fills the disk (about four per pixel of
        disk area, at most 512); each sample is bilinear. Samples off the image are
        ignored.

        Parameters
        ----------
        centres : array_like, shape (n, 2) or (2,)
            Spot centres, world cm.
        radius : float
            Spot radius, cm (0: the grey at the centre).

        Returns
        -------
        ndarray of float, shape (n,)
            Mean grey; NaN where the whole disk is off the image.
        """
        r = float(radius)
        if not math.isfinite(r) or r < 0:
            raise ArenaError(f"spot radius must be a non-negative number of cm; got {radius!r}")
        pix = self.to_pixel(as_points(centres, "spot centres"))
        offsets = _disk_offsets(r * self.px_per_cm)
        # rows grow downwards, but the disk is symmetric: offsets need no flip
        g = self._bilinear(pix[:, None, :] + offsets[None, :, :])
        n_on = np.sum(~np.isnan(g), axis=1)
        total = np.nansum(g, axis=1)
        return np.where(n_on > 0, total / np.maximum(n_on, 1), np.nan)

    # ------------------------------------------------------------------ files
    def save(self, path) -> Path:
        """Write the image as PNG (lossless) and its metadata as sidecar JSON.

        Parameters
        ----------
        path : str or os.PathLike
            Target ``.png`` file; the sidecar is ``path.with_suffix(".json")``.

        Returns
        -------
        Path
            The PNG path.
        """
        path = Path(path)
        if path.suffix.lower() != ".png":
            raise ArenaError(f"a floor is saved as PNG (lossless); give a path ending in .png, "
                             f"not {path.name!r}")
        if not path.parent.is_dir():
            raise ArenaError(f"cannot save floor: directory {str(path.parent)!r} does not exist")
        if not cv2.imwrite(str(path), self.image):
            raise ArenaError(f"OpenCV could not write {str(path)!r}; check permissions and disk")
        meta = {"format": FLOOR_FORMAT, "px_per_cm": self.px_per_cm, "origin": list(self.origin),
                "mapping": asdict(self.mapping), "arena_name": self.arena_name,
                "shape": list(self.image.shape)}
        path.with_suffix(".json").write_text(json.dumps(meta, indent=2) + "\n")
        return path

    @classmethod
    def load(cls, path) -> Floor:
        """Read a floor written by :meth:`save` (PNG plus sidecar JSON).

        Raises
        ------
        ArenaError
            If the PNG or its sidecar is missing, unreadable or inconsistent, or the
            image is not 8-bit grey.
        """
        path = Path(path)
        if path.suffix.lower() != ".png":
            raise ArenaError(f"floors are stored as PNG plus a .json sidecar; {path.name!r} is not "
                             "a .png file")
        if not path.is_file():
            raise ArenaError(f"floor image {str(path)!r} does not exist")
        img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        if img is None:
            raise ArenaError(f"cannot decode {str(path)!r} as an image: the file is corrupt or not "
                             "a PNG; re-create it with Floor.save")
        if img.ndim != 2 or img.dtype != np.uint8:
            raise ArenaError(f"{str(path)!r} is not an 8-bit grey image (shape {img.shape}, dtype "
                             f"{img.dtype}); floors are single-channel uint8 PNGs from Floor.save")
        side = path.with_suffix(".json")
        if not side.is_file():
            raise ArenaError(f"floor sidecar {str(side)!r} is missing: it holds the scale and the "
                             "signal mapping; keep it next to the PNG (Floor.save writes both)")
        try:
            meta = json.loads(side.read_text())
            if meta.get("format") != FLOOR_FORMAT:
                raise ValueError(f"format tag is {meta.get('format')!r}, expected {FLOOR_FORMAT!r}")
            mapping = GreyMapping(**meta["mapping"])
            px_per_cm, origin = meta["px_per_cm"], meta["origin"]
            name, shape = meta["arena_name"], tuple(meta["shape"])
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise ArenaError(f"floor sidecar {str(side)!r} is corrupt ({exc}); re-create it with "
                             "Floor.save") from exc
        if shape != img.shape:
            raise ArenaError(f"floor image {str(path)!r} is {img.shape} px but its sidecar says "
                             f"{shape}: the two files do not belong together")
        return cls(img, px_per_cm, origin, mapping, name)

    # ------------------------------------------------------------------ figures
    def plot(self, ax=None):
        """Show the floor in world coordinates (cm), grey colormap, 0 black .. 255 white.

        Returns
        -------
        matplotlib.axes.Axes
        """
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots()
        ax.imshow(self.image, cmap="gray", vmin=0, vmax=255, extent=self.extent,
                  origin="upper", interpolation="nearest")
        ax.set_aspect("equal")
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
        ax.set_title(f"floor: {self.arena_name}")
        return ax

    def __repr__(self) -> str:
        h, w = self.image.shape
        return (f"Floor({self.arena_name!r}, {w} x {h} px, {self.px_per_cm:g} px/cm, "
                f"u_max={self.mapping.u_max:.4g})")


def render_floor(arena: Arena, field: Callable, *, px_per_mm: float = 1.0,
                 mapping: GreyMapping | None = None, outline_grey: int = 215,
                 outline_width_mm: float = 4.0, chunk: int = 200_000) -> Floor:
    """Paint the testbed floor of `arena` with the signal `field` (Fig. 1 of Landa et al.).

    The image covers :attr:`Arena.bounds` from its lower-left corner, rounded up to
    whole pixels (exactly, when the sides are multiples of the pixel size). Free pixels (pixel centre in the free
    region) get ``mapping.grey(field)``; all other pixels get ``mapping.g_min``. The
    boundary and every obstacle outline are then drawn on top as closed polylines of
    grey `outline_grey` (OpenCV, 8-connected, no anti-aliasing).

    Parameters
    ----------
    arena : Arena
        The arena (cm).
    field : callable
        ``field(points) -> values``: (n, 2) world points (cm) in, n signal values out,
        NaN outside the free region (e.g. ``reciprocity.GreenSolver(...).field(...)``).
        It is called on the free pixel centres only, `chunk` points at a time.
    px_per_mm : float
        Resolution, pixels per mm (the default 1 gives 1400 x 1400 px for 140 cm).
    mapping : GreyMapping, optional
        Signal to grey. Default: :meth:`GreyMapping.for_values` over the free pixels.
    outline_grey : int
        Grey level of the walls, 0..255 (default 215: light grey, above the sensor's
        knee, so a sensor over a wall reads saturated).
    outline_width_mm : float
        Line width of the walls, mm (at least one pixel is drawn).
    chunk : int
        Points per call of `field`, to bound memory.

    Returns
    -------
    Floor

    Examples
    --------
    >>> import arenas
    >>> a = arenas.Arena.from_polygons([[0, 0], [20, 0], [20, 20], [0, 20]])
    >>> floor = render_floor(a, lambda p: 100 - p[:, 0], px_per_mm=0.5)
    >>> floor.image.shape
    (100, 100)
    """
    if not isinstance(arena, Arena):
        raise ArenaError(f"render_floor needs an arenas.Arena (see arenas.load); got "
                         f"{type(arena).__name__}")
    if not callable(field):
        raise ArenaError(f"field must be callable as field(points (n, 2) cm) -> n values; got "
                         f"{type(field).__name__}")
    ppmm = float(px_per_mm)
    if not math.isfinite(ppmm) or ppmm <= 0:
        raise ArenaError(f"px_per_mm must be a positive resolution in pixels per mm; got "
                         f"{px_per_mm!r}")
    if not (isinstance(outline_grey, (int, np.integer)) and 0 <= outline_grey <= 255):
        raise ArenaError(f"outline_grey must be an integer grey level 0..255; got {outline_grey!r}")
    if not math.isfinite(outline_width_mm) or outline_width_mm < 0:
        raise ArenaError(f"outline_width_mm must be a non-negative width in mm; got "
                         f"{outline_width_mm!r}")
    if int(chunk) < 1:
        raise ArenaError(f"chunk must be a positive number of points; got {chunk!r}")

    px_per_cm = 10.0 * ppmm
    (x0, x1), (y0, y1) = arena.bounds
    # round to whole pixels, but a hair of floating-point excess must not add a column
    w = max(1, math.ceil((x1 - x0) * px_per_cm - 1e-6))
    h = max(1, math.ceil((y1 - y0) * px_per_cm - 1e-6))
    cm_per_px = 1.0 / px_per_cm
    origin = (x0, y0)

    free, free_centres = free_pixels(arena.without_scenario(), px_per_cm)
    values = _evaluate(field, free_centres, int(chunk))
    if mapping is None:
        mapping = GreyMapping.for_values(values)
    elif not isinstance(mapping, GreyMapping):
        raise ArenaError(f"mapping must be a GreyMapping or None; got {type(mapping).__name__}")

    image = np.full(h * w, np.uint8(round(mapping.g_min)), dtype=np.uint8)
    image[free] = np.rint(mapping.grey(values)).astype(np.uint8)
    image = image.reshape(h, w)

    shift = 4  # sub-pixel vertex positions: OpenCV fixed point with 4 fractional bits
    thickness = max(1, round(outline_width_mm * ppmm))
    polylines = [np.rint(world_to_pixel(p, cm_per_px, h, origin) * (1 << shift)).astype(np.int32)
                 for p in [arena.boundary, *arena.obstacles]]
    cv2.polylines(image, polylines, isClosed=True, color=int(outline_grey), thickness=thickness,
                  lineType=cv2.LINE_8, shift=shift)
    return Floor(image, px_per_cm, origin, mapping, arena.name)


#: Bytes of free-pixel grids kept per process (a 140 cm arena at 1 px/mm: 2 MB of mask and
#: 27 MB of pixel centres).
FREE_PIXELS_BYTES = 96 * 2**20


@sized_cache(FREE_PIXELS_BYTES, maxsize=4)
def free_pixels(arena: Arena, px_per_cm: float) -> tuple[np.ndarray, np.ndarray]:
    """The pixels of a floor image of `arena` whose centres lie in its free region.

    Depends on the walls and the resolution only, so the floors of one arena painted with
    different fields (a campaign's episodes: one source each) share it (cached per process).

    Parameters
    ----------
    arena : Arena
        The arena (cm); its scenario (source, start) plays no part.
    px_per_cm : float
        Resolution, pixels per cm.

    Returns
    -------
    free : numpy.ndarray
        (h * w,) bool, row-major over the image (row 0 at the top).
    centres : numpy.ndarray
        (n_free, 2) the free pixels' centres, cm, in the order of ``free``'s true entries.
        Both arrays are read-only.
    """
    (x0, x1), (y0, y1) = arena.bounds
    w = max(1, math.ceil((x1 - x0) * px_per_cm - 1e-6))
    h = max(1, math.ceil((y1 - y0) * px_per_cm - 1e-6))
    # a pixel's centre: its column's x and its row's y (pixel_to_world of (k, k) gives both)
    k = np.arange(max(h, w))
    line = pixel_to_world(np.column_stack([k, k]), 1.0 / px_per_cm, h, (x0, y0))
    xs, ys = line[:w, 0].copy(), line[:h, 1].copy()

    def centres(idx: np.ndarray) -> np.ndarray:
        return np.column_stack([xs[idx % w], ys[idx // w]])

    free = _free_centres(arena, px_per_cm, (h, w), centres)
    inside = np.ascontiguousarray(centres(np.flatnonzero(free)))
    free.setflags(write=False)
    inside.setflags(write=False)
    return free, inside


#: Half-width (pixels) of the band along the walls where :func:`_free_centres` asks
#: :meth:`Arena.contains` itself; beyond it the raster's answer cannot differ.
WALL_BAND_PX = 3


def _free_centres(arena: Arena, px_per_cm: float, shape: tuple[int, int],
                  centres: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """``arena.contains`` of the centres of every pixel of an image of `shape` (row-major;
    `centres` gives those of the pixels it is given): the free region rasterised (even-odd
    over its rings, at 1/16 pixel), and the pixels within :data:`WALL_BAND_PX` of a wall
    decided by ``contains`` itself, so the answer is the same to the pixel and most pixels
    never reach shapely."""
    import shapely
    geom = arena.free_region
    parts = list(geom.geoms) if isinstance(geom, shapely.MultiPolygon) else [geom]
    if not all(isinstance(g, shapely.Polygon) for g in parts):
        return np.asarray(arena.contains(centres(np.arange(shape[0] * shape[1]))), dtype=bool)
    (x0, _), (y0, _) = arena.bounds
    mask = np.zeros(shape, np.uint8)
    band = np.zeros(shape, np.uint8)
    for ring in [r for g in parts for r in (g.exterior, *g.interiors)]:
        px = np.round(world_to_pixel(np.asarray(ring.coords)[:-1], 1.0 / px_per_cm, shape[0],
                                     (x0, y0)) * 16).astype(np.int32)
        fill = np.zeros(shape, np.uint8)
        cv2.fillPoly(fill, [px], 1, lineType=cv2.LINE_8, shift=4)
        mask ^= fill
        cv2.polylines(band, [px], True, 1, thickness=2 * WALL_BAND_PX + 1, lineType=cv2.LINE_8,
                      shift=4)
    free = mask.ravel().astype(bool)
    near = np.flatnonzero(band.ravel())
    free[near] = arena.contains(centres(near))
    return free


def _evaluate(field: Callable, points: np.ndarray, chunk: int) -> np.ndarray:
    """``field`` at `points` (n, 2), `chunk` points per call, checked to give n numbers."""
    out = np.empty(len(points))
    for start in range(0, len(points), chunk):
        part = points[start:start + chunk]
        try:
            v = np.asarray(field(part), dtype=float)
        except (TypeError, ValueError) as exc:
            raise ArenaError(f"field(points) must return {len(part)} numbers for {len(part)} "
                             f"points; it returned something else ({exc})") from exc
        if v.shape != (len(part),):
            raise ArenaError(f"field(points) returned shape {v.shape} for points of shape "
                             f"{part.shape}; it must return one value per point, shape "
                             f"({len(part)},)")
        out[start:start + chunk] = v
    return out
