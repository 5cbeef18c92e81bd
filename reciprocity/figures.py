"""Deprecated: moved to :mod:`reciprocity.viz.figures`; this path goes in the next release."""

from ._moved import alias

alias(__name__, "reciprocity.viz.figures")
