"""Deprecated: moved to :mod:`reciprocity.fem.green`; this path goes in the next release."""

from ._moved import alias

alias(__name__, "reciprocity.fem.green")
