"""reciprocity: reciprocity-based source discovery with finite-element Green's functions.

Adjoint solves (:class:`GreenSolver`), probability imaging (:class:`ImagingMap`), the
search strategies of Landa et al. (Algorithms 1 and 2), platforms and episodes.
"""

from .candidates import CandidateSet
from .episode import Episode, run_episode
from .errors import MeshError, ReciprocityError, SearchError
from .exact import disk_green, free_space_green
from .green import Field, GreenSolver
from .imaging import COMBINATIONS, ImagingMap, superlevel_area
from .mesh import mesh_free_region, reentrant_corners
from .platforms import Platform, PointPlatform
from .strategies import (STRATEGIES, GradientStrategy, ReciprocityStrategy, Request, Strategy,
                         three_point_gradient)

__all__ = [
    "COMBINATIONS", "CandidateSet", "Episode", "Field", "GradientStrategy", "GreenSolver",
    "ImagingMap", "MeshError", "Platform", "PointPlatform", "ReciprocityError",
    "ReciprocityStrategy", "Request", "STRATEGIES", "SearchError", "Strategy", "disk_green",
    "free_space_green", "mesh_free_region", "reentrant_corners", "run_episode",
    "superlevel_area", "three_point_gradient",
]
