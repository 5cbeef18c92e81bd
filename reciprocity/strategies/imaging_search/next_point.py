"""Step 13 of Algorithm 1: where the reciprocity search reads next.

The next point is at least ``d`` from every earlier point, reachable at the observer's
clearance from the walls, and chosen by the rule (:class:`NextPointRule`):

``"nearest"`` (step 13 of the paper)
    in ``{v_k > I_k}``, nearest to ``z_k``; on a mesh "nearest" is resolved to one mesh
    size: among the nodes of that nearest ring the one with the largest score of
    ``"reach"`` below. When no admissible node has ``v_k > I_k``, the nearest admissible
    node.
``"reach"``
    the point with the largest score ``Σ_x w(x) exp(-|y - x|^2 / (2 reach^2))``, ``w`` the
    imaging function times the nodal area: the imaging mass within sensing reach of ``y``
    (:func:`mass_within_reach`).
``"axis"`` (default)
    as ``"reach"`` while the imaging mass is spread wider than ``reach`` (its major
    standard deviation); once it is concentrated, the admissible point nearest to its
    major axis at ``max(d, 2 std)`` beyond its centre (:func:`axis_point`): level sets
    around a point on the axis cut across the elongated region.
``"info"``
    the point whose reading is expected to leave the smallest belief spread:
    :data:`INFO_SUPPORT` belief points drawn by systematic resampling on a lattice of
    :data:`INFO_SPACING` cm, their Green's functions ``G(·, x_i)`` (by reciprocity the
    predicted reading ``c G(y, x_i)`` at every lattice point ``y``; solved once per lattice
    point and kept per solver), scored at every admissible lattice point. A point between
    two modes whose predicted readings differ is preferred to one that cannot tell them
    apart. Once the belief sits in one lattice cell, as ``"axis"``. When no admissible
    point is expected to gain :data:`INFO_GAIN_MIN` nats and the belief has two modes, the
    search gives up and says so, rather than stop on one mode.

``"lookahead"``
    two readings ahead: as ``"info"`` with :data:`LOOKAHEAD_SUPPORT` belief points, the
    :data:`LOOKAHEAD_FIRST` lattice points of least one-step expected entropy are scored
    by the expected entropy after their reading and then the best of the
    :data:`LOOKAHEAD_SECOND` points of least one-step expected entropy at least ``d``
    from them, for each outcome of the first reading
    (:func:`~reciprocity.strategies.information.two_step_entropy`). A first point whose
    own reading tells little but sets up a decisive second one can win over the myopic
    choice. Once the belief sits in one lattice cell, as ``"axis"``.

Once more than ``TEST_REACH_ABOVE`` of the belief lies out of reach, rules ``"axis"`` and
``"reach"`` read where most of the belief within reach lies (:func:`reach_test_point`), to
find the source there or rule it out. A search for several sources, while it surveys for
one more, reads where most of the hidden region lies within reach (:func:`survey_point`).
"""

from __future__ import annotations

import numpy as np

from ...beliefs.imaging import ImagingMap
from ...errors import SearchError
from ...fem.green import GreenSolver
from ...spaces import MeshSpace
from ..information import (expected_entropy, lattice_greens, mutual_information, systematic_support,
                           two_step_entropy)

__all__ = ["NextPointRule", "RULES", "mass_within_reach", "axis_point", "reach_test_point", "survey_point",
           "INFO_SPACING", "INFO_SUPPORT", "INFO_SCORE", "INFO_GAIN_MIN", "LOOKAHEAD_SUPPORT",
           "LOOKAHEAD_FIRST", "LOOKAHEAD_SECOND"]

#: Next-observation rules.
RULES = ("axis", "reach", "nearest", "info", "lookahead")
#: Rules that score the lattice of :data:`INFO_SPACING` by expected entropy.
LATTICE_RULES = ("info", "lookahead")
#: Lattice spacing (cm) of the candidate sources and observation points of ``rule="info"``
#: (at least the mesh size).
INFO_SPACING = 2.5
#: Belief support points drawn per step by ``rule="info"``.
INFO_SUPPORT = 16
#: Score of ``rule="info"``: ``"pairs"`` (expected entropy over the support points,
#: :func:`~reciprocity.strategies.information.expected_entropy`) or ``"mi"`` (the mutual
#: information of a reading, :func:`~reciprocity.strategies.information.mutual_information`,
#: linear in the support). Neither told apart on 30 generated draws (``benchmarks/likelihood_terms.md``).
INFO_SCORE = "pairs"
#: Expected entropy gain (nats) below which ``rule="info"`` finds no point worth
#: measuring: with two modes left the search gives up and says so.
INFO_GAIN_MIN = 0.01
#: Belief support points drawn per step by ``rule="lookahead"``.
LOOKAHEAD_SUPPORT = 32
#: First points ``rule="lookahead"`` looks ahead from: the least one-step expected entropy.
LOOKAHEAD_FIRST = 16
#: Second points ``rule="lookahead"`` considers after each first reading's outcome.
LOOKAHEAD_SECOND = 64


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
    from scipy.ndimage import gaussian_filter, map_coordinates
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


