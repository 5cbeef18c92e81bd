"""Worlds (truth): what the sensor really reads. Their wiring to scenario files and
platforms is in :mod:`reciprocity.wiring`."""

from .base import Reading, World
from .poisson import Mismatch, PoissonWorld, TRUTH_H, TRUTH_ORDER, truth_solver

__all__ = ["Mismatch", "PoissonWorld", "Reading", "TRUTH_H", "TRUTH_ORDER", "World", "truth_solver"]
