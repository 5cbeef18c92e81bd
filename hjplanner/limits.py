"""Bounds of the planner's inputs: what keeps one solve within memory and time.

A solve keeps about 20 bytes per node (values, stencil masks, the free mask), so
:data:`MAX_NODES` nodes take about 1 GB; longer lengths than :data:`MAX_LENGTH` are
beyond any testbed and overflow the stencil arithmetic. Every entry point (the Python
API through :func:`check_grid`, the command line before it writes anything) checks them.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

from .errors import PlanningError

__all__ = ["MAX_LENGTH", "MAX_NODES", "MIN_NTHETA", "MAX_NTHETA", "length", "check_grid", "grid_shape"]

#: Largest turning radius, grid spacing, clearance or target radius (length unit of the domain).
MAX_LENGTH = 1e5
#: Most grid nodes ``nx · ny · ntheta`` of one value function (about 1 GB while solving).
MAX_NODES = 50_000_000
#: Fewest and most headings.
MIN_NTHETA, MAX_NTHETA = 8, 720


def length(value, name: str, *, zero: bool = False) -> float:
    """`value` as a length in ``(0, MAX_LENGTH]`` (``[0, ...]`` if `zero`), else PlanningError."""
    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)) \
        and (0 <= float(value) if zero else 0 < float(value)) and float(value) <= MAX_LENGTH
    if not ok:
        raise PlanningError(f"{name} must be a number in {'[' if zero else '('}0, {MAX_LENGTH:g}]; got {value!r}")
    return float(value)


def grid_shape(extent: tuple[float, float], h: float) -> tuple[int, int]:
    """Nodes ``(nx, ny)`` of a grid of spacing `h` over a box of size `extent` = (width, height)."""
    return (int(math.floor(extent[0] / h + 1e-9)) + 1, int(math.floor(extent[1] / h + 1e-9)) + 1)


def check_grid(rho, h, ntheta, clearance, extent: tuple[float, float] | None = None) -> None:
    """Refuse parameters out of bounds, and grids of more than :data:`MAX_NODES` nodes.

    Parameters
    ----------
    rho, h, clearance : float
        Turning radius, grid spacing and clearance (length unit of the domain).
    ntheta : int
        Headings.
    extent : (float, float), optional
        Width and height of the domain's bounding box; checks the node count.
    """
    length(rho, "rho")
    length(h, "h")
    length(clearance, "clearance", zero=True)
    if not (isinstance(ntheta, Integral) and not isinstance(ntheta, bool) and MIN_NTHETA <= ntheta <= MAX_NTHETA):
        raise PlanningError(f"ntheta must be a whole number from {MIN_NTHETA} to {MAX_NTHETA} (headings per "
                            f"turn); got {ntheta!r}")
    if extent is not None:
        nx, ny = grid_shape(extent, float(h))
        if nx * ny * int(ntheta) > MAX_NODES:
            raise PlanningError(f"grid of {nx} x {ny} x {ntheta} nodes is more than {MAX_NODES:.3g}; "
                                "increase h or reduce ntheta")
