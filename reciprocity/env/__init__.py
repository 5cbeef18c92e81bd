"""Search environments: the truth behind ``reset``/``step``, and :func:`rollout`, the one driver.

Every front door (the command line, campaign workers, ``reproduce``) checks its input
once into an :class:`EpisodeSpec` (:func:`reciprocity.api.check`), builds a
:class:`SearchEnv` from it and calls :func:`rollout`; an outside policy does the same.
"""

from ..seeds import EpisodeSeeds
from .rollout import Agent, Rollout, rollout
from .search_env import SearchEnv
from .spec import EpisodeSpec, environment_spec

__all__ = ["Agent", "EpisodeSeeds", "EpisodeSpec", "Rollout", "SearchEnv", "environment_spec", "rollout"]
