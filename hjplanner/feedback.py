"""Feedback steering for a car whose pose is estimated, not known (eq. (15), Landa et al.)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .errors import PlanningError

__all__ = ["steering"]


def steering(vf, pose: ArrayLike, dead_band: float | None = None) -> int:
    """Steering command at the current (estimated) pose.

    ``u = -sign(φ_θ)`` (eq. (15)): turn so that φ decreases fastest.  Within
    the dead band ``|φ_θ| <= dead_band`` the car drives straight: on an
    optimal straight segment φ_θ changes sign across the path, and a bare
    sign would make the car chatter left-right around it.

    The law is for forward driving; with a Reeds-Shepp value function use
    :func:`hjplanner.optimal_path`, which also chooses the direction.

    Parameters
    ----------
    vf : ValueFunction
        Value function of the current target.
    pose : array_like
        (x, y, θ), θ in radians.
    dead_band : float, optional
        Threshold on ``|φ_θ|`` (length unit per radian); default ``0.05 ρ``.

    Returns
    -------
    int
        +1 turn left, 0 straight, -1 turn right.  0 if the pose cannot reach
        the target (φ = +inf there): the caller should replan.

    Raises
    ------
    PlanningError
        If ``pose`` is not three finite numbers or ``dead_band < 0``.

    Examples
    --------
    >>> from hjplanner import solve
    >>> vf = solve(((-1, 1), (-1, 1)), (0, 0), rho=0.3, h=0.05, ntheta=32)
    >>> steering(vf, (-0.6, 0.0, 0.0)), steering(vf, (-0.6, 0.0, 0.5))
    (0, -1)
    """
    p = np.asarray(pose, dtype=float).reshape(-1)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise PlanningError(f"pose must be finite (x, y, theta), got {pose!r}")
    dead_band = 0.05 * vf.rho if dead_band is None else float(dead_band)
    if not dead_band >= 0:
        raise PlanningError(f"dead_band must be >= 0, got {dead_band}")
    if not np.isfinite(vf(*p)):
        return 0
    d_theta = float(vf.dtheta(*p))
    if not np.isfinite(d_theta):
        # One side of the heading is unreachable: turn away from it.
        return -1 if d_theta > 0 else 1
    if abs(d_theta) <= dead_band:
        return 0
    return -1 if d_theta > 0 else 1
