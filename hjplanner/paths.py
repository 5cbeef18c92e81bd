"""Optimal paths read off the value function (eqs. (15)-(17), Landa et al.)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .dubins import local_exact
from .errors import PlanningError

__all__ = ["PlannedPath", "optimal_path", "arc_step"]

LEFT, STRAIGHT, RIGHT = 1, 0, -1


@dataclass(frozen=True)
class PlannedPath:
    """A path of the car, sampled every ``ds`` or less.

    Attributes
    ----------
    poses : numpy.ndarray
        (n, 3) poses (x, y, θ), θ in [0, 2π); ``poses[0]`` is the start.
    steering : numpy.ndarray
        (n - 1,) int: +1 left, 0 straight, -1 right, applied over each step.
    direction : numpy.ndarray
        (n - 1,) int: +1 forward, -1 reverse (Reeds-Shepp value functions).
    step_lengths : numpy.ndarray
        (n - 1,) arc length of each step, at most ``ds``.
    ds : float
        Largest arc length of a step.
    reached : bool
        Whether the path ended within the stopping tolerance of the target.
    value_start : float
        φ at the start pose: the length predicted by the value function.
    """

    poses: np.ndarray
    steering: np.ndarray
    direction: np.ndarray
    step_lengths: np.ndarray
    ds: float
    reached: bool
    value_start: float

    @property
    def length(self) -> float:
        """Driven arc length (length unit)."""
        return float(self.step_lengths.sum())

    @property
    def xy(self) -> np.ndarray:
        """(n, 2) positions."""
        return self.poses[:, :2]


def arc_step(poses: np.ndarray, u: ArrayLike, v: ArrayLike, ds: ArrayLike, rho: float) -> np.ndarray:
    """Poses after arc length ``ds`` with steering ``u`` (curvature u/ρ) and direction ``v`` (±1).

    ``poses`` is (3,) or (n, 3); ``u``, ``v`` and ``ds`` broadcast against n.

    Exact integration of eq. (9) with ``θ' = u/ρ`` (forward Euler in the
    paper; exact arcs here, so paths respect the turning radius exactly).
    """
    poses = np.atleast_2d(np.asarray(poses, float))
    u = np.asarray(u, float)
    v = np.asarray(v, float)
    ds = np.asarray(ds, float)
    x, y, th = poses[..., 0], poses[..., 1], poses[..., 2]
    dth = u * ds / rho
    # chord of the arc: length 2ρ sin(dθ/2)/|u|, direction θ + dθ/2 (ds for straight steps)
    with np.errstate(invalid="ignore", divide="ignore"):
        chord = np.where(u == 0, ds, 2 * rho * np.sin(0.5 * np.abs(dth)) / np.where(u == 0, 1, np.abs(u)))
    mid = th + v * 0.5 * dth
    new_th = np.mod(th + v * dth, 2 * np.pi)
    return np.stack([x + v * chord * np.cos(mid), y + v * chord * np.sin(mid), new_th], axis=-1)


def _lenient_value(vf, poses: np.ndarray) -> np.ndarray:
    """Trilinear φ renormalised over the finite corners; +inf if a corner is blocked or none is finite."""
    g = vf.grid
    phi = vf._phi
    gx = (poses[:, 0] - g.x0) / g.h
    gy = (poses[:, 1] - g.y0) / g.h
    gt = np.mod(poses[:, 2], 2 * np.pi) / g.dtheta
    out = np.full(len(poses), np.inf)
    inside = (gx >= 0) & (gx <= g.nx - 1) & (gy >= 0) & (gy <= g.ny - 1)
    for n in np.nonzero(inside)[0]:
        i, j, k = min(int(gx[n]), g.nx - 2), min(int(gy[n]), g.ny - 2), int(gt[n]) % g.ntheta
        if not vf.free[i:i + 2, j:j + 2].all():
            continue
        fx, fy, ft = gx[n] - i, gy[n] - j, gt[n] - np.floor(gt[n])
        w = np.einsum("a,b,c->abc", [1 - ft, ft], [1 - fx, fx], [1 - fy, fy])
        values = phi[[k, (k + 1) % g.ntheta]][:, i:i + 2, j:j + 2]
        ok = np.isfinite(values) & (w > 0)
        if ok.any():
            out[n] = float((w[ok] * values[ok]).sum() / w[ok].sum())
    return out


def _first_minimum(values: np.ndarray) -> int:
    """Index of the first value within round-off of the minimum (straight controls come first)."""
    return int(np.argmax(values <= values.min() + 1e-12 * max(1.0, abs(float(values.min())))))


def _stencil_controls(vf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steering u, direction v and arc length s of the solver's stencils."""
    from .solver import SolverOptions, controls
    options = SolverOptions(**vf.meta.get("options", {}))
    ctrl = sorted(controls(vf.rho, vf.grid, options, vf.reverse), key=lambda c: (c[1] != 0, c[2]))
    v, u, s = (np.array(column) for column in zip(*ctrl))
    return u.astype(int), v.astype(int), s.astype(float)


