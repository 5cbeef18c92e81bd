"""The turbulent-plume world (truth): Poisson hits with the Vergassola et al. (2007) mean rate.

A source at ``r0`` releases patches at rate ``R``; they live ``τ``, diffuse with ``D`` and
are advected by a mean wind of speed ``V``. A spherical sensor of radius ``a`` at ``r``
meets them at the mean rate

    R(r | r0) = R / ln(λ/a) · A(r, r0) · K0(|r − r0| / λ),   λ = sqrt(D τ / (1 + V² τ / (4 D)))

and the number of hits in a step ``Δt`` is Poisson with mean ``R(r | r0) Δt``. The
advection factor ``A`` differs between the papers this world reproduces; each form is
kept as its paper writes it (:data:`FORMS`):

``"wind"``
    ``A = exp(V / (2D) · (r − r0) · ŵ)`` with ``ŵ`` the unit vector the wind blows toward.
    With ``ŵ = −ŷ`` this is Vergassola's ``exp((y0 − y) V / (2D))`` (REFERENCE.md); with
    ``ŵ = +x̂`` it is ``exp((x − x0) V / (2D))``, the variant used for Song, He & Lei
    (2019, papers/002), whose eq. (1) gives only the Poisson law and refers the rate to
    Vergassola [14] and Ristic's code, with the source near the upwind (left) end of an
    area elongated along x.
``"isotropic"``
    ``A = exp(V / (2D) · |r − r0|)``: the form Hajieghrary, Mox & Hsieh (2017,
    papers/001) write under their Section 2 (the rate depends on the distance only).
    It still decays, because ``1/λ > V/(2D)`` for every ``τ``.

Without wind (``V = 0``, ``λ = sqrt(D τ)``) both reduce to the grid model of otto (Loisy
& Eloy 2022): ``μ(d) = R Δt · K0(d/λ) / ln(λ/a)`` with ``a = Δx/2``.

Several sources (``sources``) release independently, so the hit rate is the sum of
their rates (the hits of independent Poisson processes add up).

The world can differ from what a strategy is told (:class:`PlumeMismatch`: the true rate,
wind, diffusivity and lifetime as multiples of the nominal ones), and each observer's
sensor can be faulty (:class:`SensorFault`: a gain, false alarms, a failure time), which
no strategy is told either.

A directional sensor (``sensor="directional"``, Hajieghrary, Mox & Hsieh 2017, eq. (14),
:mod:`reciprocity.models.directional`) reads at a rate that depends on the observer's
course just before the reading; the platform passes it as ``course``.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..errors import SearchError
from ..models.directional import directional_rate
from ..models.plume import FORMS, PlumeParams, plume_length, plume_rate
from ..validation import number
from .base import Reading, World, source_set

__all__ = ["FORMS", "PlumeParams", "PlumeMismatch", "SensorFault", "PlumeWorld", "plume_length", "plume_rate"]

#: Pixels along each side of the true mean-hits image of :meth:`PlumeWorld.figure_record`.
IMAGE_PIXELS = 200

@dataclass(frozen=True)
class PlumeMismatch:
    """How the true plume differs from the nominal one (all 1 / 0: no mismatch).

    Attributes
    ----------
    rate_factor, wind_factor, diffusivity_factor, tau_factor : float
        True ``R``, ``V``, ``D``, ``τ`` as multiples of the nominal values.
    wind_turn : float
        True wind direction minus the nominal one, degrees.
    """

    rate_factor: float = 1.0
    wind_factor: float = 1.0
    diffusivity_factor: float = 1.0
    tau_factor: float = 1.0
    wind_turn: float = 0.0

    @classmethod
    def from_dict(cls, d: dict) -> "PlumeMismatch":
        names = [f.name for f in fields(cls)]
        unknown = set(d) - set(names)
        if unknown:
            raise SearchError(f"unknown plume mismatch option(s) {', '.join(sorted(unknown))}; "
                              f"choose from {', '.join(names)}")
        out = {}
        for k, v in d.items():  # factors within 1000 of nominal; wind_turn in degrees
            lo, lo_open = {"wind_turn": (-360.0, False), "wind_factor": (0.0, False)}.get(k, (0.0, True))
            out[k] = number(v, f"mismatch {k}", lo, 360.0 if k == "wind_turn" else 1000.0, lo_open=lo_open)
        return cls(**out)

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class SensorFault:
    """How one observer's hit counter differs from the nominal one (defaults: healthy).

    Over a dwell ``Δt`` starting at time ``t`` the faulty counter reads
    ``Poisson(gain · R(r | r0) · Δt + false_rate · Δt)`` while ``t < fails_at``, and 0
    from then on (a dead sensor).

    Attributes
    ----------
    gain : float
        True hits counted, as a fraction of those met (0: a dead sensor; above 1: double
        counting).
    false_rate : float
        Spurious hits per unit time, wherever the observer is.
    fails_at : float or None
        Time from which the sensor reads nothing (None: never fails).
    """

    gain: float = 1.0
    false_rate: float = 0.0
    fails_at: float | None = None

    @classmethod
    def from_dict(cls, d, where: str = "sensor") -> "SensorFault":
        if not isinstance(d, dict):
            raise SearchError(f"{where} must be a mapping of gain, false_rate, fails_at; got {d!r}")
        names = [f.name for f in fields(cls)]
        unknown = set(d) - set(names)
        if unknown:
            raise SearchError(f"unknown {where} option(s) {', '.join(sorted(unknown))}; "
                              f"choose from {', '.join(names)}")
        out = {k: number(d[k], f"{where} {k}", 0.0, 1e6) for k in ("gain", "false_rate") if k in d}
        if d.get("fails_at") is not None:
            out["fails_at"] = number(d["fails_at"], f"{where} fails_at", 0.0, 1e9)
        return cls(**out)

    @property
    def healthy(self) -> bool:
        return self == SensorFault()

    def mean(self, true_mean: float, *, time: float, dwell: float) -> float:
        """The faulty counter's mean count given the true mean `true_mean` over the dwell."""
        if self.fails_at is not None and time >= self.fails_at:
            return 0.0
        return self.gain * true_mean + self.false_rate * dwell

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


