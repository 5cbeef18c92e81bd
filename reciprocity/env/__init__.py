"""Search environments: the truth behind ``reset``/``step``, and :func:`rollout`, the one driver.

Every front door (the command line, campaign workers, ``reproduce``, the Gymnasium and
PettingZoo adapters) builds a :class:`SearchEnv` and calls :func:`rollout`.
"""

from .rollout import Agent, rollout
from .search_env import SearchEnv
from .seeds import EpisodeSeeds

__all__ = ["Agent", "EpisodeSeeds", "SearchEnv", "rollout"]
