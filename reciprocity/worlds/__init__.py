"""Worlds (truth): what the sensor really reads. Importing this package registers the
world kinds with :mod:`reciprocity.scenarios`."""

from .base import Reading, World
from .poisson import Mismatch, PoissonWorld, TRUTH_MESH_RATIO, cached_solver
from . import poisson_kind  # noqa: F401  (registers "poisson")
from . import lattice_kind  # noqa: F401  (registers "lattice")
from . import filament_kind  # noqa: F401  (registers "filament")
from . import plume_kind  # noqa: F401  (registers "plume")

__all__ = ["Mismatch", "PoissonWorld", "Reading", "TRUTH_MESH_RATIO", "World", "cached_solver"]
