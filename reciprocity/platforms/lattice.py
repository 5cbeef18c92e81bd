"""The lattice searcher's platform: relative moves that fail as in eq. (45) of Ristic et al.

The searcher's controls are the five moves ``{·, →, ←, ↑, ↓}``. A control is carried out
with probability ``1 − p_e``; otherwise one of the four others, chosen uniformly, is
carried out instead (eq. (45)), the searcher not knowing. A move along a link that does
not exist in the true lattice leaves the searcher where it is. The platform reports the
position the searcher *commanded* (dead reckoning), never where it really is.

This differs from :class:`reciprocity.platforms.walker.WalkerPlatform`, whose moves are to
absolute places and whose slips go to another neighbour (never "stay"): after a slip an
absolute target is no longer adjacent, so a walker would stall, while the paper's
controls are relative.
"""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..intents import Intent, Move, Stay
from ..observations import Observation
from ..spaces.lattice import CONTROLS, LatticeSpace
from ..worlds.base import World
from .base import Platform

__all__ = ["LatticePlatform"]


class LatticePlatform(Platform):
    """One control per step on a lattice, failing with probability `slip` (eq. (45)).

    Parameters
    ----------
    space : LatticeSpace
        The *true* lattice with its missing links.
    slip : float
        p_e, probability that another control is carried out (0.04 in the paper).
    """

    name = "lattice"
    intents = (Move, Stay)

    def __init__(self, space: LatticeSpace, *, slip: float = 0.04):
        super().__init__()
        if not 0.0 <= slip < 1.0:
            raise SearchError(f"slip probability must lie in [0, 1); got {slip!r}")
        self.space, self.slip = space, float(slip)

    def reset(self, start, world: World, rng: np.random.Generator) -> None:
        s = np.asarray(start, dtype=float).ravel()
        self.world, self.rng = world, rng
        self.pose = np.array([s[0], s[1], 0.0])
        self._node = int(self.space.index_of(s[:2])[0])
        if self._node < 0:
            raise SearchError(f"start ({s[0]:g}, {s[1]:g}) is not a lattice node")
        self.path_length, self.time, self.slips = 0.0, 0.0, 0
        self.last_route = [self.true_position.copy()]

    @property
    def true_position(self) -> np.ndarray:
        return self.space.points[self._node]

    def _execute(self, intent: Intent) -> list[Observation]:
        self.last_route = [self.true_position.copy()]
        u = np.rint(intent.point - self.pose[:2]).astype(int)
        k = np.flatnonzero(np.all(CONTROLS == u, axis=1))
        if isinstance(intent, Stay):
            k = np.array([0])
        if k.size == 0:
            raise SearchError(f"a lattice move must be one unit east, west, north or south; got {u.tolist()}")
        c = int(k[0])
        if self.rng.random() < self.slip:                  # eq. (45)
            others = [j for j in range(len(CONTROLS)) if j != c]
            c = others[int(self.rng.integers(len(others)))]
            self.slips += 1
        if c > 0:
            lid = self.space.link_of[self._node, c - 1]
            if lid >= 0 and self.space.present[lid]:
                self._node = int(self.space.step_of[self._node, c - 1])
                self.path_length += 1.0
        self.pose = np.array([self.pose[0] + u[0], self.pose[1] + u[1], 0.0])
        self.last_route.append(self.true_position.copy())
        r = self.world.read(self.true_position, time=self.time, dwell=1.0, rng=self.rng, observer=self.agent)
        obs = Observation(self.pose[:2].copy(), r.value, self.time, 1.0, r.kind, r.saturated,
                          self.agent, r.data)
        self.time += 1.0
        return [obs]

    def summary(self) -> dict:
        return dict(slips=int(self.slips))
