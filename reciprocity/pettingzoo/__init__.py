"""A PettingZoo parallel face of the search worlds, for several observers (extra ``[gym]``).

``reciprocity.pettingzoo.parallel_env(scenario="hajieghrary", agents=3)`` gives one
:class:`SearchParallelEnv`: every observer (``observer_0`` ...) acts each round through its
world's face (:mod:`reciprocity.gym.faces`), and every observation also carries what the
team shares (``team_positions``, ``team_readings``: each observer's last reading, sent to
all, as in the multi-agent papers' full sharing). :class:`TeamPolicy` drives all of them
with a built-in team strategy (``voi``), as ``reciprocity run`` does.
"""

from __future__ import annotations

import functools

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from ..env import Rollout, SearchEnv
from ..errors import SearchError
from ..intents import Intent
from ..outcome import StopReason
from ..scenarios import load_scenario
from ..strategies.agent import StrategyAgent
from ..gym.env import SUCCESS_REWARD, DeclaringAgent, Delivering, end_reward
from ..gym.faces import STOP, face_for

__all__ = ["parallel_env", "SearchParallelEnv", "TeamPolicy"]


def parallel_env(scenario="hajieghrary", agents: int | None = None, **kwargs) -> "SearchParallelEnv":
    """The PettingZoo parallel environment of `scenario` with `agents` observers (default:
    the scenario's); other keyword arguments as :class:`SearchParallelEnv`."""
    return SearchParallelEnv(scenario, agents=agents, **kwargs)


class _TeamDeclaring(DeclaringAgent):
    """The environment's stand-in for outside policies (:class:`~reciprocity.gym.DeclaringAgent`
    for a team): declares the mean of the stop actions' estimates, or of where the observers
    stand."""

    def __init__(self):
        super().__init__("pettingzoo-policies")

    def reset(self, task, seed) -> None:
        super().reset(task, seed)
        self.positions = np.array(task.starts[:, :2], dtype=float)
        self.estimates: dict[int, np.ndarray] = {}

    def observe(self, percept, intent) -> None:
        super().observe(percept, intent)
        if percept.unreachable is None and percept.observations:
            self.positions[percept.agent] = percept.observations[-1].position

    def report(self):
        if self.outcome is not None:
            self.estimate = (np.mean(list(self.estimates.values()), axis=0) if self.estimates
                             else self.positions.mean(axis=0))
        return super().report()


