"""Probability imaging of the source position from point measurements.

For each measurement ``I_k`` taken at ``z_k`` the adjoint field ``v_k = c G(·, z_k)``
gives the imaging map ``p_k = exp(-(v_k - I_k)^2 / sigma^2)`` (eq. 7 of Landa et al.);
the maps are combined into ``P_M`` (eq. 8, their mean) or, as the Bayesian
alternative, into their normalised product (the likelihood of all measurements,
rescaled to a maximum of 1). The region of possible sources ``{P_M >= eps}`` has its
area computed exactly on the piecewise-linear interpolant of ``P_M`` over the mesh.

The map is composed of parts: how the maps combine (:mod:`.combiners`) and the geometry of
its superlevel sets (:mod:`.level_sets`).
"""

from __future__ import annotations

import copy

import numpy as np

from arenas import as_points

from ..errors import ReciprocityError
from ..fem.green import Field, GreenSolver
from ..fem.mesh import node_areas, triangle_areas
from .base import Belief, Predictive, shannon_entropy
from .combiners import COMBINATIONS, STRENGTH_CELLS, combiner, correlated_misfit, marginal_misfit
from .level_sets import contour, refined_maximum, superlevel_area

__all__ = ["ImagingMap", "superlevel_area", "COMBINATIONS", "STRENGTH_CELLS"]

class _Columns:
    """An (n, m) array grown one column at a time inside a buffer of doubling width:
    adding a column writes n numbers instead of copying all n × m (issue 24: an
    Algorithm-1 step on 27 000 nodes spent more time copying than back-substituting)."""

    def __init__(self, n: int):
        self._buf = np.empty((n, 8))
        self.m = 0

    @property
    def array(self) -> np.ndarray:
        """The columns so far, shape (n, m): a view to read, never to write."""
        return self._buf[:, :self.m]

    def append(self, cols: np.ndarray) -> None:
        """Add the columns of `cols`, shape (n,) or (n, k)."""
        cols = np.asarray(cols, dtype=float).reshape(len(self._buf), -1)
        end = self.m + cols.shape[1]
        if end > self._buf.shape[1]:
            buf = np.empty((len(self._buf), max(2 * self._buf.shape[1], end)))
            buf[:, :self.m] = self.array
            self._buf = buf
        self._buf[:, self.m:end] = cols
        self.m = end

    def first(self, k: int) -> "_Columns":
        """A copy holding the first `k` columns."""
        out = _Columns(len(self._buf))
        out.append(self._buf[:, :k])
        return out