def axis_point(space: MeshSpace, mass: np.ndarray, allowed: np.ndarray, reach: float,
               d: float) -> np.ndarray | None:
    """The ``"axis"`` rule's point once a belief is concentrated, else None.

    Parameters
    ----------
    space : MeshSpace
        The candidate points (its nodes carry `mass`).
    mass : ndarray, shape (n,)
        The belief's mass at each node (any positive scale).
    allowed : ndarray of bool, shape (n,)
        Where the next point may be.
    reach, d : float
        Sensing reach and least separation of points read, cm.

    Returns
    -------
    ndarray (2,) or None
        None while the mass spreads wider than `reach` (its major standard deviation);
        else the allowed node nearest to the mass's major axis at ``max(d, 2 std)`` beyond
        its centre, on the side where one lies nearer: level sets around a point on the
        axis cut across the elongated region.
    """
    nodes = space.points
    w = mass / mass.sum()
    centre = w @ nodes
    cov = np.cov(nodes.T, aweights=w, bias=True)
    evals, evecs = np.linalg.eigh(cov)
    std = float(np.sqrt(max(evals[-1], 0.0)))
    if std > reach:
        return None
    axis = evecs[:, -1]
    dist = max(d, 2.0 * std)
    best, best_gap = None, np.inf
    for sign in (1.0, -1.0):
        target = centre + sign * dist * axis
        cand = space.nearest_in(target, allowed)
        if cand is not None and np.hypot(*(cand - target)) < best_gap:
            best, best_gap = cand, np.hypot(*(cand - target))
    return best


def reach_test_point(space: MeshSpace, allowed: np.ndarray, near: np.ndarray, weights: np.ndarray,
                     reach: float) -> np.ndarray | None:
    """The allowed node with the most belief within reach around it (the score of rule
    ``"reach"`` over the possible sources `near`, within reach, only): where a reading
    confirms or rules out most of what the search can still find; None if none.

    Parameters
    ----------
    space : MeshSpace
        The candidate points.
    allowed, near : ndarray of bool, shape (n,)
        Where the next point may be; the possible sources within reach.
    weights : ndarray, shape (n,)
        The belief's weights at the nodes.
    reach : float
        Sensing reach, cm.
    """
    idx = np.flatnonzero(allowed)
    if idx.size == 0 or not near.any():
        return None
    pts = space.points
    score = mass_within_reach(pts[idx], pts[near], weights[near], reach)
    return space.nodes[idx[np.argmax(score)]].copy()


def survey_point(space: MeshSpace, allowed: np.ndarray, hidden: np.ndarray, reach: float,
                 travel: float | None, last: np.ndarray) -> np.ndarray | None:
    """Several sources, surveying for one more: the allowed node with the most of the
    `hidden` region's area within `reach` (cm) around it, discounted by
    ``exp(-distance / travel)`` from the last point read `last` (cm) when `travel` is
    given; None if no node is allowed."""
    score = np.full(len(space.points), -np.inf)
    idx = np.flatnonzero(allowed)
    if idx.size and hidden.any():
        score[idx] = mass_within_reach(space.points[idx], space.points, hidden, reach)
        if travel is not None:   # the near hidden region first: less travel
            gap = np.hypot(*(space.points[idx] - last).T)
            score[idx] *= np.exp(-gap / travel)
    return None if idx.size == 0 else space.nodes[idx[np.argmax(score[idx])]].copy()


