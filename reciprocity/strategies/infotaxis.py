"""Infotaxis-type strategies for plume worlds, over a particle belief.

One decision scores every admissible move ``v`` with the joint table ``w'_i p(z | i, v)``
of :meth:`ParticleBelief.outcomes` (outcomes × moves × particles, one vectorised pass)
and takes the lowest score (the first on ties, as otto does):

``infotaxis``
    expected entropy change, eq. (3) of Song et al. (2019, papers/002), after Vergassola
    et al. (2007): ``P(r_v)(0 − S) + (1 − P(r_v)) Σ_z ρ_z (S_z − S)``, ``P(r_v)`` the
    posterior mass within the found radius of ``r_v``.
``free-energy``
    expected free energy, eqs. (5), (8)–(10) of papers/002:
    ``Σ_z ρ_z [Σ_i w_i^z |r_v − r0_i|^γ + α tr(Σ^z)^β S_z]``, each term on the posterior
    after outcome ``z``.
``mapless-infotaxis``
    Masson (2013) as papers/002 uses it: the first term of eq. (3) on an extended
    domain (mass within `extent` of ``r_v``) and a constant temperature ``T`` on the
    explorative term: ``−P_ext(r_v) S + T (1 − P_ext(r_v)) Σ_z ρ_z (S_z − S)``. papers/002
    gives no formula for it; this is our reading of its description.
``entrotaxis``
    Hutchinson et al. (2018): the move whose next reading is the most uncertain,
    ``max_v −Σ_z ρ_z ln ρ_z``.
``space-aware-infotaxis``
    otto (Loisy & Eloy 2022): ``(1 − p_end) Σ_z ρ_z log2(D_z + 2^(H_z − 1) − 1/2)`` with
    ``D_z`` the posterior mean Manhattan distance (cells) and ``H_z`` the entropy in bits
    (the log only where its argument is positive).
``voi``
    Hajieghrary, Mox & Hsieh (2017, papers/001): N searchers, one belief each, infotaxis
    moves; each reading is offered to the others (``share="all"``) or only to those for
    which its value of information passes a threshold (``share="voi"``, Section 3.3.2),
    or kept (``share="none"``: independent searchers, the team baseline).

Moves depend on the world's motion (``nominal["motion"]``): ``turn`` (a unit step after
a heading change among ``n_turns`` values within ``±max_turn`` degrees, papers/002
Section 4: V = {1}, Ω = {−3..3}°, T = {1}), ``grid`` (4 or 8 cell moves, otto) or
``reach`` (8 compass moves of ``step`` per axis, papers/001).
"""

from __future__ import annotations

import numpy as np

from ..beliefs.base import MIN_PARTICLES, posterior_entropies
from ..beliefs.gaussian_basis import GaussianBasisBelief, basis_width
from ..beliefs.particles import ParticleBelief, grid_particles
from ..spaces.walker import candidate_moves, turn_inward
from ..errors import SearchError
from ..validation import number, positive
from ..intents import Move, Stay
from ..observations import Observation
from . import register
from .base import SearchContext, Status, Strategy

__all__ = ["PlumeSearch", "Infotaxis", "FreeEnergyInfotaxis", "MaplessInfotaxis", "Entrotaxis",
           "SpaceAwareInfotaxis", "VoIInfotaxis", "candidate_moves", "make_belief", "posterior_entropies",
           "turn_inward", "walker_proposal"]

#: otto's tie tolerance between scores.
TIE = 1e-10
#: Steps between stored particle snapshots (figures).
SNAPSHOT_EVERY = 10


def walker_proposal(nominal: dict, pos: np.ndarray, heading: float, choose) -> tuple:
    """The next intent of a plume walker and its heading after it.

    Parameters
    ----------
    nominal : dict
        The plume world's nominal description.
    pos : ndarray, shape (2,)
        Where the walker stands.
    heading : float
        Its heading, rad.
    choose : callable
        ``choose(candidates (m, 2)) -> index`` of the admissible move to take.

    Returns
    -------
    (Intent, float)
        ``Move`` to the chosen candidate and its heading, or, at the edge facing out with
        no admissible move, ``Stay`` and :func:`turn_inward`'s heading.
    """
    cands, hds = candidate_moves(nominal, pos, heading)
    if len(cands) == 0:
        return Stay(pos), turn_inward(nominal, pos, heading)
    k = int(choose(cands))
    return Move(cands[k]), float(hds[k])


