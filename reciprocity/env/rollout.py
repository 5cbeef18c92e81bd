"""The one driver of every search: :func:`rollout` (an environment, an agent, a seed)."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ..episode import Episode, StepRecord
from ..outcome import StopReason
from ..task import Percept, Report, Task
from .search_env import SearchEnv, intents_of

__all__ = ["Agent", "Rollout", "rollout"]


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


class Rollout:
    """One episode being driven: the loop of :func:`rollout` taken apart, so that a driver
    that receives its actions from outside (the Gymnasium and PettingZoo adapters) runs the
    very same steps.

    Parameters
    ----------
    env : SearchEnv
        The environment (the truth).
    agent : Agent
        Receives the task, the percepts and the stop; declares the report.
    progress : callable, optional
        Called with each :class:`~reciprocity.episode.StepRecord`.
    figures : bool
        Record what the figures draw of the truth (:meth:`SearchEnv.figure_record`) in the
        episode, and the agent's :attr:`Report.figures <reciprocity.task.Report.figures>`.
    """

    def __init__(self, env: SearchEnv, agent: Agent, *, progress=None, figures: bool = False):
        self.env, self.agent, self.progress, self.figures = env, agent, progress, figures
        self.records: list[StepRecord] = []
        self.task: Task | None = None
        #: The percepts of the last round with their intents, ``[(Percept, Intent), ...]``.
        self.last: list = []

    def start(self, seed: int, options: dict | None = None, *, reset_agent: bool = True) -> Task:
        """Reset the environment with `seed` and (unless told not to) hand the agent its
        task and its own random stream; return the task."""
        _, info = self.env.reset(seed=seed, options=options)
        self.task, self.agent_seed = info["task"], info["agent_seed"]
        self.records = []
        if reset_agent:
            self.agent.reset(self.task, self.agent_seed)
        if self.env.max_steps is not None and callable(getattr(self.progress, "set_total", None)):
            self.progress.set_total(self.env.max_steps * self.env.n_agents)   # one record per observer a round
        return self.task

    def advance(self, action) -> bool:
        """Carry out `action` (None: the agent proposes nothing more); True while the
        episode goes on. When the round budget is already spent, the agent is stopped
        (``STEP_CAP``) instead."""
        env, agent = self.env, self.agent
        self.last = []
        if agent.done or action is None:
            return False
        if env.budget_spent:
            agent.stop(StopReason.STEP_CAP, f"{env.max_steps} steps")
            return False
        intents = intents_of(action, env.n_agents)
        percepts, _, terminated, _, step_info = env.carry_out(intents)
        self.last = [(p, intents[p.agent]) for p in percepts]
        for percept, log in zip(percepts, step_info["records"]):
            intent = intents[percept.agent]
            agent.observe(percept, intent)
            self.records.append(_record(len(self.records) + 1, percept, intent, log, agent.status()))
            if self.progress is not None and percept.unreachable is None:
                self.progress(self.records[-1])
        if terminated and not agent.done:
            agent.stop(StopReason.FOUND, f"observer {step_info['found_by']} reached the source")
        return not agent.done

    def finish(self) -> Episode:
        """The agent's report, judged by the environment."""
        report = self.agent.report()
        if report is None or report.stop is None:
            self.agent.stop(StopReason.GAVE_UP, "the strategy proposed nothing more")
            report = self.agent.report()
        summary = self.env.judge(report)
        truth = self.env.figure_record() if self.figures else {}
        return Episode(summary, self.records, report.messages, belief=dict(report.figures), truth=truth)


def rollout(env: SearchEnv, agent: Agent, seed: int, *, progress=None, options: dict | None = None,
            figures: bool = False) -> Episode:
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
    figures : bool
        Keep what the figures draw of the truth and of the agent's belief in the episode
        (:attr:`Episode.truth`, :attr:`Episode.belief`).

    Returns
    -------
    Episode
        The summary (judged by the environment), the trace and the messages.
    """
    run = Rollout(env, agent, progress=progress, figures=figures)
    run.start(seed, options)
    while not agent.done and run.advance(agent.act()):
        pass
    return run.finish()


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
