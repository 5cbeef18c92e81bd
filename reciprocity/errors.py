"""Exceptions raised by :mod:`reciprocity`."""

__all__ = ["ReciprocityError", "MeshError", "SearchError"]


class ReciprocityError(ValueError):
    """Invalid input to the inverse-problem toolkit; the message says how to fix it."""


class MeshError(ReciprocityError):
    """The free region cannot be meshed with the requested parameters."""


class SearchError(ReciprocityError):
    """A search strategy or episode was configured or driven incorrectly."""
