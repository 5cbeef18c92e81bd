"""Beliefs: one protocol (update, weights, estimate, entropy, predictive) for every
strategy's state of knowledge. :class:`reciprocity.ImagingMap` is one of them."""

from .base import Belief, Predictive, credible_mass, shannon_entropy

__all__ = ["Belief", "Predictive", "credible_mass", "shannon_entropy"]
