"""Motion of the simple car: the one arc integrator, the control set and arc clearance checks."""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike

from ._grid import Grid, lower_wall_bound

LEFT, STRAIGHT, RIGHT = 1, 0, -1


def arc_step(poses: ArrayLike, u: ArrayLike, v: ArrayLike, ds: ArrayLike, rho: float) -> np.ndarray:
    """Poses after arc length ``ds`` with steering ``u`` (curvature u/ρ) and direction ``v`` (±1).

    Exact integration of eq. (9) of Landa et al. with ``θ' = u/ρ`` (forward
    Euler in the paper; exact arcs here, so paths respect the turning radius
    exactly): the car moves along the chord of the arc, of length
    ``2ρ sin(|u| ds/2ρ)/|u|`` (``ds`` when straight), in direction ``θ + v u ds/2ρ``.

    Parameters
    ----------
    poses : array_like
        (..., 3) poses (x, y, θ); length unit of ``rho``, θ in radians.
    u : array_like
        Steering in [-1, 1]: +1 full left, 0 straight, -1 full right.
    v : array_like
        Direction of motion, +1 forward, -1 reverse.
    ds : array_like
        Arc length driven, >= 0 (length unit).
    rho : float
        Minimum turning radius (length unit).

    Returns
    -------
    numpy.ndarray
        (..., 3) end poses, θ in [0, 2π), broadcast over all arguments; at
        least 2-D.
    """
    poses = np.atleast_2d(np.asarray(poses, float))
    u = np.asarray(u, float)
    v = np.asarray(v, float)
    ds = np.asarray(ds, float)
    x, y, th = poses[..., 0], poses[..., 1], poses[..., 2]
    dth = u * ds / rho
    with np.errstate(invalid="ignore", divide="ignore"):
        chord = np.where(u == 0, ds, 2 * rho * np.sin(0.5 * np.abs(dth)) / np.where(u == 0, 1, np.abs(u)))
    mid = th + v * 0.5 * dth
    new_th = np.mod(th + v * dth, 2 * np.pi)
    return np.stack(np.broadcast_arrays(x + v * chord * np.cos(mid), y + v * chord * np.sin(mid), new_th), axis=-1)


def controls(rho: float, grid: Grid, turn_steps, straight_cells, reverse: bool) -> list[tuple[int, int, float]]:
    """The (direction v = ±1, steering u ∈ {-1, 0, 1}, arc length s) of each solver stencil.

    Straight steps of ``straight_cells`` grid spacings, arcs turning by
    ``turn_steps`` angular steps (arc length ``m ρ Δθ``, landing on a grid heading).
    """
    out = []
    for v in ((1, -1) if reverse else (1,)):
        out += [(v, STRAIGHT, c * grid.h) for c in straight_cells]
        out += [(v, u, m * rho * grid.dtheta) for m in turn_steps for u in (RIGHT, LEFT)]
    return out


#: Clearance samples along an arc are spaced this fraction of the grid spacing apart.
SAMPLE_FRACTION = 0.25


def sample_spacing(h: float) -> float:
    """Arc-length spacing of the clearance samples along an arc: ``h/4``."""
    return SAMPLE_FRACTION * h


def arc_samples(poses: np.ndarray, u: np.ndarray, v: np.ndarray, s: np.ndarray, rho: float,
                spacing: float) -> np.ndarray:
    """(n, m, 2) positions every ``spacing`` or less along each of n arcs, both ends included."""
    m = max(2, int(np.ceil(float(np.max(s)) / spacing - 1e-9)) + 1)
    fractions = np.linspace(0.0, 1.0, m)
    ends = arc_step(poses[:, None, :], u[:, None], v[:, None], s[:, None] * fractions[None, :], rho)
    return ends[..., :2]


