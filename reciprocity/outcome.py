"""How a search ended: a typed stop reason, and what counts as converged and successful."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = ["StopReason", "Stop", "is_success"]


class StopReason(str, Enum):
    """Why a search stopped.

    ``CONVERGED`` and ``FOUND`` are a strategy's own stopping rule; the others are not:
    a run that hits the step cap, runs out of admissible targets or gives up never
    succeeds, however close its last estimate.
    """

    CONVERGED = "converged"        # the strategy's own rule (small region, gradient, I_max)
    FOUND = "found"                # the observer reached the source (where the paper says so)
    STEP_CAP = "step cap"          # the strategy's or the scenario's step limit
    NO_TARGET = "no target"        # no admissible place left to go
    UNREACHABLE = "unreachable"    # the whole region of possible sources is out of reach
    GAVE_UP = "gave up"            # too many unreachable targets, or the belief collapsed

    @property
    def converged(self) -> bool:
        return self in (StopReason.CONVERGED, StopReason.FOUND)


@dataclass(frozen=True)
class Stop:
    """A stop reason with a human-readable detail."""

    reason: StopReason
    detail: str = ""

    def __str__(self) -> str:
        return f"{self.reason.value}: {self.detail}" if self.detail else self.reason.value


def is_success(stop: Stop | None, error: float | None, radius: float, *, found: bool = False) -> bool:
    """Success: the strategy stopped by its own rule and its estimate lies within `radius`
    of the true source (or, for ``found`` worlds, an observer reached the source)."""
    if stop is None or not stop.reason.converged:
        return False
    if found:
        return stop.reason is StopReason.FOUND
    return error is not None and error <= radius
