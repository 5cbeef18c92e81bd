"""Deprecated: moved to :mod:`reciprocity.platforms.lattice`; this path goes in the next release."""

from ._moved import alias

alias(__name__, "reciprocity.platforms.lattice")