class SearchParallelEnv(ParallelEnv):
    """Several observers of one scenario as a PettingZoo ``ParallelEnv``.

    Parameters
    ----------
    scenario : str or Scenario
        A built-in scenario name or a YAML path.
    agents : int, optional
        Observers (default: the scenario's).
    platform : str, optional
    render_mode : {"rgb_array"}, optional
    success_reward : float
        Added to every observer's last reward when the team succeeds.
    **world
        The scenario's world keys.

    Notes
    -----
    Each round every live observer acts. A *stop* action declares that observer done
    with its estimate (it stays where it is from then on); the episode ends for all when
    every observer has stopped, an observer reaches the source (worlds that end so), or
    the round budget is spent (truncation). The last ``infos`` hold the summary keys.
    """

    metadata = {"name": "reciprocity_search_v0", "render_modes": ["rgb_array"], "is_parallelizable": True}

    def __init__(self, scenario="hajieghrary", *, agents: int | None = None, platform: str | None = None,
                 render_mode: str | None = None, success_reward: float = SUCCESS_REWARD, **world):
        sc = load_scenario(scenario) if not hasattr(scenario, "kind") else scenario
        sc = sc.with_limits(max_steps=world.pop("max_steps", None), success_radius=world.pop("success_radius", None))
        self.search = SearchEnv(sc, platform=platform, agents=agents, world=world or None)
        n = self.search.n_agents
        self.possible_agents = [f"observer_{k}" for k in range(n)]
        self.agents: list[str] = []
        self.render_mode = render_mode
        self.success_reward = float(success_reward)
        nominal = self.search.scenario.build_world(0).nominal()
        self.faces = [face_for(self.search.scenario.world, self.search.platform_name, nominal) for _ in range(n)]
        self._own = _TeamDeclaring()
        self.agent = self._own
        self.run: Rollout | None = None
        self.summary: dict | None = None

    # -- spaces (one object per observer) -------------------------------------------------------
    @functools.lru_cache(maxsize=None)
    def observation_space(self, agent: str) -> spaces.Dict:
        face = self.faces[self._index(agent)]
        n = len(self.possible_agents)
        lo, hi = face.bounds()
        out = dict(face.observation_space().spaces)
        out["team_positions"] = spaces.Box(np.tile(lo, (n, 1)), np.tile(hi, (n, 1)), dtype=np.float64)
        out["team_readings"] = spaces.Box(-np.inf, np.inf, (n,), dtype=np.float64)
        return spaces.Dict(out)

    @functools.lru_cache(maxsize=None)
    def action_space(self, agent: str) -> spaces.Space:
        return self.faces[self._index(agent)].action_space()

    def _index(self, agent: str) -> int:
        try:
            return self.possible_agents.index(agent)
        except ValueError:
            raise SearchError(f"no observer {agent!r}; the observers are {self.possible_agents}") from None

    def attach(self, agent) -> None:
        """Let a team agent (:class:`TeamPolicy`'s) receive the percepts and declare the report."""
        self.agent = agent

    @property
    def task(self):
        return self.run.task

    @property
    def agent_seed(self):
        return self.run.agent_seed

    # -- PettingZoo ---------------------------------------------------------------------------------
    def reset(self, seed: int | None = None, options: dict | None = None):
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1, dtype=np.uint64)[0] >> 2)
        self.episode_seed = int(seed)
        self.run = Rollout(self.search, Delivering(self.agent, [self._face_observes]))
        task = self.run.start(self.episode_seed, options, reset_agent=self.agent is self._own)
        self.agents = list(self.possible_agents)
        self.stopped: set[int] = set()
        self.summary = None
        for face, pose in zip(self.faces, task.starts):
            face.reset(pose)
        return self._observations(), {a: {"task": task} for a in self.agents}

    def _face_observes(self, percept, intent) -> None:
        """Each percept, once, to its observer's face (on its way to the agent)."""
        self.faces[percept.agent].observe(percept, intent)

    def _observations(self) -> dict:
        pos = np.array([np.clip(f.position, *f.bounds()) for f in self.faces])
        reads = np.array([f.reading for f in self.faces])
        return {a: {**self.faces[k].observation(), "team_positions": pos.copy(), "team_readings": reads.copy()}
                for k, a in enumerate(self.possible_agents) if a in self.agents}

    def step(self, actions: dict):
        if self.run is None or not self.agents:
            raise SearchError("call reset() before step()")
        rounds = self.search.rounds
        intents: dict[int, Intent] = {}
        for name, action in actions.items():
            k = self._index(name)
            if k in self.stopped:
                continue                               # a stopped observer stays where it is
            intent = action if isinstance(action, Intent) else self.faces[k].intent(action)
            if isinstance(intent, tuple) and intent[0] == STOP:
                self.stopped.add(k)
                self._own.estimates[k] = intent[1]
                continue
            intents[k] = intent
        if len(self.stopped) == len(self.faces):
            if self.agent is self._own:
                self._own.stop(StopReason.CONVERGED, "every observer stopped")
            going = self.run.advance(None)
        elif intents:
            going = self.run.advance(intents)
            for k, intent in intents.items():
                self.faces[k].moved(intent)
            if going and self.search.budget_spent:
                going = self.run.advance(self.agent.act())
        else:
            going = True
        obs = self._observations()
        names = list(self.agents)
        spent = -float(self.search.rounds - rounds)
        if going:
            return (obs, {a: spent for a in names}, {a: False for a in names}, {a: False for a in names},
                    {a: {} for a in names})
        episode = self.run.finish()
        self.summary = episode.summary
        bonus = end_reward(self.summary, self.search, self.success_reward)
        truncated = str(self.summary.get("stop_reason", "")).startswith(StopReason.STEP_CAP.value)
        info = dict(self.summary, summary=self.summary, episode=episode)
        self.agents = []
        return (obs, {a: spent + bonus for a in names}, {a: not truncated for a in names},
                {a: truncated for a in names}, {a: dict(info) for a in names})

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        from ..gym.render import frame

        class _View:                                   # the first observer's face, the whole team's path
            face, agent, run = self.faces[0], self.agent, self.run
        return frame(_View)

    def close(self) -> None:
        pass


class TeamPolicy:
    """A built-in strategy that directs every observer (``voi``) driving a
    :class:`SearchParallelEnv`: ``policy.reset(seed)`` after ``env.reset(seed=seed)``, then
    ``actions = policy(observations)``. The episode is the one ``reciprocity run
    --scenario ... --strategy NAME --seed seed`` runs."""

    def __init__(self, name: str, env: SearchParallelEnv, **params):
        from ..api import check
        self.name, self.env = name, env
        self.agent = StrategyAgent(check(env.search.spec, name, params=params))   # checked once (api.check)
        env.attach(self.agent)

    def reset(self, seed: int | None = None) -> None:
        if seed is not None and int(seed) != self.env.episode_seed:
            raise SearchError(f"the environment was reset with seed {self.env.episode_seed}, not {seed}")
        self.agent.reset(self.env.task, self.env.agent_seed)

    def __call__(self, observations: dict) -> dict:
        env = self.env
        names = env.possible_agents
        if self.agent.done:
            return {a: env.faces[k].stop_action() for k, a in enumerate(names) if a in env.agents}
        intents = self.agent.act()
        if intents is None:
            return {a: env.faces[k].stop_action() for k, a in enumerate(names) if a in env.agents}
        if isinstance(intents, Intent):
            intents = {0: intents}
        return {names[k]: env.faces[k].action_of(intent) for k, intent in intents.items()}
