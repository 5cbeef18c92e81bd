"""Arenas drawn as pictures: a floor plan image plus a scale becomes polygons."""

from __future__ import annotations

import math
from numbers import Real
from pathlib import Path

import cv2
import numpy as np

from .errors import ArenaError
from .frames import pixel_to_world
from .geometry import MAX_COORD_CM, Arena

__all__ = ["from_image", "MAX_PIXELS", "MAX_IMAGE_BYTES"]

#: Most pixels of a floor plan (a 4096 x 4096 picture).
MAX_PIXELS = 4096 * 4096
#: Largest image file read, bytes.
MAX_IMAGE_BYTES = 64 * 2**20


def _number(value, key: str, lo: float, hi: float, *, open_lo: bool = False) -> float:
    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)) \
        and (float(value) > lo if open_lo else float(value) >= lo) and float(value) <= hi
    if not ok:
        raise ArenaError(f"{key} must be a number in {'(' if open_lo else '['}{lo:g}, {hi:g}]; got {value!r}")
    return float(value)


def _read_image(path: Path) -> np.ndarray:
    """The grey pixels of an image file: a regular file of bounded size whose header
    OpenCV accepts."""
    if not path.is_file():
        what = "a folder" if path.is_dir() else "missing" if not path.exists() else "not a regular file"
        raise ArenaError(f"cannot read image {str(path)!r}: {what}")
    if path.stat().st_size > MAX_IMAGE_BYTES:
        raise ArenaError(f"image {str(path)!r} has more than {MAX_IMAGE_BYTES} bytes")
    try:
        img = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    except cv2.error as exc:  # e.g. a header claiming more pixels than OpenCV allows
        raise ArenaError(f"cannot read image {str(path)!r}: {str(exc).strip().splitlines()[-1]}") from None
    if img is None:
        raise ArenaError(f"cannot read image {str(path)!r}: not an image OpenCV can decode")
    return img


def _grey(img: np.ndarray) -> np.ndarray:
    """A grey uint8 picture from a 2-D grey, 3-D BGR or BGRA array of numbers 0-255."""
    if img.dtype.kind not in "uifb" or img.ndim not in (2, 3) or img.size == 0 or (
            img.ndim == 3 and img.shape[2] not in (3, 4)):
        raise ArenaError(f"image must be a 2-D grey or 3-D colour (3 or 4 channels) array of numbers; got "
                         f"shape {img.shape} of {img.dtype}")
    if not np.all(np.isfinite(img)):
        raise ArenaError("image has NaN or infinite pixels; give grey levels 0-255")
    img = np.clip(img, 0, 255).astype(np.uint8)
    if img.ndim == 3:
        img = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY if img.shape[2] == 3 else cv2.COLOR_BGRA2GRAY)
    return img


def from_image(image, cm_per_px: float, *, threshold: int = 128, simplify_cm: float = 0.5,
               min_area_cm2: float = 1.0, name: str | None = None, **scenario) -> Arena:
    """Build an arena from a black-and-white (or grey) floor-plan picture.

    The image frame is the outer boundary; dark pixels (grey below `threshold`) are
    obstacles. Each dark blob's outer contour (OpenCV ``findContours``) is simplified
    with the Douglas-Peucker tolerance `simplify_cm`; holes inside a blob are filled
    (an enclosed pocket is unreachable anyway).

    Parameters
    ----------
    image : str, os.PathLike or ndarray
        Path of an image file readable by OpenCV (at most 64 MB), or a 2-D (grey) / 3-D
        (BGR or BGRA) array; at most 4096 x 4096 pixels.
    cm_per_px : float
        Scale: the side of one pixel, cm, in (0, 1e5]; the picture spans at most 1e5 cm.
    threshold : int
        Grey level (0-256) below which a pixel is an obstacle.
    simplify_cm : float
        Polygon simplification tolerance, cm, >= 0.
    min_area_cm2 : float
        Dark blobs smaller than this (specks, cm^2, >= 0) are ignored.
    name : str, optional
        Arena name (default: file stem, or ``"image"``).
    **scenario
        ``source``, ``strength``, ``start`` passed to :meth:`Arena.from_polygons`.

    Returns
    -------
    Arena
    """
    cm_per_px = _number(cm_per_px, "cm_per_px", 0.0, MAX_COORD_CM, open_lo=True)
    threshold = _number(threshold, "threshold", 0, 256)
    simplify_cm = _number(simplify_cm, "simplify_cm", 0.0, MAX_COORD_CM)
    min_area_cm2 = _number(min_area_cm2, "min_area_cm2", 0.0, MAX_COORD_CM**2)
    unknown = set(scenario) - {"source", "strength", "start"}
    if unknown:
        raise ArenaError(f"unknown keyword(s) {', '.join(sorted(unknown))}; choose from source, strength, start")
    if isinstance(image, (str, Path)):
        img = _read_image(Path(image))
        name = name or Path(image).stem
    else:
        img = _grey(np.asarray(image))
    if img.size > MAX_PIXELS:
        raise ArenaError(f"image of {img.shape[1]} x {img.shape[0]} px has more than {MAX_PIXELS} pixels")
    if max(img.shape) * cm_per_px > MAX_COORD_CM:
        raise ArenaError(f"image of {img.shape[1]} x {img.shape[0]} px at {cm_per_px:g} cm/px spans more than "
                         f"{MAX_COORD_CM:g} cm")
    h, w = img.shape
    if min(h, w) < 4:
        raise ArenaError(f"image of {w} x {h} px is too small to hold an arena")
    mask = (img < threshold).astype(np.uint8)
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    obstacles = []
    for c in contours:
        poly = cv2.approxPolyDP(c, simplify_cm / cm_per_px, True)[:, 0, :]
        if len(poly) < 3 or cv2.contourArea(poly) * cm_per_px**2 < min_area_cm2:
            continue
        pts = pixel_to_world(poly, cm_per_px, h)
        # contour points are the centres of the blob's rim pixels: a blob reaching the
        # frame is snapped onto it, so it becomes a wall attached to the boundary
        for k, size in enumerate((w * cm_per_px, h * cm_per_px)):
            pts[pts[:, k] < cm_per_px, k] = 0.0
            pts[pts[:, k] > size - cm_per_px, k] = size
        obstacles.append(pts)
    boundary = [[0, 0], [w * cm_per_px, 0], [w * cm_per_px, h * cm_per_px], [0, h * cm_per_px]]
    return Arena.from_polygons(boundary, obstacles, name=name or "image", **scenario)
