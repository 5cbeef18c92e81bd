"""Observation wrappers for learning agents: the belief as an image."""

from __future__ import annotations

import numpy as np
import gymnasium
from gymnasium import spaces

from ..errors import SearchError
from ..strategies import STRATEGIES
from ..strategies.agent import StrategyAgent
from .render import belief_points

__all__ = ["BeliefImage", "BELIEF_OF"]

#: The strategy whose belief :class:`BeliefImage` keeps, per world kind: the Bayesian
#: model each world's papers use (the imaging map, the RBPF, the particle belief, the
#: detection grid).
BELIEF_OF = {"poisson": "reciprocity", "lattice": "rbpf", "plume": "infotaxis", "filament": "detection-infotaxis"}


class BeliefImage(gymnasium.ObservationWrapper):
    """The observation becomes a float32 image in [0, 1] of the posterior over the source (a
    built-in belief, updated with every percept the observer receives; its mass per pixel
    over its maximum).

    By default ``(2, size, size)``: channel 0 the posterior over the world, channel 1 the
    observer's pixel. With ``centred=True``, ``(1, 2 size - 1, 2 size - 1)``: the posterior
    shifted so that the observer's pixel is the centre (zero outside the world), the view
    learning searchers train best on (it does not change with where the observer is, only
    with what it believes relative to itself).

    Row 0 is the top of the world (y largest), as images are drawn.

    Parameters
    ----------
    env : gymnasium.Env
        A reciprocity environment.
    size : int
        Pixels per side (8 to 256).
    belief : str, optional
        The strategy whose belief is drawn (default: :data:`BELIEF_OF` of the world kind);
        only its belief is used, never its moves.
    centred : bool
        Centre the image on the observer (see above).
    **params
        That strategy's parameters (e.g. ``h=3.0`` for a coarser imaging mesh).
    """

    def __init__(self, env: gymnasium.Env, size: int = 32, belief: str | None = None, *, centred: bool = False,
                 **params):
        super().__init__(env)
        if isinstance(size, bool) or not isinstance(size, int) or not 8 <= size <= 256:
            raise SearchError(f"size must be a whole number of pixels from 8 to 256; got {size!r}")
        inner = env.unwrapped
        name = belief or BELIEF_OF[inner.search.scenario.world]
        if name not in STRATEGIES:
            raise SearchError(f"unknown strategy {name!r} for the belief")
        self.size = size
        self._belief = StrategyAgent(STRATEGIES[name], params)
        self.centred = bool(centred)
        shape = (1, 2 * size - 1, 2 * size - 1) if self.centred else (2, size, size)
        self.observation_space = spaces.Box(0.0, 1.0, shape, dtype=np.float32)

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        inner = self.env.unwrapped
        self._belief.reset(inner.task, inner.agent_seed)
        return self.observation(obs), info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        for percept, intent in self.env.unwrapped.last_percepts:
            if percept.unreachable is None and percept.observations and not self._belief.done:
                self._belief.observe(percept, intent)
        return self.observation(obs), reward, terminated, truncated, info

    def _pixel(self, points, lo, hi):
        ij = np.floor((np.asarray(points, dtype=float) - lo) / (hi - lo) * self.size).astype(int)
        ij = np.clip(ij, 0, self.size - 1)
        return self.size - 1 - ij[:, 1], ij[:, 0]            # rows from the top, columns

    def observation(self, observation):
        face = self.env.unwrapped.face
        lo, hi = face.bounds()
        image = np.zeros((2, self.size, self.size), dtype=np.float32)
        belief = belief_points(self._belief)
        if belief is not None and belief[1].size:
            r, c = self._pixel(belief[0], lo, hi)
            np.add.at(image[0], (r, c), belief[1])
            if hasattr(self._belief.strategy, "cells"):
                # equal cells on their own grid: the mean per pixel (a sum would stripe
                # where pixels hold different numbers of cells)
                count = np.zeros_like(image[0])
                np.add.at(count, (r, c), 1.0)
                image[0] = np.where(count > 0, image[0] / np.maximum(count, 1.0), 0.0)
            top = image[0].max()
            if top > 0:
                image[0] /= top
        r, c = self._pixel(np.asarray(observation["position"])[None], lo, hi)
        image[1, r, c] = 1.0
        if not self.centred:
            return image
        n = self.size
        out = np.zeros(self.observation_space.shape, dtype=np.float32)
        r0, c0 = n - 1 - int(r[0]), n - 1 - int(c[0])
        out[0, r0:r0 + n, c0:c0 + n] = image[0]
        return out
