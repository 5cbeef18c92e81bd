"""Feedback steering for a car whose pose is estimated, not known (eq. (15), Landa et al.)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .errors import PlanningError

__all__ = ["steering"]


def steering(vf, pose: ArrayLike, dead_band: float | None = None, direction: int = 1) -> int:
    """Steering command at the current (estimated) pose.

    ``u = -v sign(φ_θ)`` (eq. (15), with ``v`` the direction of motion): turn
    so that φ decreases fastest -- when reversing, the heading changes by
    ``v u ds/ρ``, so the same turn needs the opposite steering.  Within the
    dead band ``|φ_θ| <= dead_band`` the car drives straight: on an optimal
    straight segment φ_θ changes sign across the path, and a bare sign would
    make the car chatter left-right around it.  With a Reeds-Shepp value
    function, :func:`hjplanner.optimal_path` tells the direction (the gear
    of each path step).

    Parameters
    ----------
    vf : ValueFunction
        Value function of the current target.
    pose : array_like
        (x, y, θ), θ in radians.
    dead_band : float, optional
        Threshold on ``|φ_θ|`` (length unit per radian); default ``0.05 ρ``.
    direction : {1, -1}, optional
        Gear: +1 forward, -1 reverse.

    Returns
    -------
    int
        +1 turn left, 0 straight, -1 turn right.  0 if the pose cannot reach
        the target (φ = +inf there): the caller should replan.

    Raises
    ------
    PlanningError
        If ``pose`` is not three finite numbers, ``dead_band < 0`` or
        ``direction`` is not ±1.

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
    if direction not in (1, -1):
        raise PlanningError(f"direction must be 1 (forward) or -1 (reverse), got {direction!r}")
    # φ at the pose and at θ ± Δθ/2 in one evaluation: the centred difference of vf.dtheta,
    # of the interpolant alone (the arc readings are a minimum of several, with kinks in θ)
    step = vf.grid.dtheta / 2
    here, plus, minus = vf(p[0], p[1], np.array([p[2], p[2] + step, p[2] - step]), arcs=False)
    if not np.isfinite(here):
        return 0
    with np.errstate(invalid="ignore"):
        d_theta = float((plus - minus) / (2 * step))
    d_theta = 0.0 if np.isnan(d_theta) else d_theta
    # Off the dead band -- or with one side of the heading unreachable (φ_θ
    # infinite) -- turn towards decreasing φ.
    if np.isfinite(d_theta) and abs(d_theta) <= dead_band:
        return 0
    return -direction if d_theta > 0 else direction
