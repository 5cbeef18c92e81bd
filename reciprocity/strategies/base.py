"""The strategy interface every search strategy implements."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from arenas import Arena

__all__ = ["Request", "Strategy"]


@dataclass
class Request:
    """Where a strategy wants the platform to measure next.

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        Observation points, visited in order, cm.
    kind : str
        ``"signal"`` (a measurement the strategy counts as one of its observations) or
        ``"gradient"`` (extra samples around the current point for a gradient estimate).
    """

    points: np.ndarray
    kind: str = "signal"


@dataclass
class Status:
    """What a strategy believes after an update (recorded in the episode trace)."""

    estimate: np.ndarray | None = None
    region_area: float | None = None
    note: str = ""
    extra: dict = field(default_factory=dict)


class Strategy(ABC):
    """A source-search strategy: proposes observation points, receives readings.

    A strategy never sees the true source or the true pose: only the points where its
    readings were taken (as reported by the platform) and the readings.
    """

    name: str = "strategy"

    def __init__(self) -> None:
        self.done = False
        self.stop_reason = ""
        self.status = Status()
        self.n_measurements = 0
        self.n_samples = 0

    @abstractmethod
    def start(self, arena: Arena, pose: np.ndarray, rng: np.random.Generator) -> None:
        """Begin a search in `arena` from `pose` (x, y cm; heading rad)."""

    @abstractmethod
    def propose(self) -> Request | None:
        """The next request, or None once :attr:`done`."""

    @abstractmethod
    def observe(self, request: Request, points: np.ndarray, readings: np.ndarray) -> None:
        """Receive the readings taken for `request` at `points` (as reached), cm."""

    @property
    def estimate(self) -> np.ndarray | None:
        """Current source estimate (cm) or None."""
        return self.status.estimate

    def params(self) -> dict:
        """The strategy's parameters, for the episode summary."""
        return {}
