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

from ..errors import SearchError
from ..outcome import MAX_SOURCES

__all__ = ["World", "Reading", "source_set"]


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

    #: The task's public bound on the number of sources (1: the classic problem).
    max_sources: int = 1
    #: The task's public statement that every source lies at least this far (cm) from the
    #: walls (0: anywhere in the free region; a campaign's ``random_source`` draws them
    #: ``SOURCE_CLEARANCE`` cm off). Part of the prior, not of the truth.
    source_clearance: float = 0.0

    @property
    def sources(self) -> np.ndarray:
        """Every true source, shape (K, 2) (the one `source` unless a world sets several)."""
        several = self.__dict__.get("_sources")
        return np.asarray(self.source, dtype=float).reshape(1, 2) if several is None else several

    @sources.setter
    def sources(self, value) -> None:
        self.__dict__["_sources"] = np.asarray(value, dtype=float).reshape(-1, 2)

    @property
    def n_sources(self) -> int:
        """Number of true sources."""
        return len(self.sources)

    def found(self, position: np.ndarray) -> bool:
        """An observer at `position` has reached a source (``found_radius`` worlds)."""
        if self.found_radius is None:
            return False
        d = np.hypot(*(self.sources - np.asarray(position, dtype=float)[:2]).T)
        return bool(d.min() <= self.found_radius)

    def _nominal_sources(self, out: dict) -> dict:
        """`out` with the task's bound on the number of sources, when above 1, and its
        ``source_clearance``, when above 0 (never the sources, their number or strengths)."""
        if self.max_sources > 1:
            out["max_sources"] = self.max_sources
        if self.source_clearance > 0:
            out["source_clearance"] = float(self.source_clearance)
        return out

    def _described_sources(self, out: dict) -> dict:
        """`out` with the sources, their strengths, number and bound, when several may be."""
        if self.max_sources > 1 or self.n_sources > 1:
            out.update(sources=self.sources.tolist(), strengths=np.asarray(self.strengths).tolist(),
                       n_sources=self.n_sources, max_sources=self.max_sources)
        return out

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

    def figure_record(self) -> dict:
        """What the episode's figures draw of the truth (:attr:`reciprocity.episode.Episode.truth`),
        after the episode, never shown to a strategy; empty by default."""
        return {}


def source_set(kind: str, source, sources, strengths, default: float, max_sources: int | None,
               *, each: str = "strength") -> tuple[np.ndarray, np.ndarray, int]:
    """A world's true sources, their strengths and the task's bound on their number.

    Parameters
    ----------
    kind : str
        The world kind, for messages.
    source : array_like or None
        The one source (or None when `sources` are given).
    sources : array_like or None, shape (K, 2)
        Several sources, replacing `source`; its first point must then equal `source`.
    strengths : array_like or None, shape (K,)
        Their strengths (default: each `default`).
    default : float
        The nominal strength.
    max_sources : int or None
        The task's public bound (default 1 with one source, MAX_SOURCES with `sources`).
    each : str
        What one strength is, in messages.

    Returns
    -------
    (ndarray (K, 2), ndarray (K,), int)
    """
    pts = np.asarray(source if sources is None else sources, dtype=float).reshape(-1, 2)
    if not 1 <= len(pts) <= MAX_SOURCES:
        raise SearchError(f"a {kind} world has 1 to {MAX_SOURCES} sources; got {len(pts)}")
    if sources is not None and source is not None \
            and not np.array_equal(np.asarray(source, dtype=float).reshape(2), pts[0]):
        raise SearchError(f"{kind} source {source!r} differs from the first of sources {sources!r}; "
                          "give either source (one source) or sources (several)")
    given = np.full(len(pts), float(default)) if strengths is None else np.asarray(strengths, dtype=float)
    if given.shape != (len(pts),) or not np.all(np.isfinite(given) & (given > 0)):
        raise SearchError(f"{kind} strengths must be one positive {each} per source; got {strengths!r}")
    bound = int(max_sources if max_sources is not None else (1 if sources is None else MAX_SOURCES))
    return pts, given, bound
