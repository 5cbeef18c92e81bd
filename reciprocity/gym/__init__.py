"""Gymnasium faces of the search worlds (extra ``[gym]``).

``import reciprocity.gym`` registers:

============================  =====================  ==========================================
id                            default scenario       action
============================  =====================  ==========================================
``reciprocity/Poisson-v0``    ``paper`` (point)      ``Box [x, y, stop]``: next point, cm
``reciprocity/PoissonCar-v0`` ``paper`` (car)        ``Box [x, y, stop]``: next point, cm
``reciprocity/Lattice-v0``    ``ristic-lattice``     ``Discrete(6)``: stay, E, W, N, S, stop
``reciprocity/Plume-v0``      ``otto-2d``            ``Discrete(n + 2)``: the moves, stay, stop
``reciprocity/Filament-v0``   ``farrell``            ``Box [x, y, stop]``: next point, m
``reciprocity/Flow-v0``       ``paper-wind``         ``Box [x, y, stop]``: next point, cm
============================  =====================  ==========================================

``Poisson-v0`` draws a new source and start at every reset, from its seed
(``random_source=True``), and has a budget of 40 rounds that is part of the task
(``max_steps=40``: a failed stop pays the rounds left, and a spent budget *terminates*,
``cap_terminates=True``), so that it can be learned; ``random_source=False`` gives the
arena's own source and start.

Each takes ``scenario=`` (a built-in name or a YAML path) and the scenario's world keys
as keyword arguments, e.g. ``gymnasium.make("reciprocity/Poisson-v0", scenario="maze",
noise=20.0)``. :class:`StrategyPolicy` drives any of them with a built-in strategy, and
:class:`BeliefImage` turns the observation into the belief as an image.
"""

from __future__ import annotations

import gymnasium

from .env import SUCCESS_REWARD, DeclaringAgent, SearchGymEnv
from .policy import StrategyPolicy
from .wrappers import BeliefImage, BeliefStop

__all__ = ["SearchGymEnv", "StrategyPolicy", "BeliefImage", "BeliefStop", "DeclaringAgent", "SUCCESS_REWARD", "IDS"]

#: The registered ids and their default arguments.
IDS = {
    "reciprocity/Poisson-v0": dict(scenario="paper", platform="point", random_source=True, max_steps=40,
                                   cap_terminates=True),
    "reciprocity/PoissonCar-v0": dict(scenario="paper", platform="car"),
    "reciprocity/Lattice-v0": dict(scenario="ristic-lattice"),
    "reciprocity/Plume-v0": dict(scenario="otto-2d"),
    "reciprocity/Filament-v0": dict(scenario="farrell"),
    "reciprocity/Flow-v0": dict(scenario="paper-wind"),
}

for _id, _kwargs in IDS.items():
    if _id not in gymnasium.registry:
        gymnasium.register(_id, entry_point="reciprocity.gym.env:SearchGymEnv", kwargs=_kwargs,
                           disable_env_checker=True)
