"""Arenas drawn as pictures: a floor plan image plus a scale becomes polygons."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from .errors import ArenaError
from .frames import pixel_to_world
from .geometry import Arena

__all__ = ["from_image"]


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
        Path of an image file readable by OpenCV, or a 2-D (grey) / 3-D (BGR) array.
    cm_per_px : float
        Scale: the side of one pixel, cm.
    threshold : int
        Grey level (0-255) below which a pixel is an obstacle.
    simplify_cm : float
        Polygon simplification tolerance, cm.
    min_area_cm2 : float
        Dark blobs smaller than this (specks, cm^2) are ignored.
    name : str, optional
        Arena name (default: file stem, or ``"image"``).
    **scenario
        ``source``, ``strength``, ``start`` passed to :meth:`Arena.from_polygons`.

    Returns
    -------
    Arena
    """
    if not np.isfinite(cm_per_px) or cm_per_px <= 0:
        raise ArenaError(f"cm_per_px must be a positive scale (cm per pixel); got {cm_per_px!r}")
    if isinstance(image, (str, Path)):
        img = cv2.imread(str(image), cv2.IMREAD_GRAYSCALE)
        if img is None:
            raise ArenaError(f"cannot read image {str(image)!r}: missing file or unknown format")
        name = name or Path(image).stem
    else:
        img = np.asarray(image)
        if img.ndim == 3:
            img = cv2.cvtColor(img.astype(np.uint8), cv2.COLOR_BGR2GRAY)
        if img.ndim != 2 or img.size == 0:
            raise ArenaError(f"image must be a 2-D grey or 3-D colour array; got shape {img.shape}")
        img = img.astype(np.uint8)
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
