"""Observation wrappers for learning agents: the belief as an image."""

from __future__ import annotations

import numpy as np
import gymnasium
from gymnasium import spaces

from ..errors import SearchError
from ..strategies.agent import StrategyAgent
from .faces import PointFace
from .render import belief_points

__all__ = ["BeliefImage", "BeliefStop", "BELIEF_OF"]

#: The strategy whose belief :class:`BeliefImage` keeps, per world kind: the Bayesian
#: model each world's papers use (the imaging map, the RBPF, the particle belief, the
#: detection grid).
BELIEF_OF = {"poisson": "reciprocity", "lattice": "rbpf", "plume": "infotaxis", "filament": "detection-infotaxis",
             "flow": "reciprocity-wind"}


class BeliefImage(gymnasium.ObservationWrapper, gymnasium.utils.RecordConstructorArgs):
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
    features : bool
        Make the observation a Dict: ``"image"`` the image above; ``"spread"`` (2,) the
        belief's standard deviations along its principal axes, largest first, as
        ``log(1 + σ) / log(1 + d)`` with σ and the world's diagonal d in world units (0 a
        point, 1 the whole world): a pixel is coarser than a search's last centimetres,
        and these say how far the belief still is from a point; ``"budget"`` (1,) the
        share of the round budget spent (0 without a budget), so that a policy can
        know how much search it has left.
    **params
        That strategy's parameters (e.g. ``h=3.0`` for a coarser imaging mesh).
    """

    def __init__(self, env: gymnasium.Env, size: int = 32, belief: str | None = None, *, centred: bool = False,
                 features: bool = False, **params):
        gymnasium.utils.RecordConstructorArgs.__init__(self, size=size, belief=belief, centred=centred,
                                                       features=features, **params)
        super().__init__(env)
        if isinstance(size, bool) or not isinstance(size, int) or not 8 <= size <= 256:
            raise SearchError(f"size must be a whole number of pixels from 8 to 256; got {size!r}")
        inner = env.unwrapped
        from ..api import check
        name = belief or BELIEF_OF[inner.search.scenario.world]
        self.size = size
        self._belief = StrategyAgent(check(inner.search.spec, name, params=params))   # checked once (api.check)
        inner.listen(self._take)
        self.centred = bool(centred)
        shape = (1, 2 * size - 1, 2 * size - 1) if self.centred else (2, size, size)
        image = spaces.Box(0.0, 1.0, shape, dtype=np.float32)
        self.features = bool(features)
        self.observation_space = spaces.Dict({"image": image, "spread": spaces.Box(0.0, 1.0, (2,), dtype=np.float32),
                                              "budget": spaces.Box(0.0, 1.0, (1,), dtype=np.float32)}) \
            if self.features else image

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        inner = self.env.unwrapped
        self._belief.reset(inner.task, inner.agent_seed)
        return self.observation(obs), info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)    # the belief took its percepts
        return self.observation(obs), reward, terminated, truncated, info

    def _take(self, percept, intent) -> None:
        """One percept of the step going on, for the belief (once; its stop is its own)."""
        if self._belief.strategy is not None and percept.unreachable is None and percept.observations \
                and not self._belief.done:
            self._belief.observe(percept, intent)

    def estimate(self) -> np.ndarray | None:
        """The belief's estimate of the source now (world units), or None before it has one."""
        strategy = self._belief.strategy
        return None if strategy is None else strategy.estimate

    def moments(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """``(mean (2,), axes (2, 2), sd (2,))`` of the belief now: its mean, its principal
        axes as columns (largest spread first) and the standard deviations along them
        (world units); None while the belief has no mass."""
        belief = belief_points(self._belief)
        if belief is None or not belief[1].size or not belief[1].sum() > 0:
            return None
        points, w = belief[0], belief[1] / belief[1].sum()
        mean = w @ points
        d = points - mean
        var, axes = np.linalg.eigh(d.T @ (d * w[:, None]))
        return mean, axes[:, ::-1], np.sqrt(np.maximum(var[::-1], 0.0))

    def _spread(self) -> np.ndarray:
        lo, hi = self.env.unwrapped.face.bounds()
        moments = self.moments()
        diagonal = float(np.hypot(*(hi - lo)))
        sd = np.full(2, diagonal) if moments is None else moments[2]
        return np.clip(np.log1p(sd) / np.log1p(diagonal), 0.0, 1.0).astype(np.float32)

    def _budget(self) -> np.ndarray:
        search = self.env.unwrapped.search
        spent = 0.0 if not search.max_steps else min(search.rounds / search.max_steps, 1.0)
        return np.array([spent], dtype=np.float32)

    def _pixel(self, points, lo, hi):
        ij = np.floor((np.asarray(points, dtype=float) - lo) / (hi - lo) * self.size).astype(int)
        ij = np.clip(ij, 0, self.size - 1)
        return self.size - 1 - ij[:, 1], ij[:, 0]            # rows from the top, columns

    def observation(self, observation):
        image = self._image(observation)
        if not self.features:
            return image
        return {"image": image, "spread": self._spread(), "budget": self._budget()}

    def _image(self, observation):
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


def _belief_wrapper(env) -> BeliefImage:
    """The :class:`BeliefImage` inside `env`'s wrapper chain."""
    inner = env
    while isinstance(inner, gymnasium.Wrapper):
        if isinstance(inner, BeliefImage):
            return inner
        inner = inner.env
    raise SearchError("BeliefStop wraps a BeliefImage (BeliefStop(BeliefImage(env)))")


class BeliefStop(gymnasium.ActionWrapper, gymnasium.utils.RecordConstructorArgs):
    """A point world's action for learning agents: ``Box(-1, 1, (3,))``.

    ``(a0, a1)`` is the next point. With ``frame="spread"`` (the default) it is placed in
    the belief's own frame: its mean plus ``a0`` times two standard deviations along its
    longest axis and ``a1`` times two along the other (:meth:`BeliefImage.moments`), so
    that the same action reads ever closer as the belief shrinks (the world's centre and
    half extents while the belief is empty). With ``frame="arena"`` it is mapped affinely
    onto the world's bounds (-1 the lower edge, +1 the upper). Points are clipped to the
    bounds. ``a2 >= 0``
    stops the search and declares the estimate of the belief that the
    :class:`BeliefImage` below keeps (the reciprocity imaging map's on the Poisson
    arenas). So the learner chooses where to read and when to stop; what the readings
    mean is the belief's business, as for a person reading the imaging map.

    Parameters
    ----------
    env : gymnasium.Env
        A point world (``Poisson-v0``, ``PoissonCar-v0``, ``Filament-v0``) wrapped in a
        :class:`BeliefImage`.
    frame : {"spread", "arena"}
        What the point is relative to (see above).
    """

    FRAMES = ("spread", "arena")

    def __init__(self, env: gymnasium.Env, frame: str = "spread"):
        gymnasium.utils.RecordConstructorArgs.__init__(self, frame=frame)
        super().__init__(env)
        if not isinstance(env.unwrapped.face, PointFace):
            raise SearchError("BeliefStop takes a point world (Poisson-v0, PoissonCar-v0, Filament-v0)")
        if frame not in self.FRAMES:
            raise SearchError(f"frame must be one of {', '.join(self.FRAMES)}; got {frame!r}")
        self._image = _belief_wrapper(env)
        self.frame = frame
        self.action_space = spaces.Box(-1.0, 1.0, (3,), dtype=np.float32)

    def action(self, action):
        a = np.clip(np.asarray(action, dtype=float).reshape(-1), -1.0, 1.0)
        lo, hi = self.env.unwrapped.face.bounds()
        estimate = self._image.estimate()
        moments = self._image.moments() if self.frame == "spread" else None
        if moments is not None:
            mean, axes, sd = moments
            point = np.clip(mean + axes @ (a[:2] * 2.0 * sd), lo, hi)
        else:
            point = lo + (a[:2] + 1.0) / 2.0 * (hi - lo)
        if a[2] >= 0.0 and estimate is not None:
            point = np.clip(np.asarray(estimate, dtype=float)[:2], lo, hi)
        return np.array([point[0], point[1], float(a[2] >= 0.0)])
