"""Helpers for training learners on the search environments: held-out evaluation beside
a built-in strategy, and a progress line for stable-baselines3 (imported only where used).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from typing import Callable, Iterable

import numpy as np

__all__ = ["Evaluation", "evaluate", "sb3_progress"]


@dataclass(frozen=True)
class Evaluation:
    """A policy's episodes on held-out seeds.

    Attributes
    ----------
    success : ndarray of bool, shape (n,)
        Whether each episode succeeded (the environment's judgement).
    steps : ndarray of int, shape (n,)
        Rounds each episode took.
    """

    success: np.ndarray
    steps: np.ndarray

    @property
    def rate(self) -> float:
        """Fraction of episodes that succeeded."""
        return float(np.mean(self.success))

    def interval(self, z: float = 1.96) -> tuple[float, float]:
        """Wilson score interval of :attr:`rate` (95 % by default)."""
        n = len(self.success)
        p = self.rate
        centre = (p + z * z / (2 * n)) / (1 + z * z / n)
        half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
        return float(max(0.0, centre - half)), float(min(1.0, centre + half))

    def mean_steps(self, budget: int | None = None) -> float:
        """Mean rounds per episode; with `budget`, a failure counts the whole budget."""
        steps = self.steps if budget is None else np.where(self.success, self.steps, budget)
        return float(np.mean(steps))


def evaluate(make_env: Callable, seeds: Iterable[int], act: Callable | None = None, *,
             strategy: str | None = None, desc: str = "evaluating") -> Evaluation:
    """Run one episode per seed with a fresh environment from `make_env()`.

    Parameters
    ----------
    make_env : callable
        Returns the environment (wrappers included) the policy sees.
    seeds : iterable of int
        Episode seeds (keep them apart from the training seeds).
    act : callable, optional
        ``act(observation) -> action``: the policy.
    strategy : str, optional
        Instead of `act`, a built-in strategy (:class:`~reciprocity.gym.StrategyPolicy`),
        which acts on the environment under the wrappers.
    desc : str
        Label of the progress bar (shown on a terminal only).
    """
    from tqdm import tqdm

    from .policy import StrategyPolicy
    if (act is None) == (strategy is None):
        raise ValueError("give either act or strategy")
    success, steps = [], []
    seeds = [int(s) for s in seeds]
    for seed in tqdm(seeds, desc=desc, unit="ep", leave=False, file=sys.stderr, disable=not sys.stderr.isatty()):
        env = make_env()
        policy = None if strategy is None else StrategyPolicy(strategy, env)
        obs, _ = env.reset(seed=seed)
        if policy is not None:          # the strategy's own actions, past the wrappers
            policy.reset(seed)
            env, act = env.unwrapped, policy
        done, info = False, {}
        while not done:
            obs, _, terminated, truncated, info = env.step(act(obs))
            done = terminated or truncated
        success.append(bool(info["success"]))
        steps.append(int(info["steps"]))
    return Evaluation(np.array(success), np.array(steps))


def sb3_progress(total: int, every: int):
    """A stable-baselines3 callback that prints the steps trained every `every` steps,
    with the rate (steps per second)."""
    from stable_baselines3.common.callbacks import BaseCallback

    class Progress(BaseCallback):
        def _on_training_start(self) -> None:
            self.t0, self.n0 = time.perf_counter(), self.num_timesteps

        def _on_step(self) -> bool:
            if self.num_timesteps % every < self.training_env.num_envs:
                rate = (self.num_timesteps - self.n0) / max(time.perf_counter() - self.t0, 1e-9)
                print(f"  {self.num_timesteps:>8} / {total} steps trained ({rate:.0f} steps/s)", flush=True)
            return True
    return Progress()