class NextPointRule:
    """Step 13: the next observation point by `rule` (see the module's text).

    Parameters
    ----------
    rule : {"axis", "reach", "nearest", "info", "lookahead"}
        The rule.
    d : float
        Minimum separation of observation points, cm.
    reach : float
        Kernel length (cm) of the ``"reach"`` score: about the distance at which the
        signal still stands out of the noise.
    """

    def __init__(self, rule: str = "axis", d: float = 6.0, reach: float = 12.0):
        for key, value in (("d", d), ("reach", reach)):
            if not np.isfinite(value) or value <= 0:
                raise SearchError(f"{key} must be a positive number; got {value!r}")
        if rule not in RULES:
            raise SearchError(f"rule must be one of {RULES}; got {rule!r}")
        self.rule, self.d, self.reach = rule, float(d), float(reach)

    @property
    def tests_reach(self) -> bool:
        """Whether the rule reads where the belief within reach lies once most of it lies
        out of reach (:func:`reach_test_point`)."""
        return self.rule in ("axis", "reach")

    def start(self, space: MeshSpace, solver: GreenSolver, rng: np.random.Generator | None = None) -> None:
        """Rules on the candidate points of `space` with `solver`'s Green's functions
        (again after a re-mesh, keeping the random generator when `rng` is None)."""
        self.space, self.node_area, self.h = space, space.cell_areas, solver.h
        self._far, self._far_count = np.ones(len(space.points), dtype=bool), 0
        self._lattice = (lattice_greens(solver, max(INFO_SPACING, solver.h)) if self.rule in LATTICE_RULES
                         else None)
        if rng is not None:
            self.rng = rng

    def separated(self, read: np.ndarray) -> np.ndarray:
        """Mask of the nodes at least `d` from every point in `read` (cm), brought up to
        date with the points read since the last call only (not all of them every step)."""
        if self._far_count < len(read):
            self._far &= self.space.separated(read[self._far_count:], self.d)
            self._far_count = len(read)
        return self._far

    def choose(self, im: ImagingMap, allowed: np.ndarray, noise: float,
               near: np.ndarray | None = None) -> tuple[np.ndarray | None, bool]:
        """The next point among the `allowed` nodes for the belief `im`: ``(point cm or
        None, undecided)``. `near` (the possible sources within reach) is given when most
        of the belief lies out of reach; `noise` is a reading's (signal units).
        `undecided` says the ``"info"`` (or ``"lookahead"``) rule expects less than
        INFO_GAIN_MIN nats from its point (the caller gives up when the belief has several
        modes)."""
        if near is not None and self.tests_reach:
            nxt = reach_test_point(self.space, allowed, near, im.weights(), self.reach)
            if nxt is not None:
                return nxt, False
        if self.rule in LATTICE_RULES:
            nxt, gain = (self._info_point if self.rule == "info" else self._lookahead_point)(im, allowed, noise)
            if nxt is not None:
                return nxt, gain < INFO_GAIN_MIN
        if self.rule in ("axis",) + LATTICE_RULES:
            nxt = axis_point(self.space, im.values() * self.node_area, allowed, self.reach, self.d)
            if nxt is not None:
                return nxt, False
        score = self.score(im, allowed)  # only when the rules above did not decide
        if self.rule != "nearest":
            idx = np.flatnonzero(np.isfinite(score))
            return (None if idx.size == 0 else self.space.nodes[idx[np.argmax(score[idx])]].copy()), False
        inside = im.model()[:, -1] > im.readings[-1]                   # {v_k > I_k}
        mask = allowed & inside if (allowed & inside).any() else allowed
        return self.space.nearest_ring(im.points[-1], mask, score, self.h), False

    def score(self, im: ImagingMap, allowed: np.ndarray) -> np.ndarray:
        """Imaging mass within reach of the allowed nodes; -inf elsewhere. The imaging
        function weighted by nodal area is the density."""
        nodes = self.space.points
        w = im.values() * self.node_area
        idx = np.flatnonzero(allowed)
        out = np.full(len(nodes), -np.inf)
        if idx.size:
            out[idx] = mass_within_reach(nodes[idx], nodes, w, self.reach)
        return out

    def _predicted(self, im: ImagingMap, allowed: np.ndarray, support: int):
        """`support` belief points drawn on the lattice and their predicted readings at the
        admissible lattice points: ``(weights, candidate points cm, means)``, means of shape
        (candidates, support points) ``c_i G(y, x_i)`` by reciprocity; None when the belief
        sits in one lattice cell or no lattice point is admissible."""
        lat = self._lattice
        mass = np.bincount(lat.anchor, im.weights(), minlength=len(lat.nodes))
        anchors, w = systematic_support(mass, support, self.rng)
        cand = np.flatnonzero(allowed[lat.nodes])
        if anchors.size < 2 or cand.size == 0:
            return None
        c = im.strength_map()[lat.nodes[anchors]]
        return w, lat.points[cand], lat.columns(anchors)[cand] * c[None, :]

    def _info_point(self, im: ImagingMap, allowed: np.ndarray, noise: float) -> tuple[np.ndarray | None, float]:
        """The ``"info"`` rule: the admissible lattice point of least expected entropy and
        the expected gain (nats); ``(None, 0)`` when the belief sits in one lattice cell or
        no lattice point is admissible."""
        got = self._predicted(im, allowed, INFO_SUPPORT)
        if got is None:
            return None, 0.0
        w, pts, means = got
        if INFO_SCORE == "mi":
            gain = mutual_information(means, w, noise)
        else:
            gain = -w @ np.log(w) - expected_entropy(means, w, noise)
        best = int(np.argmax(gain))
        return pts[best].copy(), float(gain[best])

    def _lookahead_point(self, im: ImagingMap, allowed: np.ndarray, noise: float
                         ) -> tuple[np.ndarray | None, float]:
        """The ``"lookahead"`` rule: the admissible lattice point of least expected entropy
        two readings ahead and that gain (nats); ``(None, 0)`` as :meth:`_info_point`."""
        got = self._predicted(im, allowed, LOOKAHEAD_SUPPORT)
        if got is None:
            return None, 0.0
        w, pts, means = got
        order = np.argsort(expected_entropy(means, w, noise), kind="stable")
        first, second = order[:LOOKAHEAD_FIRST], order[:LOOKAHEAD_SECOND]
        gap = np.hypot(*(pts[first][:, None, :] - pts[second][None, :, :]).transpose(2, 0, 1))
        two = two_step_entropy(means[first], means[second], w, noise, apart=gap >= self.d)
        best = int(np.argmin(two))
        return pts[first[best]].copy(), float(-w @ np.log(w) - two[best])

    def params(self) -> dict:
        """The settings, as :meth:`ReciprocityStrategy.params` reports them."""
        return dict(rule=self.rule, reach=self.reach, d=self.d)
