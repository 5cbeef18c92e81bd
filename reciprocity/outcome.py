"""How a search ended: a typed stop reason, and what counts as converged and successful."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np

__all__ = ["StopReason", "Stop", "is_success", "match_sources", "MAX_SOURCES"]

#: Most sources of one world (``sources: [[x, y], ...]``) and of one search.
MAX_SOURCES = 4


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


def match_sources(true: np.ndarray, estimates: np.ndarray) -> list[float | None]:
    """The error of each true source (cm): the distance to the estimate assigned to it
    by the optimal assignment (least total distance, :func:`scipy.optimize.linear_sum_assignment`);
    None for a true source left without an estimate (more sources than estimates).

    Parameters
    ----------
    true : ndarray, shape (K, 2)
        The true sources.
    estimates : ndarray, shape (k, 2)
        The estimates (k may differ from K; extra estimates stay unmatched).
    """
    from scipy.optimize import linear_sum_assignment
    true = np.atleast_2d(np.asarray(true, dtype=float))
    est = np.asarray(estimates, dtype=float).reshape(-1, 2)
    out: list[float | None] = [None] * len(true)
    if len(est) == 0:
        return out
    d = np.hypot(*(true[:, None, :] - est[None, :, :]).transpose(2, 0, 1))
    for i, j in zip(*linear_sum_assignment(d)):
        out[int(i)] = float(d[i, j])
    return out
