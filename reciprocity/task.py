"""What crosses the boundary between the environment and an agent, besides observations.

:class:`Task` is the public description an agent receives when an episode starts (what
the world and the platform are nominally like, where the observers start, the budget);
:class:`Report` is what an agent declares when it stops (its estimate and its own
counts). Neither holds any part of the truth: the true source, the true walls, the true
poses and the seeds stay inside :class:`reciprocity.env.SearchEnv`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from .errors import SearchError
from .observations import MessageLog, Observation
from .outcome import Stop

__all__ = ["Task", "Percept", "Report", "RemoteReachable"]


@dataclass(frozen=True)
class Task:
    """The public description of one search, given to the agent at reset.

    Attributes
    ----------
    world : str
        The world kind (``"poisson"``, ``"lattice"``, ``"plume"``, ``"filament"``).
    scenario : str
        The scenario's name.
    world_nominal : Mapping
        The world as the agent is told it is (``World.nominal()``): the believed arena
        or lattice, nominal strength and noise, wind; never the source or the mismatch.
    platform : str
        The platform's name (``"point"``, ``"car"``, ``"walker"``, ``"lattice"``).
    platform_nominal : Mapping
        What the platform tells of its own readings (e.g. the car's calibrated noise).
    limits : Mapping
        Platform limits a strategy should respect, as defaults of its parameters of the
        same names (the car's ``clearance`` in cm, the sensor's top ``i_max``).
    starts : ndarray, shape (n_agents, 3)
        Start poses as the platforms report them (x, y, heading rad).
    max_steps : int or None
        The episode's budget of rounds (one intent per observer each).
    reachable : callable or None
        ``reachable(points) -> bool mask``: where the (first) platform can go, computed
        from the believed map; None where every point of the space can be reached.
    intents : tuple of str
        The intents the platform takes, by name (``"measure"``, ``"survey"``, ...: the
        lower-case class names of :mod:`reciprocity.intents`); empty when not told.
    """

    world: str
    scenario: str
    world_nominal: Mapping
    platform: str
    platform_nominal: Mapping
    limits: Mapping
    starts: np.ndarray
    max_steps: int | None = None
    reachable: Callable | None = None
    intents: tuple = ()

    def __post_init__(self):
        for name in ("world_nominal", "platform_nominal", "limits"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))
        starts = np.array(self.starts, dtype=float)
        starts.setflags(write=False)
        object.__setattr__(self, "starts", starts)
        object.__setattr__(self, "intents", tuple(str(i) for i in self.intents))

    def __reduce__(self):
        # A task crosses process boundaries (subprocess vector environments send reset
        # infos back): read-only mappings do not pickle, so it travels as plain dicts and
        # is made read-only again on arrival; `reachable` asks the live platform, which
        # stays in the environment's process (see RemoteReachable).
        reachable = None if self.reachable is None else RemoteReachable()
        return (type(self), (self.world, self.scenario, dict(self.world_nominal), self.platform,
                             dict(self.platform_nominal), dict(self.limits), np.array(self.starts),
                             self.max_steps, reachable, self.intents))

    def __copy__(self) -> "Task":
        return self                                  # immutable: a copy in this process is itself

    def __deepcopy__(self, memo) -> "Task":
        return self

    @property
    def n_agents(self) -> int:
        return len(self.starts)

    @property
    def nominal(self) -> dict:
        """World and platform descriptions in one mapping; a key both give is an error,
        never a silent override."""
        clash = set(self.world_nominal) & set(self.platform_nominal)
        if clash:
            raise SearchError(f"the world and the platform both describe {sorted(clash)}")
        return {**self.world_nominal, **self.platform_nominal}


class RemoteReachable:
    """The ``reachable`` of a task copied into another process (e.g. a reset info sent
    back by a subprocess vector environment): the platform it would ask stays in the
    environment's process, so calling it raises :class:`~reciprocity.errors.SearchError`
    instead of answering for a platform it cannot see."""

    def __call__(self, points: np.ndarray) -> np.ndarray:
        raise SearchError("this task was copied from another process: its reachable set can "
                          "only be asked where the environment runs (use a synchronous "
                          "vector environment, or the environment's own task)")


@dataclass(frozen=True)
class Percept:
    """What one observer's platform returns for one intent: its observations, or why the
    intent's point could not be reached.

    Attributes
    ----------
    agent : int
        The observer.
    observations : list of Observation
        The readings made (empty when unreachable).
    unreachable : tuple (point, reason) or None
        The point (cm or the world's unit) that could not be reached, and why.
    """

    agent: int
    observations: list[Observation]
    unreachable: tuple | None = None


@dataclass(frozen=True)
class Report:
    """What an agent declares when its search ends; the environment judges it.

    Attributes
    ----------
    strategy : str
        The agent's name.
    estimate : ndarray or None
        The source estimate.
    stop : Stop
        Why the agent stopped (its own rule, or the reason the environment gave it).
    region_area : float or None
        The area of the belief's region of possible sources, where it has one.
    n_measurements, n_samples, n_rejected : int
        Readings the agent used, all readings it asked for, targets it had refused.
    params : dict
        The agent's parameters (for the summary).
    position_support : ndarray or None, shape (m, 2)
        Where the agent believes its first observer may be (agents that estimate their
        own position, e.g. Ristic et al. 2014); the environment checks the true position
        against it.
    messages : MessageLog
        What several observers shared.
    agents : int or None
        How many observers the agent directs (None: any number).
    estimates : ndarray or None, shape (k, 2)
        Every source the agent found, where the task allows several (``max_sources`` of
        the nominal world above 1); None: the one `estimate`.
    estimates_sd : ndarray or None, shape (k,)
        The uncertainty of each of `estimates` (cm: the standard deviation of its belief).
    notes : dict
        What the agent records about its own run, added to the summary (e.g.
        ``remesh_failures`` on an unknown map); a key of the summary's own is refused.
    figures : dict
        What the episode's figures draw of the agent's belief at the end (the strategy's
        :meth:`~reciprocity.strategies.base.Strategy.figure_record`), when the agent was
        asked to keep it; never judged.
    """

    strategy: str
    estimate: np.ndarray | None
    stop: Stop
    region_area: float | None = None
    n_measurements: int = 0
    n_samples: int = 0
    n_rejected: int = 0
    params: dict = field(default_factory=dict)
    position_support: np.ndarray | None = None
    messages: MessageLog = field(default_factory=MessageLog)
    agents: int | None = 1
    estimates: np.ndarray | None = None
    estimates_sd: np.ndarray | None = None
    notes: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)