class PlumeWorld(World):
    """Sources in a rectangle, read by a hit counter (the truth of ``plume`` scenarios).

    Parameters
    ----------
    bounds : ((x0, x1), (y0, y1))
        The search area (length unit).
    source : array_like, shape (2,), or None
        The true source (length unit); None when `sources` gives them.
    params : PlumeParams
        The nominal hit model (what a strategy is told).
    mismatch : PlumeMismatch
        How the truth differs from `params`.
    found_radius : float
        The search ends (FOUND) once an observer is within this distance of a source.
    grid : float or None
        Cell size when observers move on a grid of cell centres (otto), else None.
    nominal_extra : dict
        Further keys of :meth:`nominal` (motion, dt, initial hit, hit-count cap).
    sensors : sequence of SensorFault, optional
        Observer k's sensor fault, as observer k's start in a scenario's ``start`` list:
        observers beyond the list are healthy (a faulty entry beyond the run's observers
        is refused by the scenario's ``check_observers``).
    sources : array_like, shape (K, 2), optional
        Several true sources (length unit), replacing `source` (which, if given, must be
        the first); the hit rate is the sum of their rates.
    strengths : array_like, shape (K,), optional
        Their release rates (per unit time, the unit of ``params.rate``; default: each the
        nominal ``params.rate``), before the mismatch's ``rate_factor``. The strategy is
        told the nominal rate only.
    max_sources : int, optional
        The task's public bound on the number of sources (default 1 with `source`,
        MAX_SOURCES with `sources`): part of what a strategy is told, never the number of
        sources itself.
    sense : {None, "toward", "printed"}
        None: the sensor has no direction; else the directional sensor of eq. (14) of
        papers/001 read in that sense (:data:`reciprocity.models.directional.SENSES`),
        at the course the platform passes to :meth:`read`.
    """

    kind = "plume"

    def __init__(self, bounds, source, params: PlumeParams, *, mismatch: PlumeMismatch | None = None,
                 found_radius: float = 1.0, grid: float | None = None, nominal_extra: dict | None = None,
                 sensors=(), sources=None, strengths=None, max_sources: int | None = None,
                 sense: str | None = None):
        #: the directional sensor's sense (None: no direction)
        self.sense = sense
        self.bounds = tuple(tuple(float(v) for v in b) for b in bounds)
        self.sources, given, self.max_sources = source_set("plume", source, sources, strengths, params.rate,
                                                           max_sources, each="release rate")
        self.source = self.sources[0]
        self.params = params
        self.mismatch = mismatch or PlumeMismatch()
        self.truth = params.scaled(self.mismatch)
        # each source's rate as a multiple of the nominal one (1 exactly when not given),
        # applied to the true model, which carries the mismatch's rate_factor
        self._weights = given / params.rate
        #: true release rates (per unit time; the nominal rate is the task's, ``params.rate``)
        self.strengths = self._weights * self.truth.rate
        self.found_radius = float(found_radius)
        self.grid = grid
        self._extra = dict(nominal_extra or {})
        self.sensors = tuple(sensors)

    def rate(self, at) -> np.ndarray:
        """True mean hit rate at `at` (m, 2), shape (m,), hits per unit time: the sum of
        the sources' rates (independent releases)."""
        return plume_rate(at, self.sources, self.truth) @ self._weights

    def read(self, position, *, time, dwell, rng, observer: int = 0, course: float | None = None) -> Reading:
        """Poisson hits over the dwell; `course` (rad) is the observer's heading just before
        the reading, used by a directional sensor only (required by it)."""
        at = np.asarray(position, dtype=float)[None]
        if self.sense is None:
            mu = float(self.rate(at)[0]) * float(dwell)
        else:
            if course is None:
                raise SearchError("a directional plume sensor needs the observer's course")
            rates = directional_rate(at, [course], self.sources, self.truth, self.sense)[0]
            mu = float(rates @ self._weights) * float(dwell)
        if observer < len(self.sensors):
            mu = self.sensors[observer].mean(mu, time=float(time), dwell=float(dwell))
        return Reading(float(rng.poisson(mu)), False, "hits")

    def mean_hits_image(self, n: int = IMAGE_PIXELS) -> np.ndarray:
        """The true mean number of hits per step (rate × the task's ``dt``, 1 when it has
        none) on an `n` × `n` grid spanning :attr:`bounds`, corners included; row 0 at the
        lowest y, shape (n, n)."""
        (x0, x1), (y0, y1) = self.bounds
        X, Y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
        return self.rate(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape) * self._extra.get("dt", 1.0)

    def figure_record(self) -> dict:
        """What the figures draw of the truth (:attr:`reciprocity.episode.Episode.truth`):
        ``mean_hits`` (:meth:`mean_hits_image`, hits per step), ``bounds``
        (``((x0, x1), (y0, y1))``, length unit), ``source`` (the first true source, (2,)) and
        ``form`` (the rate's advection form, :data:`FORMS`)."""
        return dict(mean_hits=self.mean_hits_image(), bounds=self.bounds, source=self.source.copy(),
                    form=self.params.form)

    def contains(self, points) -> np.ndarray:
        p = np.atleast_2d(np.asarray(points, dtype=float))
        (x0, x1), (y0, y1) = self.bounds
        return (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)

    def nominal(self) -> dict:
        out = dict(bounds=self.bounds, plume=self.params, found_radius=self.found_radius,
                   grid=self.grid, **self._extra)
        return self._nominal_sources(out)

    def describe(self) -> dict:
        out = dict(plume=self.params.as_dict(), mismatch=self.mismatch.as_dict(),
                   found_radius=self.found_radius, initial_hit=self._extra.get("initial_hit"))
        if any(not f.healthy for f in self.sensors):      # the env refuses faults beyond its observers
            out["sensors"] = [f.as_dict() for f in self.sensors]
        return self._described_sources(out)
