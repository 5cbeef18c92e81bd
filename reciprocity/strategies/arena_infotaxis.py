"""Cross-run: infotaxis on the Poisson arena, with the FEM likelihood (issue 12, beyond the papers).

The plume searchers of :mod:`reciprocity.strategies.infotaxis` move one step at a time
and choose the step whose reading is expected to leave the least entropy. Here the same
rule searches the ``poisson`` arenas (walls, a steady source, Gaussian readings), so that
it meets the reciprocity search on its home ground:

- **belief**: a grid posterior over the nodes of the lattice of
  :func:`reciprocity.strategies.information.lattice_nodes` (``spacing`` cm, every node in
  the free region), uniform prior;
- **likelihood**: a reading ``z`` at lattice node ``y`` has mean ``c G(y, x)`` for a source
  at ``x``, with ``G`` the FEM Green's function of the strategy's own mesh, and Gaussian
  noise of standard deviation ``sigma`` (``"auto"``: ``√2`` times the stated reading noise,
  the reciprocity search's own default, which leaves room for the mesh's model error).
  By reciprocity ``G(y, x) = G(x, y)``, so one adjoint solve per *place read* gives the
  predicted reading there for every candidate source: the columns of
  :class:`~reciprocity.strategies.information.LatticeGreens`, shared with ``rule="info"``;
- **moves**: to any lattice node within ``step`` cm (straight-line distance; the point
  platform walks the free path), the one of least expected posterior entropy. The
  expectation is over the predictive mixture, by Gauss-Hermite quadrature (3 nodes)
  around the predicted readings of ``support`` points drawn from the belief, and each
  expected posterior is the full lattice posterior (not the reduced support);
- **stop**: the arena worlds do not end a search when the observer reaches the source
  (success is a converged estimate within the success radius), so infotaxis' own end,
  stepping onto the source, is replaced by a confidence test: CONVERGED once a share
  ``confidence`` of the posterior lies within ``radius`` cm of its mean (the estimate).
  This stop is ours; the papers of the infotaxis family stop on contact.

Costs are counted as for the home strategy: ``n_measurements`` (one reading per step) and
the path walked.

Measured against the reciprocity search on ``paper`` (readings, path, success):
``benchmarks/plume_beyond.md``, section 2.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.base import gaussian_expected_entropy
from ..errors import SearchError
from ..validation import positive
from ..intents import Measure
from ..outcome import StopReason
from ..models.green import cached_solver
from . import register
from .base import SearchContext, Status, Strategy
from .information import lattice_greens, systematic_support

__all__ = ["ArenaInfotaxis", "gaussian_expected_entropy"]

#: Smallest reading noise (signal units), as the reciprocity search's MIN_NOISE.
MIN_NOISE = 1.0


@register
class ArenaInfotaxis(Strategy):
    """Infotaxis on the Poisson arena with the FEM likelihood (cross-run; see the module doc).

    Parameters
    ----------
    step : float
        Largest move between readings (cm, straight line).
    spacing : float
        Lattice spacing of the belief and of the places read (cm).
    support : int
        Belief points drawn per decision for the predictive mixture.
    confidence : float
        Posterior share within `radius` of the estimate that stops the search, in (0, 1).
    radius : float
        Radius of the confidence test (cm).
    sigma : float or "auto"
        Reading noise of the likelihood (signal units); "auto": √2 × the stated noise.
    h : float
        Mesh size of the strategy's FEM model (cm).
    max_steps : int
        Readings before the search stops at its cap.
    """

    name = "arena-infotaxis"
    worlds = ("poisson",)
    agents = 1

    def __init__(self, *, step: float = 5.0, spacing: float = 2.5, support: int = 24, confidence: float = 0.9,
                 radius: float = 5.0, sigma="auto", h: float = 1.0, max_steps: int = 150):
        self.step = positive(step, "step")
        self.spacing = positive(spacing, "spacing")
        if isinstance(support, bool) or not isinstance(support, int) or support < 1:
            raise SearchError(f"support must be a positive whole number; got {support!r}")
        self.support = support
        self.confidence = positive(confidence, "confidence")
        if self.confidence >= 1:
            raise SearchError(f"confidence must lie in (0, 1); got {confidence!r}")
        self.radius = positive(radius, "radius")
        self.sigma = sigma if sigma == "auto" else positive(sigma, "sigma")
        self.h = positive(h, "h")
        if isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1:
            raise SearchError(f"max_steps must be a positive whole number; got {max_steps!r}")
        self.max_steps = max_steps
        super().__init__()

    def params(self) -> dict:
        return dict(step=self.step, spacing=self.spacing, support=self.support, confidence=self.confidence,
                    radius=self.radius, sigma=self.sigma, h=self.h, max_steps=self.max_steps)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        if ctx.world not in self.worlds:
            raise SearchError(f"strategy {self.name!r} applies to poisson worlds; got {ctx.world!r}")
        arena = ctx.arena
        self.solver = cached_solver(arena.without_scenario(), self.h)
        self.lat = lattice_greens(self.solver, max(self.spacing, self.solver.h))
        self.c = float(ctx.nominal.get("strength", arena.strength))
        noise = max(float(ctx.nominal.get("noise", 12.0)), MIN_NOISE)
        self.sigma_used = np.sqrt(2.0) * noise if self.sigma == "auto" else float(self.sigma)
        self.rng = ctx.rng
        self.logw = np.zeros(len(self.lat.nodes))
        self.allowed = np.ones(len(self.lat.nodes), dtype=bool)
        pos = np.asarray(ctx.start[:2], dtype=float)
        self._next = self._nearest(pos, self.allowed)
        self._update_status()

    def restrict(self, mask_of) -> None:
        m = mask_of(self.lat.points)
        if m is not None:
            self.allowed &= np.asarray(m, dtype=bool)

    def _nearest(self, p, mask) -> int:
        idx = np.flatnonzero(mask)
        return int(idx[np.argmin(np.hypot(*(self.lat.points[idx] - p).T))])

    # -- belief ------------------------------------------------------------------------
    def weights(self) -> np.ndarray:
        w = np.exp(self.logw - self.logw.max())
        return w / w.sum()

    def _update_status(self) -> None:
        w = self.weights()
        est = w @ self.lat.points
        within = float(w[np.hypot(*(self.lat.points - est).T) <= self.radius].sum())
        H = float(-np.sum(w * np.log(np.maximum(w, 1e-300))))
        self.status = Status(est, float(np.exp(H)) * self.spacing ** 2,
                             extra=dict(entropy=H, mass_within=within))

    # -- protocol ----------------------------------------------------------------------
    def propose(self):
        if self.done:
            return None
        return Measure(self.lat.points[self._next].copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        obs = observations[0]
        self.n_measurements += 1
        self.n_samples += 1
        a = self._nearest(np.asarray(obs.position, dtype=float), np.ones_like(self.allowed))
        mean = self.c * self.lat.columns(np.array([a]))[:, 0]                # c G(y, x) for every x
        r = (float(obs.value) - mean) / self.sigma_used
        self.logw += -0.5 * r * r
        self.logw -= self.logw.max()
        self._update_status()
        if self.status.extra["mass_within"] >= self.confidence:
            self.stop(StopReason.CONVERGED, f"{self.confidence:.0%} of the belief within {self.radius:g} cm")
        elif self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} readings")
        else:
            self._choose(a)

    def _choose(self, here: int) -> None:
        pts = self.lat.points
        near = self.allowed & (np.hypot(*(pts - pts[here]).T) <= self.step)
        near[here] = False
        cand = np.flatnonzero(near)
        if cand.size == 0:
            self.stop(StopReason.NO_TARGET, f"no lattice node within {self.step:g} cm")
            return
        w = self.weights()
        sup, sw = systematic_support(w, self.support, self.rng)
        means = self.c * self.lat.columns(cand).T                               # (m, L): c G(y_m, x)
        score = gaussian_expected_entropy(means, self.logw, sup, sw, self.sigma_used)
        self._next = int(cand[np.argmin(score)])

    def reject(self, intent, point, reason: str, agent: int = 0) -> None:
        if self._count_rejection(reason):
            return
        self.allowed[self._next] = False
        here = self._nearest(np.asarray(point, dtype=float), self.allowed)
        self._next = here
