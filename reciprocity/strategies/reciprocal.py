"""Algorithm 1 of Landa et al.: reciprocity-based source discovery."""

from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter, map_coordinates

from ..errors import SearchError
from ..green import GreenSolver
from ..imaging import ImagingMap
from ..intents import Measure
from ..outcome import StopReason
from ..spaces import MeshSpace, mesh_space
from ..worlds.poisson import cached_solver
from .base import SearchContext, Status, Strategy

__all__ = ["ReciprocityStrategy", "RULES", "mass_within_reach"]

#: Next-observation rules.
RULES = ("axis", "reach", "nearest")


def mass_within_reach(candidates: np.ndarray, support: np.ndarray, weights: np.ndarray,
                      reach: float, cell: float | None = None) -> np.ndarray:
    """``Σ_x w(x) exp(-|y - x|^2 / (2 reach^2))`` for each candidate ``y``.

    The weights are binned on a lattice of `cell` cm (default ``reach / 6``), blurred
    with a Gaussian filter and read back by linear interpolation: O(n + m) instead of
    O(n m), with a relative error of order ``(cell / reach)^2``.

    Parameters
    ----------
    candidates : ndarray, shape (m, 2)
        Points ``y``, cm.
    support : ndarray, shape (n, 2)
        Points ``x``, cm.
    weights : ndarray, shape (n,)
        Non-negative weights ``w(x)``.
    reach : float
        Kernel length, cm.
    cell : float, optional
        Lattice spacing, cm.
    """
    cell = reach / 6.0 if cell is None else float(cell)
    pad = 4.0 * reach
    lo = np.minimum(support.min(axis=0), candidates.min(axis=0)) - pad
    hi = np.maximum(support.max(axis=0), candidates.max(axis=0)) + pad
    nx, ny = np.ceil((hi - lo) / cell).astype(int) + 1
    hist, _, _ = np.histogram2d(support[:, 0], support[:, 1], bins=(nx, ny),
                                range=[(lo[0], lo[0] + nx * cell), (lo[1], lo[1] + ny * cell)],
                                weights=weights)
    sigma = reach / cell
    # the filter is normalised; the kernel above is not: restore its 2 pi reach^2 / cell^2
    blurred = gaussian_filter(hist, sigma, mode="constant", truncate=4.0) * (2 * np.pi * sigma**2)
    coords = ((candidates - lo) / cell - 0.5).T
    return map_coordinates(blurred, coords, order=1, mode="constant")


