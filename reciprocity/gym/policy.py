"""Any built-in strategy as a Gymnasium policy: :class:`StrategyPolicy`."""

from __future__ import annotations

from ..errors import SearchError
from ..strategies.agent import StrategyAgent

__all__ = ["StrategyPolicy"]


class StrategyPolicy:
    """A built-in strategy driving a :class:`~reciprocity.gym.SearchGymEnv`.

    ``policy.reset(seed)`` after ``env.reset(seed=seed)``, then ``action =
    policy(observation)`` until the episode ends. The strategy receives exactly what it
    receives under ``reciprocity run`` (the public task, its own random stream, every
    percept), so the episode is the same as ``reciprocity run ... --seed seed``.

    Parameters
    ----------
    name : str
        A strategy name (``reciprocity strategies`` lists them).
    env : gymnasium.Env
        The environment (wrappers allowed); the strategy's percepts come from its
        unwrapped :class:`~reciprocity.gym.SearchGymEnv`.
    **params
        The strategy's parameters.

    Examples
    --------
    >>> import gymnasium, reciprocity.gym
    >>> env = gymnasium.make("reciprocity/Plume-v0", scenario="otto-2d")
    >>> policy = reciprocity.gym.StrategyPolicy("infotaxis", env)
    >>> obs, info = env.reset(seed=1)
    >>> policy.reset(1)
    >>> done = False
    >>> while not done:
    ...     obs, reward, terminated, truncated, info = env.step(policy(obs))
    ...     done = terminated or truncated
    >>> sorted(k for k in ("success", "steps", "error") if k in info)
    ['error', 'steps', 'success']
    """

    def __init__(self, name: str, env, **params):
        from ..api import check
        self.name = name
        self.env = env.unwrapped
        # checked as every front door checks an episode: the strategy, its parameters and
        # that it applies to the environment's world, before any work (api.check)
        self.agent = StrategyAgent(check(self.env.search.spec, name, params=params))
        self.env.attach(self.agent)

    @property
    def strategy(self):
        """The strategy object (its belief, its status)."""
        return self.agent.strategy

    def reset(self, seed: int | None = None) -> None:
        """Begin the episode the environment was just reset to (with `seed`)."""
        if self.env.agent is not self.agent:
            self.env.attach(self.agent)
            raise SearchError("the environment was reset before this policy was attached to it; reset it again")
        if seed is not None and int(seed) != self.env.episode_seed:
            raise SearchError(f"the environment was reset with seed {self.env.episode_seed}, not {seed}")
        self.agent.reset(self.env.task, self.env.agent_seed)

    def __call__(self, observation):
        face = self.env.face
        if self.agent.strategy is None:
            raise SearchError("call policy.reset(seed) after env.reset(seed=seed)")
        if self.agent.done:
            return face.stop_action(self.agent.strategy.estimate)
        intent = self.agent.act()
        if intent is None:
            return face.stop_action(self.agent.strategy.estimate)
        if isinstance(intent, dict):
            if set(intent) != {0}:
                raise SearchError(f"strategy {self.name!r} directs several observers: use reciprocity.pettingzoo")
            intent = intent[0]
        return face.action_of(intent)