def arcs_are_clear(distance: np.ndarray, grid: Grid, clearance: float, poses: np.ndarray, u: np.ndarray,
                   v: np.ndarray, s: np.ndarray, rho: float) -> np.ndarray:
    """Whether each arc stays certified at ``clearance`` from every wall, all along its length.

    Each sample, spaced ``σ = sample_spacing(h)`` or less, must have a
    certified wall distance (see :mod:`hjplanner._grid`) of at least
    ``clearance + σ/2``: every point of the arc is then at least
    ``clearance`` from every wall.

    Parameters
    ----------
    distance : numpy.ndarray
        Signed wall-distance raster (nx, ny).
    grid : Grid
        Its grid.
    clearance : float
        Required wall distance (length unit).
    poses : numpy.ndarray
        (n, 3) start poses.
    u, v, s : numpy.ndarray
        (n,) steering, direction and arc length of each arc.
    rho : float
        Minimum turning radius.

    Returns
    -------
    numpy.ndarray
        (n,) bool.
    """
    poses = np.ascontiguousarray(poses, float).reshape(-1, 3)
    u, v, s = (np.ascontiguousarray(np.broadcast_to(a, len(poses)), float) for a in (u, v, s))
    if not len(poses):
        return np.ones(0, dtype=bool)
    return _arcs_clear(distance, grid.x0, grid.y0, grid.h, float(clearance), poses, u, v, s, float(rho))


@njit(cache=True, nogil=True, inline="always")
def _sample_count(longest, h):
    """Clearance samples per arc, both ends included, when the longest arc is ``longest``:
    as many as :func:`arc_samples` takes at :func:`sample_spacing`."""
    return max(2, int(np.ceil(longest / (SAMPLE_FRACTION * h) - 1e-9)) + 1)


@njit(cache=True, nogil=True, inline="always")
def _arc_is_clear(distance, x0, y0, h, need, x, y, th, u, v, s, k, rho):
    """Whether the k samples of one arc (fractions of ``np.linspace(0, 1, k)``) all have a
    certified wall distance of at least ``need``."""
    frac_step = 1.0 / (k - 1)
    for j in range(k):
        frac = 1.0 if j == k - 1 else j * frac_step
        px, py, _ = _arc_end(x, y, th, u, v, s * frac, rho)
        if not lower_wall_bound(distance, x0, y0, h, px, py) >= need:
            return False
    return True


@njit(cache=True, nogil=True)
def _arcs_clear(distance, x0, y0, h, clearance, poses, u, v, s, rho):
    """:func:`arcs_are_clear`, compiled: as many samples on every arc as on the longest."""
    k = _sample_count(np.max(s), h)
    out = np.empty(poses.shape[0], dtype=np.bool_)
    for n in range(poses.shape[0]):
        out[n] = _arc_is_clear(distance, x0, y0, h, clearance + 0.5 * (s[n] / (k - 1)), poses[n, 0], poses[n, 1],
                               poses[n, 2], u[n], v[n], s[n], k, rho)
    return out


@njit(cache=True, nogil=True, inline="always")
def _arc_end(x, y, th, u, v, ds, rho):
    """:func:`arc_step` of one pose, in the same floating-point operations (so the same bits)."""
    dth = u * ds / rho
    chord = ds if u == 0 else 2 * rho * np.sin(0.5 * abs(dth)) / abs(u)
    mid = th + v * 0.5 * dth
    return x + v * chord * np.cos(mid), y + v * chord * np.sin(mid), np.mod(th + v * dth, 2 * np.pi)


@njit(cache=True, nogil=True)
def arcs_from(pose, u, v, s, rho, distance, x0, y0, h, clearance):
    """End poses and clearance of the arcs (u, v, s) (m,) from one pose (3,).

    The same as :func:`arc_step` of the pose for every control and
    :func:`arcs_are_clear` of those arcs (sampled together, so every arc has
    as many samples as the longest), in one compiled pass: the hybrid A*
    of :func:`hjplanner.optimal_path` calls it once per pose it expands.

    Returns
    -------
    ends : numpy.ndarray
        (m, 3) end poses, θ in [0, 2π).
    clear : numpy.ndarray
        (m,) bool: the arc stays certified at ``clearance`` all along.
    """
    m = u.shape[0]
    k = _sample_count(np.max(s), h)
    ends = np.empty((m, 3))
    clear = np.empty(m, dtype=np.bool_)
    for c in range(m):
        uc, vc, sc = float(u[c]), float(v[c]), s[c]
        clear[c] = _arc_is_clear(distance, x0, y0, h, clearance + 0.5 * (sc / (k - 1)), pose[0], pose[1], pose[2],
                                 uc, vc, sc, k, rho)
        ex, ey, et = _arc_end(pose[0], pose[1], pose[2], uc, vc, sc, rho)
        ends[c, 0], ends[c, 1], ends[c, 2] = ex, ey, et
    return ends, clear


