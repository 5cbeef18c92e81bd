"""Cross-run (b): the reciprocity search's imaging and next-point rule on the plume world.

An adapter, not the strategy of :mod:`reciprocity.strategies.reciprocity` itself (which
is built on a FEM ``GreenSolver`` and jumps between distant measurement points): the
parts of Algorithm 1 of Landa et al. that carry over to a plume, with the plume's mean
rate in the place of the Green's function:

- **imaging function** on a lattice of candidate sources (spacing `h`): the product over
  readings of the per-reading maps (``combine="product"``, the home default), with the
  Poisson probability of the ``z_k`` hits read at ``r_k``, ``p_k(x) = Pois(z_k; R(r_k | x) Δt)``,
  in the place of the Gaussian map of eq. (7) (the predicted reading ``c G(r_k, x)``
  becomes the mean count ``R(r_k | x) Δt``); lattice points within the found radius of
  a place visited are ruled out (the search would have ended there);
- **next point** by the home strategy's ``"reach"`` rule: the lattice point ``y`` at
  least `d` from every place read that maximises ``Σ_x P_M(x) exp(−|y − x|² / (2 reach²))``,
  the imaging mass within sensing reach;
- **motion**: the plume world's walker takes one unit step per reading (no jumps), so the
  observer steps toward that point along the admissible move nearest to it, reading at
  every step, and the point is chosen again after every reading;
- **stop**: on contact (the plume world's FOUND), as every plume strategy.

What the real strategy would need to run here unchanged: an ``ImagingMap`` that accepts
any column provider (``nodes``, ``h``, ``field(source) -> mean reading at every node``)
instead of a ``GreenSolver``, a per-reading likelihood other than eq. (7) (Poisson
counts), and a route from the chosen point to unit steps (a platform that walks the plan
and reads on the way).

Measured on ``song-100`` and ``otto-2d`` against the infotaxis family:
``benchmarks/plume_beyond.md``, section 3.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln

from ..errors import SearchError
from ..validation import positive
from ..models.plume import plume_rate
from . import register
from .base import SearchContext, Status, Strategy
from .infotaxis import walker_proposal

__all__ = ["PlumeImaging"]


@register
class PlumeImaging(Strategy):
    """The reciprocity search's imaging and ``"reach"`` rule on a plume (cross-run; module doc).

    Parameters
    ----------
    h : float
        Lattice spacing of the imaging function (length unit); grid worlds use their cells.
    reach : float
        Sensing reach of the ``"reach"`` rule (length unit).
    d : float or None
        Least distance of the next point from every place read (length unit); None: the
        world's found radius.
    """

    name = "plume-reciprocity"
    worlds = ("plume",)
    agents = 1

    def __init__(self, *, h: float = 2.0, reach: float = 10.0, d: float | None = None):
        self.h = positive(h, "h")
        self.reach = positive(reach, "reach")
        self.d = None if d is None else positive(d, "d")
        super().__init__()

    def params(self) -> dict:
        return dict(h=self.h, reach=self.reach, d=self.d)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        if ctx.world not in self.worlds:
            raise SearchError(f"strategy {self.name!r} applies to plume worlds; got {ctx.world!r}")
        self.nominal = nom = ctx.nominal
        (x0, x1), (y0, y1) = nom["bounds"]
        h = float(nom["grid"]) if nom.get("grid") is not None else self.h
        gx = np.arange(x0 + h / 2, x1, h)
        gy = np.arange(y0 + h / 2, y1, h)
        self.shape = (len(gy), len(gx))
        self.nodes = np.column_stack([a.ravel() for a in np.meshgrid(gx, gy)])
        self.h_used = h
        self.logp = np.zeros(len(self.nodes))
        self.far = np.ones(len(self.nodes), dtype=bool)    # at least d from every place read
        self.read_at: list[np.ndarray] = []
        self.pos = ctx.start[:2].astype(float).copy()
        self.heading = float(ctx.start[2])
        self._next_heading = self.heading
        self.d_used = max(self.d if self.d is not None else float(nom["found_radius"]), 1e-9)
        h0 = nom.get("initial_hit")
        if h0 is not None:
            self._image(self.pos, float(h0))
        self._status()

    # -- the imaging function ---------------------------------------------------------------
    def _image(self, r: np.ndarray, z: float) -> None:
        mu = np.maximum(plume_rate(r[None], self.nodes, self.nominal["plume"])[0] * self.nominal["dt"], 1e-300)
        cap = self.nominal.get("max_hits")
        if cap is not None and z >= cap:
            k = np.arange(cap)[:, None]
            below = np.exp(k * np.log(mu)[None] - mu[None] - gammaln(k + 1)).sum(axis=0)
            self.logp += np.log(np.maximum(1.0 - below, 1e-300))
        else:
            self.logp += z * np.log(mu) - mu - gammaln(z + 1)
        self.logp[np.hypot(*(self.nodes - r).T) <= self.nominal["found_radius"]] = -np.inf
        self.read_at.append(np.asarray(r, dtype=float).copy())
        self.far &= np.hypot(*(self.nodes - r).T) >= self.d_used
        if not np.isfinite(self.logp).any():
            self.logp = np.zeros(len(self.nodes))
        self.logp -= np.max(self.logp)

    def weights(self) -> np.ndarray:
        w = np.exp(self.logp)
        return w / w.sum()

    def _status(self) -> None:
        w = self.weights()
        est = w @ self.nodes
        self.status = Status(est, float(np.exp(-np.sum(w[w > 0] * np.log(w[w > 0])))) * self.h ** 2)

    def target(self) -> np.ndarray:
        """The ``"reach"`` rule's point: the most imaging mass within reach, at least `d`
        from every place read."""
        # the sum over the lattice is a Gaussian blur of the weight image (zero outside);
        # scipy.ndimage is imported here, not when the strategies are listed (issue 24)
        from scipy.ndimage import gaussian_filter
        img = gaussian_filter(self.weights().reshape(self.shape), self.reach / self.h_used, mode="constant",
                              truncate=6.0).ravel()
        idx = np.flatnonzero(self.far) if self.far.any() else np.arange(len(self.nodes))
        return self.nodes[idx[int(np.argmax(img[idx]))]]

    # -- protocol ------------------------------------------------------------------------------
    def propose(self):
        if self.done:
            return None
        intent, self._next_heading = walker_proposal(self.nominal, self.pos, self.heading, self._toward_goal)
        return intent

    def _toward_goal(self, cands: np.ndarray) -> int:
        """The admissible move nearest to the ``"reach"`` rule's target (kept as `goal`)."""
        self.goal = self.target()
        return int(np.argmin(np.hypot(*(cands - self.goal).T)))

    def observe(self, observations, intent, agent: int = 0) -> None:
        for obs in observations:
            self.pos = np.asarray(obs.position, dtype=float).copy()
            self._image(self.pos, float(obs.value))
            self.n_measurements += 1
            self.n_samples += 1
        self.heading = self._next_heading
        self._status()
