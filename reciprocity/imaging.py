"""Probability imaging of the source position from point measurements.

For each measurement ``I_k`` taken at ``z_k`` the adjoint field ``v_k = c G(·, z_k)``
gives the imaging map ``p_k = exp(-(v_k - I_k)^2 / sigma^2)`` (eq. 7 of Landa et al.);
the maps are combined into ``P_M`` (eq. 8, their mean) or, as the Bayesian
alternative, into their normalised product (the likelihood of all measurements,
rescaled to a maximum of 1). The region of possible sources ``{P_M >= eps}`` has its
area computed exactly on the piecewise-linear interpolant of ``P_M`` over the mesh.
"""

from __future__ import annotations

import copy

import numpy as np

from arenas import as_points

from .beliefs.base import Belief, Predictive, shannon_entropy
from .errors import ReciprocityError
from .fem.green import Field, GreenSolver
from .fem.mesh import node_areas, triangle_areas

__all__ = ["ImagingMap", "superlevel_area", "COMBINATIONS"]

COMBINATIONS = ("mean", "product")
#: Log-spaced cells over which the prior ``1/c`` of an unknown strength is averaged
#: (:class:`ImagingMap`, ``strength_range``): over a factor 100, neighbouring edges 21 %
#: apart; ``1/c`` is taken at the mean of ``c`` within each cell, so the marginal agrees
#: with quadrature to within 2 % (``tests/reciprocity/test_imaging.py``).
STRENGTH_CELLS = 24


