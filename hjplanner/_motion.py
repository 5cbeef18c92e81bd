"""Motion of the simple car: the one arc integrator, the control set and arc clearance checks."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ._grid import Grid, lower_wall_distance

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


def sample_spacing(h: float) -> float:
    """Arc-length spacing of the clearance samples along an arc: ``h/4``."""
    return 0.25 * h


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
    spacing = sample_spacing(grid.h)
    points = arc_samples(poses, u, v, s, rho, spacing)
    step = s / (points.shape[1] - 1)
    bound = lower_wall_distance(distance, grid.x0, grid.y0, grid.h, np.ascontiguousarray(points[..., 0].ravel()),
                                np.ascontiguousarray(points[..., 1].ravel())).reshape(points.shape[:2])
    return (bound >= clearance + 0.5 * step[:, None]).all(axis=1)
