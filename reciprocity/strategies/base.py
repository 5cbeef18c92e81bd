"""The strategy interface every search strategy implements.

A strategy is started with a :class:`SearchContext` (what it is told: the world's
nominal description, the start poses, a random generator, the message log), proposes
:mod:`intents <reciprocity.intents>` and receives :class:`~reciprocity.observations.Observation`
records. It never sees the world or the true poses.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..intents import Intent
from ..observations import MessageLog, Observation
from ..outcome import Stop, StopReason

__all__ = ["SearchContext", "Status", "Strategy", "MAX_REJECTIONS"]

#: A strategy gives up after this many unreachable targets in one search.
MAX_REJECTIONS = 20


@dataclass
class SearchContext:
    """What a strategy is told when a search starts.

    Attributes
    ----------
    world : str
        The world kind (``"poisson"``, ``"lattice"``, ...).
    nominal : dict
        The world's nominal description (``World.nominal()``): geometry and nominal
        parameters, never the source, never the mismatch.
    starts : ndarray, shape (n_agents, 3)
        Start poses as the platforms report them (x, y, heading rad).
    rng : numpy.random.Generator
        The strategy's own random generator.
    messages : MessageLog
        Where multi-observer strategies record what they share.
    intents : tuple of str
        The intents the platform takes, by name (the task's ``intents``); empty when not
        told, and then a strategy asks only for what every platform of its world takes.
    limits : Mapping
        The task's platform limits named in the strategy's :attr:`Strategy.start_limits`
        that its parameters left unset (e.g. the car sensor's ``i_max``, known only once
        the episode's floor is calibrated); empty otherwise.
    """

    world: str
    nominal: dict
    starts: np.ndarray
    rng: np.random.Generator
    messages: MessageLog = field(default_factory=MessageLog)
    intents: tuple = ()
    limits: Mapping = field(default_factory=dict)

    @property
    def n_agents(self) -> int:
        return len(self.starts)

    @property
    def arena(self):
        """The nominal arena (geometry, nominal strength; no source), where there is one."""
        return self.nominal.get("arena")

    @property
    def start(self) -> np.ndarray:
        """The first observer's start pose."""
        return self.starts[0]


@dataclass
class Status:
    """What a strategy believes after an update (recorded in the episode trace)."""

    estimate: np.ndarray | None = None
    region_area: float | None = None
    note: str = ""
    extra: dict = field(default_factory=dict)


class Strategy(ABC):
    """A source-search strategy: proposes intents, receives observations.

    Class attributes
    ----------------
    name : str
        Name on the command line.
    worlds : tuple of str
        World kinds the strategy applies to.
    agents : int or None
        Number of observers it directs (None: any number).
    senses : tuple of str
        Kinds of :data:`~reciprocity.observations.SENSING_KINDS` (e.g. ``"scan"``) it
        reads; the others are taken out of its observations before :meth:`observe`, so a
        strategy that does not map never sees a scan.
    start_limits : tuple of str
        Task limits (``Task.limits``) that the strategy takes from
        :attr:`SearchContext.limits` when it starts, where its parameter of that name was
        left unset, rather than as a parameter when it is built: limits that differ from
        episode to episode, so that one strategy, built and checked once, serves the run.
        The other limits it accepts as parameters fill them when it is built.
    """

    name: str = "strategy"
    worlds: tuple = ("poisson",)
    agents: int | None = 1
    senses: tuple = ()
    start_limits: tuple = ()

    def __init__(self) -> None:
        self._reset_state()

    def _reset_state(self) -> None:
        self.outcome: Stop | None = None
        self.status = Status()
        self.n_measurements = 0
        self.n_samples = 0
        self.n_rejected = 0
        #: What the strategy records about its own run for the episode summary
        #: (e.g. ``remesh_failures``): keys beside the contract's.
        self.notes: dict = {}

    # -- the protocol -------------------------------------------------------------------
    @abstractmethod
    def start(self, ctx: SearchContext) -> None:
        """Begin a search (call ``self._reset_state()`` first)."""

    @abstractmethod
    def propose(self) -> Intent | dict | None:
        """The next intent (one observer), a mapping agent -> intent (several), or None
        once :attr:`done`."""

    @abstractmethod
    def observe(self, observations: list[Observation], intent: Intent, agent: int = 0) -> None:
        """Receive the observations `agent`'s platform made for `intent`."""

    def restrict(self, mask_of) -> None:
        """Restrict the points the strategy may ask for to those where ``mask_of(points)``
        is True (the platform's reachable set). Strategies with candidate sets override
        this; by default it is ignored."""

    def reject(self, intent: Intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """The platform cannot reach `point` of `intent`; `reason` says why.

        Strategies that can choose another point override this; by default the search
        stops (no target)."""
        self.stop(StopReason.NO_TARGET, f"unreachable target: {reason}")

    # -- stopping -----------------------------------------------------------------------
    def stop(self, reason: StopReason, detail: str = "") -> None:
        """Stop the search for `reason`."""
        self.outcome = Stop(StopReason(reason), detail)

    @property
    def done(self) -> bool:
        return self.outcome is not None

    @property
    def stop_reason(self) -> str:
        return "" if self.outcome is None else str(self.outcome)

    def _count_rejection(self, reason: str) -> bool:
        """Count a rejected target; True (and stop) once there were too many."""
        self.n_rejected += 1
        if self.n_rejected > MAX_REJECTIONS:
            self.stop(StopReason.GAVE_UP, f"{MAX_REJECTIONS} unreachable targets (last: {reason})")
        return self.done

    @property
    def estimate(self) -> np.ndarray | None:
        """Current source estimate or None."""
        return self.status.estimate

    def params(self) -> dict:
        """The strategy's parameters, for the episode summary."""
        return {}

    def figure_record(self) -> dict:
        """What the episode's figures draw of this strategy's belief at the end of a search
        (:attr:`reciprocity.episode.Episode.belief`): a plain mapping whose keys
        :func:`reciprocity.viz.episode.episode_figures` knows (e.g. ``imaging`` and ``eps``,
        ``gradients``). Asked for once, after the search, and only when figures are drawn;
        empty (the default): nothing to draw."""
        return {}
