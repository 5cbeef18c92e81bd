"""Optimal paths read off the value function (eqs. (15)-(17), Landa et al.)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._motion import LEFT, RIGHT, STRAIGHT, arc_step, arcs_are_clear, drive_runs
from ._search import hybrid_astar
from .dubins import local_exact
from .errors import PlanningError
from .options import SolverOptions

__all__ = ["PlannedPath", "optimal_path", "merge_short_segments", "arc_step"]


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

    @property
    def segments(self) -> list[tuple[int, int, float]]:
        """The controls as runs ``(steering, direction, arc length)`` of consecutive equal steps."""
        return [(u, v, length) for u, v, length in _runs(self.steering, self.direction, self.step_lengths)]


def _runs(steering, direction, step_lengths) -> list[list]:
    """[steering, direction, length] of each run of equal consecutive controls."""
    runs = []
    for u, v, step in zip(steering, direction, step_lengths):
        if runs and runs[-1][0] == u and runs[-1][1] == v:
            runs[-1][2] += float(step)
        else:
            runs.append([int(u), int(v), float(step)])
    return runs


def _drive(start: np.ndarray, runs, ds: float, rho: float):
    """Poses, steering, direction and step lengths of ``runs`` driven from ``start`` in steps of at most ``ds``."""
    run_u, run_v, length = (np.array([run[i] for run in runs], dtype=float).reshape(-1) for i in range(3))
    poses, n = drive_runs(np.asarray(start, float).reshape(3), run_u, run_v, length, float(ds), float(rho))
    return (poses, np.repeat(run_u.astype(int), n), np.repeat(run_v.astype(int), n),
            np.repeat(length / n, n))


def _clear(vf, poses, u, v, steps) -> bool:
    """Whether every step of a path stays certified at the value function's clearance."""
    return bool(arcs_are_clear(vf.distance, vf.grid, vf.clearance, poses[:-1], u, v, steps, vf.rho).all())


def merge_short_segments(vf, path: PlannedPath, min_segment: float, stop_tol: float) -> PlannedPath:
    """Merge the runs of ``path`` shorter than ``min_segment`` into a neighbour, where the result stays valid.

    The shortest such run takes the steering of its longer neighbour of the
    same direction, else of the other, else -- with the next run, if that
    turns the other way (a zig-zag) -- both drive straight; the last run may
    also be dropped.  A change is kept only if the re-driven path stays certified
    clear of the walls and ends within ``stop_tol`` of the target (and at
    least as close as before if it did not reach it).  Gear changes are
    kept: a run is never merged into one of the other direction.

    Parameters
    ----------
    vf : ValueFunction
        The value function the path was read off (geometry, clearance, ρ).
    path : PlannedPath
        Path to smooth.
    min_segment : float
        Shortest run the car can execute (length unit).
    stop_tol : float
        Distance to the target within which the path counts as arrived.

    Returns
    -------
    PlannedPath
        The smoothed path (``path`` itself when nothing could be merged).
    """
    runs = [run + [False] for run in _runs(path.steering, path.direction, path.step_lengths)]
    start, target = path.poses[0], vf.target
    end_gap = float(np.hypot(*(path.poses[-1, :2] - target)))
    allowed = max(stop_tol, end_gap)
    changed = False
    while len(runs) > 1:
        short = [n for n, run in enumerate(runs) if run[2] < min_segment and not run[3]]
        if not short:
            break
        n = min(short, key=lambda m: runs[m][2])
        neighbours = sorted((m for m in (n - 1, n + 1) if 0 <= m < len(runs) and runs[m][1] == runs[n][1]),
                            key=lambda m: -runs[m][2])
        candidates = [runs[:n] + [[runs[m][0], runs[n][1], runs[n][2], False]] + runs[n + 1:] for m in neighbours]
        if n + 1 < len(runs) and runs[n + 1][1] == runs[n][1] and runs[n + 1][0] == -runs[n][0] != STRAIGHT:
            # a zig-zag: two opposite turns, nearly a straight segment
            candidates.append(runs[:n] + [[STRAIGHT, runs[n][1], runs[n][2] + runs[n + 1][2], False]] + runs[n + 2:])
        if n == len(runs) - 1:
            candidates.append(runs[:n])
        for candidate in candidates:
            merged = _coalesce(candidate)
            if len(merged) >= len(runs):  # every accepted change removes a run: the loop ends
                continue
            poses, u, v, steps = _drive(start, [run[:3] for run in merged], path.ds, vf.rho)
            if np.hypot(*(poses[-1, :2] - target)) <= allowed and _clear(vf, poses, u, v, steps):
                runs, changed = merged, True
                break
        else:
            runs[n][3] = True
    if not changed:
        return path
    poses, u, v, steps = _drive(start, [run[:3] for run in runs], path.ds, vf.rho)
    reached = bool(np.hypot(*(poses[-1, :2] - target)) <= stop_tol)
    return PlannedPath(poses, u, v, steps, path.ds, reached, path.value_start)