def make_belief(nominal: dict, rng: np.random.Generator, *, particles: int, resample_below: float | None,
                mcmc_steps: int) -> ParticleBelief:
    """The belief a strategy starts with: particles on a regular grid over the area
    (papers/002, Section 4.1), or on every cell centre without resampling on grid worlds
    (otto's exact grid posterior)."""
    if nominal.get("grid") is not None:
        from ..spaces import GridSpace
        pts = GridSpace(nominal["bounds"], nominal["grid"]).points
        resample_below = None
    else:
        pts = grid_particles(nominal["bounds"], particles)
    return ParticleBelief(nominal["plume"], pts, nominal["bounds"], rng, dt=nominal["dt"],
                          resample_below=resample_below, mcmc_steps=mcmc_steps,
                          found_radius=nominal["found_radius"], max_hits=nominal.get("max_hits"))


class PlumeSearch(Strategy):
    """Base of the single-observer plume strategies: a particle belief and one-step
    scoring of the admissible moves (lower is better).

    Parameters
    ----------
    particles : int
        Number of particles M (papers/002: 600); ignored on grid worlds (one per cell).
    resample_below : float
        Resample when the effective size falls below this fraction of M (1/3).
    mcmc_steps : int
        Metropolis-Hastings moves after each resampling.
    eta : float
        Tail probability left out of the sums over counts (papers/002, Section 3.3).
    """

    worlds = ("plume",)
    agents = 1

    def __init__(self, *, particles: int = 600, resample_below: float = 1 / 3, mcmc_steps: int = 1,
                 eta: float = 1e-3):
        self.n_particles = positive(particles, "particles", integer=True)
        if self.n_particles < MIN_PARTICLES:
            raise SearchError(f"particles must be at least {MIN_PARTICLES} (Song et al. 2019 use 600); "
                              f"got {particles!r}")
        self.resample_below = positive(resample_below, "resample_below")
        if self.resample_below >= 1:
            raise SearchError(f"resample_below must lie in (0, 1); got {resample_below!r}")
        self.mcmc_steps = positive(mcmc_steps, "mcmc_steps", integer=True)
        self.eta = positive(eta, "eta")
        if self.eta >= 0.5:
            raise SearchError(f"eta must lie in (0, 0.5); got {eta!r}")
        super().__init__()

    def params(self) -> dict:
        return dict(particles=self.n_particles, resample_below=self.resample_below,
                    mcmc_steps=self.mcmc_steps, eta=self.eta)

    # -- set-up ----------------------------------------------------------------------
    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        if ctx.world not in self.worlds:
            raise SearchError(f"strategy {self.name!r} applies to plume worlds; got {ctx.world!r}")
        self.nominal = ctx.nominal
        self.ctx = ctx
        self.belief = make_belief(ctx.nominal, ctx.rng, particles=self.n_particles,
                                  resample_below=self.resample_below, mcmc_steps=self.mcmc_steps)
        self.pos = ctx.start[:2].astype(float).copy()
        self.heading = float(ctx.start[2])
        self.snapshots: list[tuple[int, np.ndarray, np.ndarray]] = []
        self._next_heading = self.heading
        h0 = ctx.nominal.get("initial_hit")
        if h0 is not None:
            # otto: the search starts after a forced first hit where the observer stands
            self.belief.update(Observation(self.pos, float(h0), 0.0, ctx.nominal["dt"], "hits"))
        self._record()

    # -- deciding ----------------------------------------------------------------------
    def scores(self, cands: np.ndarray) -> np.ndarray:
        """Score of each candidate place (lower is better), shape (m,)."""
        raise NotImplementedError

    def decide(self, cands: np.ndarray) -> int:
        """Index of the chosen candidate: the first whose score is within :data:`TIE` of the least."""
        s = self.scores(cands)
        return int(np.flatnonzero(s <= np.min(s) + TIE)[0])

    def propose(self):
        if self.done:
            return None
        intent, self._next_heading = walker_proposal(self.nominal, self.pos, self.heading, self.decide)
        return intent

    def observe(self, observations, intent, agent: int = 0) -> None:
        for obs in observations:
            self.belief.update(obs)
            self.n_measurements += 1
            self.n_samples += 1
            self.pos = np.asarray(obs.position, dtype=float).copy()
        self.heading = self._next_heading
        self._record()

    # -- records -----------------------------------------------------------------------
    def figure_record(self) -> dict:
        """``particles``: the belief's particle clouds every :data:`SNAPSHOT_EVERY`
        readings, a list of ``(readings, positions (n, 2), weights (n,))``."""
        return dict(particles=list(self.snapshots))

    def free_energy(self, alpha: float = 0.01, beta: float = 1.4, gamma: float = 3.0) -> float:
        """Free energy eq. (8) of papers/002 at the current place and belief."""
        w, x = self.belief.weights(), self.belief.support()
        d = np.hypot(*(x - self.pos).T)
        return float(w @ d ** gamma + alpha * self.belief.spread() ** beta * self.belief.entropy())

    def _record(self) -> None:
        b = self.belief
        w, x = b.weights(), b.support()
        est = w @ x
        dev = x - est
        cov = (w[:, None] * dev).T @ dev
        area = float(np.pi * 5.991 * np.sqrt(max(np.linalg.det(cov), 0.0)))
        self.status = Status(est, area, extra=dict(entropy=b.entropy(), spread=b.spread(),
                                                   free_energy=self.free_energy(), n_eff=b.n_eff()))
        if self.n_measurements % SNAPSHOT_EVERY == 0:
            self.snapshots.append((self.n_measurements, x.copy(), w.copy()))


