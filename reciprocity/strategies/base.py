"""The strategy interface every search strategy implements."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from arenas import Arena

__all__ = ["Request", "Strategy", "MAX_REJECTIONS"]

#: A strategy gives up after this many unreachable targets in one search.
MAX_REJECTIONS = 20


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
    motion : str
        How a car should get there: ``"plan"`` (the optimal path of the HJ planner),
        ``"manoeuvre"`` (the paper's short reverse, then forward and to the side, for the
        three gradient samples; the points are nominal) or ``"bangbang"`` (a step toward
        the point with the bang-bang action nearest to its direction). A point observer
        ignores it.
    """

    points: np.ndarray
    kind: str = "signal"
    motion: str = "plan"


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
        self.n_rejected = 0

    @abstractmethod
    def start(self, arena: Arena, pose: np.ndarray, rng: np.random.Generator) -> None:
        """Begin a search in `arena` from `pose` (x, y cm; heading rad)."""

    @abstractmethod
    def propose(self) -> Request | None:
        """The next request, or None once :attr:`done`."""

    @abstractmethod
    def observe(self, request: Request, points: np.ndarray, readings: np.ndarray) -> None:
        """Receive the readings taken for `request` at `points` (as reached), cm."""

    def restrict(self, mask_of) -> None:
        """Restrict the points the strategy may request to those where ``mask_of(points)``
        is True (the platform's reachable set). Strategies with a candidate set override
        this; by default it is ignored."""

    def reject(self, request: Request, point: np.ndarray, reason: str) -> None:
        """The platform cannot reach `point` of `request` (cm); `reason` says why.

        Strategies that can choose another point override this; by default the search
        stops with the reason as its stop reason.
        """
        self.done, self.stop_reason = True, f"unreachable target: {reason}"

    def _count_rejection(self, reason: str) -> bool:
        """Count a rejected target; True (and stop) once there were too many."""
        self.n_rejected += 1
        if self.n_rejected > MAX_REJECTIONS:
            self.done = True
            self.stop_reason = f"gave up after {MAX_REJECTIONS} unreachable targets (last: {reason})"
        return self.done

    @property
    def estimate(self) -> np.ndarray | None:
        """Current source estimate (cm) or None."""
        return self.status.estimate

    def params(self) -> dict:
        """The strategy's parameters, for the episode summary."""
        return {}
