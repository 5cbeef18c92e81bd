"""The car's downward reflectance sensor and its calibration (section V, Fig. 3).

Landa et al. use a Fairchild QRB1134 phototransistor reflective object sensor facing
the floor. Its 10-bit ADC reports ``V x 204.8`` counts at 30 Hz; the response rises with
the grey level beneath and *flattens out above grey 185*: brighter greys cannot be told
apart. The noise has standard deviation ``sigma = 12`` counts.

:class:`AdcCurve` is that response, :class:`ReflectanceSensor` reads a painted
:class:`arenas.floor.Floor` under a car pose, and :class:`Calibration` is the Fig. 3
procedure: read a printed strip of known greys, fit the inverse ``counts -> grey`` on the
working range, and *flag* saturated readings instead of returning a wrong number.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import isotonic_regression

from .errors import ArenaError
from .floor import Floor, GreyMapping

__all__ = ["ADC_MAX", "CALIBRATION_GREYS", "AdcCurve", "Calibration", "ReflectanceSensor"]

#: Largest count of the 10-bit ADC.
ADC_MAX = 1023

#: The printed calibration strip: grey 0 (black) to 255 (white) in steps of 5.
CALIBRATION_GREYS = np.arange(0, 256, 5, dtype=float)


@dataclass(frozen=True)
class AdcCurve:
    """Expected ADC counts (``V x 204.8``, 10 bit) of a QRB1134-like sensor over a grey level.

    Rises monotonically with the grey level and flattens above the `knee` (185): there
    is no discrimination above it (Fig. 3 of Landa et al.).

    With ``f = g - w * softplus((g - knee) / w)`` (``f ~ g`` below the knee,
    ``f ~ knee`` above it) and ``t = f / knee``::

        counts(g) = black + (knee_counts - black) * t * (1 + curvature * (1 - t))
                    + tail_slope * (g - f)

    Parameters
    ----------
    black : float
        Counts on black (grey 0). Default 110 (0.54 V).
    knee_counts : float
        Counts where the rising part meets the plateau, at grey `knee`. Default 690
        (3.37 V).
    knee : float
        Grey level where the response saturates. Default 185.
    knee_width : float
        Width ``w`` of the rounded knee, grey levels. Default 3.
    curvature : float
        Concavity of the rise, in [0, 1): the slope on black is ``1 + curvature`` times
        the mean slope ``(knee_counts - black) / knee`` and ``1 - curvature`` times it
        just below the knee. Default 0.3 (4.1 and 2.2 counts per grey level).
    tail_slope : float
        Residual slope above the knee, counts per grey level. Default 0.01 (the whole
        plateau 185..255 spans under one count).

    Examples
    --------
    >>> c = AdcCurve()
    >>> [round(float(v)) for v in c([0, 100, 185, 255])]
    [110, 467, 685, 691]
    """

    black: float = 110.0
    knee_counts: float = 690.0
    knee: float = 185.0
    knee_width: float = 3.0
    curvature: float = 0.3
    tail_slope: float = 0.01

    def __post_init__(self):
        if not 0 <= self.black < self.knee_counts <= ADC_MAX:
            raise ArenaError(f"AdcCurve needs 0 <= black < knee_counts <= {ADC_MAX}; got black="
                             f"{self.black}, knee_counts={self.knee_counts}")
        if not 0 < self.knee <= 255 or not self.knee_width > 0:
            raise ArenaError(f"AdcCurve needs 0 < knee <= 255 and knee_width > 0; got knee="
                             f"{self.knee}, knee_width={self.knee_width}")
        if not 0 <= self.curvature < 1 or not self.tail_slope >= 0:
            raise ArenaError(f"AdcCurve needs 0 <= curvature < 1 (monotone) and tail_slope >= 0; "
                             f"got curvature={self.curvature}, tail_slope={self.tail_slope}")

    def __call__(self, grey) -> np.ndarray:
        """Expected counts (float, same shape as `grey`) at grey levels (clipped to 0..255)."""
        g = np.clip(np.asarray(grey, dtype=float), 0.0, 255.0)
        w = self.knee_width
        bent = w * np.logaddexp(0.0, (g - self.knee) / w)  # softplus: 0 below, g - knee above
        t = np.clip(g - bent, 0.0, None) / self.knee
        rise = (self.knee_counts - self.black) * t * (1.0 + self.curvature * (1.0 - t))
        return self.black + rise + self.tail_slope * bent


def _check_rng(rng) -> np.random.Generator:
    if not isinstance(rng, np.random.Generator):
        raise ArenaError(f"rng must be a numpy.random.Generator (numpy.random.default_rng(seed)); "
                         f"got {type(rng).__name__}")
    return rng


@dataclass(frozen=True)
class ReflectanceSensor:
    """A downward reflectance sensor on the car, reading the painted floor.

    Parameters
    ----------
    offset : tuple of float
        Spot centre in the car frame, ``(forward, left)`` cm from the car centre.
    spot_radius : float
        Radius of the floor disk the sensor averages over, cm.
    noise : float
        Standard deviation of the reading noise, ADC counts (12 in the paper).
    rate : float
        Readings per second, Hz (30 in the paper).
    curve : AdcCurve
        Expected counts over the grey level.

    Examples
    --------
    >>> import numpy as np
    >>> s = ReflectanceSensor()
    >>> s.position([10.0, 20.0, np.pi / 2]).round(6).tolist()
    [[10.0, 22.0]]
    """

    offset: tuple[float, float] = (2.0, 0.0)
    spot_radius: float = 0.3
    noise: float = 12.0
    rate: float = 30.0
    curve: AdcCurve = AdcCurve()

    def __post_init__(self):
        off = tuple(float(v) for v in np.asarray(self.offset, dtype=float).ravel())
        if len(off) != 2 or not all(map(math.isfinite, off)):
            raise ArenaError(f"sensor offset must be finite (forward, left) cm; got {self.offset!r}")
        object.__setattr__(self, "offset", off)
        for name, ok, what in (("spot_radius", lambda v: v >= 0, "a radius >= 0 cm"),
                               ("noise", lambda v: v >= 0, "a standard deviation >= 0 counts"),
                               ("rate", lambda v: v > 0, "a positive rate in Hz")):
            v = float(getattr(self, name))
            if not (math.isfinite(v) and ok(v)):
                raise ArenaError(f"sensor {name} must be {what}; got {getattr(self, name)!r}")
            object.__setattr__(self, name, v)
        if not isinstance(self.curve, AdcCurve):
            raise ArenaError(f"sensor curve must be an AdcCurve; got {type(self.curve).__name__}")

    def position(self, poses) -> np.ndarray:
        """World spot centres, shape (n, 2) cm, of car poses ``(x, y, heading)``.

        Parameters
        ----------
        poses : array_like, shape (n, 3) or (3,)
            Car centre (cm) and heading (radians, counter-clockwise from +x).
        """
        p = np.asarray(poses, dtype=float)
        if p.ndim == 1:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 3 or not np.all(np.isfinite(p)):
            raise ArenaError(f"poses must be finite (x, y, heading) rows, shape (n, 3) or (3,); "
                             f"got shape {np.shape(poses)}")
        fwd, left = self.offset
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        return np.column_stack([p[:, 0] + fwd * c - left * s, p[:, 1] + fwd * s + left * c])

    def _counts(self, greys: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        noisy = self.curve(greys) + _check_rng(rng).normal(0.0, self.noise, greys.shape)
        return np.clip(np.rint(noisy), 0, ADC_MAX).astype(np.int64)

    def read(self, floor: Floor, poses, rng: np.random.Generator) -> np.ndarray:
        """Raw ADC counts with the car at `poses` over `floor`.

        ``round(curve(floor.spot_grey(position(poses), spot_radius)) + N(0, noise^2))``,
        clipped to 0..1023.

        Parameters
        ----------
        floor : Floor
            The painted floor.
        poses : array_like, shape (n, 3) or (3,)
            Car poses ``(x, y, heading)``: cm, cm, radians.
        rng : numpy.random.Generator
            Source of the reading noise.

        Returns
        -------
        ndarray of int, shape (n,)
        """
        if not isinstance(floor, Floor):
            raise ArenaError(f"read needs an arenas.Floor (see render_floor); got "
                             f"{type(floor).__name__}")
        centres = self.position(poses)
        greys = floor.spot_grey(centres, self.spot_radius)
        off = np.isnan(greys)
        if off.any():
            x, y = centres[np.argmax(off)]
            raise ArenaError(f"the sensor spot at ({x:.4g}, {y:.4g}) cm is off the floor image "
                             f"(extent {floor.extent} cm); keep the car inside the arena")
        return self._counts(greys, rng)

    def read_grey(self, greys, rng: np.random.Generator) -> np.ndarray:
        """Raw ADC counts (int, same shape as `greys`) over patches of known grey levels."""
        g = np.asarray(greys, dtype=float)
        if not np.all(np.isfinite(g)):
            raise ArenaError("greys must be finite grey levels 0..255")
        return self._counts(g, rng)

    def calibrate(self, rng: np.random.Generator, greys=None, samples: int = 30) -> Calibration:
        """The Fig. 3 procedure: read a printed strip of known greys and fit the inverse.

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of the reading noise.
        greys : array_like, optional
            Patch grey levels, increasing; default :data:`CALIBRATION_GREYS` (0..255 in
            steps of 5).
        samples : int
            Readings per patch (default 30: one second at 30 Hz).

        Returns
        -------
        Calibration
        """
        g = CALIBRATION_GREYS if greys is None else np.asarray(greys, dtype=float).ravel()
        if int(samples) != samples or samples < 2:
            raise ArenaError(f"samples must be an integer >= 2 (readings per patch); got {samples!r}")
        samples = int(samples)
        readings = self.read_grey(np.repeat(g, samples), rng).reshape(len(g), samples)
        return Calibration(g, readings.mean(axis=1), readings.std(axis=1, ddof=1), samples,
                           self.curve.knee)


@dataclass(frozen=True, eq=False)
class Calibration:
    """A fitted sensor calibration: ADC counts -> grey level, with saturation flags.

    Parameters
    ----------
    greys : ndarray, shape (m,)
        Patch grey levels of the calibration strip, increasing.
    mean_counts, std_counts : ndarray, shape (m,)
        Mean and standard deviation (ddof 1) of the readings on each patch, counts.
    samples : int
        Readings per patch.
    knee : float
        Top of the working range, grey level (185).
    noise : float, optional (keyword only)
        Reading noise, counts. Default: pooled over the patches,
        ``sqrt(mean(std_counts ** 2))``.

    Notes
    -----
    The inverse is fitted only on patches at or below the knee: their means are made
    monotone (isotonic regression; tied blocks become one point at their mean grey) and
    interpolated with a monotone cubic (:class:`scipy.interpolate.PchipInterpolator`).
    A reading near the plateau only bounds the grey from below, so
    :meth:`saturated` flags it and :meth:`intensity` reports the bound, ``u_max``.
    """

    greys: np.ndarray
    mean_counts: np.ndarray
    std_counts: np.ndarray
    samples: int
    knee: float = 185.0
    noise: float | None = field(default=None, kw_only=True)

    def __post_init__(self):
        arrays = [np.asarray(getattr(self, k), dtype=float).ravel()
                  for k in ("greys", "mean_counts", "std_counts")]
        g, mean, std = arrays
        if not (len(g) == len(mean) == len(std)) or not all(np.all(np.isfinite(a)) for a in arrays):
            raise ArenaError(f"greys, mean_counts and std_counts must be finite and of equal length; "
                             f"got lengths {len(g)}, {len(mean)}, {len(std)}")
        if np.any(np.diff(g) <= 0):
            raise ArenaError("calibration greys must be strictly increasing")
        knee = float(self.knee)
        if not 0 < knee <= 255:
            raise ArenaError(f"knee must be a grey level in (0, 255]; got {self.knee!r}")
        if int(self.samples) != self.samples or self.samples < 2:
            raise ArenaError(f"samples must be an integer >= 2; got {self.samples!r}")
        noise = math.sqrt(float(np.mean(std ** 2))) if self.noise is None else float(self.noise)
        if not math.isfinite(noise) or noise < 0:
            raise ArenaError(f"noise must be a standard deviation >= 0 counts; got {self.noise!r}")
        for k, v in (("greys", g), ("mean_counts", mean), ("std_counts", std), ("knee", knee),
                     ("samples", int(self.samples)), ("noise", noise)):
            object.__setattr__(self, k, v)

        work = g <= knee
        iso = isotonic_regression(mean[work]).x
        counts, block = np.unique(iso, return_inverse=True)
        if len(counts) < 2:
            raise ArenaError(f"the calibration has fewer than two distinct levels at or below the "
                             f"knee {knee:g}: the readings do not rise with grey; check the strip "
                             "and the sensor")
        block_grey = np.bincount(block, g[work]) / np.bincount(block)
        object.__setattr__(self, "_inverse", PchipInterpolator(counts, block_grey))
        object.__setattr__(self, "_forward", PchipInterpolator(block_grey, counts))
        object.__setattr__(self, "_fit", (counts, block_grey, float(g[work][0])))

    @property
    def knee_counts(self) -> float:
        """Fitted counts at the top of the working range (the plateau level), counts."""
        return float(self._fit[0][-1])

    def grey(self, counts) -> np.ndarray:
        """Grey level (float, same shape as `counts`) of readings, on [0, knee].

        Monotone non-decreasing in `counts`. Counts below the fitted range give the
        lowest patch grey (0), counts above it give `knee`: there the grey is only
        bounded from below (see :meth:`saturated`).
        """
        c = np.asarray(counts, dtype=float)
        lo, hi = self._fit[0][0], self._fit[0][-1]
        g = self._inverse(np.clip(c, lo, hi))
        return np.where(c < lo, self._fit[2], np.where(c > hi, self.knee, g))

    def counts(self, grey) -> np.ndarray:
        """The fitted forward curve: expected counts at grey levels, flat above the knee."""
        g = np.asarray(grey, dtype=float)
        lo, hi = self._fit[1][0], self._fit[1][-1]
        return self._forward(np.clip(g, lo, hi))

    def saturated(self, counts, n: int = 1) -> np.ndarray:
        """Whether readings are at the plateau, where the sensor does not discriminate.

        Parameters
        ----------
        counts : array_like
            Each entry the mean of `n` readings, counts.
        n : int
            Readings averaged per entry.

        Returns
        -------
        ndarray of bool
            True where ``counts >= knee_counts - 2 * noise / sqrt(n)``: such a reading
            only bounds the grey from below.
        """
        if int(n) != n or n < 1:
            raise ArenaError(f"n must be a positive integer number of readings; got {n!r}")
        margin = 2.0 * self.noise / math.sqrt(n)
        return np.asarray(counts, dtype=float) >= self.knee_counts - margin

    def signal_noise(self, mapping: GreyMapping, n: int = 1) -> float:
        """Standard deviation of :meth:`intensity` for the mean of `n` readings, signal units.

        Three parts, added in quadrature and carried through the fitted inverse (grey
        per count: its median slope over the working range) and `mapping` (signal per
        grey): the reading noise of the mean, ``noise / sqrt(n)`` counts; the error of the
        fitted curve itself, ``noise / sqrt(samples)`` counts (each patch mean carries it,
        and it is the same for every reading of a run: a bias, which independent-noise
        imaging can only absorb as extra spread); and the floor's 8-bit grey quantisation,
        ``1/sqrt(12)`` grey. With the defaults (30 Hz, 1 s dwell, 30 samples per patch,
        12 counts) this is about 2.1 signal units on ``paper``. Why the first part alone
        is not enough (car readings measured against it): ``docs/testbed.md``.

        Parameters
        ----------
        mapping : GreyMapping
            How the floor was painted (:attr:`Floor.mapping`).
        n : int
            Readings averaged per value (a 1 s dwell at 30 Hz: 30).

        Returns
        -------
        float
        """
        return math.hypot(*self.signal_noise_parts(mapping, n))

    def signal_noise_parts(self, mapping: GreyMapping, n: int = 1) -> tuple[float, float]:
        """:meth:`signal_noise` split into what differs between readings and what they share.

        Parameters
        ----------
        mapping : GreyMapping
        n : int
            Readings averaged per value.

        Returns
        -------
        independent : float
            Reading noise of the mean and grey quantisation, signal units: independent from
            one reading to the next.
        shared : float
            The fitted curve's own error, signal units: the same offset for every reading
            of a run (one calibration).
        """
        if not isinstance(mapping, GreyMapping):
            raise ArenaError(f"mapping must be a GreyMapping (Floor.mapping); got "
                             f"{type(mapping).__name__}")
        if int(n) != n or n < 1:
            raise ArenaError(f"n must be a positive integer number of readings; got {n!r}")
        counts = self._fit[0]
        grid = np.linspace(counts[0], counts[-1], 64)
        grey_per_count = float(np.median(self._inverse.derivative()(grid)))
        independent = math.hypot(self.noise / math.sqrt(n) * grey_per_count, 1.0 / math.sqrt(12.0))
        shared = self.noise / math.sqrt(self.samples) * grey_per_count
        return independent / mapping.slope, shared / mapping.slope

    def intensity(self, counts, mapping: GreyMapping, n: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Calibrated signal of readings and their saturation flags.

        Parameters
        ----------
        counts : array_like
            Each entry the mean of `n` readings, counts.
        mapping : GreyMapping
            How the floor was painted (:attr:`Floor.mapping`).
        n : int
            Readings averaged per entry.

        Returns
        -------
        values : ndarray of float
            ``mapping.signal(grey(counts))``; where saturated, ``mapping.u_max`` (a lower
            bound of the true signal).
        saturated : ndarray of bool
            :meth:`saturated` of the readings.
        """
        if not isinstance(mapping, GreyMapping):
            raise ArenaError(f"mapping must be a GreyMapping (Floor.mapping); got "
                             f"{type(mapping).__name__}")
        flags = self.saturated(counts, n)
        values = np.where(flags, mapping.u_max, mapping.signal(self.grey(counts)))
        return values, flags

    def plot(self, ax=None):
        """Fig. 3: ADC counts over grey 0..255 with the working range marked.

        Patch means with error bars (standard deviation), the fitted curve (flat beyond
        the knee) and a vertical line at the knee.

        Returns
        -------
        matplotlib.axes.Axes
        """
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots()
        ax.errorbar(self.greys, self.mean_counts, yerr=self.std_counts, fmt="o", ms=3, capsize=2,
                    color="k", label=f"patch mean ± std ({self.samples} readings)")
        g = np.linspace(0.0, 255.0, 512)
        ax.plot(g, self.counts(g), color="C0", label="fitted curve")
        ax.axvline(self.knee, color="C3", ls="--", label=f"working range (grey {self.knee:g})")
        ax.set_xlim(0, 255)
        ax.set_xlabel("grey level (0 black .. 255 white)")
        ax.set_ylabel("sensor output (ADC counts, V × 204.8)")
        ax.set_title(f"sensor calibration, noise σ = {self.noise:.1f} counts")
        ax.legend(loc="lower right")
        return ax

    def to_dict(self) -> dict:
        """A JSON-able dict (lists and numbers); :meth:`from_dict` restores it."""
        return {"greys": self.greys.tolist(), "mean_counts": self.mean_counts.tolist(),
                "std_counts": self.std_counts.tolist(), "samples": self.samples,
                "knee": self.knee, "noise": self.noise}

    @classmethod
    def from_dict(cls, d: dict) -> Calibration:
        """Rebuild a calibration from :meth:`to_dict` output."""
        try:
            return cls(d["greys"], d["mean_counts"], d["std_counts"], d["samples"], d["knee"],
                       noise=d["noise"])
        except (KeyError, TypeError) as exc:
            raise ArenaError(f"not a calibration dict ({exc!r}); expected the keys greys, "
                             "mean_counts, std_counts, samples, knee, noise") from exc

    def __repr__(self) -> str:
        return (f"Calibration({len(self.greys)} patches, {self.samples} readings each, knee "
                f"{self.knee:g} at {self.knee_counts:.1f} counts, noise {self.noise:.2f} counts)")