@register
class Infotaxis(PlumeSearch):
    """Infotaxis (Vergassola et al. 2007; eq. (3) of papers/002) on a particle belief."""

    name = "infotaxis"

    def scores(self, cands):
        joint, p_found, _ = self.belief.outcomes(cands, eta=self.eta)
        rho, H, _ = posterior_entropies(joint)
        S = self.belief.entropy()
        return p_found * (0.0 - S) + (1.0 - p_found) * np.sum(rho * (H - S), axis=0)


@register
class FreeEnergyInfotaxis(PlumeSearch):
    """Free-energy infotaxis (Song, He & Lei 2019, eqs. (5), (8)–(10)).

    Parameters
    ----------
    alpha, beta : float
        Temperature ``T = alpha · tr(Σ)^beta`` (the paper's 0.01, 1.4).
    gamma : float
        Exponent of the distance in the potential energy (3).
    area_exponent : float
        Beyond the paper: the temperature's factor grows with the search area,
        ``alpha · (L / 100)^area_exponent`` with ``L`` the square root of the area (the
        task's bounds, length unit). 0 (default): the paper's one ``alpha`` at every size.
        How much the printed ``alpha`` lets the temperature decide, and how the ``alpha``
        that balances the two terms grows with the area, is in
        ``docs/papers/song2019.md``.

    Attributes
    ----------
    alpha_used : float
        The temperature's factor in force for the current task (``alpha`` scaled to its
        area, see `area_exponent`).
    """

    name = "free-energy"

    def __init__(self, *, alpha: float = 0.01, beta: float = 1.4, gamma: float = 3.0, area_exponent: float = 0.0,
                 particles: int = 600, resample_below: float = 1 / 3, mcmc_steps: int = 1, eta: float = 1e-3):
        self.alpha = positive(alpha, "alpha")
        self.beta = positive(beta, "beta")
        self.gamma = positive(gamma, "gamma")
        self.area_exponent = number(area_exponent, "area_exponent", 0.0, 10.0)
        #: the temperature's factor in force: `alpha`, scaled to the task's area by :meth:`start`
        self.alpha_used = self.alpha
        super().__init__(particles=particles, resample_below=resample_below, mcmc_steps=mcmc_steps, eta=eta)

    def params(self) -> dict:
        return dict(super().params(), alpha=self.alpha, beta=self.beta, gamma=self.gamma,
                    area_exponent=self.area_exponent)

    def start(self, ctx: SearchContext) -> None:
        (x0, x1), (y0, y1) = ctx.nominal["bounds"]
        side = float(np.sqrt((x1 - x0) * (y1 - y0)))
        self.alpha_used = self.alpha * (side / 100.0) ** self.area_exponent
        super().start(ctx)

    def terms(self, cands) -> tuple[np.ndarray, np.ndarray]:
        """The two terms of the expected free energy of each candidate, eqs. (8)–(10):
        ``E_z{W}`` (length^γ) and ``E_z{tr(Σ)^β S}`` (length^2β · nats), so that the
        score is ``E_z{W} + α E_z{tr(Σ)^β S}``; shapes (m,)."""
        joint, _, dist = self.belief.outcomes(cands, eta=self.eta)
        rho, H, P = posterior_entropies(joint)
        Ps = np.maximum(P, 1e-300)
        x = self.belief.support()
        W = np.einsum("zmi,mi->zm", joint, dist ** self.gamma) / Ps                 # eq. (4)
        mean = np.einsum("zmi,ic->zmc", joint, x) / Ps[..., None]
        second = np.einsum("zmi,i->zm", joint, np.sum(x * x, axis=1)) / Ps
        tr = np.maximum(second - np.sum(mean ** 2, axis=2), 0.0)
        return np.sum(rho * W, axis=0), np.sum(rho * tr ** self.beta * H, axis=0)   # eq. (10)

    def scores(self, cands):
        potential, temperate = self.terms(cands)
        return potential + self.alpha_used * temperate                              # eq. (8)

    def free_energy(self, alpha=None, beta=None, gamma=None) -> float:
        return super().free_energy(self.alpha_used, self.beta, self.gamma)