class ImagingMap(Belief):
    """Cumulative probability imaging function on a :class:`GreenSolver`'s mesh: a
    :class:`~reciprocity.beliefs.Belief` over the mesh nodes.

    Parameters
    ----------
    solver : GreenSolver
        Provides the adjoint solves and the mesh (nodes, P1 triangles).
    sigma : float
        ``sigma`` of eq. (7), in signal units. With Gaussian measurement noise of
        standard deviation ``s``, ``p_k`` at the true source has mean
        ``(1 + 2 s^2/sigma^2)^(-1/2)``.
    strength : float or None
        Known source strength ``c`` (``v_k = c G(·, z_k)``). ``None`` estimates ``c``
        at every candidate point by least squares, ``c(x) = Σ g_k I_k / Σ g_k^2``
        (clamped at 0), the closed-form minimiser of ``Σ (c g_k(x) - I_k)^2``, unless
        `strength_range` is given.
    strength_range : (float, float), optional
        With ``strength=None`` and ``combine="product"``: the strength is integrated out
        over a log-uniform prior on ``[lo, hi]`` (``p(c) ∝ 1/c``, the scale-invariant
        prior, units of ``c``) instead of fitted per point. Fitting ``c`` per point lets
        a far-away point explain any small reading with ``c ≈ 0`` and any large one with
        a huge ``c``; the prior bound and the integral remove both. The likelihood is
        Gaussian in ``c``, so its integral over each of STRENGTH_CELLS log-spaced cells
        is a difference of normal CDFs, weighted by ``1/c`` at the mean of ``c`` within
        the cell. A uniform prior instead would favour points weakly coupled to every
        observation point (the integral's width grows as ``1/|g|``): on the mirror test of
        ``tests/reciprocity/test_reciprocity_rules.py`` it put both modes against the
        walls. Saturated (censored) readings are scored at each point's most probable
        ``c``. The mean combination (eq. 8) keeps the per-point fit.
    offset_sd : float
        With ``combine="product"`` and no `strength_range`: standard deviation (signal
        units) of one offset shared by every reading (a sensor calibration's error), added
        to the independent noise of ``sigma`` and integrated out in closed form (the
        readings' covariance is ``(sigma^2/2) I + offset_sd^2 11^T``). 0: none.
    model_error : float
        With ``combine="product"`` and no `strength_range`: the model's own relative error
        (the FEM field near the source, the painted floor), a fraction of the predicted
        reading added in quadrature to the noise: reading ``k`` at a candidate ``x`` has
        variance ``sigma^2/2 + (model_error v_k(x))^2``. 0: none.
    position_error : bool
        With ``combine="product"`` and no `strength_range`: a node stands for every source
        in its lumped area, not only for a source at the node, so reading ``k`` has the
        variance of ``v_k`` over that area added in quadrature, ``(rho_x |∇v_k|_x)^2``
        with ``rho_x^2`` the node's area over 6 (the mean square distance to the centre of
        a square cell of that area, cm²) and ``|∇v_k|_x`` the RMS slope of ``v_k`` around
        the node (:class:`~reciprocity.fem.gradients.NodalSlope`). It counts within a few
        cm of a reading point, where ``v_k`` is steepest, and matters where the noise is
        small. False: none.
    combine : {"mean", "product"}
        ``"mean"``: eq. (8). ``"product"``: ``Π p_k`` rescaled to maximum 1.

    Examples
    --------
    >>> import arenas, reciprocity
    >>> solver = reciprocity.GreenSolver(arenas.load("empty"), h=4.0)
    >>> u = solver.field((90.0, 60.0), strength=600.0)
    >>> im = reciprocity.ImagingMap(solver, sigma=12.0, strength=600.0)
    >>> for z in [(30.0, 30.0), (60.0, 100.0), (110.0, 30.0)]:
    ...     im.add(z, float(u([z])[0]))
    >>> bool(abs(im.estimate()[0] - 90.0) < 4.0)
    True
    """

    def __init__(self, solver: GreenSolver, sigma: float, *, strength: float | None,
                 combine: str = "mean", strength_range: tuple[float, float] | None = None,
                 offset_sd: float = 0.0, model_error: float = 0.0, position_error: bool = False):
        if not isinstance(solver, GreenSolver):
            raise ReciprocityError("solver must be a reciprocity.GreenSolver")
        if not np.isfinite(sigma) or sigma <= 0:
            raise ReciprocityError(f"sigma must be a positive number (signal units); got {sigma!r}")
        if strength is not None and (not np.isfinite(strength) or strength <= 0):
            raise ReciprocityError(f"strength must be positive, or None when unknown; got {strength!r}")
        if combine not in COMBINATIONS:
            raise ReciprocityError(f"combine must be one of {COMBINATIONS}; got {combine!r}")
        if strength_range is not None:
            lo, hi = (float(v) for v in strength_range)
            if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
                raise ReciprocityError(f"strength_range must be (lo, hi) with 0 <= lo < hi; got "
                                       f"{strength_range!r}")
            strength_range = (lo, hi)
        if not np.isfinite(offset_sd) or offset_sd < 0:
            raise ReciprocityError(f"offset_sd must be a standard deviation >= 0 (signal units); "
                                   f"got {offset_sd!r}")
        self.solver, self.sigma, self.strength, self.combine = solver, float(sigma), strength, combine
        self.offset_sd = float(offset_sd)
        if not np.isfinite(model_error) or not 0 <= model_error < 1:
            raise ReciprocityError(f"model_error must be a fraction in [0, 1); got {model_error!r}")
        self.model_error = float(model_error)
        self.position_error = bool(position_error)
        self._slope = None
        self.strength_range = strength_range if strength is None else None
        self.nodes = solver.nodes
        self.triangles = solver.triangles
        self._tri_areas = triangle_areas(self.nodes, self.triangles)
        self.points = np.empty((0, 2))
        self.readings = np.empty(0)
        self.saturated = np.empty(0, dtype=bool)
        self._columns = _Columns(len(self.nodes))
        self._clear()
        self._node_areas = None
        self.allowed: np.ndarray | None = None

    def _clear(self) -> None:
        """Forget what derives from the readings; with a known strength the columns of
        the model and of the residuals stay, as each depends on its own reading alone."""
        self._cache: dict = {}
        self._model_columns = _Columns(len(self.nodes))
        self._residual_columns = _Columns(len(self.nodes))
        self._spread_columns = _Columns(len(self.nodes))

    @property
    def _g(self) -> np.ndarray:
        """Dof values of ``G(·, z_k)``, one column per reading, shape (n_nodes, M)."""
        return self._columns.array

    @property
    def greens(self) -> np.ndarray:
        """The adjoint fields of the readings: nodal values of ``G(·, z_k)``, one column
        per reading, shape (n_nodes, M). By reciprocity column ``k`` at a node ``x`` is
        ``G(z_k, x)``, what a unit source at ``x`` reads at ``z_k``. A view: read it,
        never write it."""
        return self._columns.array

    # ------------------------------------------------------------------ data
    def add(self, z, reading: float, green: np.ndarray | None = None, *,
            saturated: bool = False) -> None:
        """Add the measurement `reading` taken at `z` (cm).

        Parameters
        ----------
        z : array_like, shape (2,)
            Observation point in the free region, cm.
        reading : float
            Measured signal ``I_k`` (signal units).
        green : ndarray, shape (n_dofs,), optional
            Precomputed dof values of ``G(·, z)``; solved for when omitted.
        saturated : bool
            The sensor was at its ceiling: the true signal is *at least* `reading`. The
            map is then censored: ``p_k = 1`` where ``v_k >= I_k``, eq. (7) below.
        """
        z = as_points(z, "observation point")[0]
        if not np.isfinite(reading):
            raise ReciprocityError(f"reading must be a finite number; got {reading!r}")
        g = self.solver.green(z).dofs if green is None else np.asarray(green, dtype=float)
        self.points = np.vstack([self.points, z])
        self.readings = np.append(self.readings, float(reading))
        self.saturated = np.append(self.saturated, bool(saturated))
        self._columns.append(g)
        self._cache.clear()
        if self.strength is None:   # the fitted strength moves every column
            self._clear()

    def on(self, solver: GreenSolver, *, model_error: float | None = None) -> "ImagingMap":
        """The same readings and parameters imaged on another `solver` (a re-meshed
        domain: the walls a strategy believes changed), each adjoint solved anew; with
        another relative `model_error` when given. A subclass stays itself, with its own
        attributes."""
        other = copy.copy(self)
        ImagingMap.__init__(other, solver, self.sigma, strength=self.strength, combine=self.combine,
                            strength_range=self.strength_range, offset_sd=self.offset_sd,
                            model_error=self.model_error if model_error is None else model_error,
                            position_error=self.position_error)
        for z, reading, sat in zip(self.points, self.readings, self.saturated):
            other.add(z, float(reading), saturated=bool(sat))
        return other

    def first(self, k: int) -> "ImagingMap":
        """A map holding only the first `k` measurements (for step-by-step figures)."""
        if not 1 <= k <= self.n:
            raise ReciprocityError(f"k must lie in 1..{self.n}; got {k!r}")
        other = copy.copy(self)
        other._clear()
        other.points, other.readings = self.points[:k].copy(), self.readings[:k].copy()
        other.saturated = self.saturated[:k].copy()
        other._columns = self._columns.first(k)
        return other

    @property
    def n(self) -> int:
        """Number of measurements."""
        return len(self.readings)

    def model(self) -> np.ndarray:
        """Predicted readings ``v_k(x)`` at every node, shape (n_nodes, M)."""
        done = self._model_columns
        if done.m < self.n:      # the new readings' columns only (all after _clear)
            done.append(self._g[:, done.m:] * self.strength_map()[:, None])
        return done.array

    def strength_map(self) -> np.ndarray:
        """Source strength at every node: the known ``c``, or its least-squares estimate."""
        if self.strength is not None:
            return np.full(len(self.nodes), float(self.strength))
        num = self._g @ self.readings
        den = np.einsum("ij,ij->i", self._g, self._g)
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(den > 0, num / den, 0.0)
        if self.strength_range is not None:
            return np.clip(c, *self.strength_range)
        return np.maximum(c, 0.0)

    def _marginal_misfit(self) -> np.ndarray:
        """:meth:`_marginal_misfit_now`, kept until the next reading."""
        if "marginal" not in self._cache:
            self._cache["marginal"] = self._marginal_misfit_now()
        return self._cache["marginal"]

    def _marginal_misfit_now(self) -> np.ndarray:
        """:func:`~reciprocity.beliefs.combiners.marginal_misfit` of the readings now."""
        return marginal_misfit(self._g, self.readings, self.saturated, self.sigma, self.strength_range)

    def p_maps(self) -> np.ndarray:
        """The maps ``p_k`` of eq. (7) at every node, shape (n_nodes, M)."""
        self._require_data()
        if "p" not in self._cache:
            r = self._residuals()
            self._cache["p"] = np.exp(-r * r)
        return self._cache["p"]

    def position_variance(self) -> np.ndarray | None:
        """``(rho_x |∇v_k|_x)^2`` at every node, shape (n_nodes, M), signal units²: the
        variance of each predicted reading over the sources a node stands for (see
        `position_error`); None without the term, and on a P2 solver (whose dofs are not
        the mesh nodes the slope is taken at)."""
        if not self.position_error or self.solver.order != 1:
            return None
        done = self._spread_columns
        if done.m < self.n:      # the new readings' columns only (all after _clear)
            if self._slope is None:     # per mesh: reset by __init__ (and so by on())
                from ..fem.gradients import nodal_slope
                self._slope = nodal_slope(self.solver)
                self._rho2 = self._slope.node_areas / 6.0
            new = self.model()[:, done.m:]
            done.append(self._rho2[:, None] * self._slope(new) ** 2)
        return done.array

    def _correlated_misfit(self, r: np.ndarray) -> np.ndarray:
        """:func:`~reciprocity.beliefs.combiners.correlated_misfit` of the residuals `r`
        over ``sigma`` (censoring applied), with this map's errors."""
        return correlated_misfit(r, self.sigma, self.model(), self.model_error, self.offset_sd,
                                 self.position_variance())

    def _residuals(self) -> np.ndarray:
        """``(v_k - I_k) / sigma`` at every node; 0 where a saturated reading is
        exceeded (a censored reading only says the signal is at least ``I_k``). A view
        of the columns kept: read it, never write it."""
        done = self._residual_columns
        if done.m < self.n:      # the new readings' columns only (all after _clear)
            new = slice(done.m, self.n)
            r = (self.model()[:, new] - self.readings[new]) / self.sigma
            saturated = self.saturated[new]
            if saturated.any():
                r[:, saturated] = np.minimum(r[:, saturated], 0.0)
            done.append(r)
        return done.array

    def values(self) -> np.ndarray:
        """The combined imaging function ``P_M`` at every node, in [0, 1]."""
        self._require_data()
        if "P" not in self._cache:
            self._cache["P"] = combiner(self.combine).values(self)
        return self._cache["P"]

    def restrict(self, allowed: np.ndarray | None) -> None:
        """Let the source lie only at the nodes where `allowed` (bool, one per node) is
        True: a prior that is zero elsewhere. None lifts it."""
        if allowed is not None:
            allowed = np.asarray(allowed, dtype=bool)
            if allowed.shape != (len(self.nodes),) or not allowed.any():
                raise ReciprocityError("allowed must be a mask over the nodes with at least one True")
        self.allowed = allowed
        self._cache.clear()

    def log_evidence_ratio(self) -> np.ndarray:
        """Per node, the log Bayes factor of "a source here" against "no source": ``log
        p(I | x) - log p(I | none)``, the strength integrated over the log-uniform prior of
        `strength_range`, the readings' noise that of eq. (7) (variance ``sigma^2/2``).

        A node no reading sees scores 0 (the readings cannot tell); a node where a source of
        any strength in the prior would have raised the readings scores below 0; a node
        that explains readings the null cannot scores above 0. Needs `strength_range`. A
        saturated reading is scored as the map scores it (a censored reading: a penalty
        only where the prediction falls short of it), under the null too.
        """
        if self.strength_range is None:
            raise ReciprocityError("log_evidence_ratio needs strength_range (the prior of the strength)")
        self._require_data()
        lo, hi = self.strength_range
        lo_g = max(lo, hi * 1e-6)
        free, short = self.readings[~self.saturated], np.maximum(self.readings[self.saturated], 0.0)
        null = float(free @ free + short @ short) / self.sigma ** 2
        return null - self._marginal_misfit() - np.log(np.log(hi / lo_g))

    # ------------------------------------------------------------------ belief protocol
    def update(self, obs) -> None:
        """Add an :class:`~reciprocity.observations.Observation` (signal or gradient
        reading; a saturated one is censored)."""
        self.add(obs.position, float(obs.value), saturated=bool(obs.saturated))

    def support(self) -> np.ndarray:
        """Candidate sources: the mesh nodes, cm."""
        return self.nodes

    def weights(self) -> np.ndarray:
        """Posterior weights: ``P_M`` times the nodal area, normalised (before any reading
        uniform over the nodes where a source may lie, :meth:`restrict`)."""
        if self._node_areas is None:
            self._node_areas = node_areas(self.nodes, self.triangles)
        if self.n:
            w = self._node_areas * self.values()
        else:                               # the prior: uniform where a source may lie
            w = self._node_areas * (1.0 if self.allowed is None else self.allowed)
        return w / w.sum()

    def entropy(self) -> float:
        """Shannon entropy (nats) of :meth:`weights`."""
        return shannon_entropy(self.weights())

    def predictive(self, candidates):
        """Predictive distribution of a reading at `candidates` (m, 2), cm.

        By reciprocity the reading at ``y`` for a source at node ``x`` has mean
        ``c(x) G(y, x) = c(x) G(x, y)``: one back-substitution per candidate. The noise
        is the Gaussian whose likelihood is eq. (7): standard deviation ``sigma / sqrt 2``.
        """
        from ..models.base import GaussianNoise
        pts = as_points(candidates, "candidates")
        g = self.solver.greens(pts)                       # (n_dofs, m)
        means = (g * self.strength_map()[:, None]).T      # (m, n)
        return Predictive(self.weights(), means, GaussianNoise(self.sigma / np.sqrt(2.0)))

    def __call__(self, points) -> np.ndarray:
        """``P_M`` interpolated at `points` (n, 2), cm; NaN outside the free region."""
        return Field(self.solver, self.values(), "P")(points)

    def _require_data(self) -> None:
        if self.n == 0:
            raise ReciprocityError("no measurements yet: call add(z, reading) first")

    # ------------------------------------------------------------------ geometry
    def area(self, eps: float) -> float:
        """Area (cm^2) of the region of possible sources ``{P_M >= eps}``."""
        if not 0 < eps < 1:
            raise ReciprocityError(f"eps must lie strictly between 0 and 1; got {eps!r}")
        return superlevel_area(self.nodes, self.triangles, self.values(), eps, self._tri_areas)

    def estimate(self) -> np.ndarray:
        """Source estimate (cm): the maximiser of ``P_M``, refined below the mesh size.

        The node maximising ``P_M`` is refined by the vertex of a least-squares quadratic
        fitted to the nodes within ``2.5 h``, when that quadratic is concave and its
        vertex stays within ``1.5 h`` of the node.
        """
        return refined_maximum(self.solver, self.values())

    def level_set(self, k: int = -1) -> list[np.ndarray]:
        """Polylines (cm) of the reciprocity level set ``{v_k = I_k}`` (eq. 5)."""
        self._require_data()
        return contour(self.solver, self.model()[:, k], self.readings[k])

    def region_boundary(self, eps: float) -> list[np.ndarray]:
        """Polylines (cm) bounding the region ``{P_M >= eps}``."""
        return contour(self.solver, self.values(), eps)
