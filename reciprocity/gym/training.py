"""Helpers for training learners on the search environments: held-out evaluation beside
a built-in strategy, and a progress line for stable-baselines3 (imported only where used).
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

__all__ = ["Evaluation", "evaluate", "sb3_progress", "training_parser", "checked", "require_sb3", "HELD_OUT"]

#: First seed of the held-out evaluation episodes (training episodes draw their seeds).
HELD_OUT = 10_000


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


def training_parser(description: str, out: str, *, eval_every: int = 20_000) -> argparse.ArgumentParser:
    """The command line the training examples share: ``--timesteps``, ``--eval-every``,
    ``--eval-seeds``, ``--seed``, ``--out``, ``--threads`` (torch's, default 1) and
    ``--report-every``; :func:`checked` refuses values below 1."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--timesteps", type=int, default=200_000)
    ap.add_argument("--eval-every", type=int, default=eval_every)
    ap.add_argument("--eval-seeds", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=Path(out))
    ap.add_argument("--threads", type=int, default=1, help="torch threads (default 1)")
    ap.add_argument("--report-every", type=int, default=5_000, help="print the steps trained this often")
    return ap


def checked(ap: argparse.ArgumentParser, args: argparse.Namespace) -> argparse.Namespace:
    """`args` with every count of :func:`training_parser` (and ``envs``, if any) at least 1;
    otherwise the parser's error (exit 2, one line)."""
    for key in ("timesteps", "eval_every", "eval_seeds", "threads", "report_every", "envs"):
        if getattr(args, key, 1) < 1:
            ap.error(f"--{key.replace('_', '-')} must be at least 1; got {getattr(args, key)}")
    return args


def require_sb3(threads: int):
    """Import PyTorch and stable-baselines3, or exit with one line saying what to install;
    torch is held to `threads` threads. Returns the torch module."""
    try:
        import stable_baselines3  # noqa: F401
        import torch
    except ImportError:
        sys.exit("error: this example needs stable-baselines3 (pip install stable-baselines3)")
    torch.set_num_threads(threads)
    return torch