def optimal_path(vf, start_pose: ArrayLike, ds: float | None = None, *, stop_tol: float | None = None,
                 max_length: float | None = None) -> PlannedPath:
    """Follow the characteristics of φ from ``start_pose`` to the target.

    From the current pose the path drives the whole arc of the solver
    stencil minimising ``s + φ(end of the arc of length s)`` -- the discrete
    form of eq. (15), ``θ' = -sign(φ_θ)/ρ`` (eq. (16) run forwards) and the
    same choice the scheme made at the grid nodes, so the path stays in the
    region where φ is finite, hence out of the (inflated) obstacles -- then
    decides again.  Arcs are integrated exactly and sampled every ``ds`` or
    less.  Within the solver's exact layer around a point target the path
    descends the exact φ in steps of ``ds``.  Ties go to driving straight.

    Parameters
    ----------
    vf : ValueFunction
        Value function of the target.
    start_pose : array_like
        (x, y, θ) with θ in radians.
    ds : float, optional
        Arc-length step; default ``h/2``.
    stop_tol : float, optional
        Stop when within this distance of the target; default ``max(2 h, tol)``.
    max_length : float, optional
        Give up after this length; default ``1.5 φ(start) + 20 h``.

    Returns
    -------
    PlannedPath
        ``reached`` is False if the path gave up.

    Raises
    ------
    PlanningError
        If the start pose is invalid or cannot reach the target (φ = +inf).

    Examples
    --------
    >>> from hjplanner import solve
    >>> vf = solve(((-1, 1), (-1, 1)), (0, 0), rho=0.3, h=0.05, ntheta=32)
    >>> path = optimal_path(vf, (-0.8, 0.0, 0.0))
    >>> path.reached, round(path.length, 2)
    (True, 0.7)
    """
    start = np.asarray(start_pose, dtype=float).reshape(-1)
    if start.shape != (3,) or not np.isfinite(start).all():
        raise PlanningError(f"start_pose must be finite (x, y, theta), got {start_pose!r}")
    h = vf.grid.h
    ds = 0.5 * h if ds is None else float(ds)
    if not ds > 0:
        raise PlanningError(f"ds must be positive, got {ds}")
    stop_tol = max(2 * h, float(vf.meta.get("tol", 0.0))) if stop_tol is None else float(stop_tol)
    value_start = float(vf(*start))
    if not np.isfinite(value_start):
        raise PlanningError(
            f"start pose ({start[0]:g}, {start[1]:g}, {np.degrees(start[2]):.1f} deg) cannot reach the target: "
            "it is blocked, outside the domain, or facing a wall too close to turn")
    max_length = 1.5 * value_start + 20 * h if max_length is None else float(max_length)
    us, vs, lengths = _stencil_controls(vf)
    rho, target = vf.rho, vf.target
    poses, steering, direction = [start], [], []
    pose = start
    reached = bool(np.hypot(*(pose[:2] - target)) <= stop_tol)
    r0 = float(vf.meta.get("local_radius", 0.0))
    short_u = np.array([STRAIGHT, LEFT, RIGHT] * (2 if vf.reverse else 1))
    short_v = np.repeat((1, -1) if vf.reverse else (1,), 3)
    driven, step_lengths = 0.0, []
    while not reached and driven < max_length:
        best, u_set, v_set, spans = -1, us, vs, lengths
        if r0 > 0 and np.isfinite(local_exact(*pose, target, rho, r0, vf.reverse)):
            # Inside the exact layer: descend the exact φ with steps ds; the
            # solver's longer stencils would overshoot the target.
            ends = arc_step(np.repeat(pose[None], len(short_u), axis=0), short_u, short_v, ds, rho)
            values = local_exact(ends[:, 0], ends[:, 1], ends[:, 2], target, rho, r0, vf.reverse)
            if np.isfinite(values.min()):
                best, u_set, v_set, spans = _first_minimum(values), short_u, short_v, np.full(len(short_u), ds)
        if best < 0:
            ends = arc_step(np.repeat(pose[None], len(us), axis=0), us, vs, lengths, rho)
            values = lengths + vf(ends[:, 0], ends[:, 1], ends[:, 2], cubic=False)
            best = _first_minimum(values)
            if not np.isfinite(values[best]):
                # Between nodes at the edge of the reachable set every stencil may
                # end next to a +inf node; then average φ over the finite corners
                # only, still refusing feet in cells touching blocked nodes.
                values = lengths + _lenient_value(vf, ends)
                best = _first_minimum(values)
                if not np.isfinite(values[best]):
                    break
        # Drive the whole chosen arc, as the scheme's characteristic does, in
        # sub-steps of at most ds: re-deciding after every ds lets the pose
        # drift off the discrete characteristic near obstacles.
        n_sub = max(1, int(np.ceil(spans[best] / ds - 1e-9)))
        for _ in range(n_sub):
            pose = arc_step(pose, u_set[best], v_set[best], spans[best] / n_sub, rho)[0]
            poses.append(pose)
            steering.append(u_set[best])
            direction.append(v_set[best])
            step_lengths.append(spans[best] / n_sub)
            driven += spans[best] / n_sub
            reached = bool(np.hypot(*(pose[:2] - target)) <= stop_tol)
            if reached:
                break
    return PlannedPath(np.array(poses), np.array(steering, dtype=int), np.array(direction, dtype=int),
                       np.array(step_lengths), ds, reached, value_start)
