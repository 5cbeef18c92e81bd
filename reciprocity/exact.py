"""Deprecated: moved to :mod:`reciprocity.fem.exact`; this path goes in the next release."""

from ._moved import alias

alias(__name__, "reciprocity.fem.exact")
