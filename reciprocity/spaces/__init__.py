"""Search spaces: the FEM mesh of a free region, a regular grid, (a lattice)."""

from .base import SearchSpace
from .grid import GridSpace
from .mesh import MeshSpace, mesh_space

__all__ = ["GridSpace", "MeshSpace", "SearchSpace", "mesh_space"]
