"""Models (inference): likelihoods and predictions a strategy assumes."""

from .base import BernoulliNoise, GaussianNoise, Model, NoiseModel, PoissonNoise

__all__ = ["BernoulliNoise", "GaussianNoise", "Model", "NoiseModel", "PoissonNoise"]