@njit(cache=True, nogil=True)
def drive_runs(start, run_u, run_v, run_length, ds, rho):
    """Poses of runs of equal controls driven from ``start`` in steps of at most ``ds``.

    Run r is cut into ``n = ceil(length / ds)`` equal steps, its poses
    ``arc_step(pose at the run's start, u, v, length * k / n)`` for k = 1..n
    (one arc from the run's start, not a chain of steps).

    Returns
    -------
    poses : numpy.ndarray
        (1 + total steps, 3), the start first.
    steps : numpy.ndarray
        (runs,) int: the number of steps of each run.
    """
    steps = np.empty(run_u.shape[0], np.int64)
    for r in range(run_u.shape[0]):
        steps[r] = max(1, int(np.ceil(run_length[r] / ds - 1e-9)))
    poses = np.empty((1 + steps.sum(), 3))
    poses[0, 0], poses[0, 1], poses[0, 2] = start[0], start[1], start[2]
    at = 0
    for r in range(run_u.shape[0]):
        x, y, th = poses[at, 0], poses[at, 1], poses[at, 2]
        n = steps[r]
        for k in range(1, n + 1):
            px, py, pt = _arc_end(x, y, th, run_u[r], run_v[r], run_length[r] * k / n, rho)
            poses[at + k, 0], poses[at + k, 1], poses[at + k, 2] = px, py, pt
        at += n
    return poses, steps


@njit(cache=True, nogil=True)
def first_hits(rx, ry, shapes, s, fractions, adm, radius):
    """Arc length along each clear stencil from nodes to a disk about the target: the
    kernel of :func:`hjplanner.solver._first_hits`.

    Parameters
    ----------
    rx, ry : numpy.ndarray
        (n,) node positions relative to the target (length unit).
    shapes : numpy.ndarray
        (ntheta, nc, m, 3) poses along each stencil's arc from the origin, at the arc-length
        ``fractions`` (m,) of the arc lengths ``s`` (nc,).
    adm : numpy.ndarray
        (ntheta, n) uint32 clear-arc bitmasks of the nodes.
    radius : float
        Radius of the disk.

    Returns
    -------
    numpy.ndarray
        (ntheta, n): the least arc length to the disk over the clear stencils that hit it,
        placed between the last sample outside and the first inside by linear
        interpolation of the distance to the disk; +inf where none does.
    """
    nt, nc, m = shapes.shape[0], shapes.shape[1], shapes.shape[2]
    n = rx.shape[0]
    df = fractions[1] - fractions[0]
    out = np.full((nt, n), np.inf)
    gap = np.hypot(rx, ry) - radius       # no arc shorter than this (less round-off) reaches the disk
    for k in range(nt):
        for p in range(n):
            best = np.inf
            for c in range(nc):
                if gap[p] > s[c] + 1e-9 or (adm[k, p] >> np.uint32(c)) & np.uint32(1) == 0:
                    continue
                before = 0.0
                for q in range(m):
                    d = np.hypot(rx[p] + shapes[k, c, q, 0], ry[p] + shapes[k, c, q, 1]) - radius
                    if d <= 0:
                        if q == 0:
                            first = s[c] * fractions[0]
                        else:
                            step = before / (before - d)
                            first = s[c] * (fractions[q - 1] + step * df)
                        if first < best:
                            best = first
                        break
                    before = d
            out[k, p] = best
    return out