class ReciprocityStrategy(Strategy):
    """Reciprocity search (Algorithm 1): adjoint solves, probability imaging, level sets.

    At each observation point ``z_k`` the reading ``I_k`` and the adjoint field
    ``v_k = c G(·, z_k)`` add the map ``p_k`` to the imaging function ``P_M``. The search
    stops when the region ``{P_M >= eps}`` has area below `area_tol`. Otherwise the next
    point is at least `d` from every earlier point, reachable at `clearance` from the
    walls, and chosen by `rule`:

    ``"nearest"`` (step 13 of the paper)
        in ``{v_k > I_k}``, nearest to ``z_k``; among the points of that nearest ring
        (one mesh size wide) the one with the largest score below.
    ``"reach"``
        the point with the largest score ``Σ_x w(x) exp(-|y - x|^2 / (2 reach^2))``,
        ``w`` the imaging function times the nodal area: the imaging mass within
        sensing reach of ``y``. While the signal is weak this sends the observer to the
        largest unexplored part of the arena; once the region is small, to the points
        nearest to it that keep the separation `d`, which surround the source.
    ``"axis"`` (default)
        as ``"reach"`` while the imaging mass is spread wider than `reach` (its major
        standard deviation); once it is concentrated, the admissible point nearest to
        its major axis at ``max(d, 2 std)`` beyond its centre. The imaging region is
        elongated along the level sets already measured; level sets around a point on
        its axis cut across it.

    The search stops when the region ``{P_M >= eps}`` has area below `area_tol` and,
    unless `extent_tol` is None, also lies within `extent_tol` of the estimate (a thin
    curved sliver can have a small area and still be long).

    Parameters
    ----------
    eps : float
        Threshold ``0 < eps < 1`` defining the region of possible sources.
    area_tol : float
        ``A_eps``, cm^2: stop when the region is smaller.
    d : float
        Minimum separation of observation points, cm.
    sigma : float
        ``sigma`` of eq. (7), signal units.
    max_steps : int
        Give up after this many measurements.
    clearance : float
        Observation points keep this distance (cm) from walls.
    extent_tol : float or None
        Largest distance (cm) from the estimate to the region for stopping.
    rule : {"axis", "reach", "nearest"}
        Next-point rule (see above).
    reach : float
        Kernel length (cm) of the ``"reach"`` score: about the distance at which the
        signal still stands out of the noise.
    combine : {"mean", "product"}
        Combination of the maps (eq. 8, or the normalised likelihood).
    strength : float or "arena" or None
        Source strength: a number, ``"arena"`` for the arena's nominal strength, or
        None for unknown (estimated per point by least squares).
    h : float
        Mesh size (cm) of the solver built by :meth:`start` when none is given.
    solver : GreenSolver, optional
        A prebuilt solver for the arena (shared across episodes: factorized once).
    """

    name = "reciprocity"

    def __init__(self, *, eps: float = 0.1, area_tol: float = 40.0,
                 extent_tol: float | None = 5.0, d: float = 6.0, sigma: float = 17.0,
                 max_steps: int = 30, clearance: float = 3.0, rule: str = "axis",
                 reach: float = 12.0, combine: str = "product", strength="arena", h: float = 1.0,
                 solver: GreenSolver | None = None):
        super().__init__()
        if not 0 < eps < 1:
            raise SearchError(f"eps must lie strictly between 0 and 1; got {eps!r}")
        for key, val in dict(area_tol=area_tol, d=d, sigma=sigma, h=h).items():
            if not np.isfinite(val) or val <= 0:
                raise SearchError(f"{key} must be a positive number; got {val!r}")
        if clearance < 0:
            raise SearchError(f"clearance must be >= 0 cm; got {clearance!r}")
        if int(max_steps) < 1:
            raise SearchError(f"max_steps must be at least 1; got {max_steps!r}")
        if rule not in RULES:
            raise SearchError(f"rule must be one of {RULES}; got {rule!r}")
        if extent_tol is not None and (not np.isfinite(extent_tol) or extent_tol <= 0):
            raise SearchError(f"extent_tol must be a positive length in cm or None; got {extent_tol!r}")
        if not np.isfinite(reach) or reach <= 0:
            raise SearchError(f"reach must be a positive length in cm; got {reach!r}")
        self.rule, self.reach, self.extent_tol = rule, float(reach), extent_tol
        self.eps, self.area_tol, self.d, self.sigma = float(eps), float(area_tol), float(d), float(sigma)
        self.max_steps, self.clearance, self.combine = int(max_steps), float(clearance), combine
        self.strength, self.h, self.solver = strength, float(h), solver

    def params(self) -> dict:
        return dict(rule=self.rule, reach=self.reach, eps=self.eps, area_tol=self.area_tol,
                    extent_tol=self.extent_tol, d=self.d, sigma=self.sigma,
                    max_steps=self.max_steps, clearance=self.clearance, combine=self.combine,
                    strength=self.strength if not isinstance(self.strength, float) else float(self.strength),
                    h=self.h if self.solver is None else self.solver.h)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        arena, pose = ctx.arena, ctx.start
        geometry = arena.without_scenario()
        if self.solver is None or self.solver.arena.without_scenario() is not geometry:
            self.solver = cached_solver(geometry, self.h)
        c = ctx.nominal.get("strength", arena.strength) if self.strength == "arena" else self.strength
        self.imaging = ImagingMap(self.solver, self.sigma, strength=c, combine=self.combine)
        self.space = self._space(geometry)
        self._reachable = self.space.reachable_from(pose[:2], self.clearance)
        self._next = np.asarray(pose[:2], dtype=float)
        self._node_area = self.space.cell_areas

    def _space(self, geometry) -> MeshSpace:
        """The candidate points: the nodes of the solver's own P1 mesh."""
        space = mesh_space(geometry, self.solver.h)
        if self.solver.order != 1 or space.points.shape != self.solver.nodes.shape or \
                not np.allclose(space.points, self.solver.nodes, atol=1e-9):
            raise SearchError("the reciprocity strategy needs a P1 solver (order=1) on the arena's mesh")
        return space

    def propose(self) -> Measure | None:
        if self.done:
            return None
        return Measure(self._next.copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        obs = observations[0]
        self.n_measurements += 1
        self.n_samples += 1
        self.imaging.update(obs)                                       # steps 9-11
        area = self.imaging.area(self.eps)                             # step 12
        estimate = self.imaging.estimate()
        self.status = Status(estimate, area)
        region = self.imaging.nodes[self.imaging.values() >= self.eps]
        extent = float(np.hypot(*(region - estimate).T).max()) if len(region) else 0.0
        self.status.extra["region_extent"] = extent
        if area < self.area_tol and (self.extent_tol is None or extent <= self.extent_tol):
            self.stop(StopReason.CONVERGED, "region smaller than area_tol")
        elif self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} measurements")
        else:
            self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def _choose_next(self) -> None:
        nxt = self.next_point()                                        # step 13
        if nxt is None:
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
        else:
            self._next = nxt

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None and (self._reachable & mask).any():
            self._reachable &= mask

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Exclude the neighbourhood of an unreachable target and choose again."""
        if self._count_rejection(reason):
            return
        if not len(self.imaging.points):
            super().reject(intent, point, reason, agent)
            return
        self._reachable &= ~self.space.around(point, max(0.5 * self.d, self.solver.h))
        self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def next_point(self) -> np.ndarray | None:
        """Step 13: the next observation point (cm), or None if none is admissible."""
        im, cand = self.imaging, self.space
        z = im.points[-1]
        allowed = self._reachable & cand.separated(im.points, self.d)
        if self.rule == "axis":
            nxt = self._axis_point(allowed)
            if nxt is not None:
                return nxt
        score = self._score(allowed)  # only when the axis rule did not decide
        if self.rule in ("axis", "reach"):
            idx = np.flatnonzero(np.isfinite(score))
            return None if idx.size == 0 else cand.nodes[idx[np.argmax(score[idx])]].copy()
        inside = im.model()[:, -1] > im.readings[-1]                   # {v_k > I_k}
        mask = allowed & inside if (allowed & inside).any() else allowed
        return cand.nearest_ring(z, mask, score, self.solver.h)

    def _axis_point(self, allowed: np.ndarray) -> np.ndarray | None:
        """The ``"axis"`` rule once the imaging mass is concentrated, else None."""
        nodes = self.space.points
        w = self.imaging.values() * self._node_area
        w = w / w.sum()
        centre = w @ nodes
        cov = np.cov(nodes.T, aweights=w, bias=True)
        evals, evecs = np.linalg.eigh(cov)
        std = float(np.sqrt(max(evals[-1], 0.0)))
        if std > self.reach:
            return None
        axis = evecs[:, -1]
        dist = max(self.d, 2.0 * std)
        best, best_gap = None, np.inf
        for sign in (1.0, -1.0):
            target = centre + sign * dist * axis
            cand = self.space.nearest_in(target, allowed)
            if cand is not None and np.hypot(*(cand - target)) < best_gap:
                best, best_gap = cand, np.hypot(*(cand - target))
        return best

    def _score(self, allowed: np.ndarray) -> np.ndarray:
        """Imaging mass within reach of the allowed nodes; -inf elsewhere. The imaging
        function weighted by nodal area is the density."""
        nodes = self.space.points
        w = self.imaging.values() * self._node_area
        idx = np.flatnonzero(allowed)
        out = np.full(len(nodes), -np.inf)
        if idx.size:
            out[idx] = mass_within_reach(nodes[idx], nodes, w, self.reach)
        return out
