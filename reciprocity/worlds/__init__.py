"""Worlds (truth): what the sensor really reads. Each world kind registers itself with
:data:`reciprocity.scenarios.WORLD_KINDS` when its ``*_kind`` module is imported, which
the registry does on first use of the kind's name."""

from .base import Reading, World
from .poisson import Mismatch, PoissonWorld, TRUTH_MESH_RATIO, truth_solver

__all__ = ["Mismatch", "PoissonWorld", "Reading", "TRUTH_MESH_RATIO", "World", "truth_solver"]
