"""Exceptions raised by :mod:`reciprocity`."""

import numpy as np

__all__ = ["ReciprocityError", "MeshError", "SearchError", "UnreachableTarget"]


class ReciprocityError(ValueError):
    """Invalid input to the inverse-problem toolkit; the message says how to fix it."""


class MeshError(ReciprocityError):
    """The free region cannot be meshed with the requested parameters."""


class SearchError(ReciprocityError):
    """A search strategy or episode was configured or driven incorrectly."""


class UnreachableTarget(SearchError):
    """A platform cannot reach a requested point (enclosed, or closer to a wall than the
    clearance). The episode passes it to :meth:`Strategy.reject`, which picks another.

    Attributes
    ----------
    point : ndarray, shape (2,)
        The point that cannot be reached, cm.
    """

    def __init__(self, point, message: str):
        super().__init__(message)
        self.point = np.asarray(point, dtype=float)
