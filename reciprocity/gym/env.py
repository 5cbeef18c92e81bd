"""A search as a Gymnasium environment: :class:`SearchGymEnv`, a thin face over
:class:`~reciprocity.env.SearchEnv` driven by :class:`~reciprocity.env.Rollout`.

The environment behind the face is the same one every front door uses; the face only
translates actions into intents and percepts into observations, so an episode driven
here is the episode ``reciprocity run`` drives with the same seed.
"""

from __future__ import annotations

import numpy as np
import gymnasium

from ..env import Rollout, SearchEnv
from ..errors import SearchError
from ..intents import Intent
from ..observations import MessageLog, readings_of
from ..outcome import Stop, StopReason
from ..scenarios import load_scenario
from ..strategies.base import Status
from ..task import Report, Task
from .faces import STOP, face_for

__all__ = ["SearchGymEnv", "DeclaringAgent", "Delivering", "SUCCESS_REWARD", "end_reward"]

#: Reward added at the end of a successful episode (every round costs 1).
SUCCESS_REWARD = 100.0


def end_reward(summary: dict, search: SearchEnv, success_reward: float) -> float:
    """What the last round adds to its -1: `success_reward` on success; on failure, -1 for
    every round of the budget left, so that giving up early never pays better than
    searching to the end."""
    if summary.get("success"):
        return success_reward
    if search.max_steps is None:
        return 0.0
    return -float(max(search.max_steps - search.rounds, 0))


class DeclaringAgent:
    """The environment's stand-in for an outside policy in :class:`~reciprocity.env.Rollout`:
    it counts the readings and declares what the policy's stop action says (its estimate,
    or else where the observer stands).

    Parameters
    ----------
    name : str
        The name the episode summary gives the policy.
    """

    def __init__(self, name: str = "gym-policy"):
        self.name = name
        self.done = True

    def reset(self, task: Task, seed) -> None:
        self.task, self.done, self.estimate, self.outcome = task, False, None, None
        self.n_readings, self.position = 0, np.array(task.starts[0][:2], dtype=float)
        self.messages = MessageLog()

    def act(self):
        return ()                                   # the policy's action comes from outside

    def declare(self, estimate) -> None:
        """The policy stops and declares `estimate`."""
        self.estimate = np.asarray(estimate, dtype=float)
        self.stop(StopReason.CONVERGED, "the policy stopped")

    def observe(self, percept, intent) -> None:
        if percept.unreachable is None and percept.observations:
            self.n_readings += len(readings_of(percept.observations))
            self.position = np.asarray(percept.observations[-1].position, dtype=float)

    def status(self) -> Status:
        return Status(self.estimate)

    def stop(self, reason: StopReason, detail: str) -> None:
        if self.outcome is None:
            self.outcome, self.done = Stop(reason, detail), True

    def report(self) -> Report | None:
        if self.outcome is None:
            return None
        est = self.estimate if self.estimate is not None else self.position
        return Report(strategy=self.name, estimate=est, stop=self.outcome, n_measurements=self.n_readings,
                      n_samples=self.n_readings, messages=self.messages, agents=None)


class Delivering:
    """The agent a Gymnasium episode's :class:`~reciprocity.env.Rollout` drives: `agent`
    with the listeners of the percepts (the face, a wrapper's belief). Each percept is
    delivered once, here, to each of them and then to `agent`.

    Parameters
    ----------
    agent : Agent
        The agent that acts, stops and declares (:class:`DeclaringAgent` or a policy's).
    listeners : list of callable
        ``listener(percept, intent)``, called in order before `agent` observes.
    """

    def __init__(self, agent, listeners: list):
        self.agent, self.listeners = agent, listeners

    @property
    def done(self) -> bool:
        return self.agent.done

    def reset(self, task: Task, seed) -> None:
        self.agent.reset(task, seed)

    def act(self):
        return self.agent.act()

    def observe(self, percept, intent) -> None:
        for listener in self.listeners:
            listener(percept, intent)
        self.agent.observe(percept, intent)

    def status(self) -> Status:
        return self.agent.status()

    def stop(self, reason: StopReason, detail: str) -> None:
        self.agent.stop(reason, detail)

    def report(self) -> Report | None:
        return self.agent.report()