@register
class MaplessInfotaxis(PlumeSearch):
    """Mapless infotaxis (Masson 2013) as papers/002 compares it: infotaxis with the
    exploitative term on an extended domain and a constant temperature.

    Parameters
    ----------
    extent : float
        Radius of the extended domain (length unit).
    temperature : float
        Weight of the explorative term.
    """

    name = "mapless-infotaxis"

    def __init__(self, *, extent: float = 10.0, temperature: float = 1.0, particles: int = 600, resample_below: float = 1 / 3, mcmc_steps: int = 1,
                 eta: float = 1e-3):
        self.extent = positive(extent, "extent")
        self.temperature = positive(temperature, "temperature")
        super().__init__(particles=particles, resample_below=resample_below, mcmc_steps=mcmc_steps, eta=eta)

    def params(self) -> dict:
        return dict(super().params(), extent=self.extent, temperature=self.temperature)

    def scores(self, cands):
        joint, _, dist = self.belief.outcomes(cands, eta=self.eta)
        rho, H, _ = posterior_entropies(joint)
        S = self.belief.entropy()
        p_ext = (dist <= self.extent).astype(float) @ self.belief.weights()
        return -p_ext * S + self.temperature * (1.0 - p_ext) * np.sum(rho * (H - S), axis=0)


@register
class Entrotaxis(PlumeSearch):
    """Entrotaxis (Hutchinson, Oh & Chen 2018): the most uncertain next reading."""

    name = "entrotaxis"

    def scores(self, cands):
        joint, _, _ = self.belief.outcomes(cands, eta=self.eta)
        rho, _, _ = posterior_entropies(joint)
        return np.sum(rho * np.log(np.where(rho > 0, rho, 1.0)), axis=0)   # = -entropy


@register
class SpaceAwareInfotaxis(PlumeSearch):
    """Space-aware infotaxis (otto, Loisy & Eloy 2022)."""

    name = "space-aware-infotaxis"

    def scores(self, cands):
        joint, p_found, _ = self.belief.outcomes(cands, eta=self.eta)
        rho, H, P = posterior_entropies(joint)
        x = self.belief.support()
        cell = float(self.nominal["step"])
        man = (np.abs(cands[:, None, 0] - x[None, :, 0]) + np.abs(cands[:, None, 1] - x[None, :, 1])) / cell
        D = np.einsum("zmi,mi->zm", joint, man) / np.maximum(P, 1e-300)
        v = D + 2.0 ** (H / np.log(2.0) - 1.0) - 0.5
        v = np.where(v > 0, np.log2(np.where(v > 0, v, 1.0)), v)
        return (1.0 - p_found) * np.sum(rho * v, axis=0)


