"""The world (truth): what a sensor really reads at a place and time.

A world is never seen by a strategy. It holds the true source, evolves in time when the
physics does (a plume), and answers one question: *what does the sensor read here, now,
over this dwell?* Every world can be made to differ on purpose from the model a strategy
assumes (mismatch options), so that a benchmark does not flatter a method by simulating
the world with the method's own equations.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

__all__ = ["World", "Reading"]


@dataclass(frozen=True)
class Reading:
    """What the sensor returned: a value and whether it was at its ceiling."""

    value: float
    saturated: bool = False
    kind: str = "signal"
    data: dict | None = None


class World(ABC):
    """Truth of a search.

    Attributes
    ----------
    kind : str
        The world kind of scenario files (``"poisson"``, ``"lattice"``, ``"plume"``, ...).
    source : ndarray, shape (2,)
        The true source (cm or the world's unit).
    success_radius : float
        A converged estimate within this distance of the source is a success.
    found_radius : float or None
        For worlds whose paper defines success as *reaching* the source: an observer
        within this distance has found it (None elsewhere).
    """

    kind: str = "world"
    source: np.ndarray
    success_radius: float = 5.0
    found_radius: float | None = None

    def reset(self, rng: np.random.Generator) -> None:
        """Start the world's clock (time-varying worlds draw their randomness from `rng`)."""

    @abstractmethod
    def read(self, position: np.ndarray, *, time: float, dwell: float,
             rng: np.random.Generator, observer: int = 0) -> Reading:
        """The sensor's reading at `position` over ``[time, time + dwell]``, by observer
        number `observer` (worlds whose observers' sensors differ, e.g. a faulty one)."""

    @abstractmethod
    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of `points` (n, 2) where an observer can be."""

    def found(self, position: np.ndarray) -> bool:
        """An observer at `position` has reached the source (``found_radius`` worlds)."""
        if self.found_radius is None:
            return False
        return bool(np.hypot(*(np.asarray(position, dtype=float)[:2] - self.source)) <= self.found_radius)

    def nominal(self) -> dict:
        """What a strategy is told about this world: its geometry and nominal parameters,
        *without* the source and without any mismatch."""
        return {}

    def describe(self) -> dict:
        """Summary keys describing the world (including its mismatch options)."""
        return {}

    def describe_start(self, start) -> dict:
        """Summary keys describing the world as seen from an observer's `start` (e.g. the
        lattice's shortest path to the source); the evaluator's, never a strategy's."""
        return {}
