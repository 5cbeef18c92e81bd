"""One seed tree per episode, derived in one place (the environment, the scenario's world
and default starts all draw from it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["EpisodeSeeds"]

# Distinct spawn keys for the world's construction and the default start poses, so that
# neither stream overlaps the noise streams spawned from the bare seed.
_BUILD_KEY = 0x57A7
_START_KEY = 0x5747


@dataclass(frozen=True)
class EpisodeSeeds:
    """The independent random streams of one episode, all derived from its seed.

    Attributes
    ----------
    seed : int
        The episode seed (non-negative).
    build : SeedSequence
        The world's random parts (a lattice's missing links, a plume's wind).
    starts : SeedSequence
        Default start poses where the scenario gives none.
    world : SeedSequence
        The world's reading noise.
    agent : SeedSequence
        The agent's own draws (given to it at reset).
    platforms : tuple of SeedSequence
        One per observer: its motion noise, slips, camera.
    """

    seed: int
    build: np.random.SeedSequence
    starts: np.random.SeedSequence
    world: np.random.SeedSequence
    agent: np.random.SeedSequence
    platforms: tuple

    @classmethod
    def from_seed(cls, seed: int, n_platforms: int) -> "EpisodeSeeds":
        """The seed tree of episode `seed` with `n_platforms` observers."""
        seed = int(seed)
        world, agent, *platforms = np.random.SeedSequence(seed).spawn(2 + int(n_platforms))
        return cls(seed, np.random.SeedSequence([seed, _BUILD_KEY]), np.random.SeedSequence([seed, _START_KEY]),
                   world, agent, tuple(platforms))

    @staticmethod
    def rng(ss: np.random.SeedSequence) -> np.random.Generator:
        """A generator on stream `ss` (a fresh one each call: same stream, same draws)."""
        return np.random.default_rng(ss)