@register
class VoIInfotaxis(Strategy):
    """Multi-searcher infotaxis with shared readings (Hajieghrary, Mox & Hsieh 2017).

    Every searcher keeps its own belief and takes infotaxis moves on it. Each
    reading is an event ``(r, z)``; with ``share="all"`` every event goes to every other
    searcher (Section 3.3.1); with ``share="voi"`` a searcher incorporates a teammate's
    event only when its value of information passes `threshold` (Section 3.3.2); with
    ``share="none"`` the searchers are independent (no messages). The
    paper names two factors, how probable the event is under the receiver's belief and
    how much it changes it, without a formula; we take their product,
    ``VoI = P_A(z at r) · KL(post_A || prior_A)`` (nats), the event's share of the
    expected information gain. One message is recorded per event that at least one
    teammate takes (receivers: those that take it).

    Parameters
    ----------
    share : {"all", "voi", "none"}
    threshold : float
        VoI threshold (nats).
    particles, resample_below, mcmc_steps, eta
        As for :class:`PlumeSearch` (the particle belief).
    belief : {"particles", "gaussian-basis"}
        Each searcher's belief: the particle cloud of :class:`PlumeSearch`, or the
        paper's fixed Gaussian basis functions (its Sections 3.1-3.2,
        :class:`~reciprocity.beliefs.gaussian_basis.GaussianBasisBelief`), scored with
        the mixture entropy of its eq. (12).
    basis : int
        Number of Gaussian basis functions (papers/001: 100 to 300), scattered at random.
    width : float, optional
        Standard deviation of a basis function (length unit); default
        :func:`~reciprocity.beliefs.gaussian_basis.basis_width`, half the mean spacing.
    pose_variance : float
        The robot's position variance per axis (length²) in the pose-uncertainty mixture
        (papers/001, Section 3.1; ``Σ = 2 I`` in its Section 4).
    own : {"all", "voi"}
        ``"all"``: a searcher always takes its own readings; ``"voi"``: its own hits pass
        the same value-of-information test as a teammate's (papers/001, Remark 3: "a
        robot does not always contribute its own positive sensor detection").
    rejuvenate : bool
        Particle belief only: Metropolis-Hastings moves after each resampling (True, as
        :class:`PlumeSearch`), or plain resampling (False: the paper's particle filter,
        in which hypotheses are only ever eliminated, its Remark 1).
    preset : {None, "paper"}
        ``"paper"``: the paper's own set-up, ``belief="gaussian-basis"``, ``basis=300``
        (its Fig. 7), ``pose_variance=2``, ``own="voi"``; parameters given explicitly
        win over the preset.
    """

    name = "voi"
    worlds = ("plume",)
    agents = None
    #: The paper's set-up (``preset="paper"``).
    PAPER = dict(belief="gaussian-basis", basis=300, pose_variance=2.0, own="voi")
    _DEFAULTS = dict(belief="particles", basis=300, width=None, pose_variance=2.0, own="all", rejuvenate=True)

    def __init__(self, *, share: str = "voi", threshold: float = 0.01, particles: int = 600,
                 resample_below: float = 1 / 3, mcmc_steps: int = 1, eta: float = 1e-3,
                 belief: str | None = None, basis: int | None = None, width: float | None = None,
                 pose_variance: float | None = None, own: str | None = None, rejuvenate: bool | None = None,
                 preset: str | None = None):
        if share not in ("all", "voi", "none"):
            raise SearchError(f"share must be 'all', 'voi' or 'none'; got {share!r}")
        if preset not in (None, "paper"):
            raise SearchError(f"preset must be 'paper' or not given; got {preset!r}")
        self.share = share
        self.threshold = positive(threshold, "threshold")
        self._single = dict(particles=particles, resample_below=resample_below, mcmc_steps=mcmc_steps, eta=eta)
        Infotaxis(**self._single)          # validates the shared parameters
        given = dict(belief=belief, basis=basis, width=width, pose_variance=pose_variance, own=own,
                     rejuvenate=rejuvenate)
        chosen = {**self._DEFAULTS, **(self.PAPER if preset == "paper" else {}),
                  **{k: v for k, v in given.items() if v is not None}}
        if chosen["belief"] not in ("particles", "gaussian-basis"):
            raise SearchError(f"belief must be 'particles' or 'gaussian-basis'; got {chosen['belief']!r}")
        if chosen["own"] not in ("all", "voi"):
            raise SearchError(f"own must be 'all' or 'voi'; got {chosen['own']!r}")
        if not isinstance(chosen["rejuvenate"], bool):
            raise SearchError(f"rejuvenate must be true or false; got {chosen['rejuvenate']!r}")
        chosen["basis"] = positive(chosen["basis"], "basis", integer=True)
        if chosen["basis"] < MIN_PARTICLES:
            raise SearchError(f"basis must be at least {MIN_PARTICLES} (the paper uses 100 to 300); "
                              f"got {chosen['basis']!r}")
        if chosen["width"] is not None:
            chosen["width"] = positive(chosen["width"], "width")
        chosen["pose_variance"] = number(chosen["pose_variance"], "pose_variance", 0.0, 1e6)
        self.preset = preset
        self.setup = chosen
        super().__init__()

    def params(self) -> dict:
        extra = {k: v for k, v in self.setup.items() if v != self._DEFAULTS[k]}
        return dict(self._single, share=self.share, threshold=self.threshold, **extra)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        self.ctx = ctx
        self.searchers = []
        for k in range(ctx.n_agents):
            sub = Infotaxis(**self._single)
            sub.start(SearchContext(ctx.world, ctx.nominal, ctx.starts[k:k + 1], ctx.rng, ctx.messages))
            if self.setup["belief"] == "gaussian-basis":
                sub.belief = self._basis_belief(ctx)
                sub.snapshots = []
                sub._record()
            elif not self.setup["rejuvenate"]:
                sub.belief.mcmc_steps = 0
            self.searchers.append(sub)
        self.n_shared = np.zeros(ctx.n_agents, dtype=int)
        self.sense = ctx.nominal.get("sense")
        if self.sense is not None and self.setup["belief"] != "gaussian-basis":
            raise SearchError("a directional plume sensor (papers/001, eq. (14)) needs belief='gaussian-basis'")
        #: each searcher's course, rad: the heading of its last move (a directional sensor reads by it)
        self.courses = [float(s.heading) for s in self.searchers]
        self._update_status()

    def _basis_belief(self, ctx: SearchContext) -> GaussianBasisBelief:
        """A Gaussian-basis belief with means scattered at random over the area."""
        nom, n = ctx.nominal, self.setup["basis"]
        (x0, x1), (y0, y1) = nom["bounds"]
        means = np.column_stack([ctx.rng.uniform(x0, x1, n), ctx.rng.uniform(y0, y1, n)])
        width = self.setup["width"] if self.setup["width"] is not None else basis_width(nom["bounds"], n)
        return GaussianBasisBelief(nom["plume"], means, nom["bounds"], width=width,
                                   pose_variance=self.setup["pose_variance"], dt=nom["dt"],
                                   found_radius=nom["found_radius"], max_hits=nom.get("max_hits"),
                                   sense=nom.get("sense"))

    def propose(self):
        if self.done:
            return None
        if self.setup["belief"] != "gaussian-basis":
            return {k: s.propose() for k, s in enumerate(self.searchers)}
        out = {}
        for k, s in enumerate(self.searchers):
            out[k], s._next_heading = walker_proposal(s.nominal, s.pos, s.heading,
                                                      lambda c, s=s: self._basis_choice(s.belief, s.pos, c))
        return out

    def _basis_choice(self, belief: GaussianBasisBelief, pos: np.ndarray, cands: np.ndarray) -> int:
        """Infotaxis on a Gaussian-basis belief: eq. (5) with the entropies of eq. (12)."""
        d = cands - pos
        joint, p_found, _ = belief.outcomes(cands, eta=self._single["eta"], courses=np.arctan2(d[:, 1], d[:, 0]))
        P = joint.sum(axis=-1)
        rho = P / np.maximum(P.sum(axis=0, keepdims=True), 1e-300)
        S = belief.entropy()
        H = belief.entropies(joint)
        s = p_found * (0.0 - S) + (1.0 - p_found) * np.sum(rho * (H - S), axis=0)
        return int(np.flatnonzero(s <= np.min(s) + TIE)[0])

    @staticmethod
    def _event_loglik(belief, obs: Observation, course: float | None) -> np.ndarray:
        """Log-likelihood of event `obs` (taken along `course`) for each hypothesis of `belief`."""
        if isinstance(belief, GaussianBasisBelief):
            return belief.log_likelihood(obs, course)
        return belief._loglik(float(obs.value), belief.mean_counts(np.asarray(obs.position)[None])[0])

    def value_of_information(self, belief, obs: Observation, course: float | None = None) -> float:
        """``P(z at r) · KL(posterior || prior)`` of event `obs` (taken along `course`, rad,
        for a directional sensor) for `belief` (nats)."""
        w = belief.weights()
        ll = self._event_loglik(belief, obs, course)
        lik = np.exp(ll - np.max(ll))
        pz_scaled = w @ lik
        if pz_scaled <= 0:
            return 0.0
        post = w * lik / pz_scaled
        nz = post > 0
        kl = float(np.sum(post[nz] * np.log(post[nz] / w[nz])))
        return float(pz_scaled * np.exp(np.max(ll))) * kl

    def _update(self, belief, obs: Observation, course: float | None) -> None:
        if course is None:
            belief.update(obs)
        else:
            belief.update(obs, course)

    def _observe_own(self, own: PlumeSearch, observations, intent, courses) -> None:
        """The searcher's own readings; with ``own="voi"`` a hit it judges of too little
        value moves it on without entering its belief (papers/001, Remark 3)."""
        if self.setup["own"] == "all" and self.sense is None:
            own.observe(observations, intent, 0)
            return
        for obs, course in zip(observations, courses):
            if (self.setup["own"] == "all" or obs.value <= 0
                    or self.value_of_information(own.belief, obs, course) >= self.threshold):
                self._update(own.belief, obs, course)
            own.n_measurements += 1
            own.n_samples += 1
            own.pos = np.asarray(obs.position, dtype=float).copy()
        own.heading = own._next_heading
        own._record()

    def _courses(self, agent: int, observations) -> list:
        """The course of `agent` into the place of each of `observations` (rad): the
        direction of that move, or its last course where it stayed; all None without a
        directional sensor."""
        if self.sense is None:
            return [None] * len(observations)
        out, prev = [], self.searchers[agent].pos
        for obs in observations:
            d = np.asarray(obs.position, dtype=float) - prev
            if np.hypot(*d) > 0:
                self.courses[agent] = float(np.arctan2(d[1], d[0]))
            out.append(self.courses[agent])
            prev = np.asarray(obs.position, dtype=float)
        return out

    def observe(self, observations, intent, agent: int = 0) -> None:
        courses = self._courses(agent, observations)
        self._observe_own(self.searchers[agent], observations, intent, courses)
        self.n_measurements += len(observations)
        self.n_samples += len(observations)
        for obs, course in zip(observations, courses) if self.share != "none" else ():
            takers = []
            for k, s in enumerate(self.searchers):
                if k == agent:
                    continue
                if self.share == "all" or self.value_of_information(s.belief, obs, course) >= self.threshold:
                    takers.append(k)
            if takers:
                self.ctx.messages.send(obs.time, agent, takers, "observation", 1)
                for k in takers:
                    self._update(self.searchers[k].belief, obs, course)
                    self.n_shared[k] += 1
        self._update_status()

    def _update_status(self) -> None:
        ents = [s.belief.entropy() for s in self.searchers]
        best = int(np.argmin(ents))
        st = self.searchers[best].status
        self.status = Status(st.estimate, st.region_area,
                             extra=dict(entropy=ents[best], entropies=ents, shared=self.n_shared.tolist()))