def _coalesce(runs: list[list]) -> list[list]:
    """Join consecutive runs of equal controls (their 'cannot merge' marks are reset)."""
    out = []
    for u, v, length, stuck in runs:
        if out and out[-1][0] == u and out[-1][1] == v:
            out[-1][2] += length
            out[-1][3] = False
        else:
            out.append([u, v, length, stuck])
    return out


def _first_minimum(values: np.ndarray) -> int:
    """Index of the first value within round-off of the minimum (straight controls come first)."""
    return int(np.argmax(values <= values.min() + 1e-12 * max(1.0, abs(float(values.min())))))


def _stencil_controls(vf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steering u, direction v and arc length s of the solver's stencils, straight and short first."""
    options = SolverOptions(**vf.meta.get("options", {}))
    ctrl = sorted(options.controls(vf.rho, vf.grid, vf.reverse), key=lambda c: (c[1] != 0, c[2]))
    v, u, s = (np.array(column) for column in zip(*ctrl))
    return u.astype(int), v.astype(int), s.astype(float)


def _search(vf, start: np.ndarray, us, vs, lengths, stop_tol: float, ds: float, max_length: float,
            max_steps: int) -> tuple[list, bool]:
    """A* over chains of stencil arcs from ``start``, guided by φ (hybrid A*).

    A pose reached with arc length ``g`` is ranked by ``g + φ(pose)``; its
    successors are the stencil arcs certified clear of the walls, with φ at
    their end interpolated as at the scheme's feet (+inf where a corner of
    the end's cell is blocked or unreached).  Where φ is accurate the
    search expands the poses along the discrete characteristic -- the arcs
    the scheme chose at the nodes -- and little else; next to a wall, where
    interpolation is optimistic, it backs out of poses from which no arc
    leads on.  A pose is expanded once per (x, y, θ) grid cell.

    Returns the controls [(u, v, s), ...] up to the first pose that arrives
    (within ``stop_tol`` of the target or in the exact layer) or the first
    arc that arrives somewhere along its length, sampled every ``ds`` -- or,
    failing that, up to the expanded pose of smallest φ -- and whether it
    arrived.  The search runs compiled (:func:`hjplanner._search.hybrid_astar`).
    """
    g = vf.grid
    value_start = float(vf(*start, cubic=False, lenient=True))
    moves, arrived = hybrid_astar(
        vf._phi, vf.free, vf.distance, g.x0, g.y0, g.h, g.dtheta, g.ntheta, np.asarray(start, float), value_start,
        np.ascontiguousarray(us, np.int64), np.ascontiguousarray(vs, np.int64), np.ascontiguousarray(lengths, float),
        vf.rho, vf.clearance, float(vf.target[0]), float(vf.target[1]), float(stop_tol),
        float(vf.meta.get("local_radius", 0.0)), vf.reverse, float(ds), float(max_length), int(max_steps))
    return [(int(us[c]), int(vs[c]), float(lengths[c])) for c in moves], bool(arrived)


def optimal_path(vf, start_pose: ArrayLike, ds: float | None = None, *, stop_tol: float | None = None,
                 max_length: float | None = None, min_segment: float | None = None) -> PlannedPath:
    """Follow the characteristics of φ from ``start_pose`` to the target.

    The path is a chain of the solver's stencil arcs, each certified clear
    of the walls all along, found by a best-first (A*) search ranked by
    ``driven length + φ(end of the arc)``: where φ is accurate the search
    just follows the discrete characteristic -- the arc minimising ``s +
    φ(end)``, the discrete form of eq. (15), ``θ' = -sign(φ_θ)/ρ`` (eq. (16)
    run forwards), and the choice the scheme made at the grid nodes -- and
    where interpolating φ next to a wall is optimistic it backs out of
    poses from which no arc leads on (see :func:`_search`).  So the path
    never comes closer than the clearance to a wall, whatever the
    clearance, and its length stays within a few grid spacings of
    φ(start).  Arcs are integrated exactly and sampled every ``ds`` or
    less.  Within the solver's exact layer around a point target the path
    descends the exact φ in steps of ``ds``.  Ties go to driving straight.
    Finally runs shorter than ``min_segment`` are merged into their
    neighbours where the path stays clear and still arrives
    (:func:`merge_short_segments`).

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
    min_segment : float, optional
        Shortest run of one control the car should execute; default ``2 h``;
        0 keeps the path as read off φ.

    Returns
    -------
    PlannedPath
        ``reached`` is False if the path gave up.

    Raises
    ------
    PlanningError
        If the start pose or a parameter is invalid, or the start cannot
        reach the target (φ = +inf).

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
    min_segment = 2 * h if min_segment is None else float(min_segment)
    if not min_segment >= 0:
        raise PlanningError(f"min_segment must be >= 0, got {min_segment}")
    stop_tol = max(2 * h, float(vf.meta.get("tol", 0.0))) if stop_tol is None else float(stop_tol)
    value_start = float(vf(*start))
    if not np.isfinite(value_start):
        raise PlanningError(
            f"start pose ({start[0]:g}, {start[1]:g}, {np.degrees(start[2]):.1f} deg) cannot reach the target: "
            "it is blocked, outside the domain, within the clearance of a wall, or facing a wall too close to turn")
    max_length = 1.5 * value_start + 20 * h if max_length is None else float(max_length)
    us, vs, lengths = _stencil_controls(vf)
    rho, target = vf.rho, vf.target
    r0 = float(vf.meta.get("local_radius", 0.0))

    def in_exact_layer(pose) -> bool:
        return r0 > 0 and bool(np.isfinite(local_exact(*pose, target, rho, r0, vf.reverse)))

    def arrived(poses) -> np.ndarray:
        """Whether each pose (n, 3) is within stop_tol of the target or in the exact layer."""
        out = np.hypot(*(poses[:, :2] - target).T) <= stop_tol
        if r0 > 0:
            out |= np.isfinite(local_exact(poses[:, 0], poses[:, 1], poses[:, 2], target, rho, r0, vf.reverse))
        return out

    budget = max(2000, int(20 * max_length / lengths.min()))
    runs, _ = _search(vf, start, us, vs, lengths, stop_tol, ds, max_length, budget)
    poses, steering, direction, step_lengths = _drive(start, runs, ds, rho)
    # stop where the last arc first comes within stop_tol or enters the exact layer
    cut = int(np.argmax(arrived(poses))) if arrived(poses).any() else len(poses) - 1
    poses, steering, direction, step_lengths = poses[:cut + 1], steering[:cut], direction[:cut], step_lengths[:cut]
    pose = poses[-1]
    # Inside the exact layer (a disk certified clear of the walls): descend
    # the exact φ with steps ds; the solver's longer stencils would overshoot.
    short_u = np.array([STRAIGHT, LEFT, RIGHT] * (2 if vf.reverse else 1))
    short_v = np.repeat((1, -1) if vf.reverse else (1,), 3)
    tail = []
    driven = float(step_lengths.sum())
    inside = in_exact_layer(pose)
    while not np.hypot(*(pose[:2] - target)) <= stop_tol and inside and driven < max_length:
        ends = arc_step(np.repeat(pose[None], len(short_u), axis=0), short_u, short_v, ds, rho)
        exact = local_exact(ends[:, 0], ends[:, 1], ends[:, 2], target, rho, r0, vf.reverse)
        best = _first_minimum(exact)
        pose, inside = ends[best], bool(np.isfinite(exact[best]))
        tail.append((short_u[best], short_v[best], ds))
        driven += ds
    if tail:
        poses, steering, direction, step_lengths = _drive(start, _runs(steering, direction, step_lengths) + tail,
                                                          ds, rho)
    reached = bool(np.hypot(*(poses[-1, :2] - target)) <= stop_tol)
    path = PlannedPath(poses, steering, direction, step_lengths, ds, reached, value_start)
    if min_segment > 0 and len(path.steering):
        path = merge_short_segments(vf, path, min_segment, stop_tol)
    return path
