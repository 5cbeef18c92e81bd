"""Search environments: the truth behind ``reset``/``step``, and :func:`rollout`, the one driver.

Every front door (the command line, campaign workers, ``reproduce``) builds a
:class:`SearchEnv` and calls :func:`rollout`; an outside policy does the same.
"""

from ..seeds import EpisodeSeeds
from .rollout import Agent, Rollout, rollout
from .search_env import SearchEnv

__all__ = ["Agent", "EpisodeSeeds", "Rollout", "SearchEnv", "rollout"]
