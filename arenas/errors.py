"""Exceptions raised by :mod:`arenas`."""

__all__ = ["ArenaError"]


class ArenaError(ValueError):
    """An arena (geometry, file, image or pose) is invalid.

    The message says what is wrong and how to fix it.
    """
