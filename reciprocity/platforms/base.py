"""The platform interface: what turns a strategy's intents into motion and readings.

A platform holds the world (the truth) and the observer's true pose; it moves as an
intent asks, in its own way, and returns :class:`~reciprocity.observations.Observation`
records made from what the world's sensor read. Three platforms exist: the point
observer (:mod:`reciprocity.platforms.point`, moves instantly along free paths), the
walker (:mod:`reciprocity.platforms.walker`, one move per time step, on a lattice, a grid
or the plane, and may slip) and the car (:mod:`reciprocity.platforms.car`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..errors import SearchError
from ..intents import Intent
from ..observations import Observation
from ..worlds.base import World

__all__ = ["Platform"]


class Platform(ABC):
    """Moves as intents ask and returns observations.

    Attributes
    ----------
    pose : ndarray, shape (3,)
        Current pose as the platform reports it (x, y; heading rad).
    path_length : float
        Distance travelled so far.
    time : float
        The platform's clock (s, or steps in time-stepped worlds).
    last_route : list
        The way travelled during the last intent, points (2,).
    """

    #: Name recorded in the episode summary.
    name: str = "platform"
    #: Intent types the platform can carry out.
    intents: tuple = ()

    def __init__(self) -> None:
        self.agent = 0

    def reachable(self, points: np.ndarray) -> np.ndarray | None:
        """Mask of `points` (n, 2) the platform can reach from where it stands, or None
        when it can reach the whole free region (the episode then adds no restriction)."""
        return None

    def truly_reachable(self, points: np.ndarray) -> np.ndarray | None:
        """:meth:`reachable` judged on the true walls from the true pose: the evaluator's
        classification of a source (``source_reachable``), never shown to a strategy. The
        same as :meth:`reachable` unless the platform plans on a map that differs from the
        truth."""
        return self.reachable(points)

    #: Keys of the world's nominal description that this platform's :meth:`nominal`
    #: states in its place, because it reads the world its own way (the car: ``noise``,
    #: its calibrated reading noise, not the world's point-reading noise). Any other key
    #: both give is an error (:attr:`reciprocity.task.Task.nominal`).
    restates: tuple[str, ...] = ()

    def nominal(self) -> dict:
        """What the platform knows of its own readings, added to the world's nominal
        description a strategy sees (e.g. ``reading_noise``: the standard deviation of one
        reading, signal units, from the platform's own calibration). Called after
        :meth:`reset`."""
        return {}

    def takes(self) -> tuple[str, ...]:
        """The names of the intents this platform takes as configured (the task tells
        them to the agent): its :attr:`intents`, less a ``survey`` without a range sensor."""
        names = tuple(t.__name__.lower() for t in self.intents)
        return tuple(n for n in names if n != "survey" or getattr(self, "lidar", None) is not None)

    def step_log(self) -> dict:
        """Platform-specific records of the last intent for the episode trace."""
        return {}

    def summary(self) -> dict:
        """Platform-specific keys for the episode summary."""
        return {}

    def figure_record(self) -> dict:
        """What the episode's figures draw of this platform (beside the world's
        :meth:`~reciprocity.worlds.base.World.figure_record`); empty by default."""
        return {}

    @property
    def true_position(self) -> np.ndarray:
        """Where the observer really is (the episode's business, never a strategy's)."""
        return self.pose[:2]

    @abstractmethod
    def reset(self, start, world: World, rng: np.random.Generator) -> None:
        """Place the platform at `start` (x, y[, heading]) in `world`."""

    def execute(self, intent: Intent) -> list[Observation]:
        """Carry out `intent`; the observations it produced."""
        if not isinstance(intent, self.intents):
            names = ", ".join(t.__name__ for t in self.intents)
            raise SearchError(f"the {self.name} platform cannot carry out {type(intent).__name__}; "
                              f"it takes {names}")
        return self._execute(intent)

    @abstractmethod
    def _execute(self, intent: Intent) -> list[Observation]:
        """Carry out a supported intent."""
