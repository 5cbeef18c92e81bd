"""The likelihood of the reciprocity search: how one reading is scored.

Eq. (7) of Landa et al. scores reading ``I_k`` at a candidate source ``x`` by
``exp(-(c G(x, z_k) - I_k)^2 / sigma^2)``. This part chooses

- ``sigma`` (:meth:`Likelihood.reading_sigma`): a number, or a rule on what the task states:
  ``"auto"`` is ``sqrt 2`` times the noise the world states (its nominal ``noise``, else
  :data:`PAPER_NOISE`); ``"noise"`` that noise itself, as the paper states eq. (7) (the
  variance of the measurement noise: the noise of one reading as the platform takes it, in
  signal units; the paper's 12 is ADC counts per raw 30 Hz sample); ``"calibrated"``
  (default) where the platform reports its own ``reading_noise`` (the car's calibration:
  :meth:`arenas.sensor.Calibration.signal_noise_parts` of one 1 s dwell), ``sqrt 2`` times
  its independent part, with its shared part ``reading_bias`` imaged as one offset of all
  readings (:meth:`Likelihood.reading_bias`); else as ``"auto"``. Each at least
  :data:`MIN_NOISE`;
- the relative error terms of a predicted reading (:meth:`Likelihood.error_terms`), added
  in quadrature: the belief's discretisation, estimated from its own solver by halving the
  mesh (:func:`~reciprocity.fem.discretisation.discretisation_error`), the platform's model
  (:data:`CALIBRATED_MODEL_ERROR` with a calibrated platform), and the stated strength's
  relative error; or one fixed ``model_error`` in place of the first two;
- the strength: known (a number, or the arena's nominal one, as the paper assumes), or
  unknown and integrated out over a log-uniform prior (:meth:`Likelihood.prior_range`), or
  fitted per point.

The error terms apply to the product of the maps with a known strength (the mean of
eq. (8) has none); :meth:`Likelihood.belief` builds the
:class:`~reciprocity.beliefs.imaging.ImagingMap` with all of them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...beliefs.imaging import ImagingMap
from ...errors import SearchError
from ...fem.discretisation import discretisation_error
from ...fem.green import GreenSolver

__all__ = ["Likelihood", "Scoring", "SIGMA_RULES", "PAPER_NOISE", "MIN_NOISE", "CALIBRATED_MODEL_ERROR",
           "RELATIVE_TERMS"]

#: Noise (signal units) assumed when the world states none: the paper's sensor noise
#: (its section V).
PAPER_NOISE = 12.0
#: Smallest reading noise used for ``sigma="auto"`` / ``"noise"``, signal units: keeps
#: eq. (7) defined in noise-free worlds (the strategy's mesh differs from the truth's by
#: about this much near the source).
MIN_NOISE = 1.0
SIGMA_RULES = ("auto", "noise", "calibrated")
#: ``sigma="calibrated"``: relative error of the model's predicted reading (the FEM field
#: at h = 1 cm against the truth mesh and the painted floor near the source), added in
#: quadrature to the calibrated noise; why 0.05 and not less, measured on the car:
#: ``docs/testbed.md`` (*Two defaults of the car's searches*).
CALIBRATED_MODEL_ERROR = 0.05
#: The error terms relative to the predicted reading, added in quadrature into the
#: map's ``model_error`` (see :meth:`Likelihood.error_terms`).
RELATIVE_TERMS = ("fixed", "discretisation", "platform", "strength")


class Scoring(NamedTuple):
    """What :meth:`Likelihood.belief` builds: the imaging map and the terms it scores with."""

    imaging: ImagingMap
    #: ``sigma`` of eq. (7) in use, signal units.
    sigma: float
    #: The error terms (:meth:`Likelihood.error_terms`); empty when none apply.
    error_terms: dict
    #: Their relative terms added in quadrature (before an unknown map's share).
    model_error: float
    #: The strength assumed, or None when unknown.
    strength: float | None


class Likelihood:
    """How the reciprocity search scores a reading (see the module's text).

    Parameters
    ----------
    sigma : float or {"calibrated", "auto", "noise"}
        ``sigma`` of eq. (7), signal units, or the rule that sets it from the task.
    model_error : "estimate" or float
        ``"estimate"``: the discretisation and platform terms; a fraction in [0, 1)
        replaces both.
    strength_error : float
        Relative standard deviation of the stated strength, a fraction in [0, 1).
    strength : float or "arena" or None
        The source strength: a number, the arena's nominal one, or None for unknown.
    strength_range : "decade" or "fit" or (float, float)
        With an unknown strength: the log-uniform prior's ``(lo, hi)`` (``"decade"``: a
        tenth to ten times the world's nominal strength), or ``"fit"`` per point.
    position_error : bool
        With a known strength and the product: a node stands for the sources in its area,
        and each reading's variance over them is added
        (:class:`~reciprocity.beliefs.imaging.ImagingMap`'s `position_error`).
    """

    def __init__(self, *, sigma="calibrated", model_error: float | str = "estimate", strength_error: float = 0.0,
                 strength="arena", strength_range="decade", position_error: bool = True):
        if sigma not in SIGMA_RULES and (isinstance(sigma, str) or not np.isfinite(sigma) or sigma <= 0):
            raise SearchError(f"sigma must be a positive number or one of {SIGMA_RULES}; got {sigma!r}")
        self.sigma = sigma if sigma in SIGMA_RULES else float(sigma)
        self.strength_range = _strength_range(strength_range)
        if model_error != "estimate" and (isinstance(model_error, (bool, str)) or not isinstance(model_error, (int, float))
                                          or not 0 <= model_error < 1):
            raise SearchError(f"model_error must be 'estimate' or a fraction in [0, 1); got {model_error!r}")
        self.model_error = model_error if model_error == "estimate" else float(model_error)
        if isinstance(strength_error, bool) or not isinstance(strength_error, (int, float)) \
                or not 0 <= strength_error < 1:
            raise SearchError(f"strength_error must be a fraction in [0, 1); got {strength_error!r}")
        self.strength_error = float(strength_error)
        self.strength = strength
        if not isinstance(position_error, bool):
            raise SearchError(f"position_error must be true or false; got {position_error!r}")
        self.position_error = position_error

    def reading_sigma(self, nominal: dict) -> float:
        """``sigma`` of eq. (7) for a world described by `nominal` (signal units)."""
        if not isinstance(self.sigma, str):
            return self.sigma
        noise = nominal.get("noise", PAPER_NOISE)
        if self.sigma == "calibrated" and "reading_noise" in nominal:
            noise = nominal["reading_noise"]
            # the shared part of the calibrated noise is imaged as one offset (offset_sd)
            noise = np.sqrt(max(noise ** 2 - self.reading_bias(nominal) ** 2, 0.0))
        noise = max(float(noise), MIN_NOISE)
        return noise if self.sigma == "noise" else np.sqrt(2.0) * noise

    def reading_bias(self, nominal: dict) -> float:
        """Standard deviation of an offset shared by every reading (signal units): the
        platform's ``reading_bias`` with ``sigma="calibrated"``, else 0."""
        if self.sigma != "calibrated" or "reading_noise" not in nominal:
            return 0.0
        return float(nominal.get("reading_bias", 0.0))

    def error_terms(self, nominal: dict, offset: float, solver: GreenSolver, sigma: float) -> dict:
        """The likelihood's error terms: the reading noise and shared offset (signal
        units), and the relative errors of a predicted reading, each a fraction, added in
        quadrature (:data:`RELATIVE_TERMS`): the belief's discretisation (estimated from
        `solver`), the platform's model (the car's floor print and sensor curve), the
        stated strength. `sigma` is eq. (7)'s in use. :meth:`belief` adds ``position``,
        the RMS distance (cm) from a source to its node, when that term is on."""
        terms = {"noise": sigma / np.sqrt(2.0), "offset": float(offset)}
        if not isinstance(self.model_error, str):
            terms["fixed"] = float(self.model_error)
        else:
            terms["discretisation"] = discretisation_error(solver).relative if solver.order == 1 else 0.0
            calibrated = self.sigma == "calibrated" and "reading_noise" in nominal
            terms["platform"] = CALIBRATED_MODEL_ERROR if calibrated else 0.0
        terms["strength"] = float(self.strength_error)
        return terms

    def prior_range(self, nominal: dict) -> tuple[float, float] | None:
        """The strength prior ``(lo, hi)`` for an unknown strength, or None to fit it."""
        if self.strength_range == "fit":
            return None
        if self.strength_range == "decade":
            stated = nominal.get("strength")
            if stated is None or not np.isfinite(stated) or stated <= 0:
                return None
            return (float(stated) / 10.0, float(stated) * 10.0)
        return self.strength_range

    def assumed_strength(self, nominal: dict, arena_strength: float | None) -> float | None:
        """The strength assumed (units of the signal per unit Green's function), None if
        unknown."""
        return nominal.get("strength", arena_strength) if self.strength == "arena" else self.strength

    def belief(self, solver: GreenSolver, nominal: dict, arena_strength: float | None, combine: str,
               widen=None) -> Scoring:
        """The imaging map on `solver` for a task stating `nominal`, its maps combined by
        `combine` (:mod:`reciprocity.beliefs.combiners`). `widen` (optional) maps the
        relative model error to the one used (an unknown map's share of unseen space)."""
        c = self.assumed_strength(nominal, arena_strength)
        sigma = float(self.reading_sigma(nominal))
        prior = self.prior_range(nominal) if c is None else None
        product = prior is None and combine == "product"
        offset = self.reading_bias(nominal) if product else 0.0
        terms = self.error_terms(nominal, offset, solver, sigma) if product else {}
        model_error = float(np.sqrt(sum(v * v for k, v in terms.items() if k in RELATIVE_TERMS)))
        used = widen(model_error) if widen is not None and product else model_error
        position = product and self.position_error
        imaging = ImagingMap(solver, sigma, strength=c, combine=combine, strength_range=prior,
                             offset_sd=offset, model_error=used, position_error=position)
        if position:   # the RMS distance (cm) from a source to the node that stands for it
            from ...fem.gradients import nodal_slope
            terms["position"] = float(np.sqrt(np.median(nodal_slope(solver).node_areas) / 6.0))
        return Scoring(imaging, sigma, terms, model_error, c)

    def params(self) -> dict:
        """The settings, as :meth:`ReciprocityStrategy.params` reports them."""
        return dict(sigma=self.sigma, strength=self.strength if not isinstance(self.strength, float)
                    else float(self.strength),
                    strength_range=self.strength_range if isinstance(self.strength_range, str)
                    else list(self.strength_range),
                    model_error=self.model_error, strength_error=self.strength_error,
                    position_error=self.position_error)


def _strength_range(value):
    """`value` checked: ``"decade"``, ``"fit"`` or ``(lo, hi)`` with ``0 <= lo < hi``."""
    if isinstance(value, str):
        if value not in ("decade", "fit"):
            raise SearchError(f"strength_range must be 'decade', 'fit' or (lo, hi); got {value!r}")
        return value
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise SearchError(f"strength_range must be 'decade', 'fit' or (lo, hi); got {value!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
        raise SearchError(f"strength_range needs 0 <= lo < hi; got {value!r}")
    return (lo, hi)
