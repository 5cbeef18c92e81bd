"""What a strategy sees: time-stamped observations, and the messages observers exchange.

A strategy never sees the world: only :class:`Observation` records, made by a platform
from what the world's sensor read at the platform's (reported) position.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

__all__ = ["Observation", "Message", "MessageLog", "KINDS", "SENSING_KINDS", "readings_of", "scans_of"]

#: Kinds of reading: a signal value, a gradient sample (an extra reading around a point),
#: a number of particle hits, a detection (0/1), a detection of links around a node, a
#: range scan of the walls around the observer (``data``: ``angles`` rad, ``ranges`` cm,
#: ``hit``, ``max_range`` cm; ``value``: the nearest range, cm).
KINDS = ("signal", "gradient", "hits", "detection", "links", "scan")
#: Kinds that sense the surroundings, not the source: a platform puts them after the
#: source readings of the same intent, and strategies that do not map skip them.
SENSING_KINDS = ("scan",)


def readings_of(observations) -> list:
    """The observations that read the source (every kind but :data:`SENSING_KINDS`), in order."""
    return [o for o in observations if o.kind not in SENSING_KINDS]


def scans_of(observations) -> list:
    """The range scans among `observations`, in order."""
    return [o for o in observations if o.kind == "scan"]


@dataclass(frozen=True)
class Observation:
    """One sensor reading as a platform reports it.

    Attributes
    ----------
    position : ndarray, shape (2,)
        Where the reading was taken, as the platform reports it (cm, or the world's unit);
        on the car this is the camera's estimate, not the true position.
    value : float
        The reading: signal units, a count of hits, or 0/1 for a detection.
    time : float
        Start of the reading, s (or steps in time-stepped worlds).
    dwell : float
        Duration of the reading (same unit as `time`); readings are averages over it.
    kind : str
        One of :data:`KINDS`.
    saturated : bool
        The sensor was at its ceiling: the true value is *at least* `value` (a censored
        reading), not equal to it.
    agent : int
        Index of the observer that took it.
    data : mapping, optional
        Structured readings that are not one number (e.g. the links detected around a
        lattice node).
    """

    position: np.ndarray
    value: float
    time: float = 0.0
    dwell: float = 0.0
    kind: str = "signal"
    saturated: bool = False
    agent: int = 0
    data: Mapping[str, Any] | None = None

    def __post_init__(self):
        object.__setattr__(self, "position", np.asarray(self.position, dtype=float).reshape(2))
        if self.kind not in KINDS:
            raise ValueError(f"observation kind must be one of {KINDS}; got {self.kind!r}")

    def as_dict(self) -> dict:
        """JSON-ready record."""
        out = dict(position=self.position.tolist(), value=float(self.value), time=float(self.time),
                   dwell=float(self.dwell), kind=self.kind, saturated=bool(self.saturated),
                   agent=int(self.agent))
        if self.data is not None:
            out["data"] = dict(self.data)
        return out


@dataclass(frozen=True)
class Message:
    """A message between observers: who sent what to whom, when.

    Attributes
    ----------
    time : float
        When it was sent (the episode's clock).
    sender : int
        Index of the sending observer.
    receivers : tuple of int
        Indices of the receiving observers.
    content : str
        What was shared (e.g. ``"observation"``).
    size : int
        Number of observations (or numbers) it carries.
    """

    time: float
    sender: int
    receivers: tuple
    content: str = "observation"
    size: int = 1


@dataclass
class MessageLog:
    """The explicit log of every message of an episode (multi-observer strategies)."""

    messages: list = field(default_factory=list)

    def send(self, time: float, sender: int, receivers, content: str = "observation",
             size: int = 1) -> Message:
        """Record a message and return it."""
        msg = Message(float(time), int(sender), tuple(int(r) for r in receivers), content, int(size))
        self.messages.append(msg)
        return msg

    def __len__(self) -> int:
        return len(self.messages)
