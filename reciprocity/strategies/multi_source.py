"""Several sources, their number unknown: find one, explain it, subtract it, look again.

The Poisson equation is linear, so the readings of ``K`` sources are the sum of their
fields: ``I_k = Σ_j c_j G(z_k, S_j) + noise``. :class:`SourceBook` keeps every reading
and the sources found so far; the reciprocity search (:class:`~reciprocity.strategies.
reciprocity.ReciprocityStrategy`) images each new source on the *residual* readings,
``r_k = I_k - Σ_found ĉ_j G(z_k, Ŝ_j)``, where by reciprocity ``G(z_k, Ŝ_j)`` is the
adjoint field of reading ``k`` read at ``Ŝ_j`` (no extra solve).

**The number of sources** is decided by a Bayes factor, the model-selection stop:

- the residual map of a further source has the strength integrated over the prior
  ``EXTRA_STRENGTH`` times the nominal strength, so each node ``x`` has the log Bayes
  factor ``B(x)`` of "one more source at x" against "no more"
  (:meth:`~reciprocity.beliefs.imaging.ImagingMap.log_evidence_ratio`);
- ``max B >= LOG_DETECT`` (odds of 100 to 1, "decisive" on Jeffreys' scale; with
  Gaussian noise, about BIC's penalty of 3 parameters at 20 readings) is evidence of a
  further source: the search images it as it imaged the first, and accepts it when its
  region converges;
- otherwise the search surveys where a further source could still be: with even prior
  odds of one more source, spread uniformly over the nodes within reach of the observer,
  at least ``WALL_MARGIN`` from the walls and MIN_SEPARATION from the sources found, its
  posterior odds are the area-weighted mean of ``exp B(x)``
  (:meth:`SourceBook.more_probability`). The next point maximises that posterior
  density within reach, and the search stops with the sources found once the
  probability of one more falls below the strategy's ``more_tol``.

**Confirmed sources.** A source's region may converge early on readings that a second,
not yet found, source distorts. Before the search stops, each source found is imaged
again on the readings less the others' fields, within CONFIRM_RADIUS of its estimate;
one whose region has not converged there is located again (the search measures around it
as it did the first time) and its estimate replaced.

**Explained readings.** Once two sources are found, after each reading and each new or
confirmed source, the found sources are settled together (:meth:`SourceBook.settle`):

- a source whose map, on the readings less the others' fields over the whole region, peaks
  more than REFINE_RADIUS away, where the readings' χ² falls by at least ``2 LOG_DETECT``,
  moves there and is confirmed again: its region converged on readings that a source not
  yet found distorted;
- each position is re-imaged on the readings less the others' fields (within REFINE_RADIUS
  of where its region converged) and the strengths refitted by non-negative least squares,
  in turn, until no estimate moves SETTLE_TOL (at most SETTLE_ROUNDS rounds);
- a source that explains no reading is dropped: one whose removal raises the χ² by less
  than ``2 LOG_DETECT``, the likelihood ratio a further source needs at the least.

One source alone is not settled: on readings that a second, not yet found, source also
explains, it would drift toward that one. The χ² weighs each reading as the residual maps
do: the found sources' predicted readings carry a relative error RESIDUAL_ERROR, added in
quadrature to the noise (a found source misplaced by 1 cm leaves residuals of about a tenth
of its reading 5 cm away, which would otherwise look like a second source beside it). A
further source is sought at least MIN_SEPARATION from those found.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.imaging import ImagingMap

__all__ = ["SourceBook", "RESIDUAL_ERROR", "LOG_DETECT", "EXTRA_STRENGTH",
           "MIN_SEPARATION", "WALL_MARGIN", "REFINE_RADIUS", "CONFIRM_RADIUS", "SETTLE_TOL",
           "SETTLE_ROUNDS", "spread_of"]

#: Relative error of a found source's predicted reading (see the module doc).
RESIDUAL_ERROR = 0.15
#: Log Bayes factor of a further source that counts as evidence of one (log 100).
LOG_DETECT = float(np.log(100.0))
#: The prior of a further source's strength: log-uniform on these multiples of the
#: nominal strength. Weaker sources may go unnoticed; the issue's aim is stated for
#: sources of the nominal strength.
EXTRA_STRENGTH = (0.5, 2.0)
#: A further source is sought at least this far (cm) from every source found.
MIN_SEPARATION = 20.0
#: The hidden region counts nodes at least this far (cm) from the walls: next to a
#: Dirichlet wall a source's field vanishes, and no reading could ever exclude it there.
WALL_MARGIN = 3.0
#: Radius (cm) around a found source within which its position is refined.
REFINE_RADIUS = 8.0
#: Radius (cm) around a found source within which it is confirmed.
CONFIRM_RADIUS = 15.0
#: Settling the found sources stops when no estimate moves more than this (cm) in a round.
SETTLE_TOL = 0.05
#: At most this many rounds of settling.
SETTLE_ROUNDS = 8


class SourceBook:
    """The readings and the sources found so far, and the residual maps of the search.

    Parameters
    ----------
    raw : ImagingMap
        The strategy's own map of every reading (its settings image the first source;
        its adjoint columns serve every residual map).
    strength : float
        The nominal strength of one source (signal units × cm², as the arena's).
    max_sources : int
        The task's bound on the number of sources.
    wall_distance : ndarray, shape (n_nodes,)
        Each node's distance to the nearest wall, cm.
    """

    def __init__(self, raw: ImagingMap, strength: float, max_sources: int, wall_distance: np.ndarray):
        self.raw = raw
        self.nominal = float(strength)
        self.max_sources = int(max_sources)
        self.inner = np.asarray(wall_distance) >= WALL_MARGIN
        self.found: list[np.ndarray] = []
        self.anchors: list[np.ndarray] = []     # where each found source's region converged
        self.strengths = np.empty(0)
        self.spread: list[float] = []
        self.located = False        # the active map holds evidence of a further source
        self.confirming: int | None = None   # the found source being located again
        self.confirmed: set[int] = set()
        self.dropped = 0            # found sources dropped by :meth:`settle` (explaining no reading)
        self.relocated = 0          # found sources moved by :meth:`settle` beyond their region
        self._active = raw
        self._prior = raw         # the residual map under the strength prior (the Bayes factor's)

    # ------------------------------------------------------------------ the maps
    @property
    def active(self) -> ImagingMap:
        """The map the search steers by: the raw map until a source is found, then the
        residual map of a further source."""
        return self._active

    @property
    def full(self) -> bool:
        """As many sources found as the task allows."""
        return len(self.found) >= self.max_sources

    @property
    def surveying(self) -> bool:
        """Looking for evidence of a further source (none yet)."""
        return bool(self.found) and not self.located and self.confirming is None

    def add(self, obs) -> ImagingMap:
        """Add a reading (an Observation) and return the active map brought up to date:
        the found sources settled on every reading (unless one is being located again)."""
        self.raw.update(obs)
        if len(self.found) > 1 and self.confirming is None:
            self.settle()
        return self._refresh()

    def _refresh(self) -> ImagingMap:
        """Rebuild the active map from the readings and the sources found."""
        if self.found:
            self._prior = self.residual_map(exclude_near=self.found)
            self.located = not self.full and bool(self._evidence() >= LOG_DETECT)
        if self.confirming is not None:
            self._active = self.confirm_map(self.confirming)
        elif self.found:
            # evidence of one more: located with the first source's own model
            self._active = self.residual_map(exclude_near=self.found, own=True) if self.located else self._prior
        else:
            self._active = self.raw
        return self._active

    def rebase(self, raw: ImagingMap, wall_distance: np.ndarray) -> ImagingMap:
        """The same readings on another mesh (the believed walls changed, ``map:
        unknown``): `raw` holds them imaged there, `wall_distance` is its nodes' distance
        to the believed walls. The found sources stay; the active map is rebuilt."""
        self.raw = raw
        self.inner = np.asarray(wall_distance) >= WALL_MARGIN
        return self._refresh()

    def confirm_map(self, j: int) -> ImagingMap:
        """The map of found source `j` on the readings less the others' fields, within
        CONFIRM_RADIUS of its estimate."""
        others = [s for i, s in enumerate(self.found) if i != j]
        return self.residual_map(skip=j, exclude_near=others, within=(self.found[j], CONFIRM_RADIUS))

    def next_unconfirmed(self, converged) -> int | None:
        """The first found source whose :meth:`confirm_map` has not converged
        (``converged(map) -> bool``); the search then locates it again (it becomes the
        active map). None when every source is confirmed."""
        for j in range(len(self.found)):
            if j in self.confirmed:
                continue
            im = self.confirm_map(j)
            self.confirmed.add(j)
            if not converged(im):
                self.confirming, self._active = j, im
                return j
        return None

    def couplings(self, sources) -> np.ndarray:
        """``G(z_k, S_j)`` for every reading ``k`` and source ``j``, shape (m, J): each
        reading's adjoint field read at the sources (reciprocity)."""
        pts = np.asarray(sources, dtype=float).reshape(-1, 2)
        probe, _ = self.raw.solver.probe_matrix(pts)
        return np.asarray((probe @ self.raw.greens).T)

    def predicted(self, skip: int | None = None) -> np.ndarray:
        """The readings the found sources predict (all but number `skip`), shape (m,)."""
        keep = [j for j in range(len(self.found)) if j != skip]
        if not keep:
            return np.zeros(self.raw.n)
        return self.couplings([self.found[j] for j in keep]) @ self.strengths[keep]

    def residual_map(self, *, skip: int | None = None, exclude_near=(), within=None, own: bool = False) -> ImagingMap:
        """A map of one further source on the readings less the found sources' fields.

        Parameters
        ----------
        skip : int, optional
            Leave this found source in the readings (to re-image it).
        exclude_near : sequence of points
            No source within MIN_SEPARATION of these (cm).
        within : (point, radius), optional
            The source lies within `radius` cm of `point`.
        own : bool
            Image with the first source's own model (the raw map's strength, known or
            not, and its calibrated errors) instead of the prior EXTRA_STRENGTH (which the
            Bayes factor needs): locating a further source is then as accurate as
            locating the first. Confirmation keeps the prior: a strength the model does
            not take as known asks for readings a known one would skip.
        """
        raw = self.raw
        lo, hi = EXTRA_STRENGTH
        if own:
            plain = raw.strength_range is None
            im = ImagingMap(raw.solver, raw.sigma, strength=raw.strength, combine="product",
                            strength_range=raw.strength_range, offset_sd=raw.offset_sd if plain else 0.0,
                            model_error=raw.model_error if plain else 0.0)
        else:
            im = ImagingMap(raw.solver, raw.sigma, strength=None, combine="product",
                            strength_range=(lo * self.nominal, hi * self.nominal))
        pred = self.predicted(skip)
        noise = raw.sigma / np.sqrt(2.0)
        w = noise / np.sqrt(noise ** 2 + (RESIDUAL_ERROR * pred) ** 2)
        g = raw.greens
        for k in range(raw.n):
            # whitened: (c g_k - r_k)^2 / var_k = (c w_k g_k - w_k r_k)^2 / noise^2; a
            # saturated reading stays censored (the residual is at least this)
            im.add(raw.points[k], w[k] * (raw.readings[k] - pred[k]), green=w[k] * g[:, k],
                   saturated=bool(raw.saturated[k]))
        if not im.n:
            return raw
        nodes = raw.nodes
        # the raw map's own prior (e.g. the task's source clearance) holds for every source
        allowed = np.ones(len(nodes), dtype=bool) if raw.allowed is None else raw.allowed.copy()
        for s in exclude_near:
            allowed &= np.hypot(*(nodes - s).T) >= MIN_SEPARATION
        if within is not None:
            allowed &= np.hypot(*(nodes - within[0]).T) <= within[1]
        if allowed.any():
            im.restrict(allowed)
        return im

    def _evidence(self) -> float:
        """The largest log Bayes factor of a further source over the allowed nodes."""
        im = self._prior
        if im is self.raw:
            return np.inf
        b = im.log_evidence_ratio()
        ok = self.inner if im.allowed is None else im.allowed & self.inner
        return float(b[ok].max()) if ok.any() else -np.inf

    def hidden(self, near: np.ndarray, areas: np.ndarray, unseen: np.ndarray | None = None) -> np.ndarray:
        """Per node, the posterior mass of "one more source here" (up to the prior odds):
        nodal area times ``exp B``, over the nodes within reach (`near`), away from the
        walls and from the sources found; 0 elsewhere. Where `unseen` (an unknown map's
        nodes not yet seen) no reading excludes a source (``B`` at least 0): a wall there
        that the model does not know could hide it."""
        im = self._prior
        support = near & self.inner
        if im.allowed is not None:
            support &= im.allowed
        b = np.minimum(im.log_evidence_ratio(), 50.0)
        if unseen is not None:
            b = np.where(unseen, np.maximum(b, 0.0), b)
        return np.where(support, areas * np.exp(b), 0.0)

    def more_probability(self, near: np.ndarray, areas: np.ndarray, unseen: np.ndarray | None = None) -> float:
        """The posterior probability of one more source, from even prior odds spread
        uniformly over the support of :meth:`hidden` (0 when that support is empty)."""
        im = self._prior
        support = near & self.inner
        if im.allowed is not None:
            support &= im.allowed
        prior = float(np.sum(areas[support]))
        if prior <= 0:
            return 0.0
        odds = float(np.sum(self.hidden(near, areas, unseen))) / prior
        return odds / (1.0 + odds)

    # ------------------------------------------------------------------ accepting sources
    def accept(self, estimate: np.ndarray, spread: float) -> None:
        """A source's region converged at `estimate` (cm): keep it, refit the strengths,
        re-image every found source on the readings less the others, and look again."""
        if self.confirming is not None:
            self.found[self.confirming] = np.asarray(estimate, dtype=float).copy()
            self.anchors[self.confirming] = self.found[self.confirming].copy()
            self.spread[self.confirming] = float(spread)
            self.confirming = None
            self._fit_strengths()
            if len(self.found) > 1:
                self.settle()
            self._refresh()
            return
        self.found.append(np.asarray(estimate, dtype=float).copy())
        self.anchors.append(self.found[-1].copy())
        self.spread.append(float(spread))
        self.confirmed.clear()
        self._fit_strengths()
        if len(self.found) > 1:
            self.settle()
        self._refresh()

    def settle(self) -> int:
        """Settle the found sources on every reading: move those the readings place
        elsewhere (:meth:`_relocate`), re-image each in turn on the
        readings less the others' fields (within REFINE_RADIUS of where its region
        converged) and refit
        the strengths, until no estimate moves SETTLE_TOL cm (at most SETTLE_ROUNDS
        rounds); then drop the sources that explain no reading (:meth:`_prune`).

        Returns
        -------
        int
            The number of sources dropped.
        """
        self._relocate()
        for _ in range(SETTLE_ROUNDS):
            moved = 0.0
            for j in range(len(self.found)):
                others = [s for i, s in enumerate(self.found) if i != j]
                im = self.residual_map(skip=j, exclude_near=others, within=(self.anchors[j], REFINE_RADIUS), own=True)
                new = im.estimate()
                moved = max(moved, float(np.hypot(*(new - self.found[j]))))
                self.found[j] = new
                self.spread[j] = spread_of(im)
            self._fit_strengths()
            if moved <= SETTLE_TOL:
                break
        return self._prune()

    def _relocate(self) -> int:
        """Move each found source whose map on the readings less the others' fields, over
        the whole region, peaks more than REFINE_RADIUS away, where the readings' χ² falls
        by at least ``2 LOG_DETECT``: its region converged where a source not yet found
        distorted the readings. It is then no longer confirmed (the search goes to measure
        it there before it stops). Returns how many moved."""
        moved = 0
        for j in range(len(self.found)):
            others = [s for i, s in enumerate(self.found) if i != j]
            candidate = self.residual_map(skip=j, exclude_near=others, own=True).estimate()
            if np.hypot(*(candidate - self.found[j])) <= REFINE_RADIUS:
                continue
            if self.chi2(self.found) - self.chi2(others + [candidate]) >= 2.0 * LOG_DETECT:
                self.found[j], self.anchors[j] = candidate, candidate.copy()
                self.confirmed.discard(j)
                self.relocated += 1
                moved += 1
        if moved:
            self._fit_strengths()
        return moved

    def chi2(self, sources) -> float:
        """The readings' χ² under `sources` (their strengths refitted by non-negative
        least squares), each reading weighted as the residual maps weight it: the noise
        and RESIDUAL_ERROR of the predicted reading in quadrature. Saturated readings are
        left out."""
        from scipy.optimize import nnls
        free = ~self.raw.saturated
        y = self.raw.readings[free]
        if len(sources):
            a = self.couplings(sources)[free]
            c, _ = nnls(a, y)
            pred = a @ np.maximum(c, 0.0)
        else:
            pred = np.zeros_like(y)
        noise = self.raw.sigma / np.sqrt(2.0)
        return float(np.sum((y - pred) ** 2 / (noise ** 2 + (RESIDUAL_ERROR * pred) ** 2)))

    def _prune(self) -> int:
        """Drop, weakest first, each found source whose removal raises :meth:`chi2` by
        less than ``2 LOG_DETECT``; one source is always kept."""
        dropped = 0
        while len(self.found) > 1:
            base = self.chi2(self.found)
            rise = [self.chi2([s for i, s in enumerate(self.found) if i != j]) - base
                    for j in range(len(self.found))]
            j = int(np.argmin(rise))
            if rise[j] >= 2.0 * LOG_DETECT:
                break
            del self.found[j], self.anchors[j], self.spread[j]
            self.confirmed.clear()
            dropped += 1
            self._fit_strengths()
        self.dropped += dropped
        return dropped

    def _fit_strengths(self) -> None:
        """Non-negative least squares of the readings on the found sources' fields (the
        saturated readings left out), each strength at least a tenth of the nominal."""
        from scipy.optimize import nnls
        free = ~self.raw.saturated
        a = self.couplings(self.found)[free]
        c, _ = nnls(a, self.raw.readings[free])
        self.strengths = np.maximum(c, 0.1 * self.nominal)


def spread_of(im: ImagingMap) -> float:
    """The standard deviation (cm) of a map's belief about its source's position: the
    root of the trace of its weighted covariance."""
    w = im.weights()
    x = im.nodes
    mean = w @ x
    return float(np.sqrt(np.sum(w * np.sum((x - mean) ** 2, axis=1))))
