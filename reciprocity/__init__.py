"""reciprocity: reciprocity-based source discovery with finite-element Green's functions.

Adjoint solves (:class:`GreenSolver`), probability imaging (:class:`ImagingMap`), the
search strategies of Landa et al. (Algorithms 1 and 2), and the framework every
strategy plugs into: worlds (truth), models and beliefs (inference), search spaces,
intents, platforms, episodes and scenarios.
"""

from .api import check, execute, run
from .beliefs import Belief, Predictive
from .episode import SUMMARY_KEYS, Episode, StepRecord
from .errors import MeshError, ReciprocityError, SearchError, UnreachableTarget
from .fem import Field, GreenSolver, disk_green, free_space_green, mesh_free_region, reentrant_corners
from .imaging import COMBINATIONS, ImagingMap, superlevel_area
from .intents import Intent, Measure, Move, SampleGradient, Stay, StepToward
from .observations import Message, MessageLog, Observation
from .outcome import Stop, StopReason
from .platforms import Platform, PointPlatform, WalkerPlatform
from .scenarios import Scenario, load_scenario, scenario_names
from .spaces import GridSpace, MeshSpace, SearchSpace
from .strategies import (STRATEGIES, GradientStrategy, RandomWalkStrategy, ReciprocityStrategy,
                         SearchContext, Strategy, three_point_gradient)
from .worlds import Mismatch, PoissonWorld, World

__all__ = [
    "Belief", "COMBINATIONS", "Episode", "Field", "GradientStrategy", "GreenSolver", "GridSpace",
    "ImagingMap", "Intent", "Measure", "MeshError", "MeshSpace", "Message", "MessageLog", "Mismatch",
    "Move", "Observation", "Platform", "PointPlatform", "PoissonWorld", "Predictive",
    "RandomWalkStrategy", "ReciprocityError", "ReciprocityStrategy", "STRATEGIES", "SUMMARY_KEYS",
    "SampleGradient", "Scenario", "SearchContext", "SearchError", "SearchSpace", "Stay", "StepRecord",
    "StepToward", "Stop", "StopReason", "Strategy", "UnreachableTarget", "WalkerPlatform", "World",
    "check", "disk_green", "execute", "free_space_green", "load_scenario", "mesh_free_region",
    "reentrant_corners", "run", "scenario_names", "superlevel_area",
    "three_point_gradient",
]
