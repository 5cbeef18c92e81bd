"""The one driver of every search: :func:`rollout` (an environment, an agent, a seed)."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ..episode import Episode, StepRecord
from ..outcome import StopReason
from ..task import Percept, Report, Task
from .search_env import SearchEnv, intents_of

__all__ = ["Agent", "rollout"]


class Agent(Protocol):
    """What :func:`rollout` drives: a built-in strategy (:class:`reciprocity.strategies.agent.StrategyAgent`)
    or any policy with these methods."""

    done: bool

    def reset(self, task: Task, seed: np.random.SeedSequence) -> None:
        """Begin a search with the public task and the agent's own random stream."""

    def act(self):
        """The next action (an Intent or a mapping observer -> Intent), or None to stop."""

    def observe(self, percept: Percept, intent) -> None:
        """One observer's percept for its intent."""

    def status(self):
        """What the agent believes now (a :class:`reciprocity.strategies.base.Status`)."""

    def stop(self, reason: StopReason, detail: str) -> None:
        """The environment ended the search for `reason`."""

    def report(self) -> Report:
        """The final declaration."""


def rollout(env: SearchEnv, agent: Agent, seed: int, *, progress=None, options: dict | None = None) -> Episode:
    """Run one episode of `agent` in `env` from `seed`.

    The loop reads like the papers' algorithm boxes: reset the world and hand the agent
    its task; while the agent acts, the environment carries out each observer's intent
    and the agent updates from what came back; the agent declares its estimate and the
    environment judges it.

    Parameters
    ----------
    env : SearchEnv
        The environment (the truth).
    agent : Agent
        The searcher.
    seed : int
        Episode seed: the environment derives every random stream from it.
    progress : callable, optional
        Called with each :class:`~reciprocity.episode.StepRecord`.
    options : dict, optional
        Passed to :meth:`SearchEnv.reset`.

    Returns
    -------
    Episode
        The summary (judged by the environment), the trace and the messages.
    """
    _, info = env.reset(seed=seed, options=options)
    agent.reset(info["task"], info["agent_seed"])
    records: list[StepRecord] = []
    while not agent.done:
        action = agent.act()
        if action is None:
            break
        if env.budget_spent:
            agent.stop(StopReason.STEP_CAP, f"{env.max_steps} steps")
            break
        intents = intents_of(action, env.n_agents)
        percepts, _, terminated, _, step_info = env.step(action)
        for percept, log in zip(percepts, step_info["records"]):
            intent = intents[percept.agent]
            agent.observe(percept, intent)
            records.append(_record(len(records) + 1, percept, intent, log, agent.status()))
            if progress is not None and percept.unreachable is None:
                progress(records[-1])
        if terminated and not agent.done:
            agent.stop(StopReason.FOUND, f"observer {step_info['found_by']} reached the source")
    report = agent.report()
    if report is None or report.stop is None:
        agent.stop(StopReason.GAVE_UP, "the strategy proposed nothing more")
        report = agent.report()
    return Episode(env.judge(report), records, report.messages)


def _record(step: int, percept: Percept, intent, log: dict, status) -> StepRecord:
    """The trace's record of one percept: the platform's log beside the agent's status."""
    if percept.unreachable is not None:
        return StepRecord(step, percept.agent, intent.name, "unreachable", intent.point, [], log["pose"],
                          log["route"], log["path_length"], log["time"], message=percept.unreachable[1],
                          platform=log["log"])
    obs = percept.observations
    return StepRecord(step, percept.agent, intent.name, obs[0].kind if obs else "none", intent.point, obs,
                      log["pose"], log["route"], log["path_length"], log["time"],
                      None if status.estimate is None else np.asarray(status.estimate, dtype=float),
                      status.region_area, belief=dict(status.extra), platform=log["log"])
