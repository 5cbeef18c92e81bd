"""A simulated range sensor (lidar) on the true walls: the truth side of unknown maps.

The scan is a fan of `beams` rays over 360° from the platform's true position; each
returns the distance to the first wall of the *true* arena (its boundary and its
obstacles), capped at the sensor's range, plus Gaussian noise. The strategy receives
the scan as an :class:`~reciprocity.observations.Observation` of kind ``"scan"`` and
never the walls themselves.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from arenas import Arena

from ..validation import number, whole

__all__ = ["Lidar", "Scan", "wall_segments", "ray_ranges", "LIDAR_DEFAULTS"]

#: The sensor a ``map: unknown`` scenario gets when it names none: 64 beams, 40 cm range,
#: 0.5 cm noise (standard deviation of one range).
LIDAR_DEFAULTS = {"beams": 64, "range": 40.0, "noise": 0.5}
#: Most beams of one scan (a scan is an (beams, edges) intersection test).
MAX_BEAMS = 4096
#: Longest range, cm (10 m: beyond any arena of the testbed's scale).
MAX_RANGE = 1000.0
#: Largest range noise, cm.
MAX_RANGE_NOISE = 100.0


def wall_segments(arena: Arena) -> tuple[np.ndarray, np.ndarray]:
    """Every wall edge of `arena` (its boundary and its obstacles) as segments.

    Parameters
    ----------
    arena : Arena
        The walls, cm.

    Returns
    -------
    a, b : ndarray, shape (m, 2)
        Start and end of each edge, cm.
    """
    rings = [arena.boundary, *arena.obstacles]
    a = np.vstack(rings)
    b = np.vstack([np.roll(r, -1, axis=0) for r in rings])
    return a, b


def ray_ranges(origin, angles: np.ndarray, a: np.ndarray, b: np.ndarray,
               max_range: float) -> tuple[np.ndarray, np.ndarray]:
    """Distance along each ray to the first segment it meets, vectorised over rays and
    segments (one (rays, segments) array, no loop).

    Parameters
    ----------
    origin : array_like, shape (2,)
        Where the rays start, cm.
    angles : ndarray, shape (n,)
        Directions, radians (world frame, counter-clockwise from +x).
    a, b : ndarray, shape (m, 2)
        Segments, cm.
    max_range : float
        Longest distance returned, cm.

    Returns
    -------
    ranges : ndarray, shape (n,)
        Distance to the first hit, or `max_range` when none is nearer, cm.
    hit : ndarray of bool, shape (n,)
        Whether the ray met a segment within `max_range`.

    Notes
    -----
    The ray ``p + t d`` meets the segment ``a + s (b - a)`` where ``t = ((a - p) × e) /
    (d × e)`` and ``s = ((a - p) × d) / (d × e)``, ``e = b - a``, ``×`` the 2-D cross
    product; it counts when ``t >= 0`` and ``0 <= s <= 1``. Parallel segments (``d × e =
    0``) are never hit (a ray grazing a wall along its length meets the wall's ends).

    Examples
    --------
    >>> a, b = np.array([[10.0, -5.0]]), np.array([[10.0, 5.0]])
    >>> r, hit = ray_ranges((0.0, 0.0), np.array([0.0, np.pi]), a, b, 40.0)
    >>> r.tolist(), hit.tolist()
    ([10.0, 40.0], [True, False])
    """
    p = np.asarray(origin, dtype=float)[:2]
    d = np.column_stack([np.cos(angles), np.sin(angles)])          # (n, 2)
    e = b - a                                                       # (m, 2)
    ap = a - p                                                      # (m, 2)
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]       # d × e, (n, m)
    t_num = ap[None, :, 0] * e[None, :, 1] - ap[None, :, 1] * e[None, :, 0]   # (a - p) × e
    s_num = ap[None, :, 0] * d[:, None, 1] - ap[None, :, 1] * d[:, None, 0]   # (a - p) × d
    with np.errstate(divide="ignore", invalid="ignore"):
        t, s = t_num / den, s_num / den
    ok = (np.abs(den) > 1e-12) & (t >= 0) & (s >= -1e-9) & (s <= 1 + 1e-9)
    t = np.where(ok, t, np.inf).min(axis=1)
    hit = t <= max_range
    return np.where(hit, t, float(max_range)), hit


@dataclass(frozen=True)
class Scan:
    """One scan: beam directions, measured ranges, which beams hit a wall, the range cap.

    Attributes
    ----------
    angles : ndarray, shape (beams,)
        World-frame directions, radians.
    ranges : ndarray, shape (beams,)
        Measured distances, cm (noisy, within ``[0, max_range]``).
    hit : ndarray of bool, shape (beams,)
        The beam met a wall within range; a beam with no hit reads `max_range`.
    max_range : float
        The sensor's range, cm.
    """

    angles: np.ndarray
    ranges: np.ndarray
    hit: np.ndarray
    max_range: float

    def as_data(self) -> dict:
        """The scan as an observation's ``data`` (lists: JSON-ready)."""
        return {"angles": self.angles.tolist(), "ranges": self.ranges.tolist(), "hit": self.hit.tolist(),
                "max_range": float(self.max_range)}


class Lidar:
    """A 2-D range sensor: `beams` rays over 360°, `range` cm, Gaussian range noise.

    Parameters
    ----------
    beams : int
        Rays per scan, evenly spaced over 360° from the platform's heading (at least 4).
    range : float
        Longest distance measured, cm (> 0).
    noise : float
        Standard deviation of one range, cm (>= 0); only beams that hit are perturbed (a
        beam with no hit reads exactly `range` and says so).

    Examples
    --------
    >>> import arenas
    >>> lidar = Lidar(beams=4, range=200.0, noise=0.0)
    >>> s = lidar.scan(arenas.load("empty"), (20.0, 70.0, 0.0), np.random.default_rng(0))
    >>> s.ranges.round(1).tolist()
    [120.0, 70.0, 20.0, 70.0]
    """

    def __init__(self, beams: int = 64, range: float = 40.0, noise: float = 0.5):
        self.beams = whole(beams, "lidar beams", 4, MAX_BEAMS)
        self.range = number(range, "lidar range", 0.0, MAX_RANGE, lo_open=True, unit="cm")
        self.noise = number(noise, "lidar noise", 0.0, MAX_RANGE_NOISE, unit="cm")
        self._walls: tuple | None = None

    @classmethod
    def from_dict(cls, params: dict) -> "Lidar":
        """A lidar from ``{beams, range, noise}`` (missing keys: :data:`LIDAR_DEFAULTS`)."""
        return cls(**{**LIDAR_DEFAULTS, **params})

    def nominal(self) -> dict:
        """The sensor's parameters as a strategy is told them."""
        return {"beams": self.beams, "range": self.range, "noise": self.noise}

    def scan(self, arena: Arena, pose, rng: np.random.Generator) -> Scan:
        """Scan the walls of `arena` (the truth) from `pose` (x, y cm, heading rad).

        Parameters
        ----------
        arena : Arena
            The true walls.
        pose : array_like, shape (3,)
            The true pose.
        rng : numpy.random.Generator
            Draws the range noise (one normal per beam that hits).
        """
        pose = np.asarray(pose, dtype=float)
        if self._walls is None or self._walls[0] is not arena:
            self._walls = (arena, *wall_segments(arena))
        _, a, b = self._walls
        angles = (pose[2] + 2 * np.pi * np.arange(self.beams) / self.beams) % (2 * np.pi)
        ranges, hit = ray_ranges(pose[:2], angles, a, b, self.range)
        if self.noise > 0 and hit.any():
            ranges = ranges.copy()
            ranges[hit] += self.noise * rng.standard_normal(int(hit.sum()))
            ranges = np.clip(ranges, 0.0, self.range)
        return Scan(angles, ranges, hit, self.range)