class SearchGymEnv(gymnasium.Env):
    """One scenario as a Gymnasium environment (one observer; several: the PettingZoo face).

    Parameters
    ----------
    scenario : str, Scenario or arenas.Arena
        A built-in scenario name or a YAML path (scenario or plain arena file).
    platform : str, optional
        The platform (default: the scenario's; ``"car"`` for the car on an arena).
    render_mode : {"rgb_array"}, optional
    success_reward : float
        Added to the last reward when the episode succeeds (every round costs 1).
    platform_options : dict, optional
        Options of the platform (the car's).
    random_source : bool
        Draw the true source and the start afresh at every reset, from the episode seed
        (arena scenarios; as a campaign's ``random_source: true`` and ``reciprocity run
        --random-source`` draw them), so that a policy cannot learn one place by heart.
    cap_terminates : bool
        When the round budget is spent, report ``terminated`` instead of ``truncated``.
        The budget is then part of the task, as the reward already treats it (a failed
        stop pays the rounds left). A learner that bootstraps the value of a truncated
        state (stable-baselines3 does) then sees the spent budget as the end it is.
    **world
        The scenario's keys: its world's (``source``, ``strength``, ``noise``,
        ``mismatch``, ``start`` with the heading in radians, ...), ``max_steps`` and
        ``success_radius``.

    Notes
    -----
    ``reset(seed=s)`` starts the episode that ``reciprocity run ... --seed s`` starts
    (with ``random_source``, ``reciprocity run ... --random-source --seed s``); without a
    seed, the episode seed is drawn from the environment's own generator.
    The observation is a Dict (``position``, ``reading``, ``time`` and the world's own
    keys); the action is the face's (see :mod:`reciprocity.gym.faces`). The reward is -1
    per round, plus `success_reward` at the end of a successful episode; a failed episode
    also pays -1 for each round of the budget left (see :func:`end_reward`). ``terminated``
    when the search ends by itself (the source reached, or the policy's stop action);
    ``truncated`` when the scenario's round budget is spent (``terminated`` with
    `cap_terminates`). The last ``info`` holds
    every key of the episode summary (``success``, ``error``, ``n_measurements``, ...)
    and ``summary`` itself.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}

    def __init__(self, scenario="paper", *, platform: str | None = None, render_mode: str | None = None,
                 success_reward: float = SUCCESS_REWARD, platform_options: dict | None = None,
                 random_source: bool = False, cap_terminates: bool = False, **world):
        if render_mode not in (None, "rgb_array"):
            raise SearchError(f"render_mode must be 'rgb_array' or None; got {render_mode!r}")
        if random_source not in (True, False):
            raise SearchError(f"random_source must be true or false; got {random_source!r}")
        if cap_terminates not in (True, False):
            raise SearchError(f"cap_terminates must be true or false; got {cap_terminates!r}")
        sc = load_scenario(scenario) if not hasattr(scenario, "kind") else scenario
        sc = sc.with_limits(max_steps=world.pop("max_steps", None), success_radius=world.pop("success_radius", None))
        if random_source and (sc.world != "poisson" or {"source", "sources", "start"} & set(world)):
            raise SearchError("random_source draws the source and the start of an arena (poisson) scenario; "
                              f"scenario {sc.name!r} is a {sc.world} world" if sc.world != "poisson" else
                              "random_source draws the source and the start: give neither source nor start, "
                              "or random_source=False")
        self.search = SearchEnv(sc, platform=platform, world=world or None, platform_options=platform_options)
        self.random_source, self._scenario = bool(random_source), self.search.scenario
        if self.search.n_agents != 1:
            raise SearchError(f"scenario {sc.name!r} has {self.search.n_agents} observers: use "
                              "reciprocity.pettingzoo.parallel_env for several")
        self.render_mode = render_mode
        self.cap_terminates = bool(cap_terminates)
        self.success_reward = float(success_reward)
        nominal = self.search.scenario.build_world(0).nominal()         # public: the spaces
        self.face = face_for(self.search.scenario.world, self.search.platform_name, nominal)
        self.action_space = self.face.action_space()
        self.observation_space = self.face.observation_space()
        self._own = DeclaringAgent()
        self.agent = self._own
        self._listeners: list = [self.face.observe]
        self.run: Rollout | None = None
        self.summary: dict | None = None
        self.last_percepts: list = []

    # -- policies that bring their own agent --------------------------------------------------
    def attach(self, agent) -> None:
        """Let `agent` (an :class:`~reciprocity.env.Agent`, e.g. the one of
        :class:`~reciprocity.gym.StrategyPolicy`) receive the percepts and declare the
        report; the policy resets it after each :meth:`reset`."""
        self.agent = agent

    def listen(self, listener) -> None:
        """Let `listener(percept, intent)` receive each percept of every later step, once,
        as the face and the agent do (a wrapper's belief)."""
        self._listeners.append(listener)

    @property
    def task(self) -> Task:
        """The public task of the current episode."""
        if self.run is None:
            raise SearchError("call reset() first")
        return self.run.task

    @property
    def agent_seed(self) -> np.random.SeedSequence:
        """The agent's own random stream of the current episode (derived from its seed)."""
        return self.run.agent_seed

    # -- Gymnasium --------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        if seed is None:
            seed = int(self.np_random.integers(0, 2**62))
        self.episode_seed = int(seed)
        if self.random_source:
            from ..campaign.worker import world_draw
            self.search.scenario = self._scenario.with_world(world_draw(self._scenario, self.episode_seed))
        self.run = Rollout(self.search, Delivering(self.agent, self._listeners))
        task = self.run.start(self.episode_seed, options, reset_agent=self.agent is self._own)
        self.summary, self.last_percepts = None, []
        obs = self.face.reset(task.starts[0])
        return obs, {"task": task}

    def step(self, action):
        if self.run is None:
            raise SearchError("call reset() before step()")
        if self.summary is not None:
            raise SearchError("the episode is over; call reset()")
        intent = action if isinstance(action, Intent) else self.face.intent(action)
        rounds = self.search.rounds
        if isinstance(intent, tuple) and intent[0] == STOP:
            if self.agent is self._own:
                self._own.declare(intent[1])
            going = self.run.advance(None)
        else:
            going = self.run.advance(intent)              # the face observes each percept on the way
            self.last_percepts = list(self.run.last)
            self.face.moved(intent)
            if going and self.search.budget_spent:
                going = self.run.advance(self.agent.act())     # as rollout: the agent's last word
        obs = self.face.observation()
        if going:
            return obs, -float(self.search.rounds - rounds), False, False, {}
        episode = self.run.finish()
        self.summary = episode.summary
        spent = -float(self.search.rounds - rounds)                    # -1 per round carried out
        reward = spent + end_reward(self.summary, self.search, self.success_reward)
        capped = str(self.summary.get("stop_reason", "")).startswith(StopReason.STEP_CAP.value)
        truncated = capped and not self.cap_terminates
        info = dict(self.summary)
        info["summary"] = self.summary
        info["episode"] = episode
        return obs, reward, not truncated, truncated, info

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        from .render import frame
        return frame(self)

