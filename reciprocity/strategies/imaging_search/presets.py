"""Named assemblies of the reciprocity search: which settings each part takes, the
defaults, and the presets.

A preset is a table of part settings (:data:`PRESETS`), applied over :data:`DEFAULTS`;
settings given explicitly override both (``preset="paper", sigma=17`` is the paper with
``sigma = 17``). :func:`assemble` builds the parts from the merged table.

**The paper's settings** (``preset="paper"``): ``rule="nearest"``, ``combine="mean"``
(eq. 8), ``sigma="noise"`` (eq. 7 with ``sigma^2`` the variance of the measurement noise,
as the paper states), and no extent, tail or credible rule. The paper gives no values for
``eps``, ``A_eps`` and ``d``; these are ours: ``d = 12.7 cm``, one spacing of the paper's
bank of value functions (the car measures at the bank's lattice point nearest to the
requested one, and with a smaller ``d`` the next point snaps back to the lattice point
just read and the car never leaves its start); ``eps = 0.7`` with ``A_eps = 40 cm^2`` (a
disk of radius 3.6 cm, inside the 5 cm success radius), the pair that stops nearest the
paper's readings when re-evaluated offline on recorded runs of the car as the paper ran it
(``benchmarks/landa_paper_preset.md``, ``docs/papers/landa2020.md``). The preset is for the
paper's platform, the car: on the point observer, whose Gaussian readings fall below zero,
eq. (8) stops on slivers far from the source (measured in the same file).
"""

from __future__ import annotations

from typing import NamedTuple

from ...beliefs.combiners import COMBINATIONS
from ...errors import SearchError
from .likelihood import Likelihood
from .next_point import NextPointRule
from .reachability import Reachability
from .several import SeveralSources
from .stop_rule import StopRule

__all__ = ["DEFAULTS", "PRESETS", "PARTS", "Parts", "settings", "assemble"]

#: Parameters a preset sets, and the defaults (no preset). ``extent_tol = inf`` is "no
#: extent rule".
DEFAULTS = dict(rule="axis", combine="product", sigma="calibrated", eps=0.1, area_tol=40.0,
                extent_tol=5.0, d=6.0, reach=12.0, tail_tol=10.0, credible_radius=3.0, credible_mass=0.95)
#: Preset name -> the settings it assembles the parts with.
PRESETS = {"paper": dict(rule="nearest", combine="mean", sigma="noise", eps=0.7, area_tol=40.0,
                         extent_tol=float("inf"), d=12.7, reach=12.0, tail_tol=float("inf"),
                         credible_radius=float("inf"))}
#: Part -> the settings it takes (``reach`` is shared by the next-point rule and the
#: reachability; ``combine`` chooses the map's combiner, :mod:`reciprocity.beliefs.combiners`).
PARTS = {"stop_rule": ("eps", "area_tol", "extent_tol", "tail_tol", "credible_radius", "credible_mass",
                       "max_steps"),
         "next_point": ("rule", "d", "reach"),
         "reachability": ("reach", "clearance"),
         "likelihood": ("sigma", "model_error", "strength_error", "strength", "strength_range",
                        "position_error"),
         "several": ("max_sources", "more_tol", "survey_travel", "survey_reach"),
         "combine": ("combine",)}


class Parts(NamedTuple):
    """The parts of one reciprocity search."""

    likelihood: Likelihood
    combine: str
    next_point: NextPointRule
    stop_rule: StopRule
    reachability: Reachability
    several: SeveralSources


def settings(preset: str | None, given: dict) -> dict:
    """:data:`DEFAULTS`, then the `preset`'s settings, then the `given` ones not None."""
    if preset is not None and preset not in PRESETS:
        raise SearchError(f"preset must be one of {tuple(PRESETS)} or None; got {preset!r}")
    return {**DEFAULTS, **PRESETS.get(preset, {}), **{k: v for k, v in given.items() if v is not None}}


def assemble(p: dict) -> Parts:
    """The parts with the settings `p` (every key of :data:`PARTS`), each checked by its
    part (a :class:`~reciprocity.errors.SearchError` names a bad one)."""
    stop_rule = StopRule(**{k: p[k] for k in PARTS["stop_rule"]})
    next_point = NextPointRule(**{k: p[k] for k in PARTS["next_point"]})
    likelihood = Likelihood(**{k: p[k] for k in PARTS["likelihood"]})
    reachability = Reachability(**{k: p[k] for k in PARTS["reachability"]})
    several = SeveralSources(**{k: p[k] for k in PARTS["several"]})
    if p["combine"] not in COMBINATIONS:
        raise SearchError(f"combine must be one of {COMBINATIONS}; got {p['combine']!r}")
    return Parts(likelihood, p["combine"], next_point, stop_rule, reachability, several)
