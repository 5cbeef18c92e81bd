"""What a strategy asks for: intents. Platforms turn them into motion.

A strategy states *what* it wants (measure here; sample a gradient around here; a short
step toward there; one move to a neighbouring place); a platform decides *how*: a point
observer jumps, a walker moves one link and may slip, the car plans, manoeuvres and
steers. No intent says anything about how a vehicle moves.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Intent", "Measure", "SampleGradient", "StepToward", "Move", "Stay", "Survey"]


def _point(p) -> np.ndarray:
    a = np.asarray(p, dtype=float).reshape(-1)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ValueError(f"an intent's point must be two finite numbers; got {p!r}")
    return a


@dataclass(frozen=True)
class Intent:
    """Base class of intents. `point` is where the strategy wants the observer."""

    point: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "point", _point(self.point))

    @property
    def name(self) -> str:
        return type(self).__name__.lower()


@dataclass(frozen=True)
class Measure(Intent):
    """Go to `point` (by any free route) and take one reading there (kind ``"signal"``)."""


@dataclass(frozen=True)
class SampleGradient(Intent):
    """Take two extra readings (kind ``"gradient"``) close to `point`, where the observer
    stands, about `offset` away and not collinear with it, for a three-point gradient."""

    offset: float = 5.0


@dataclass(frozen=True)
class StepToward(Intent):
    """A short step toward `point` (a gradient step), then one reading there."""


@dataclass(frozen=True)
class Move(Intent):
    """One move of a time-stepped observer to `point` (an adjacent node or cell, or a
    place within one step's reach), then the reading of one time step."""


@dataclass(frozen=True)
class Stay(Intent):
    """Stay at `point` (where the observer is) for one time step and read."""


@dataclass(frozen=True)
class Survey(Intent):
    """Go to `point` (by any free route) and scan the walls there with the range sensor,
    taking no reading: the observations are scans only (kind ``"scan"``). Only a platform
    with a range sensor takes it; a strategy on an unknown map explores with it."""