def superlevel_area(points: np.ndarray, triangles: np.ndarray, values: np.ndarray,
                    level: float, areas: np.ndarray | None = None) -> float:
    """Exact area of ``{f >= level}`` for the P1 interpolant ``f`` of nodal `values`.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Node coordinates, cm.
    triangles : ndarray, shape (m, 3)
        Triangles as node indices.
    values : ndarray, shape (n,)
        Nodal values of ``f``.
    level : float
        Threshold.
    areas : ndarray, shape (m,), optional
        Precomputed triangle areas.

    Returns
    -------
    float
        Area, cm^2. Each triangle contributes its area times the exact fraction where
        the linear interpolant is at least `level`.
    """
    area = triangle_areas(points, triangles) if areas is None else areas
    f = values[triangles] - level
    pos = f >= 0
    count = pos.sum(axis=1)
    frac = (count == 3).astype(float)
    mixed = (count == 1) | (count == 2)
    if mixed.any():
        fm, pm, cm = f[mixed], pos[mixed], count[mixed]
        # the lone vertex: the positive one when one is positive, else the negative one
        lone_is_pos = cm == 1
        lone = np.where(lone_is_pos, np.argmax(pm, axis=1), np.argmin(pm, axis=1))
        rows = np.arange(len(fm))
        fa = fm[rows, lone]
        fb = fm[rows, (lone + 1) % 3]
        fc = fm[rows, (lone + 2) % 3]
        corner = (fa / (fa - fb)) * (fa / (fa - fc))
        frac[mixed] = np.where(lone_is_pos, corner, 1.0 - corner)
    return float(np.sum(area * frac))


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
                 offset_sd: float = 0.0, model_error: float = 0.0):
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
                            model_error=self.model_error if model_error is None else model_error)
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
        """``-log`` of the likelihood integrated over the log-uniform strength prior, per
        node (up to a constant): ``Σ (c g_k - I_k)^2 / sigma^2`` is quadratic in ``c``,
        ``(A c^2 - 2 B c + C) / sigma^2``; its integral over ``[lo, hi]`` is a difference
        of normal CDFs, and the prior's ``1/c`` is averaged over the cells of a log grid."""
        from scipy.special import log_ndtr
        lo, hi = self.strength_range
        free = ~self.saturated
        g, I = self._g[:, free], self.readings[free]
        A = np.einsum("ij,ij->i", g, g)
        B = g @ I
        C = float(I @ I)
        tiny = A <= 1e-300
        Asafe = np.where(tiny, 1.0, A)
        chat = B / Asafe
        s = self.sigma / np.sqrt(2.0 * Asafe)                    # posterior std of c
        la, lb = log_ndtr((lo - chat) / s), log_ndtr((hi - chat) / s)
        with np.errstate(divide="ignore", invalid="ignore"):
            log_mass = lb + np.log1p(-np.exp(np.minimum(la - lb, 0.0)))
        log_int = np.log(s * np.sqrt(2.0 * np.pi)) + log_mass  # log ∫ exp(-A (c - chat)^2 / sigma^2)
        # E[1/c] under that truncated Gaussian, cell by cell of a log grid
        lo_g = max(lo, hi * 1e-6)
        edges = np.geomspace(lo_g, hi, STRENGTH_CELLS + 1)
        t = (edges[None, :] - chat[:, None]) / s[:, None]
        log_below, log_above = log_ndtr(t), log_ndtr(-t)
        mass = np.diff(np.exp(log_below), axis=1)
        pdf = np.exp(-0.5 * t * t) / np.sqrt(2.0 * np.pi)
        mid = np.sqrt(edges[:-1] * edges[1:])
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # 1/c at the mean of c within each cell (exact as the Gaussian narrows)
            within = chat[:, None] + s[:, None] * (pdf[:, :-1] - pdf[:, 1:]) / mass
            within = np.where(mass > 1e-12, within, mid)
            # a cell narrow against the Gaussian: its density is linear across it, and the
            # difference of densities above would cancel to round-off
            width, centre = np.diff(edges), 0.5 * (edges[:-1] + edges[1:])
            linear = centre - width ** 2 / 12.0 * (centre - chat[:, None]) / s[:, None] ** 2
            within = np.clip(np.where(np.diff(t, axis=1) < 1e-2, linear, within), edges[:-1], edges[1:])
            # the cells' shares of the mass from their logarithms: far in a tail (a node
            # whose fitted strength lies far outside the prior) the masses themselves
            # underflow, and their ratios are what counts
            la, lb = log_below[:, :-1], log_below[:, 1:]
            ua, ub = log_above[:, :-1], log_above[:, 1:]
            low = lb + np.log1p(-np.exp(np.minimum(la - lb, 0.0)))
            high = ua + np.log1p(-np.exp(np.minimum(ub - ua, 0.0)))
            log_cell = np.where(t[:, :-1] + t[:, 1:] < 0, low, high)
            top = log_cell.max(axis=1, keepdims=True)
            share = np.exp(log_cell - top)
            mean_inv = np.sum(share / within, axis=1) / share.sum(axis=1)
            # a Gaussian so wide that no cell differs from the next: the prior alone
            flat = np.log(hi / lo_g) / (hi - lo_g)
            mean_inv = np.where(np.isfinite(mean_inv) & np.isfinite(top[:, 0]), mean_inv, flat)
        misfit = (C - B * chat) / self.sigma ** 2 - log_int - np.log(mean_inv)
        del log_below, log_above
        # a node no reading sees: the likelihood does not depend on c, the prior integrates to 1
        misfit = np.where(tiny, C / self.sigma ** 2 - np.log(np.log(hi / lo_g)), misfit)
        if self.saturated.any():
            c = np.clip(chat, lo, hi)
            r = np.minimum(c[:, None] * self._g[:, self.saturated] - self.readings[self.saturated], 0.0)
            misfit = misfit + np.sum(r * r, axis=1) / self.sigma ** 2
        return np.where(np.isfinite(misfit), misfit, np.inf)

    def p_maps(self) -> np.ndarray:
        """The maps ``p_k`` of eq. (7) at every node, shape (n_nodes, M)."""
        self._require_data()
        if "p" not in self._cache:
            r = self._residuals()
            self._cache["p"] = np.exp(-r * r)
        return self._cache["p"]

    def _correlated_misfit(self, r: np.ndarray) -> np.ndarray:
        """``-log`` likelihood per node (up to a constant) of readings with independent
        variances ``d_k = s^2 + (model_error v_k)^2`` (``s = sigma/sqrt 2``) and one shared
        offset of variance ``offset_sd^2`` integrated out (Sherman-Morrison; the
        log-determinant counts, as the variances differ from node to node). `r` are the
        residuals over ``sigma`` (censoring applied)."""
        s2 = self.sigma ** 2 / 2.0
        d = s2 + (self.model_error * self.model()) ** 2              # (n_nodes, M)
        e = r * self.sigma                                           # residuals, signal units
        q = np.sum(e * e / d, axis=1)
        logdet = np.sum(np.log(d / s2), axis=1)
        if self.offset_sd > 0:
            b2 = self.offset_sd ** 2
            inv_sum = np.sum(1.0 / d, axis=1)
            q = q - b2 * np.sum(e / d, axis=1) ** 2 / (1.0 + b2 * inv_sum)
            logdet = logdet + np.log1p(b2 * inv_sum)
        return 0.5 * q + 0.5 * logdet

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
            if self.combine == "mean":
                P = self.p_maps().mean(axis=1)
                if self.allowed is not None:
                    P = np.where(self.allowed, P, 0.0)
            else:
                if self.strength_range is not None:
                    s = self._marginal_misfit()
                else:
                    r = self._residuals()
                    if self.model_error > 0 or self.offset_sd > 0:
                        s = self._correlated_misfit(r)
                    else:
                        s = np.sum(r * r, axis=1)
                if self.allowed is not None:
                    s = np.where(self.allowed, s, np.inf)
                P = np.exp(-(s - s.min()))
            self._cache["P"] = P
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
        from .models.base import GaussianNoise
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
        P = self.values()
        i = int(np.argmax(P))
        x0 = self.nodes[i]
        h = self.solver.h
        near = np.flatnonzero(np.hypot(*(self.nodes - x0).T) <= 2.5 * h)
        if near.size < 8:
            return x0.copy()
        d = (self.nodes[near] - x0) / h
        A = np.column_stack([np.ones(len(d)), d[:, 0], d[:, 1], d[:, 0] ** 2,
                             d[:, 0] * d[:, 1], d[:, 1] ** 2])
        coef = np.linalg.lstsq(A, P[near], rcond=None)[0]
        H = np.array([[2 * coef[3], coef[4]], [coef[4], 2 * coef[5]]])
        if np.all(np.linalg.eigvalsh(H) < 0):
            step = np.linalg.solve(H, -coef[1:3])
            if np.hypot(*step) <= 1.5:
                cand = x0 + h * step
                if self.solver.locate(cand[None])[0] >= 0:
                    return cand
        return x0.copy()

    def level_set(self, k: int = -1) -> list[np.ndarray]:
        """Polylines (cm) of the reciprocity level set ``{v_k = I_k}`` (eq. 5)."""
        self._require_data()
        return self._contour(self.model()[:, k], self.readings[k])

    def region_boundary(self, eps: float) -> list[np.ndarray]:
        """Polylines (cm) bounding the region ``{P_M >= eps}``."""
        return self._contour(self.values(), eps)

    def _contour(self, values: np.ndarray, level: float) -> list[np.ndarray]:
        # matplotlib's triangle contouring, on a figure that is never shown
        from matplotlib.figure import Figure
        from matplotlib.tri import Triangulation
        if not (values.min() < level < values.max()):
            return []
        tri = self.solver.triangulation if self.solver.order == 1 else Triangulation(
            self.nodes[:, 0], self.nodes[:, 1], self.triangles)
        cs = Figure().add_subplot().tricontour(tri, values, levels=[level])
        return [np.asarray(s) for s in cs.allsegs[0] if len(s) > 1]
