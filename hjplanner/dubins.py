"""Closed-form shortest paths of the simple car, used as exact references.

The forward-only car of minimum turning radius ``rho`` reaches a point with
free final heading along a path of type CS (arc then straight segment) or CC
(two arcs of opposite directions); see Bui, Souères, Boissonnat and Laumond
(1994).  Both families have closed forms, evaluated here vectorised.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["point_distance", "half_plane_distance", "reeds_shepp_line_distance"]

TWO_PI = 2.0 * np.pi


def _to_car_frame(x, y, theta, target):
    """Target coordinates in the car frame (car at origin heading +x)."""
    dx = target[0] - np.asarray(x, dtype=float)
    dy = target[1] - np.asarray(y, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    return c * dx + s * dy, -s * dx + c * dy


def _cs_left(a, b, rho):
    """Length of the left-turn-then-straight path to (a, b); inf if infeasible."""
    cx, cy = a, b - rho
    dc2 = cx * cx + cy * cy
    tangent = np.sqrt(np.maximum(dc2 - rho * rho, 0.0))
    psi = np.arctan2(cy, cx) - np.arctan2(tangent, rho)
    turn = np.mod(psi + 0.5 * np.pi, TWO_PI)
    # A target dead ahead gives psi = -π/2 up to round-off: no turn, not a full loop.
    turn = np.where(turn > TWO_PI - 1e-9, 0.0, turn)
    length = rho * turn + tangent
    return np.where(dc2 >= rho * rho * (1.0 - 1e-12), length, np.inf)


def _cc_right_left(a, b, rho):
    """Length of the right-arc-then-left-arc path through (a, b); inf if none."""
    dx, dy = a, b + rho  # target relative to the right circle's centre
    d = np.hypot(dx, dy)
    ok = (d >= rho) & (d <= 3.0 * rho)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_alpha = np.clip((3.0 * rho * rho + d * d) / (4.0 * rho * np.maximum(d, 1e-300)), -1.0, 1.0)
    alpha = np.arccos(cos_alpha)
    delta = np.arctan2(dy, dx)
    best = np.full(np.shape(a), np.inf)
    for sign in (-1.0, 1.0):
        direction = delta + sign * alpha  # polar angle of the second centre
        t1 = np.mod(0.5 * np.pi - direction, TWO_PI)
        c2x = 2.0 * rho * np.cos(direction)
        c2y = 2.0 * rho * np.sin(direction)
        end_angle = np.arctan2(dy - c2y, dx - c2x)
        t2 = np.mod(end_angle - (direction + np.pi), TWO_PI)
        best = np.minimum(best, rho * (t1 + t2))
    return np.where(ok, best, np.inf)


def point_distance(x: ArrayLike, y: ArrayLike, theta: ArrayLike, rho: float,
                   target: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Exact length of the shortest forward path from a pose to a point.

    Parameters
    ----------
    x, y : array_like
        Start position (length units, e.g. cm); broadcast together with `theta`.
    theta : array_like
        Start heading in radians, counter-clockwise from +x.
    rho : float
        Minimum turning radius (same length unit), ``rho > 0``.
    target : (float, float), optional
        Target point; the final heading is free.

    Returns
    -------
    numpy.ndarray
        Path length (same length unit), the value function φ of eqs. (13)-(14)
        of Landa et al. in the plane without obstacles.

    Notes
    -----
    The optimum is the shorter of the CS paths (left or right arc, then the
    tangent segment) and the CC paths (arc, then an arc of the other direction
    ending on the target), following Bui et al. (1994).  φ is discontinuous on
    the turning circles, where a CS path ceases to exist.

    References
    ----------
    X.-N. Bui, J.-D. Boissonnat, P. Souères, J.-P. Laumond, "Shortest path
    synthesis for Dubins non-holonomic robot", ICRA 1994.

    Examples
    --------
    >>> float(point_distance(-1.0, 0.0, 0.0, 0.3))
    1.0
    """
    if not rho > 0:
        raise ValueError(f"rho must be positive, got {rho}")
    a, b = _to_car_frame(x, y, theta, target)
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    lengths = np.minimum.reduce([
        _cs_left(a, b, rho), _cs_left(a, -b, rho),
        _cc_right_left(a, b, rho), _cc_right_left(a, -b, rho),
    ])
    return np.where(np.hypot(a, b) == 0.0, 0.0, lengths)


def half_plane_distance(x: ArrayLike, theta: ArrayLike, rho: float, x0: float = 0.0) -> np.ndarray:
    """Exact forward time to reach the half-plane ``{x >= x0}``.

    Turning towards heading 0 at the maximal rate, then driving straight,
    maximises the abscissa at every time, hence is optimal.

    Parameters
    ----------
    x : array_like
        Start abscissa (length unit).
    theta : array_like
        Start heading (radians).
    rho : float
        Minimum turning radius.
    x0 : float, optional
        Abscissa of the boundary line.

    Returns
    -------
    numpy.ndarray
        Path length; 0 inside the half-plane.
    """
    d = x0 - np.asarray(x, dtype=float)
    psi = np.abs(np.mod(np.asarray(theta, dtype=float) + np.pi, TWO_PI) - np.pi)
    rest = np.sin(psi) - d / rho
    with np.errstate(invalid="ignore"):
        during_turn = rho * (psi - np.arcsin(np.clip(rest, -1.0, 1.0)))
    after_turn = rho * psi + d - rho * np.sin(psi)
    value = np.where(rest >= 0.0, during_turn, after_turn)
    return np.where(d <= 0.0, 0.0, value)


def reeds_shepp_line_distance(x: ArrayLike, theta: ArrayLike, rho: float, x0: float = 0.0) -> np.ndarray:
    """Exact time for the forward-and-reverse car to reach ``{x >= x0}``.

    Driving forwards or backwards, the car picks whichever of its two
    directions of motion, heading ``theta`` or ``theta + pi``, reaches the line
    sooner; so the value is the minimum of two forward problems.

    Parameters
    ----------
    x, theta, rho, x0
        As in :func:`half_plane_distance`.

    Returns
    -------
    numpy.ndarray
        Path length.
    """
    theta = np.asarray(theta, dtype=float)
    return np.minimum(half_plane_distance(x, theta, rho, x0), half_plane_distance(x, theta + np.pi, rho, x0))


def local_exact(x, y, theta, target, rho: float, r0: float, reverse: bool = False) -> np.ndarray:
    """Exact φ where it is at most ``r0`` (paths inside the disk of radius r0), +inf elsewhere.

    The initial layer of the solver for a point target, and the value used
    near the target by :class:`hjplanner.ValueFunction`.  With ``reverse``
    the value is the better of driving forwards or backwards all the way (an
    upper bound of the Reeds-Shepp distance).
    """
    x, y, theta = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), np.asarray(theta, float))
    out = np.full(x.shape, np.inf)
    # A path is no shorter than the straight line: only poses within r0 of the
    # target (and round-off) can have a finite value, so only those are solved.
    near = np.hypot(x - target[0], y - target[1]) <= r0 * (1.0 + 1e-9) + 1e-12
    if near.any():
        xs, ys, ts = x[near], y[near], theta[near]
        values = point_distance(xs, ys, ts, rho, target)
        if reverse:
            values = np.minimum(values, point_distance(xs, ys, ts + np.pi, rho, target))
        out[near] = np.where(values <= r0, values, np.inf)
    return out
