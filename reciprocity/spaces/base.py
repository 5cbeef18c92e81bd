"""Search spaces: where sources may be and where observers may go.

Candidates, neighbours, reachability and cell areas come from the space, never from a
solver. The FEM mesh of an arena's free region (:class:`~reciprocity.spaces.MeshSpace`),
a regular grid (:class:`~reciprocity.spaces.GridSpace`) and a lattice of nodes and links
are search spaces.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

__all__ = ["SearchSpace"]


class SearchSpace(ABC):
    """A discrete set of places with areas and a neighbourhood.

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        The places (mesh nodes, cell centres, lattice nodes).
    cell_areas : ndarray, shape (n,)
        The area each place stands for (squared length units); 1 on a lattice.
    """

    points: np.ndarray
    cell_areas: np.ndarray

    @abstractmethod
    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of `points` (m, 2) inside the space."""

    @abstractmethod
    def neighbours(self, i: int) -> np.ndarray:
        """Indices of the places one step from place `i`."""

    def nearest(self, point) -> int:
        """Index of the place nearest to `point`."""
        return int(np.argmin(np.sum((self.points - np.asarray(point, dtype=float)) ** 2, axis=1)))

    def step_candidates(self, point) -> np.ndarray:
        """Places (k, 2) one step from `point` (the moves of a time-stepped observer)."""
        return self.points[self.neighbours(self.nearest(point))]

    def __len__(self) -> int:
        return len(self.points)
