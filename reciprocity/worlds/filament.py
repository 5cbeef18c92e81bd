"""A filament-based odour plume (Farrell, Murlis, Long, Li & Cardé 2002): the truth of
the hidden-Markov plume-mapping scenario.

Filaments (puffs) are released at the source at a fixed rate. Each is carried by the
wind at its centre plus a small-scale random velocity (relative dispersion), and grows
by molecular/small-eddy diffusion. The wind is a mean flow plus a spatially coherent,
time-varying meander: a uniform Ornstein-Uhlenbeck (colored-noise) component and a few
divergence-free Fourier modes of a stream function whose amplitudes are also OU
processes. The concentration at a point is the sum of the filaments' Gaussian puffs;
a detection is a concentration above a threshold, read at the sensor's sampling rate.
The vehicle also measures the local wind (``Reading.data["wind"]``).

Everything is vectorised over filaments; the world advances lazily, in steps of one
sensor period, to the time a reading asks for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Reading, World

__all__ = ["FilamentParams", "FilamentPlume", "FilamentWorld", "puff_concentration", "wind_arrows"]

#: Filaments whose centre leaves the region by more than this margin are dropped (m).
DROP_MARGIN = 10.0
#: The wind a figure draws: on ARROWS × ARROWS points, ARROW_MARGIN m in from the region's edges.
ARROWS, ARROW_MARGIN = 10, 5.0


def wind_arrows(region, wind) -> tuple[np.ndarray, np.ndarray]:
    """The wind a figure draws over `region`: its points and vectors.

    Parameters
    ----------
    region : tuple
        ``(x_min, x_max, y_min, y_max)``, m.
    wind : callable or array_like, shape (2,)
        ``wind(points) -> (n, 2)`` (m/s), or a uniform flow (m/s).

    Returns
    -------
    points, vectors : ndarray, shape (ARROWS², 2)
        A regular grid :data:`ARROW_MARGIN` m in from the edges, and the wind there (m/s).
    """
    x0, x1, y0, y1 = region
    gx, gy = np.meshgrid(np.linspace(x0 + ARROW_MARGIN, x1 - ARROW_MARGIN, ARROWS),
                         np.linspace(y0 + ARROW_MARGIN, y1 - ARROW_MARGIN, ARROWS))
    pts = np.c_[gx.ravel(), gy.ravel()]
    u = wind(pts) if callable(wind) else np.tile(np.asarray(wind, dtype=float), (len(pts), 1))
    return pts, u


def puff_concentration(d2: np.ndarray, sigma2: np.ndarray, mass: float) -> np.ndarray:
    """Concentration of 2-D Gaussian puffs at squared distance `d2` (m^2) from their
    centres, variance `sigma2` (m^2) per axis and `mass` each (mass units / m^2):
    ``c = Q / (2 π σ²) exp(-d² / (2 σ²))``; each puff integrates to `mass`."""
    return mass / (2 * np.pi * sigma2) * np.exp(-0.5 * d2 / sigma2)


@dataclass(frozen=True)
class FilamentParams:
    """Parameters of the filament plume (validated by :mod:`reciprocity.wiring.filament`).

    Attributes
    ----------
    region : tuple
        ``(x_min, x_max, y_min, y_max)``, m.
    source : tuple
        Source position, m.
    release_rate : float
        Filaments released per second.
    puff_mass : float
        Mass of one filament (concentration units × m^2).
    puff_sigma0 : float
        Standard deviation of a filament at release, m.
    puff_diffusivity : float
        Growth of a filament, ``σ² = σ0² + 2 D age`` (m^2/s).
    centre_diffusivity : float
        Small-scale random walk of filament centres (relative dispersion), m^2/s.
    wind_mean : tuple
        Mean wind (u_x, u_y), m/s.
    wind_sigma : float
        Standard deviation of the meander's velocity (uniform part and each mode), m/s.
    wind_tau : float
        Correlation time of the meander (OU processes), s.
    wind_modes : int
        Number of Fourier modes of the stream function (0–4).
    wind_scale : float
        Longest wavelength of the modes, m.
    threshold : float
        Detection threshold (concentration units).
    sampling_rate : float
        Sensor readings per second (the simulation step is one sensor period).
    spinup : float
        Seconds of plume simulated before the search starts.
    """

    region: tuple = (0.0, 100.0, -50.0, 50.0)
    source: tuple = (20.0, 0.0)
    release_rate: float = 10.0
    puff_mass: float = 1.0
    puff_sigma0: float = 0.2
    puff_diffusivity: float = 0.01
    centre_diffusivity: float = 0.05
    wind_mean: tuple = (1.0, 0.0)
    wind_sigma: float = 0.3
    wind_tau: float = 20.0
    wind_modes: int = 4
    wind_scale: float = 200.0
    threshold: float = 0.05
    sampling_rate: float = 10.0
    spinup: float = 120.0


#: Wave-number directions (p, q) of the stream-function modes, in units of 2π/scale.
_MODE_DIRECTIONS = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, -1.0]])


class FilamentPlume:
    """The state of the plume: filaments and wind, advanced in fixed steps.

    Parameters
    ----------
    params : FilamentParams
    rng : numpy.random.Generator
        Draws the wind's colored noise and the filaments' random walk.
    """

    def __init__(self, params: FilamentParams, rng: np.random.Generator):
        self.p, self.rng = params, rng
        self.dt = 1.0 / params.sampling_rate
        self.k = 2 * np.pi / params.wind_scale * _MODE_DIRECTIONS[:params.wind_modes]     # (K, 2)
        knorm = np.hypot(self.k[:, 0], self.k[:, 1])
        # stream-function amplitudes scaled so each mode's velocity has std wind_sigma
        self._amp_sigma = params.wind_sigma / np.maximum(knorm, 1e-12)
        self.uniform = np.zeros(2)                                      # uniform meander, m/s
        self.amps = np.zeros((params.wind_modes, 2))                    # cos, sin amplitudes
        cap = int(np.ceil(params.release_rate * 1e3)) + 16
        self.pos = np.zeros((cap, 2))
        self.age = np.zeros(cap)
        self.alive = np.zeros(cap, dtype=bool)
        self.time = 0.0
        self.n_released = 0
        self.n_dropped = 0

    # -- wind ---------------------------------------------------------------------------
    def wind(self, points: np.ndarray) -> np.ndarray:
        """Wind (u_x, u_y) at `points` (n, 2), m/s: mean + uniform meander + the curl of
        the stream function ``ψ = Σ a_j cos(k_j·x) + b_j sin(k_j·x)``."""
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        u = np.empty_like(pts)
        u[:] = np.asarray(self.p.wind_mean) + self.uniform
        if len(self.k):
            phase = pts @ self.k.T                                      # (n, K)
            c, s = np.cos(phase), np.sin(phase)
            # dψ/dx_i = Σ (-a sin + b cos) k_i ;  u = dψ/dy, v = -dψ/dx
            g = -s * self.amps[:, 0] + c * self.amps[:, 1]              # (n, K)
            u[:, 0] += g @ self.k[:, 1]
            u[:, 1] -= g @ self.k[:, 0]
        return u

    def _ou(self, x: np.ndarray, sigma) -> np.ndarray:
        """Exact Ornstein-Uhlenbeck step of length dt (colored noise, std `sigma`)."""
        rho = np.exp(-self.dt / self.p.wind_tau)
        return rho * x + np.asarray(sigma) * np.sqrt(1 - rho ** 2) * self.rng.standard_normal(x.shape)

    # -- one step -----------------------------------------------------------------------
    def step(self) -> None:
        """Advance the plume by one sensor period: release, advect, diffuse, drop."""
        p, dt = self.p, self.dt
        idx = np.flatnonzero(self.alive)
        if idx.size:
            x = self.pos[idx]
            noise = np.sqrt(2 * p.centre_diffusivity * dt) * self.rng.standard_normal(x.shape)
            self.pos[idx] = x + self.wind(x) * dt + noise
            self.age[idx] += dt
            x0, x1, y0, y1 = p.region
            q = self.pos[idx]
            out = ((q[:, 0] < x0 - DROP_MARGIN) | (q[:, 0] > x1 + DROP_MARGIN)
                   | (q[:, 1] < y0 - DROP_MARGIN) | (q[:, 1] > y1 + DROP_MARGIN))
            self.alive[idx[out]] = False
            self.n_dropped += int(out.sum())
        self.uniform = self._ou(self.uniform, p.wind_sigma)
        self.amps = self._ou(self.amps, self._amp_sigma[:, None])
        self.time += dt
        n_new = int(np.floor(p.release_rate * self.time + 1e-9)) - self.n_released
        if n_new > 0:
            free = np.flatnonzero(~self.alive)[:n_new]
            if free.size < n_new:
                raise RuntimeError("filament capacity exceeded")   # cannot happen with the drop margin
            self.pos[free] = p.source
            self.age[free] = 0.0
            self.alive[free] = True
            self.n_released += n_new

    def advance_to(self, time: float) -> None:
        """Step until the plume's clock reaches `time` (s)."""
        while self.time < time - 1e-9:
            self.step()

    # -- what the sensor reads ------------------------------------------------------------
    def sigma2(self, age: np.ndarray) -> np.ndarray:
        """Variance per axis of filaments of `age` s: ``σ0² + 2 D age`` (m^2)."""
        return self.p.puff_sigma0 ** 2 + 2 * self.p.puff_diffusivity * age

    def concentration(self, points: np.ndarray) -> np.ndarray:
        """Concentration at `points` (n, 2): the sum of the filaments' puffs."""
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        idx = np.flatnonzero(self.alive)
        if not idx.size:
            return np.zeros(len(pts))
        c = self.pos[idx]
        d2 = (pts[:, None, 0] - c[None, :, 0]) ** 2 + (pts[:, None, 1] - c[None, :, 1]) ** 2
        return puff_concentration(d2, self.sigma2(self.age[idx])[None, :], self.p.puff_mass).sum(axis=1)

    @property
    def filaments(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres (n, 2) and ages (n,) of the live filaments."""
        idx = np.flatnonzero(self.alive)
        return self.pos[idx].copy(), self.age[idx].copy()

    def snapshot(self) -> dict:
        """What a figure draws of the plume now: ``filaments`` (centres of the live
        filaments, (n, 2), m), ``radii`` (their puffs' σ, (n,), m) and ``wind`` (the
        :func:`wind_arrows` over the region: points and vectors, m and m/s)."""
        centres, age = self.filaments
        return dict(filaments=centres, radii=np.sqrt(self.sigma2(age)), wind=wind_arrows(self.p.region, self.wind))


class FilamentWorld(World):
    """The truth of the ``filament`` world kind: a filament plume read by a binary
    detector at the sensor's sampling rate, plus the local wind.

    Parameters
    ----------
    params : FilamentParams
    cells : tuple of int
        The map's cells (m along x, n along y), told to strategies.
    speed : float
        The vehicle's speed, m/s (told to strategies).
    """

    kind = "filament"

    def __init__(self, params: FilamentParams, cells=(40, 25), speed: float = 1.0):
        self.p = params
        self.source = np.asarray(params.source, dtype=float)
        self.cells = (int(cells[0]), int(cells[1]))
        self.speed = float(speed)
        self.plume: FilamentPlume | None = None

    def reset(self, rng: np.random.Generator) -> None:
        """A new plume from `rng`, spun up for ``spinup`` s; the search clock starts at 0."""
        self.plume = FilamentPlume(self.p, rng)
        self.plume.advance_to(self.p.spinup)
        self._offset = self.plume.time

    def read(self, position, *, time: float, dwell: float, rng: np.random.Generator,
             observer: int = 0) -> Reading:
        """Advance the plume to `time` (s after the start) and read at `position`:
        value 1 if the concentration exceeds the threshold, else 0; ``data`` holds the
        local wind ``{"wind": [u_x, u_y]}`` (m/s)."""
        self.plume.advance_to(self._offset + float(time))
        x = np.asarray(position, dtype=float).reshape(1, 2)
        c = float(self.plume.concentration(x)[0])
        u = self.plume.wind(x)[0]
        return Reading(float(c > self.p.threshold), False, "detection", {"wind": [float(u[0]), float(u[1])]})

    def contains(self, points: np.ndarray) -> np.ndarray:
        pts = np.atleast_2d(points)
        x0, x1, y0, y1 = self.p.region
        return (pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)

    def nominal(self) -> dict:
        """Region, cells, sampling rate and speed; never the source or the plume."""
        x0, x1, y0, y1 = self.p.region
        return dict(region=tuple(self.p.region), cells=self.cells, sampling_rate=self.p.sampling_rate,
                    speed=self.speed, bounds=((x0, x1), (y0, y1)),
                    max_step=self.speed / self.p.sampling_rate)

    def describe(self) -> dict:
        return dict(release_rate=self.p.release_rate, threshold=self.p.threshold,
                    wind_sigma=self.p.wind_sigma)

    def figure_record(self) -> dict:
        """What the figures draw of the truth (:attr:`reciprocity.episode.Episode.truth`):
        ``plume`` (the plume at the end, :meth:`FilamentPlume.snapshot`), ``region``
        (``(x_min, x_max, y_min, y_max)``, m), ``cells`` (the map's m × n) and ``source``
        (the true source, (2,), m)."""
        return dict(plume=self.plume.snapshot(), region=tuple(self.p.region), cells=self.cells,
                    source=self.source.copy())
