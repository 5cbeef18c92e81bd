"""A built-in strategy as an agent of :func:`reciprocity.env.rollout`."""

from __future__ import annotations

import inspect

import numpy as np

from ..errors import SearchError
from ..observations import SENSING_KINDS, MessageLog
from ..outcome import Stop, StopReason
from ..task import Percept, Report, Task
from .base import SearchContext, Status, Strategy
from .map_steps import with_map_steps

__all__ = ["StrategyAgent"]


class StrategyAgent:
    """Drive a :class:`Strategy` through the environment boundary.

    Parameters
    ----------
    factory : EpisodeSpec, type or Strategy
        The checked :class:`~reciprocity.env.spec.EpisodeSpec` of the episode
        (:func:`reciprocity.api.check`: its strategy class and parameters, taken without
        checking again; the strategy the check built serves the first reset); or the
        strategy class (``reciprocity.strategies.STRATEGIES[name]``), built anew at every
        reset; or a strategy already built (started afresh at every reset, its parameters
        as given).
    params : dict, optional
        The strategy's parameters (with a class). The task's platform limits (the car's
        ``clearance``, the sensor's ``i_max``) fill those the strategy accepts and `params`
        leaves out (:func:`with_limits`); those in its ``start_limits`` reach it through
        :attr:`~reciprocity.strategies.base.SearchContext.limits` when it starts.
    figures : bool
        Keep what the figures draw of the strategy's belief (its
        :meth:`~reciprocity.strategies.base.Strategy.figure_record`) in the report; on an
        unknown map also the believed map step by step
        (:func:`~reciprocity.strategies.map_steps.with_map_steps`, from the percepts).
    """

    def __init__(self, factory, params: dict | None = None, *, figures: bool = False):
        if isinstance(factory, Strategy) and params:
            raise TypeError("give params with a strategy class, not with a strategy already built")
        self._spec = factory if hasattr(factory, "strategy_class") else None   # an EpisodeSpec
        if self._spec is not None:
            if params:
                raise TypeError("an EpisodeSpec brings its strategy's params; give none")
            factory, params = self._spec.strategy_class, self._spec.params
        self._factory = factory
        self._params = dict(params or {})
        self._figures = bool(figures)
        self._percepts: list[Percept] = []
        self.strategy: Strategy | None = None
        self.messages = MessageLog()

    def reset(self, task: Task, seed: np.random.SeedSequence) -> None:
        if isinstance(self._factory, Strategy):
            strategy, late = self._factory, {}                  # its parameters as given
        else:
            params = with_limits(self._factory, self._params, task.limits)
            late = {key: value for key, value in task.limits.items()
                    if key in getattr(self._factory, "start_limits", ()) and key not in self._params}
            built = self._spec.take_strategy(params) if self._spec is not None else None
            strategy = built if built is not None else self._factory(**params)
        if self._spec is None:
            _check_fits(strategy, task)
        self.strategy = strategy
        self.messages = MessageLog()
        self._percepts: list[Percept] = []                      # for the figures' records only
        strategy.start(SearchContext(task.world, task.nominal, np.array(task.starts),
                                     np.random.default_rng(seed), self.messages, tuple(task.intents), late))
        if task.reachable is not None:
            for _ in range(task.n_agents):
                strategy.restrict(task.reachable)

    @property
    def done(self) -> bool:
        return self.strategy.done

    def act(self):
        return self.strategy.propose()

    def observe(self, percept: Percept, intent) -> None:
        if self._figures:
            self._percepts.append(percept)
        if percept.unreachable is not None:
            point, reason = percept.unreachable
            self.strategy.reject(intent, point, reason, percept.agent)
        else:
            obs = [o for o in percept.observations if o.kind not in SENSING_KINDS or o.kind in self.strategy.senses]
            self.strategy.observe(obs, intent, percept.agent)

    def status(self) -> Status:
        return self.strategy.status

    def stop(self, reason: StopReason, detail: str) -> None:
        self.strategy.stop(reason, detail)

    def report(self) -> Report | None:
        s = self.strategy
        if s.outcome is None:
            return None
        support = getattr(s, "position_support", None)
        return Report(strategy=s.name, estimate=None if s.estimate is None else np.asarray(s.estimate, dtype=float),
                      stop=Stop(s.outcome.reason, s.outcome.detail), region_area=s.status.region_area,
                      n_measurements=s.n_measurements, n_samples=s.n_samples, n_rejected=s.n_rejected,
                      params=s.params(), position_support=support() if callable(support) else None,
                      messages=self.messages, agents=s.agents,
                      estimates=_array(getattr(s, "estimates", None)),
                      estimates_sd=_array(getattr(s, "estimates_sd", None)),
                      notes=dict(getattr(s, "notes", None) or {}),
                      figures=with_map_steps(s.figure_record(), self._percepts) if self._figures else {})


def _check_fits(strategy: Strategy, task: Task) -> None:
    """Refuse a strategy (not checked by an EpisodeSpec) that cannot search `task`."""
    if task.world not in strategy.worlds:
        raise SearchError(f"strategy {strategy.name!r} does not apply to {task.world!r} worlds "
                          f"(it supports {', '.join(strategy.worlds)})")
    if strategy.agents is not None and strategy.agents != task.n_agents:
        raise SearchError(f"strategy {strategy.name!r} directs {strategy.agents} observer(s); "
                          f"got {task.n_agents}")


def _array(value) -> np.ndarray | None:
    """`value` (a strategy attribute or method) as an array, or None."""
    value = value() if callable(value) else value
    return None if value is None else np.asarray(value, dtype=float)


def _accepted(cls) -> set[str]:
    """The keyword parameters of strategy class `cls`."""
    return {p.name for p in inspect.signature(cls.__init__).parameters.values() if p.kind is p.KEYWORD_ONLY}


def with_limits(cls: type, params, limits) -> dict:
    """`params` with the platform `limits` that strategy class `cls` takes as parameters
    and `params` leaves out: those it accepts, but not its ``start_limits`` (which it
    reads when it starts). The one rule for a checked spec's build and an agent's."""
    out = dict(params or {})
    accepted = _accepted(cls)
    for key, value in limits.items():
        if key in accepted and key not in getattr(cls, "start_limits", ()):
            out.setdefault(key, value)
    return out
