"""Where the reciprocity search can read, and which possible sources a reading there sees.

The observer reads at the nodes it can reach at ``clearance`` from the walls
(:attr:`Reachability.reachable`, less the neighbourhoods of targets the platform refused).
A possible source is *within reach* (:meth:`Reachability.near`) when it lies within
``reach`` of a reachable node in a straight line and along the free region (mesh edges,
:data:`PATH_SLACK` times ``reach``: a source in a room closed off by walls is not within
reach of the other side of its wall), and, once a reading was taken, is either reachable
itself or *seen* from the reachable part: its reading on the part's edge would be at least
:data:`DETECT_SNR` times the reading noise (:func:`~reciprocity.strategies.reach.greatest_green`).
A source behind a slit narrower than the car reads as nothing wherever the car can go,
however near it lies.
"""

from __future__ import annotations

import numpy as np

from ...beliefs.imaging import ImagingMap
from ...errors import SearchError
from ...fem.green import GreenSolver
from ...spaces import MeshSpace
from ..reach import greatest_green

__all__ = ["Reachability", "PATH_SLACK", "DETECT_SNR"]

#: Paths along the edges of the graded mesh are up to 1.8 times the straight line in the
#: open (``tests/reciprocity/test_spaces.py``): "within reach" allows twice `reach` along
#: the free region, which still excludes rooms closed off by walls.
PATH_SLACK = 2.0
#: ... and seen from there: a possible source outside the reachable set is within reach
#: only if its reading at some reachable point would be this many times the reading
#: noise (``reciprocity.strategies.reach``).
DETECT_SNR = 3.0


class Reachability:
    """The reachable nodes of a search and the possible sources within reach of them.

    Its caches (the nodes within reach of a reachable set, the greatest adjoint value on
    its edge) are kept between episodes on the same mesh: they depend on the mesh and the
    reachable set alone.

    Parameters
    ----------
    reach : float
        Sensing reach, cm.
    clearance : float
        Observation points keep this distance (cm) from walls.

    Attributes
    ----------
    reachable : ndarray of bool
        The nodes the observer may read at.
    sensing : ndarray of bool
        Where readings could be taken from (refused targets do not narrow it).
    """

    def __init__(self, reach: float, clearance: float):
        if clearance < 0:
            raise SearchError(f"clearance must be >= 0 cm; got {clearance!r}")
        self.reach, self.clearance = float(reach), float(clearance)
        self._near_key = self._support_key = None

    def start(self, space: MeshSpace, solver: GreenSolver, position) -> None:
        """The nodes reachable from `position` (cm) at `clearance` on `space`."""
        self.space, self.solver = space, solver
        self.reachable = space.reachable_from(position, self.clearance)
        self.sensing = self.reachable.copy()

    def rebuild(self, space: MeshSpace, solver: GreenSolver, refused) -> None:
        """On a new mesh (``map: unknown``): every node at `clearance` from the believed
        walls, whatever the gaps between them (believed walls are thicker than the true
        ones, so a gap the map closes at `clearance` may be open, and the believed free
        region is connected by construction), less the `refused` ``(point, radius)``."""
        self.space, self.solver = space, solver
        self.reachable = space.admissible(self.clearance)
        self.sensing = self.reachable.copy()           # refusals do not narrow what is read from
        for point, radius in refused:
            self.exclude(point, radius)
        self._near_key = self._support_key = None

    def exclude(self, point, radius: float) -> None:
        """Take the nodes within `radius` (cm) of `point` out of the reachable set."""
        self.reachable &= ~self.space.around(point, radius)

    def restrict(self, mask: np.ndarray) -> None:
        """Keep only the reachable nodes where `mask` holds."""
        self.reachable &= mask

    def near(self, im: ImagingMap, noise: float) -> np.ndarray:
        """Mask of the nodes within reach (see the module's text), the belief's strength
        map giving each possible source's reading against `noise` (signal units). Kept
        until the reachable set changes: do not write it."""
        key = (id(self.space), self.reachable.tobytes())
        if self._near_key != key:
            from scipy.spatial import cKDTree
            pts = self.space.points
            dist = cKDTree(pts[self.reachable]).query(pts, distance_upper_bound=self.reach)[0]
            path = self.space.within_path(self.reachable, PATH_SLACK * self.reach)
            self._near, self._near_key, self._seen_green = np.isfinite(dist) & path, key, None
        if im.n == 0:                  # no reading yet: the belief is the prior
            return self._near
        if self._seen_green is None:
            # the largest adjoint value on the edge of the part of the free region the
            # observer's clearance lets it into (the same for every start in it, so kept
            # between episodes; the platform's own reachable set lies inside it)
            self._seen_green = greatest_green(self.solver, self.space.points, self.space.edges,
                                              self.sensing, self.reach)
        seen = self._seen_green * im.strength_map() >= DETECT_SNR * noise
        return self._near & (self.reachable | seen)

    def within_path(self, length: float) -> np.ndarray:
        """Mask of the nodes within `length` (cm, along the free region) of the reachable
        ones; kept until the reachable set changes."""
        key = self.reachable.tobytes()
        if self._support_key != key:
            self._support = self.space.within_path(self.reachable, float(length))
            self._support_key = key
        return self._support
