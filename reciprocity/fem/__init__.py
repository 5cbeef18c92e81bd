"""Finite elements of the free region: meshes, Green's functions and exact references.

:mod:`~reciprocity.fem.mesh` meshes an arena's free region with Triangle, graded toward
re-entrant corners, and caches the meshes; :mod:`~reciprocity.fem.green` holds
:class:`GreenSolver`, which factorizes the stiffness matrix once and gives every adjoint
solve (a :class:`Field`) as one back-substitution; :mod:`~reciprocity.fem.exact` holds the
closed-form Green's functions the solver is checked against.
"""

# Imported on first use (PEP 562, via lazy_loader): green.py and mesh.py pull in
# scikit-fem, matplotlib's triangulation and Triangle, which the closed-form
# solutions of exact.py (numpy only) and `import reciprocity` do not need.
import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "advection": ["AdvectionSolver", "WALL_KINDS"],
    "exact": ["disk_green", "free_space_advection_green", "free_space_green"],
    "green": ["Field", "GreenSolver", "GREEN_CACHE_SIZE"],
    "disk_cache": ["cache_dir"],
    "wind": ["WindField", "boundary_segments"],
    "mesh": ["MAX_TRIANGLES", "cached_mesh", "mesh_free_region", "node_areas", "reentrant_corners", "triangle_areas",
             "triangle_budget"],
})
