"""When the reciprocity search stops: step 12 of Algorithm 1 and the stops beside it.

:class:`StopRule` is step 12 and its refinements. The search converges when the region
of possible sources ``{P_M >= eps}`` is not empty and has area below ``area_tol``, and,
unless ``extent_tol = inf``, also lies within ``extent_tol`` of the estimate; unless
``tail_tol = inf``, every node with ``P_M >=`` :data:`TAIL_EPS` lies within ``tail_tol`` of
it (no second mode is left, even an unlikely one); and, unless ``credible_radius = inf``,
the belief holds at least ``credible_mass`` within ``credible_radius`` of the estimate (a
second mode just beyond the extent, which the area counts but cannot weigh, is not left
behind). The paper's loop condition (``while 0 <= A < A_eps``) is read as "until
``A < A_eps``"; an empty region (eq. (8)'s mean below ``eps`` everywhere) is not a found
source.

The search also stops at its step cap (``max_steps`` readings), saying how many modes
(:meth:`StopRule.modes`: connected parts of the region holding at least
:data:`MODE_MASS` of the belief) it could not separate, and with ``unreachable``
(:func:`out_of_reach`) when nothing can be measured, when the whole region lies out of
reach, or, from the second reading on, when the belief holds less than
:data:`UNREACH_MASS` within reach (a source behind a gap narrower than the car: the region
stays wide, because readings through the gap are weak, but the readings the car can take
rule out every source it could reach).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...beliefs.base import credible_mass
from ...beliefs.imaging import ImagingMap
from ...errors import SearchError

__all__ = ["StopRule", "out_of_reach", "likely_out_of_reach", "TAIL_EPS", "MODE_MASS", "UNREACH_MASS",
           "UNREACH_MIN_READINGS", "TEST_REACH_ABOVE", "MAX_STEPS", "MAX_STEPS_SEVERAL"]

#: Relative likelihood of the tail checked by `tail_tol` (a Gaussian belief puts 99 %
#: of its mass above it).
TAIL_EPS = 0.01
#: A connected part of ``{P_M >= eps}`` holding at least this share of the belief is a
#: mode (reported when the search stops without separating two).
MODE_MASS = 0.05
#: Stop with ``StopReason.UNREACHABLE`` once the belief puts less than this mass within
#: reach: the source is out of reach with 95 % probability. Measured on the car in
#: ``benchmarks/car_search.md``.
UNREACH_MASS = 0.05
#: Readings before the mass rule above applies (the first reading alone leaves a band).
UNREACH_MIN_READINGS = 2
#: Once the belief puts more than this mass out of reach (from the second reading on),
#: rules ``"axis"`` and ``"reach"`` read where most of the belief within reach lies, to
#: find the source there or rule it out (the ``unreachable`` stop then comes sooner).
TEST_REACH_ABOVE = 0.5
#: Default ``max_steps``: readings of a search for one source, and for several.
MAX_STEPS = 30
MAX_STEPS_SEVERAL = 60


class StopRule:
    """Step 12 with the extent, tail and credible rules, and the step cap.

    Parameters
    ----------
    eps : float
        Threshold ``0 < eps < 1`` defining the region of possible sources.
    area_tol : float
        ``A_eps``, cm^2: converged when the region is smaller.
    extent_tol, tail_tol, credible_radius : float
        Largest distance (cm) from the estimate to the region, and to a node with
        ``P_M >= TAIL_EPS``; the radius of the credible rule. ``inf`` for none.
    credible_mass : float
        Share of the belief (0 to 1) the credible rule asks for within `credible_radius`.
    max_steps : int, optional
        The step cap in readings; None for :data:`MAX_STEPS`, or :data:`MAX_STEPS_SEVERAL`
        when the search looks for several sources (:meth:`cap`).
    """

    def __init__(self, *, eps: float, area_tol: float, extent_tol: float, tail_tol: float,
                 credible_radius: float, credible_mass: float, max_steps: int | None = None):
        if not 0 < eps < 1:
            raise SearchError(f"eps must lie strictly between 0 and 1; got {eps!r}")
        if not np.isfinite(area_tol) or area_tol <= 0:
            raise SearchError(f"area_tol must be a positive number; got {area_tol!r}")
        if not 0 < credible_mass < 1:
            raise SearchError(f"credible_mass must lie strictly between 0 and 1; got {credible_mass!r}")
        for key, value in (("extent_tol", extent_tol), ("tail_tol", tail_tol), ("credible_radius", credible_radius)):
            if not (value > 0):
                raise SearchError(f"{key} must be a positive length in cm, or inf for none; got {value!r}")
        if max_steps is not None and (isinstance(max_steps, bool) or int(max_steps) != max_steps
                                      or int(max_steps) < 1):
            raise SearchError(f"max_steps must be a whole number >= 1; got {max_steps!r}")
        self.eps, self.area_tol, self.extent_tol = float(eps), float(area_tol), float(extent_tol)
        self.tail_tol = float(tail_tol)
        self.credible_radius, self.credible_mass = float(credible_radius), float(credible_mass)
        self.max_steps_given = None if max_steps is None else int(max_steps)

    def cap(self, several: bool) -> int:
        """The step cap: `max_steps`, else the default for one source or for several."""
        return self.max_steps_given or (MAX_STEPS_SEVERAL if several else MAX_STEPS)

    def region(self, im: ImagingMap) -> np.ndarray:
        """Mask of the nodes in ``{P_M >= eps}`` (every node before the first reading)."""
        if not im.n:
            return np.ones(len(im.nodes), dtype=bool)
        return im.values() >= self.eps

    def judge(self, im: ImagingMap) -> tuple[np.ndarray, float, float, bool]:
        """Step 12 for map `im`: ``(estimate cm, area cm², extent cm, converged)``, the
        extent the largest distance from the estimate to the region."""
        area = im.area(self.eps)
        estimate = im.estimate()
        region = im.nodes[self.region(im)]
        extent = float(np.hypot(*(region - estimate).T).max()) if len(region) else 0.0
        converged = len(region) > 0 and area < self.area_tol and extent <= self.extent_tol \
            and self.tail_within(estimate, im)
        return estimate, area, extent, converged

    def converged(self, im: ImagingMap) -> bool:
        """Whether map `im` meets step 12 (:meth:`judge`)."""
        return self.judge(im)[3]

    def tail_within(self, estimate: np.ndarray, im: ImagingMap) -> bool:
        """Whether the belief of `im` holds at least `credible_mass` within `credible_radius`
        of `estimate` (the credible rule) and every node with ``P_M >= TAIL_EPS`` lies
        within `tail_tol` of it (the tail rule)."""
        if np.isfinite(self.credible_radius):
            if credible_mass(im.nodes, im.weights(), estimate, self.credible_radius) < self.credible_mass:
                return False
        if not np.isfinite(self.tail_tol):
            return True
        tail = im.nodes[im.values() >= TAIL_EPS]
        return bool(np.all(np.sum((tail - estimate) ** 2, axis=1) <= self.tail_tol ** 2))

    def modes(self, im: ImagingMap, triangles: np.ndarray) -> list[tuple[float, np.ndarray]]:
        """The connected parts of ``{P_M >= eps}`` (over the mesh's `triangles`) holding at
        least MODE_MASS of the belief: ``(mass, peak cm)`` (the peak: the part's node of
        largest ``P_M``), heaviest first."""
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components
        inside = self.region(im)
        tri = triangles[inside[triangles].all(axis=1)]
        n = len(inside)
        i, j = np.concatenate([tri[:, 0], tri[:, 1]]), np.concatenate([tri[:, 1], tri[:, 2]])
        _, label = connected_components(coo_matrix((np.ones(i.size), (i, j)), shape=(n, n)),
                                        directed=False)
        w, P = im.weights(), im.values()
        out = []
        for lab in np.unique(label[inside]):
            part = np.flatnonzero(inside & (label == lab))
            mass = float(w[part].sum())
            if mass >= MODE_MASS:
                out.append((mass, im.nodes[part[np.argmax(P[part])]].copy()))
        return sorted(out, key=lambda m: -m[0])

    def modes_note(self, im: ImagingMap, triangles: np.ndarray) -> str:
        """``"; N modes, the two largest D cm apart"`` when the belief has several modes."""
        modes = self.modes(im, triangles)
        if len(modes) < 2:
            return ""
        gap = float(np.hypot(*(modes[0][1] - modes[1][1])))
        return f"; {len(modes)} modes, the two largest {gap:.0f} cm apart"

    def params(self) -> dict:
        """The settings, as :meth:`ReciprocityStrategy.params` reports them."""
        return dict(eps=self.eps, area_tol=self.area_tol, extent_tol=self.extent_tol, tail_tol=self.tail_tol,
                    credible_radius=self.credible_radius, credible_mass=self.credible_mass)


def out_of_reach(im: ImagingMap, region: np.ndarray, near_of: Callable[[], np.ndarray], reachable: np.ndarray,
                 node_area: np.ndarray, reach: float) -> tuple[str | None, dict]:
    """The ``unreachable`` stop: ``(why, notes)``, `why` None when the search goes on.

    Parameters
    ----------
    im : ImagingMap
        The belief.
    region : ndarray of bool
        The region of possible sources (:meth:`StopRule.region`).
    near_of : callable
        Returns the mask of the nodes within reach
        (:meth:`~.reachability.Reachability.near`); called once something is reachable.
    reachable : ndarray of bool
        The nodes the observer may read at.
    node_area : ndarray
        Each node's area, cm².
    reach : float
        Sensing reach, cm (for the message).

    Returns
    -------
    why : str or None
        The stop's detail.
    notes : dict
        ``mass_out_of_reach`` and ``reachable_area`` (cm²) once a reading was taken.
    """
    if not reachable.any():
        return "no observation point is reachable", {}
    near = near_of()
    if region.any() and not (region & near).any():     # an empty region tells nothing
        return f"the whole region of possible sources ({region.sum()} nodes) lies out of reach", {}
    if not im.n:
        return None, {}
    w = im.weights()
    within = float(w[near].sum() / w.sum())
    notes = dict(mass_out_of_reach=round(max(0.0, 1.0 - within), 4),
                 reachable_area=round(float(node_area[reachable].sum()), 1))
    if im.n >= UNREACH_MIN_READINGS and within < UNREACH_MASS:
        return (f"the source lies out of reach with probability {1.0 - within:.3f} (belief mass within "
                f"{reach:g} cm of a reachable point and seen from it: {within:.3f}; reachable part "
                f"{notes['reachable_area']:.0f} cm²)"), notes
    return None, notes


def likely_out_of_reach(im: ImagingMap, notes: dict) -> bool:
    """From the second reading on, the belief puts more than TEST_REACH_ABOVE of its mass
    out of reach (``notes["mass_out_of_reach"]``, set by :func:`out_of_reach`)."""
    return im.n >= UNREACH_MIN_READINGS and notes.get("mass_out_of_reach", 0.0) > TEST_REACH_ABOVE
