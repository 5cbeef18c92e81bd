"""Finite elements of the free region: meshes, Green's functions and exact references.

:mod:`~reciprocity.fem.mesh` meshes an arena's free region with Triangle, graded toward
re-entrant corners, and caches the meshes; :mod:`~reciprocity.fem.green` holds
:class:`GreenSolver`, which factorizes the stiffness matrix once and gives every adjoint
solve (a :class:`Field`) as one back-substitution; :mod:`~reciprocity.fem.exact` holds the
closed-form Green's functions the solver is checked against.
"""

from .exact import disk_green, free_space_green
from .green import Field, GreenSolver
from .mesh import cache_dir, cached_mesh, mesh_free_region, node_areas, reentrant_corners, triangle_areas

__all__ = [
    "Field", "GreenSolver", "cache_dir", "cached_mesh", "disk_green", "free_space_green",
    "mesh_free_region", "node_areas", "reentrant_corners", "triangle_areas",
]
