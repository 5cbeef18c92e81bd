"""The one place where world coordinates (cm, y up) meet image pixels (row 0 at top).

World frame: x right, y up, origin at the arena's lower-left corner of the image.
Image frame: column ``j`` right, row ``i`` down, pixel centres at integer indices.
"""

from __future__ import annotations

import numpy as np

__all__ = ["world_to_pixel", "pixel_to_world"]


def world_to_pixel(points, cm_per_px: float, height_px: int, origin=(0.0, 0.0)) -> np.ndarray:
    """Map world points (cm), shape (n, 2), to fractional pixel ``(col, row)``, shape (n, 2)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    col = (p[:, 0] - origin[0]) / cm_per_px - 0.5
    row = height_px - (p[:, 1] - origin[1]) / cm_per_px - 0.5
    return np.column_stack([col, row])


def pixel_to_world(pixels, cm_per_px: float, height_px: int, origin=(0.0, 0.0)) -> np.ndarray:
    """Map pixel ``(col, row)``, shape (n, 2), to world points (cm), shape (n, 2)."""
    q = np.asarray(pixels, dtype=float).reshape(-1, 2)
    x = (q[:, 0] + 0.5) * cm_per_px + origin[0]
    y = (height_px - q[:, 1] - 0.5) * cm_per_px + origin[1]
    return np.column_stack([x, y])
