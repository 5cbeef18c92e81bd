"""Algorithm 1 of Landa et al.: reciprocity-based source discovery."""

from __future__ import annotations

import numpy as np

from arenas import ArenaError

from ..beliefs.base import credible_mass
from ..errors import MeshError, SearchError
from ..fem.discretisation import discretisation_error
from ..fem.green import GreenSolver
from ..imaging import COMBINATIONS, ImagingMap
from ..intents import Measure, Survey
from ..outcome import MAX_SOURCES, StopReason
from ..spaces import MeshSpace, mesh_space
from ..models.green import cached_solver
from .base import SearchContext, Status, Strategy
from .information import expected_entropy, lattice_greens, mutual_information, systematic_support
from .mapping import FRONTIER_SHARE, SURVEY_SHARE, MapKeeper
from .reach import greatest_green

# scipy's image filters, graph routines and k-d tree are imported where they are used:
# listing the strategies imports this module for its name and doc alone (issue 24).

__all__ = ["ReciprocityStrategy", "RULES", "PRESETS", "DEFAULTS", "axis_point", "mass_within_reach"]

#: Next-observation rules.
RULES = ("axis", "reach", "nearest", "info")


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


#: Source strength assumed by :meth:`ReciprocityStrategy.start` when the world states
#: no noise: the paper's sensor noise, signal units (its section V).
PAPER_NOISE = 12.0
#: Smallest reading noise used for ``sigma="auto"`` / ``"noise"``, signal units: keeps
#: eq. (7) defined in noise-free worlds (the strategy's mesh differs from the truth's by
#: about this much near the source).
MIN_NOISE = 1.0
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
#: Relative likelihood of the tail checked by `tail_tol` (a Gaussian belief puts 99 %
#: of its mass above it).
TAIL_EPS = 0.01
#: Expected entropy gain (nats) below which ``rule="info"`` finds no point worth
#: measuring: with two modes left the search gives up and says so.
INFO_GAIN_MIN = 0.01
#: A connected part of ``{P_M >= eps}`` holding at least this share of the belief is a
#: mode (reported when the search stops without separating two).
MODE_MASS = 0.05

#: Parameters a preset sets, and the defaults (no preset). Explicit parameters override
#: both. ``extent_tol = inf`` is "no extent rule".
DEFAULTS = dict(rule="axis", combine="product", sigma="calibrated", eps=0.1, area_tol=40.0,
                extent_tol=5.0, d=6.0, reach=12.0, tail_tol=10.0, credible_radius=3.0, credible_mass=0.95)
PRESETS = {"paper": dict(rule="nearest", combine="mean", sigma="noise", eps=0.7, area_tol=40.0,
                         extent_tol=float("inf"), d=12.7, reach=12.0, tail_tol=float("inf"),
                         credible_radius=float("inf"))}
SIGMA_RULES = ("auto", "noise", "calibrated")
#: ``sigma="calibrated"``: relative error of the model's predicted reading (the FEM field
#: at h = 1 cm against the truth mesh and the painted floor near the source), added in
#: quadrature to the calibrated noise; why 0.05 and not less, measured on the car:
#: ``docs/testbed.md`` (*Two defaults of the car's searches*).
CALIBRATED_MODEL_ERROR = 0.05
#: Stop with ``StopReason.UNREACHABLE`` once the belief puts less than this mass within
#: reach (:meth:`ReciprocityStrategy.within_reach`): the source is out of reach with 95 %
#: probability. Measured on the car in ``benchmarks/car_search.md``.
UNREACH_MASS = 0.05
#: Readings before the mass rule above applies (the first reading alone leaves a band).
UNREACH_MIN_READINGS = 2
#: Paths along the edges of the graded mesh are up to 1.8 times the straight line in the
#: open (``tests/reciprocity/test_spaces.py``): "within reach" allows twice `reach` along
#: the free region, which still excludes rooms closed off by walls.
PATH_SLACK = 2.0
#: ... and seen from there: a possible source outside the reachable set is within reach
#: only if its reading at some reachable point would be this many times the reading
#: noise (``reciprocity.strategies.reach``). A source behind a slit narrower than the car
#: reads as nothing wherever the car can go, however near it lies.
DETECT_SNR = 3.0
#: Once the belief puts more than this mass out of reach (from the second reading on),
#: rules ``"axis"`` and ``"reach"`` read where most of the belief within reach lies, to
#: find the source there or rule it out (the ``unreachable`` stop then comes sooner).
TEST_REACH_ABOVE = 0.5
#: Default ``max_steps``: readings of a search for one source, and for several.
MAX_STEPS = 30
#: Most surveys of a search, as a multiple of its `max_steps`.
SURVEY_CAP = 3
#: The error terms relative to the predicted reading, added in quadrature into the
#: likelihood's ``model_error`` (see :meth:`ReciprocityStrategy._error_terms`).
RELATIVE_TERMS = ("fixed", "discretisation", "platform", "strength")
MAX_STEPS_SEVERAL = 60
#: Default ``more_tol``: a search for several sources stops once the posterior
#: probability of one more source is below it (see :mod:`.multi_source`).
MORE_TOL = 0.05


class ReciprocityStrategy(Strategy):
    """Reciprocity search (Algorithm 1 of Landa et al.): adjoint solves, probability
    imaging, level sets.

    At each observation point ``z_k`` the reading ``I_k`` and the adjoint field
    ``v_k = c G(·, z_k)`` add the map ``p_k`` (eq. 7) to the imaging function ``P_M``
    (steps 9-11). The search stops when the region ``{P_M >= eps}`` is not empty and has
    area below `area_tol` (step 12) and, unless ``extent_tol = inf``, also lies within `extent_tol`
    of the estimate, and, unless ``tail_tol = inf``, every node with ``P_M >=
    TAIL_EPS`` lies within `tail_tol` of it (no second mode is left, even an unlikely
    one), and, unless ``credible_radius = inf``, the belief holds at least
    `credible_mass` within `credible_radius` of the estimate (a second mode just beyond
    the extent, which the area counts but cannot weigh, is not left at 14 % of the
    belief). Otherwise the next point is at least `d` from every earlier point,
    reachable at `clearance` from the walls, and chosen by `rule` (step 13):

    ``"nearest"`` (step 13 of the paper)
        in ``{v_k > I_k}``, nearest to ``z_k``; on a mesh "nearest" is resolved to one
        mesh size: among the nodes of that nearest ring the one with the largest score
        of ``"reach"`` below. When no admissible node has ``v_k > I_k``, the nearest
        admissible node.
    ``"reach"``
        the point with the largest score ``Σ_x w(x) exp(-|y - x|^2 / (2 reach^2))``,
        ``w`` the imaging function times the nodal area: the imaging mass within
        sensing reach of ``y``.
    ``"axis"`` (default)
        as ``"reach"`` while the imaging mass is spread wider than `reach` (its major
        standard deviation); once it is concentrated, the admissible point nearest to
        its major axis at ``max(d, 2 std)`` beyond its centre: level sets around a point
        on the axis cut across the elongated region.
    ``"info"``
        the point whose reading is expected to leave the smallest belief spread
        (:func:`~reciprocity.strategies.information.expected_spread`): INFO_SUPPORT
        belief points drawn by systematic resampling on a lattice of INFO_SPACING cm,
        their Green's functions ``G(·, x_i)`` (by reciprocity the predicted reading
        ``c G(y, x_i)`` at every lattice point ``y``; solved once per lattice point and
        kept per solver), scored at every admissible lattice point. A point between two
        modes whose predicted readings differ is preferred to one that cannot tell them
        apart. Once the belief sits in one lattice cell, as ``"axis"``.

    Every search stops at once with ``StopReason.UNREACHABLE`` when no point it may
    measure at is reachable, when the whole region of possible sources lies farther than
    `reach` (sensing reach; a source in a room closed off by walls is never within it)
    from every reachable point, or, from the second reading on, when the belief holds
    less than UNREACH_MASS within reach (a source behind a gap narrower than the car:
    the region stays wide, because readings through the gap are weak, but the readings
    the car can take rule out every source it could reach). Within reach means within
    `reach` of a reachable point and seen from one: a reading on the reachable part's edge
    would be at least DETECT_SNR times the noise (:meth:`within_reach`,
    :mod:`reciprocity.strategies.reach`). Once more than TEST_REACH_ABOVE of the belief
    lies out of reach, rules ``"axis"`` and ``"reach"`` read where most of the belief
    within reach lies, to find the source there or rule it out. The summary keys
    ``mass_out_of_reach`` and ``reachable_area`` (cm²) say where the search stood. When
    the belief has two or more separate modes in ``{P_M >= eps}`` (each holding at least
    MODE_MASS of it), a search that reaches `max_steps` says how many and how far apart
    the two largest are, and the ``"info"`` rule, when no admissible point is expected to
    gain INFO_GAIN_MIN nats, stops with ``StopReason.GAVE_UP`` and says so, rather than
    stop on one mode.

    **Unknown obstacles** (a task with ``map: "unknown"``: the strategy is told the outer
    boundary, or a partial map, and reads the platform's range scans): a
    :class:`~reciprocity.strategies.mapping.MapKeeper` turns the scans into an occupancy
    grid; the field is computed on the believed arena (unknown space free: optimistic),
    re-meshed only when the believed walls change (the solver and its factorization are
    reused otherwise) with every reading imaged again on the new mesh; the model error
    grows with the share of the arena not yet seen; observation points lie in seen-free
    space; and while most of the belief lies in unseen space the next point is the
    frontier point that best serves it (see :mod:`reciprocity.strategies.mapping`),
    surveyed (scanned, with no reading: `survey`) where the platform takes surveys.

    **The paper's settings** (``preset="paper"``): ``rule="nearest"``,
    ``combine="mean"`` (eq. 8), ``sigma="noise"`` (eq. 7 with ``sigma^2`` the variance
    of the measurement noise, as the paper states: the noise of one reading as the
    platform takes it, in signal units; the paper's 12 is ADC counts per raw 30 Hz
    sample, which is 8.4-9.2 signal units on the simulated car reading one raw sample,
    and the world's ``noise`` on the point observer), and no extent rule and no tail
    rule. The paper gives no values for ``eps``, ``A_eps`` and ``d``; these are ours:
    ``d = 12.7 cm``, one spacing of the paper's bank of value functions (the car measures
    at the bank's lattice point nearest to the requested one, and with a smaller ``d``
    the next point snaps back to the lattice point just read and the car never leaves its
    start); ``eps = 0.7`` with ``A_eps = 40 cm^2`` (a disk of radius 3.6 cm, inside the
    5 cm success radius): re-evaluated offline on recorded runs of the car as the paper
    ran it, eq. (8) with ``eps = 0.1`` never stops, and ``eps = 0.7`` is the pair that
    stops nearest the paper's 7 readings (measured in ``benchmarks/landa_paper_preset.md``
    and ``docs/papers/landa2020.md``). Choices the
    paper leaves open: the first point is the start; "nearest" and the tie-break are as above; the estimate is the maximiser of
    ``P_M`` refined below the mesh size (:meth:`ImagingMap.estimate`); the loop
    condition of Algorithm 1 (``while 0 <= A < A_eps``) is read as "until ``A <
    A_eps``". Parameters given together with a preset override it (``preset="paper",
    sigma=17`` is the paper with ``sigma = 17``).

    **Deviations of the defaults from the paper** (each measured, with the experiments
    that justify it, in ``benchmarks/reciprocity_rules.md``):

    - ``combine="product"`` (the likelihood of all readings) instead of eq. (8)'s mean;
    - ``sigma="calibrated"``: ``sqrt 2`` times the reading noise (eq. (7) is
      ``exp(-r^2/sigma^2)``); on a platform that reports its own calibrated noise (the
      car), that noise, its shared part as one offset, and CALIBRATED_MODEL_ERROR of the
      predicted reading as the model's own error;
    - ``rule="axis"`` instead of step 13's nearest point;
    - the extent rule (``extent_tol = 5 cm``);
    - the tail rule (``tail_tol = 10 cm``);
    - the credible rule (95 % of the belief within 3 cm of the estimate);
    - the likelihood's error terms (`model_error`), added in quadrature: the belief's
      discretisation, estimated from its own solver by halving the mesh
      (:func:`~reciprocity.fem.discretisation.discretisation_error`), and the platform's
      model error above.

    Parameters
    ----------
    preset : {None, "paper"}
        Start from the paper's settings instead of the defaults (see above).
    rule : {"axis", "reach", "nearest", "info"}
        Next-point rule (see above).
    combine : {"mean", "product"}
        Combination of the maps (eq. 8, or the normalised likelihood).
    sigma : float or {"calibrated", "auto", "noise"}
        ``sigma`` of eq. (7), signal units. ``"auto"``: ``sqrt 2`` times the noise the
        world states (its nominal ``noise``, else PAPER_NOISE); ``"noise"``: that noise
        itself; ``"calibrated"`` (default): where the platform reports its own
        ``reading_noise`` (the car's calibration:
        :meth:`arenas.sensor.Calibration.signal_noise_parts` of one 1 s dwell), ``sqrt 2``
        times its independent part, with its shared part ``reading_bias`` imaged as one
        offset of all readings and CALIBRATED_MODEL_ERROR as the model's relative error
        (:class:`~reciprocity.imaging.ImagingMap` ``offset_sd``, ``model_error``); else as
        ``"auto"``. Each at least MIN_NOISE.
    eps : float
        Threshold ``0 < eps < 1`` defining the region of possible sources.
    area_tol : float
        ``A_eps``, cm^2: stop when the region is smaller.
    extent_tol : float
        Largest distance (cm) from the estimate to the region for stopping; ``inf``
        for none.
    tail_tol : float
        Largest distance (cm) from the estimate to a node with ``P_M >= TAIL_EPS`` for
        stopping; ``inf`` for none.
    credible_radius : float
        Radius (cm) within which the belief must hold `credible_mass` of its mass around
        the estimate for stopping; ``inf`` for no credible rule.
    credible_mass : float
        Share of the belief (0 to 1) the credible rule asks for.
    d : float
        Minimum separation of observation points, cm.
    reach : float
        Kernel length (cm) of the ``"reach"`` score: about the distance at which the
        signal still stands out of the noise.
    max_steps : int, optional
        Stop after this many measurements (default MAX_STEPS, or MAX_STEPS_SEVERAL when
        the search looks for several sources).
    clearance : float
        Observation points keep this distance (cm) from walls.
    strength : float or "arena" or None
        Source strength: a number, ``"arena"`` for the nominal strength (the paper
        assumes it known), or None for unknown (see `strength_range`).
    strength_range : "decade" or (float, float) or "fit"
        With ``strength=None``: the strength is integrated out of the likelihood over a
        log-uniform prior on ``(lo, hi)``; ``"decade"`` (default) is a tenth to ten times the
        world's nominal strength; ``"fit"`` fits it per point by least squares instead
        (compared in ``benchmarks/reciprocity_rules.md``). Only with ``combine="product"``;
        the mean keeps the fit.
    model_error : "estimate" or float
        The model's relative error of a predicted reading, with ``combine="product"`` and a
        known strength: ``"estimate"`` (default) adds in quadrature the belief's
        discretisation (estimated from the solver, about 0.7 % at h = 1 cm) and, on a
        platform with its own calibration, CALIBRATED_MODEL_ERROR; a number replaces
        both. The terms used are kept in ``error_terms`` after :meth:`start`.
    strength_error : float
        Relative standard deviation of the stated strength (0: exactly known), added in
        quadrature to `model_error`: a world stronger or weaker than stated moves every
        reading by that fraction.
    source_clearance : "task" or float
        The prior keeps every possible source at least this far (cm, less one mesh size)
        from the walls: ``"task"`` (default) takes the task's public ``source_clearance``
        (a campaign's ``random_source`` draws sources ``SOURCE_CLEARANCE`` cm off the
        walls and says so; 0, anywhere, when the task says nothing). A source a few mm
        from an absorbing wall reads as almost nothing, so without it the belief keeps
        mass along every wall until readings are taken next to each stretch
        (``benchmarks/car_search.md``).
    survey : bool
        On an unknown map, explore by :class:`~reciprocity.intents.Survey` (go to the
        frontier point and scan, taking no reading) where the platform takes it, instead
        of reading at every frontier point: a reading far from the belief carries little
        about the source, while the scan there is what the search lacks (the episode's
        ``surveys`` counts them; at most SURVEY_CAP times `max_steps`).
    h : float
        Mesh size (cm) of the solver built by :meth:`start` when none is given.
    solver : GreenSolver, optional
        A prebuilt solver for the arena (shared across episodes: factorized once).
    max_sources : int, optional
        How many sources there may be; default the task's ``max_sources`` (1 unless the
        scenario gives ``sources``). Above 1 the search finds them all without knowing
        how many there are (:mod:`~reciprocity.strategies.multi_source`): the first as
        with one source, then one more at a time on the readings the found ones leave
        unexplained, until a further source is improbable; the summary then has
        ``estimates`` and ``estimates_sd``.
    more_tol : float
        Several sources: stop once the posterior probability of one more source (even
        prior odds) is below this.
    survey_travel : float, optional
        Several sources: while surveying for one more source, discount a point's hidden
        mass within reach by ``exp(-distance / survey_travel)`` from the last reading
        (cm): fewer cm driven for a few more readings (``benchmarks/several_sources.md``).
        None (default): no discount.
    survey_reach : "reach" or float
        Several sources: one more is sought where the search for one source would call it
        within reach (default ``"reach"``: `reach` in a straight line from a point the
        observer can reach, PATH_SLACK times it along the free region), or within this
        distance (cm, along the free region) of the points it can reach. A wider survey
        finds sources the platform cannot reach but can sense, at the cost of readings
        that cannot exclude what hides behind walls it cannot pass (measured on the car:
        ``benchmarks/several_sources.md``).

    Examples
    --------
    >>> s = ReciprocityStrategy(preset="paper", sigma=17.0)
    >>> s.rule, s.combine, s.sigma, s.extent_tol, s.tail_tol
    ('nearest', 'mean', 17.0, inf, inf)
    """

    name = "reciprocity"
    senses = ("scan",)

    def __init__(self, *, preset: str | None = None, rule: str | None = None,
                 combine: str | None = None, sigma=None, eps: float | None = None,
                 area_tol: float | None = None, extent_tol: float | None = None,
                 d: float | None = None, reach: float | None = None,
                 tail_tol: float | None = None, credible_radius: float | None = None,
                 credible_mass: float | None = None, max_steps: int | None = None,
                 clearance: float = 3.0, strength="arena", strength_range="decade",
                 h: float = 1.0, solver: GreenSolver | None = None, max_sources: int | None = None,
                 more_tol: float = MORE_TOL, survey_travel: float | None = None,
                 survey_reach: float | str = "reach", model_error: float | str = "estimate",
                 strength_error: float = 0.0, survey: bool = True, source_clearance: float | str = "task"):
        super().__init__()
        if preset is not None and preset not in PRESETS:
            raise SearchError(f"preset must be one of {tuple(PRESETS)} or None; got {preset!r}")
        given = dict(rule=rule, combine=combine, sigma=sigma, eps=eps, area_tol=area_tol,
                     extent_tol=extent_tol, d=d, reach=reach, tail_tol=tail_tol,
                     credible_radius=credible_radius, credible_mass=credible_mass)
        p = {**DEFAULTS, **PRESETS.get(preset, {}), **{k: v for k, v in given.items() if v is not None}}
        if not 0 < p["eps"] < 1:
            raise SearchError(f"eps must lie strictly between 0 and 1; got {p['eps']!r}")
        for key in ("area_tol", "d", "reach"):
            if not np.isfinite(p[key]) or p[key] <= 0:
                raise SearchError(f"{key} must be a positive number; got {p[key]!r}")
        if not np.isfinite(h) or h <= 0:
            raise SearchError(f"h must be a positive number; got {h!r}")
        if not 0 < p["credible_mass"] < 1:
            raise SearchError(f"credible_mass must lie strictly between 0 and 1; got {p['credible_mass']!r}")
        for key in ("extent_tol", "tail_tol", "credible_radius"):
            if not (p[key] > 0):
                raise SearchError(f"{key} must be a positive length in cm, or inf for none; "
                                  f"got {p[key]!r}")
        if p["sigma"] not in SIGMA_RULES and (isinstance(p["sigma"], str) or not np.isfinite(p["sigma"])
                                              or p["sigma"] <= 0):
            raise SearchError(f"sigma must be a positive number or one of {SIGMA_RULES}; "
                              f"got {p['sigma']!r}")
        if clearance < 0:
            raise SearchError(f"clearance must be >= 0 cm; got {clearance!r}")
        if max_steps is not None and (isinstance(max_steps, bool) or int(max_steps) != max_steps
                                      or int(max_steps) < 1):
            raise SearchError(f"max_steps must be a whole number >= 1; got {max_steps!r}")
        if max_sources is not None and (isinstance(max_sources, bool) or int(max_sources) != max_sources
                                        or not 1 <= int(max_sources) <= MAX_SOURCES):
            raise SearchError(f"max_sources must be a whole number from 1 to {MAX_SOURCES}, or None for "
                              f"the task's; got {max_sources!r}")
        if isinstance(more_tol, bool) or not isinstance(more_tol, (int, float)) or not 0 < more_tol < 1:
            raise SearchError(f"more_tol must be a probability in (0, 1); got {more_tol!r}")
        if isinstance(strength_range, str):
            if strength_range not in ("decade", "fit"):
                raise SearchError(f"strength_range must be 'decade', 'fit' or (lo, hi); got {strength_range!r}")
        else:
            try:
                lo, hi = (float(v) for v in strength_range)
            except (TypeError, ValueError):
                raise SearchError(f"strength_range must be 'decade', 'fit' or (lo, hi); "
                                  f"got {strength_range!r}") from None
            if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
                raise SearchError(f"strength_range needs 0 <= lo < hi; got {strength_range!r}")
            strength_range = (lo, hi)
        if p["rule"] not in RULES:
            raise SearchError(f"rule must be one of {RULES}; got {p['rule']!r}")
        if p["combine"] not in COMBINATIONS:
            raise SearchError(f"combine must be one of {COMBINATIONS}; got {p['combine']!r}")
        self.preset = preset
        self.rule, self.combine = p["rule"], p["combine"]
        self.sigma = p["sigma"] if p["sigma"] in SIGMA_RULES else float(p["sigma"])
        self.eps, self.area_tol, self.extent_tol = float(p["eps"]), float(p["area_tol"]), float(p["extent_tol"])
        self.d, self.reach, self.tail_tol = float(p["d"]), float(p["reach"]), float(p["tail_tol"])
        self.credible_radius, self.credible_mass = float(p["credible_radius"]), float(p["credible_mass"])
        self._max_steps = None if max_steps is None else int(max_steps)
        self.max_steps, self.clearance = self._max_steps or MAX_STEPS, float(clearance)
        self.max_sources = None if max_sources is None else int(max_sources)
        self.more_tol = float(more_tol)
        if survey_travel is not None and (isinstance(survey_travel, bool) or not isinstance(survey_travel, (int, float))
                                          or not 0 < survey_travel < float("inf")):
            raise SearchError(f"survey_travel must be a positive length in cm, or None; got {survey_travel!r}")
        self.survey_travel = None if survey_travel is None else float(survey_travel)
        if survey_reach != "reach" and (isinstance(survey_reach, (bool, str)) or not isinstance(survey_reach, (int, float))
                                        or not 0 < survey_reach < float("inf")):
            raise SearchError(f"survey_reach must be a positive length in cm or 'reach'; got {survey_reach!r}")
        self.survey_reach = survey_reach if survey_reach == "reach" else float(survey_reach)
        if model_error != "estimate" and (isinstance(model_error, (bool, str)) or not isinstance(model_error, (int, float))
                                          or not 0 <= model_error < 1):
            raise SearchError(f"model_error must be 'estimate' or a fraction in [0, 1); got {model_error!r}")
        self.model_error = model_error if model_error == "estimate" else float(model_error)
        if isinstance(strength_error, bool) or not isinstance(strength_error, (int, float)) \
                or not 0 <= strength_error < 1:
            raise SearchError(f"strength_error must be a fraction in [0, 1); got {strength_error!r}")
        self.strength_error = float(strength_error)
        if not isinstance(survey, bool):
            raise SearchError(f"survey must be true or false; got {survey!r}")
        self.survey = survey
        if source_clearance != "task" and (isinstance(source_clearance, (bool, str))
                                           or not isinstance(source_clearance, (int, float))
                                           or not 0 <= source_clearance < np.inf):
            raise SearchError(f"source_clearance must be 'task' or a distance >= 0 cm; got {source_clearance!r}")
        self.source_clearance = source_clearance if source_clearance == "task" else float(source_clearance)
        self.strength, self.h, self.solver = strength, float(h), solver
        self.strength_range = strength_range

    def params(self) -> dict:
        return dict(preset=self.preset, rule=self.rule, reach=self.reach, eps=self.eps,
                    area_tol=self.area_tol, extent_tol=self.extent_tol, tail_tol=self.tail_tol, d=self.d,
                    credible_radius=self.credible_radius, credible_mass=self.credible_mass,
                    sigma=self.sigma, sigma_used=getattr(self, "sigma_used", None),
                    max_steps=self.max_steps, clearance=self.clearance, combine=self.combine,
                    strength=self.strength if not isinstance(self.strength, float) else float(self.strength),
                    strength_range=self.strength_range if isinstance(self.strength_range, str)
                    else list(self.strength_range),
                    max_sources=getattr(self, "sources_bound", self.max_sources), more_tol=self.more_tol,
                    survey_travel=self.survey_travel, survey_reach=self.survey_reach,
                    model_error=self.model_error, strength_error=self.strength_error, survey=self.survey,
                    model_error_used=getattr(self, "_model_error", None),
                    source_clearance=self.source_clearance,
                    source_clearance_used=getattr(self, "clearance_used", None),
                    h=self.h if self.solver is None else self.solver.h)

    def reading_sigma(self, nominal: dict) -> float:
        """``sigma`` of eq. (7) for a world described by `nominal` (signal units)."""
        if not isinstance(self.sigma, str):
            return self.sigma
        noise = nominal.get("noise", PAPER_NOISE)
        if self.sigma == "calibrated" and "reading_noise" in nominal:
            noise = nominal["reading_noise"]
            # the shared part of the calibrated noise is imaged as one offset (offset_sd)
            noise = np.sqrt(max(noise ** 2 - self.reading_bias(nominal) ** 2, 0.0))
        noise = max(float(noise), MIN_NOISE)
        return noise if self.sigma == "noise" else np.sqrt(2.0) * noise

    def reading_bias(self, nominal: dict) -> float:
        """Standard deviation of an offset shared by every reading (signal units): the
        platform's ``reading_bias`` with ``sigma="calibrated"``, else 0."""
        if self.sigma != "calibrated" or "reading_noise" not in nominal:
            return 0.0
        return float(nominal.get("reading_bias", 0.0))

    def _error_terms(self, nominal: dict, offset: float) -> dict:
        """The likelihood's error terms (see `model_error`): the reading noise and shared
        offset (signal units), and the relative errors of a predicted reading, each a
        fraction, added in quadrature: the belief's discretisation (estimated from the
        solver, :func:`~reciprocity.fem.discretisation.discretisation_error`), the
        platform's model (the car's floor print and sensor curve), the stated strength."""
        terms = {"noise": self.sigma_used / np.sqrt(2.0), "offset": float(offset)}
        if not isinstance(self.model_error, str):
            terms["fixed"] = float(self.model_error)
        else:
            terms["discretisation"] = discretisation_error(self.solver).relative \
                if self.solver.order == 1 else 0.0
            calibrated = self.sigma == "calibrated" and "reading_noise" in nominal
            terms["platform"] = CALIBRATED_MODEL_ERROR if calibrated else 0.0
        terms["strength"] = float(self.strength_error)
        return terms

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        arena, pose = ctx.arena, ctx.start
        self.mapping = MapKeeper.from_nominal(ctx.nominal)            # map: unknown (issue 23)
        if self.mapping is not None:
            self.notes.update(remesh_failures=0, surveys=0)
        geometry = arena.without_scenario() if self.mapping is None else self.mapping.arena
        if self.solver is None or self.solver.arena.without_scenario() is not geometry:
            self.solver = cached_solver(geometry, self.h)
        c = ctx.nominal.get("strength", arena.strength) if self.strength == "arena" else self.strength
        self.sigma_used = float(self.reading_sigma(ctx.nominal))
        prior = self._prior_range(ctx) if c is None else None
        product = prior is None and self.combine == "product"
        offset = self.reading_bias(ctx.nominal) if product else 0.0
        self.error_terms = self._error_terms(ctx.nominal, offset) if product else {}
        model_error = float(np.sqrt(sum(v * v for k, v in self.error_terms.items() if k in RELATIVE_TERMS)))
        self._model_error = model_error
        if self.mapping is not None and product:
            model_error = self.mapping.model_error(model_error)
        self.imaging = ImagingMap(self.solver, self.sigma_used, strength=c, combine=self.combine,
                                  strength_range=prior, offset_sd=offset, model_error=model_error)
        if self.mapping is not None:
            self.imaging = self.mapping.imaging(self.imaging)
        self.space = self._space(geometry)
        self.clearance_used = float(ctx.nominal.get("source_clearance", 0.0)) \
            if self.source_clearance == "task" else self.source_clearance
        self._keep_off_walls(self.imaging)
        self.rng = ctx.rng
        self._reachable = self.space.reachable_from(pose[:2], self.clearance)
        self._sensing = self._reachable.copy()      # where readings could be taken from
        self._next = np.asarray(pose[:2], dtype=float)
        self._here = self._next.copy()
        self.n_surveys, self._survey_next = 0, False
        self._can_survey = self.survey and "survey" in ctx.intents
        self._no_survey = np.zeros(0, dtype=bool)
        self._node_area = self.space.cell_areas
        self._far, self._far_count = np.ones(len(self.space.points), dtype=bool), 0
        self._lattice = lattice_greens(self.solver, max(INFO_SPACING, self.solver.h)) \
            if self.rule == "info" else None
        self._start_book(ctx, c)
        self._check_reachable()

    def _keep_off_walls(self, imaging: ImagingMap) -> None:
        """The prior of `imaging` (on :attr:`space`'s nodes): no source nearer the
        (believed) walls than the source clearance in use, less one mesh size, and on an
        unknown map one more cell of its grid (believed walls reach that far into the free
        space). A clearance that would leave no node leaves the prior as it is."""
        if not self.clearance_used > 0:
            return
        margin = self.solver.h + (self.mapping.grid.cell if self.mapping is not None else 0.0)
        allowed = self.space.wall_distance >= self.clearance_used - margin
        if allowed.any():
            imaging.restrict(allowed)

    def _start_book(self, ctx: SearchContext, strength) -> None:
        """Several sources: a :class:`~reciprocity.strategies.multi_source.SourceBook` when
        the task allows more than one (its ``max_sources``, or the parameter)."""
        self.sources_bound = int(self.max_sources or ctx.nominal.get("max_sources", 1))
        self.book = None
        self.max_steps = self._max_steps or (MAX_STEPS if self.sources_bound == 1 else MAX_STEPS_SEVERAL)
        if self.sources_bound > 1:
            from .multi_source import SourceBook
            nominal = strength if strength is not None else ctx.nominal.get("strength", ctx.arena.strength)
            self.book = SourceBook(self.imaging, float(nominal), self.sources_bound, self.space.wall_distance)

    @property
    def estimates(self) -> np.ndarray | None:
        """Every source found (k, 2), cm, where the task allows several; else None."""
        book = getattr(self, "book", None)
        if book is None:
            return None
        return np.array(book.found, dtype=float).reshape(-1, 2)

    @property
    def estimates_sd(self) -> np.ndarray | None:
        """The standard deviation (cm) of the belief about each of :attr:`estimates`."""
        book = getattr(self, "book", None)
        return None if book is None else np.array(book.spread, dtype=float)

    @property
    def belief(self) -> ImagingMap:
        """The strategy's belief: its imaging map (a :class:`~reciprocity.beliefs.Belief`)."""
        return self.imaging

    def _prior_range(self, ctx: SearchContext) -> tuple[float, float] | None:
        """The strength prior ``(lo, hi)`` for an unknown strength, or None to fit it."""
        if self.strength_range == "fit":
            return None
        if self.strength_range == "decade":
            nominal = ctx.nominal.get("strength")
            if nominal is None or not np.isfinite(nominal) or nominal <= 0:
                return None
            return (float(nominal) / 10.0, float(nominal) * 10.0)
        return self.strength_range

    def _space(self, geometry) -> MeshSpace:
        """The candidate points: the nodes of the solver's own P1 mesh."""
        space = mesh_space(geometry, self.solver.h)
        if self.solver.order != 1 or space.points.shape != self.solver.nodes.shape or \
                not np.allclose(space.points, self.solver.nodes, atol=1e-9):
            raise SearchError("the reciprocity strategy needs a P1 solver (order=1) on the arena's mesh")
        return space

    def _remesh(self, position) -> None:
        """The believed walls changed (``map: unknown``): the solver on the new believed
        arena (cached: a map seen before is not factorized again), the same readings
        imaged on it with the model error of the map now, and the space and reachable set
        on its mesh, less the neighbourhoods of the targets the platform refused while
        the walls near them stay (:meth:`~reciprocity.strategies.mapping.MapKeeper.refused`).
        A re-mesh that fails (a geometry Triangle cannot mesh, out of memory) keeps the
        last good mesh, solver and space, and is counted in ``notes["remesh_failures"]``
        (the episode summary's ``remesh_failures``, with the last ``remesh_note``). Reachable: every node at `clearance` from the
        believed walls, whatever the gaps between them (believed walls are thicker than
        the true ones, so a gap the map closes at `clearance` may be open, and the
        believed free region is connected by construction)."""
        geometry = self.mapping.arena
        try:
            # not the process-wide cache: a believed map is not met again, and eight stale
            # solvers of up to ~100 k nodes each held RSS near 2 GB
            space = MeshSpace(geometry, self.h)
            solver = GreenSolver(geometry, h=self.h, order=1, mesh=space).factorize()
        except (MeshError, ArenaError, MemoryError) as exc:
            self.notes["remesh_failures"] += 1
            self.notes["remesh_note"] = (f"re-mesh of believed map {self.mapping.revision} failed "
                                         f"({str(exc)[:200]}); kept the last good mesh")
            return
        self.solver = solver
        base = self.imaging if self.book is None else self.book.raw
        error = self.mapping.model_error(self._model_error) if base.combine == "product" \
            and base.strength_range is None else base.model_error
        if self.book is None:
            self.imaging = self.mapping.imaging(self.imaging.on(self.solver, model_error=error))
            self.space = space
            self._keep_off_walls(self.imaging)
        else:       # several sources: every reading on the new mesh, the found sources kept
            raw = self.mapping.imaging(base.on(self.solver, model_error=error))
            self.space = space
            self._keep_off_walls(raw)
            self.imaging = self.book.rebase(raw, self.space.wall_distance)
        self._node_area = self.space.cell_areas
        self._reachable = self.space.admissible(self.clearance)
        self._sensing = self._reachable.copy()         # refusals do not narrow what is read from
        for point, radius in self.mapping.refused():
            self._reachable &= ~self.space.around(point, radius)
        self._far, self._far_count, self._near_key = np.ones(len(self.space.points), dtype=bool), 0, None
        self._support_key = None
        self._lattice = lattice_greens(self.solver, max(INFO_SPACING, self.solver.h)) \
            if self.rule == "info" else None

    def propose(self) -> Measure | Survey | None:
        if self.done:
            return None
        return (Survey if self._survey_next else Measure)(self._next.copy())

    def _surveyed(self, observations, intent) -> None:
        """After a :class:`~reciprocity.intents.Survey`: take in its scans, re-mesh when the
        believed walls changed, and choose the next point (no reading, no step of the
        search). A survey that showed nothing new rules its neighbourhood out of later
        surveys."""
        self.n_surveys += 1
        self.notes["surveys"] = self.n_surveys
        self._here = np.asarray(observations[0].position if observations else intent.point, dtype=float)
        if self.mapping.update(observations):
            self._remesh(self._here)
        elif len(self._no_survey) == len(self.space.points):
            self._no_survey |= self.space.around(self._here, self.mapping.lidar["range"] / 2.0)
        self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def observe(self, observations, intent, agent: int = 0) -> None:
        if isinstance(intent, Survey):
            self._surveyed(observations, intent)
            return
        obs = observations[0]
        self._here = np.asarray(obs.position, dtype=float)
        if self.mapping is not None and self.mapping.update(observations):
            self._remesh(obs.position)
        self.n_measurements += 1
        self.n_samples += 1
        if self.book is None:
            self.imaging.update(obs)                                   # steps 9-11
        else:
            self.imaging = self.book.add(obs)
        area = self.imaging.area(self.eps)                             # step 12
        estimate = self.imaging.estimate()
        self.status = Status(estimate, area)
        region = self.imaging.nodes[self.region()]
        extent = float(np.hypot(*(region - estimate).T).max()) if len(region) else 0.0
        self.status.extra["region_extent"] = extent
        # an empty region (eq. (8)'s mean below eps everywhere) is not a found source
        converged = len(region) > 0 and area < self.area_tol and extent <= self.extent_tol \
            and self._tail_within(estimate, self.imaging)
        if self.book is not None:
            self._observe_several(converged, estimate)
        elif converged:
            self.stop(StopReason.CONVERGED, "region smaller than area_tol")
        elif self.n_measurements >= self.max_steps:
            self._stop_at_cap()
        else:
            self._check_reachable()
            if not self.done:
                self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def _observe_several(self, converged: bool, estimate: np.ndarray) -> None:
        """The search for several sources after a reading: accept a converged source,
        decide the number of sources when nothing more can hide, or choose the next point."""
        book = self.book
        if converged and not book.surveying:
            from .multi_source import spread_of
            book.accept(estimate, spread_of(self.imaging))
            self.imaging = book.active
        found = len(book.found)
        if found:
            self.status = Status(book.found[0].copy(), self.status.region_area,
                                 extra=dict(self.status.extra, estimates=[f.tolist() for f in book.found]))
        if book.surveying:
            more = 0.0 if book.full else book.more_probability(self._survey_support(), self._node_area,
                                                                self._unseen())
            self.status.extra["p_more"] = more
            if more < self.more_tol and book.next_unconfirmed(self._converged) is None:
                why = "as many as the task allows" if book.full else f"probability of one more {more:.3f} < more_tol"
                self.notes.update(sources_dropped=book.dropped, sources_relocated=book.relocated)
                if not book.full:       # the unreachable rule for the next source
                    out = self._more_out_of_reach()
                    self.notes["more_out_of_reach"] = round(out, 4)
                    if out >= 1.0 - UNREACH_MASS:
                        why += f"; one more lies out of reach with probability {out:.3f}"
                self.stop(StopReason.CONVERGED, f"{found} source{'s' if found > 1 else ''} found; {why}")
            self.imaging = book.active
        if self.done:
            pass
        elif self.n_measurements >= self.max_steps:
            self._stop_at_cap()
        else:
            if not book.found:        # the first source: as the search for one
                self._check_reachable()
            elif not self._reachable.any():
                self.stop(StopReason.UNREACHABLE, "no observation point is reachable")
            if not self.done:
                self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def _more_out_of_reach(self) -> float:
        """The posterior probability of one more source out of reach: of one more anywhere
        in the free region, times the share of its mass outside :meth:`_survey_support`."""
        book, unseen = self.book, self._unseen()
        everywhere = np.ones(len(self.space.points), dtype=bool)
        total = float(book.hidden(everywhere, self._node_area, unseen).sum())
        if total <= 0:
            return 0.0
        within = float(book.hidden(self._survey_support(), self._node_area, unseen).sum())
        return book.more_probability(everywhere, self._node_area, unseen) * max(0.0, 1.0 - within / total)

    def _converged(self, im: ImagingMap) -> bool:
        """Step 12 for map `im`: its region below `area_tol`, within `extent_tol` of its
        estimate, and its tail within `tail_tol`."""
        estimate = im.estimate()
        region = im.nodes[im.values() >= self.eps]
        extent = float(np.hypot(*(region - estimate).T).max()) if len(region) else 0.0
        return len(region) > 0 and im.area(self.eps) < self.area_tol and extent <= self.extent_tol \
            and self._tail_within(estimate, im)

    def _tail_within(self, estimate: np.ndarray, im: ImagingMap) -> bool:
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

    def region(self) -> np.ndarray:
        """Mask of the nodes in the region of possible sources ``{P_M >= eps}`` (every
        node before the first reading)."""
        if not self.imaging.n:
            return np.ones(len(self.space.points), dtype=bool)
        return self.imaging.values() >= self.eps

    def modes(self) -> list[tuple[float, np.ndarray]]:
        """The connected parts of ``{P_M >= eps}`` holding at least MODE_MASS of the
        belief: ``(mass, peak cm)`` (the peak: the part's node of largest ``P_M``),
        heaviest first."""
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components
        inside = self.region()
        tri = self.space.triangles
        tri = tri[inside[tri].all(axis=1)]
        n = len(inside)
        i, j = np.concatenate([tri[:, 0], tri[:, 1]]), np.concatenate([tri[:, 1], tri[:, 2]])
        _, label = connected_components(coo_matrix((np.ones(i.size), (i, j)), shape=(n, n)),
                                        directed=False)
        w, P = self.imaging.weights(), self.imaging.values()
        out = []
        for lab in np.unique(label[inside]):
            part = np.flatnonzero(inside & (label == lab))
            mass = float(w[part].sum())
            if mass >= MODE_MASS:
                out.append((mass, self.space.points[part[np.argmax(P[part])]].copy()))
        return sorted(out, key=lambda m: -m[0])

    def _modes_note(self) -> str:
        """``"; N modes, the two largest D cm apart"`` when the belief has several modes."""
        modes = self.modes()
        if len(modes) < 2:
            return ""
        gap = float(np.hypot(*(modes[0][1] - modes[1][1])))
        return f"; {len(modes)} modes, the two largest {gap:.0f} cm apart"

    def _stop_at_cap(self) -> None:
        self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} measurements{self._modes_note()}")

    def _check_reachable(self) -> None:
        """Stop (UNREACHABLE) when nothing can be measured or no possible source is within
        `reach` of a reachable point."""
        if not self._reachable.any():
            self.stop(StopReason.UNREACHABLE, "no observation point is reachable")
            return
        near = self._near_reachable()
        region = self.region()
        if region.any() and not (region & near).any():     # an empty region tells nothing
            self.stop(StopReason.UNREACHABLE, "the whole region of possible sources "
                                              f"({region.sum()} nodes) lies out of reach")
            return
        if self.imaging.n:
            w = self.imaging.weights()
            within = float(w[near].sum() / w.sum())
            self.notes.update(mass_out_of_reach=round(max(0.0, 1.0 - within), 4),
                              reachable_area=round(float(self._node_area[self._reachable].sum()), 1))
            if self.imaging.n >= UNREACH_MIN_READINGS and within < UNREACH_MASS:
                self.stop(StopReason.UNREACHABLE, f"the source lies out of reach with probability "
                                                  f"{1.0 - within:.3f} (belief mass within {self.reach:g} cm "
                                                  f"of a reachable point and seen from it: {within:.3f}; "
                                                  f"reachable part {self.notes['reachable_area']:.0f} cm²)")

    def figure_record(self) -> dict:
        """What the figures draw: ``imaging`` (the map now: the video's), ``steps`` (the map
        of every reading as one source, whose prefixes give each step's map), ``eps``; with
        one source ``within_reach`` (:meth:`within_reach`); with several, ``residual`` (the
        map of one more source); on an unknown map ``mapping``: what rebuilds the believed
        map and its imaging after each step (:func:`reciprocity.viz.mapping.map_replay`)."""
        record = dict(imaging=self.imaging, eps=self.eps)
        if self.book is None:
            record.update(steps=self.imaging, within_reach=self.within_reach())
        else:
            record.update(steps=self.book.raw, residual=self.book.active)
        if self.mapping is not None:
            record["mapping"] = dict(known=self.mapping.grid.known, lidar=self.mapping.lidar,
                                     cell=self.mapping.grid.cell, h=self.h, model_error=self._model_error)
        return record

    def within_reach(self) -> np.ndarray:
        """Mask of the nodes within reach: the reachable part and the possible sources a
        reading there would see (within `reach` cm and above DETECT_SNR times the noise;
        :mod:`reciprocity.strategies.reach`). The rest is what an ``unreachable`` stop
        judges out of reach; the nodes are those of ``imaging``."""
        return self._near_reachable().copy()

    def _unseen(self) -> np.ndarray | None:
        """With an unknown map, the nodes its range sensor has not seen yet; else None."""
        if getattr(self, "mapping", None) is None:
            return None
        return ~self.mapping.grid.seen_at(self.space.points)

    def _survey_support(self) -> np.ndarray:
        """Where one more source is sought (see `survey_reach`)."""
        if self.survey_reach == "reach":
            return self._near_reachable()
        key = self._reachable.tobytes()
        if getattr(self, "_support_key", None) != key:
            self._support = self.space.within_path(self._reachable, float(self.survey_reach))
            self._support_key = key
        return self._support

    def _near_reachable(self) -> np.ndarray:
        key = (id(self.space), self._reachable.tobytes())
        if getattr(self, "_near_key", None) != key:
            # within reach in a straight line, and along the free region (mesh edges, at
            # most PATH_SLACK times longer than the straight line in the open): a source
            # in a closed-off room is not within reach of the other side of its wall
            from scipy.spatial import cKDTree
            pts = self.space.points
            dist = cKDTree(pts[self._reachable]).query(pts, distance_upper_bound=self.reach)[0]
            path = self.space.within_path(self._reachable, PATH_SLACK * self.reach)
            self._near, self._near_key, self._seen_green = np.isfinite(dist) & path, key, None
        if self.imaging.n == 0:                  # no reading yet: the belief is the prior
            return self._near
        if self._seen_green is None:
            # ... and seen from there: the largest adjoint value on the edge of the part of the
            # free region the observer's clearance lets it into (the same for every start in
            # it, so kept between episodes; the platform's own reachable set lies inside it)
            self._seen_green = greatest_green(self.solver, self.space.points, self.space.edges,
                                              self._sensing, self.reach)
        # a possible source outside the reachable set is within reach when a reading on its
        # edge would see it (DETECT_SNR times the reading noise; strength as believed now)
        noise = self.sigma_used / np.sqrt(2.0)
        seen = self._seen_green * self.imaging.strength_map() >= DETECT_SNR * noise
        return self._near & (self._reachable | seen)

    def _choose_next(self) -> None:
        nxt = self.next_point()                                        # step 13
        if self.done:
            return
        if nxt is None:
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
        else:
            self._next = nxt

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None:
            self._reachable &= mask
            self._check_reachable()

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Exclude the neighbourhood of an unreachable target and choose again."""
        if self._count_rejection(reason):
            return
        if not len(self.imaging.points):
            super().reject(intent, point, reason, agent)
            return
        radius = max(0.5 * self.d, self.solver.h)
        if self.mapping is not None:            # kept across the believed maps to come
            radius = self.mapping.refuse(point, radius)
        self._reachable &= ~self.space.around(point, radius)
        self._choose_next()
        self.status.extra["next"] = None if self.done else self._next.tolist()

    def next_point(self) -> np.ndarray | None:
        """Step 13: the next observation point (cm), or None if none is admissible."""
        im, cand = self.imaging, self.space
        allowed = self._reachable & self._separated()
        self._survey_next = False
        if self.mapping is not None:
            allowed = allowed & self.mapping.admissible(cand.points)
            survey = self._can_survey and self.n_surveys < SURVEY_CAP * self.max_steps
            if survey and len(self._no_survey) != len(cand.points):
                self._no_survey = np.zeros(len(cand.points), dtype=bool)
            here = self._here if survey else im.points[-1]
            nxt = self.mapping.frontier_point(cand, self.imaging.weights(),
                                              allowed & ~self._no_survey if survey else allowed, here,
                                              lambda y: mass_within_reach(y, cand.points, self.imaging.weights(),
                                                                          self.reach),
                                              share=SURVEY_SHARE if survey else FRONTIER_SHARE)
            if nxt is not None:
                self._survey_next = survey
                return nxt
        book = getattr(self, "book", None)
        if book is not None and book.surveying:
            # the hidden region's area within reach of each admissible point
            score = np.full(len(cand.points), -np.inf)
            idx = np.flatnonzero(allowed)
            hidden = book.hidden(self._survey_support(), self._node_area, self._unseen())
            if idx.size and hidden.any():
                score[idx] = mass_within_reach(cand.points[idx], cand.points, hidden, self.reach)
                if self.survey_travel is not None:   # the near hidden region first: less travel
                    gap = np.hypot(*(cand.points[idx] - self._read_points()[-1]).T)
                    score[idx] *= np.exp(-gap / self.survey_travel)
            return None if idx.size == 0 else cand.nodes[idx[np.argmax(score[idx])]].copy()
        if self.rule in ("axis", "reach") and self._likely_out_of_reach():
            nxt = self._reach_test_point(allowed)
            if nxt is not None:
                return nxt
        if self.rule == "info":
            nxt, gain = self._info_point(allowed)
            if nxt is not None and gain < INFO_GAIN_MIN:
                note = self._modes_note()
                if note:
                    self.stop(StopReason.GAVE_UP, f"no admissible point tells the modes apart{note}")
                    return None
            if nxt is not None:
                return nxt
        if self.rule in ("axis", "info"):
            nxt = self._axis_point(allowed)
            if nxt is not None:
                return nxt
        score = self._score(allowed)  # only when the rules above did not decide
        if self.rule != "nearest":
            idx = np.flatnonzero(np.isfinite(score))
            return None if idx.size == 0 else cand.nodes[idx[np.argmax(score[idx])]].copy()
        inside = im.model()[:, -1] > im.readings[-1]                   # {v_k > I_k}
        mask = allowed & inside if (allowed & inside).any() else allowed
        return cand.nearest_ring(im.points[-1], mask, score, self.solver.h)

    def _likely_out_of_reach(self) -> bool:
        """From the second reading on, the belief puts more than TEST_REACH_ABOVE of its
        mass out of reach (:meth:`within_reach`)."""
        return self.imaging.n >= UNREACH_MIN_READINGS and \
            self.notes.get("mass_out_of_reach", 0.0) > TEST_REACH_ABOVE

    def _reach_test_point(self, allowed: np.ndarray) -> np.ndarray | None:
        """The admissible node with the most belief within reach around it (the score of
        rule ``"reach"`` over the possible sources within reach only): where a reading
        confirms or rules out most of what the search can still find."""
        idx = np.flatnonzero(allowed)
        near = self._near_reachable()
        if idx.size == 0 or not near.any():
            return None
        pts = self.space.points
        score = mass_within_reach(pts[idx], pts[near], self.imaging.weights()[near], self.reach)
        return self.space.nodes[idx[np.argmax(score)]].copy()

    def _separated(self) -> np.ndarray:
        """Mask of the nodes at least `d` from every point read, brought up to date with
        the points read since the last call only (not all of them at every step)."""
        read = self._read_points()
        if self._far_count < len(read):
            self._far &= self.space.separated(read[self._far_count:], self.d)
            self._far_count = len(read)
        return self._far

    def _read_points(self) -> np.ndarray:
        """Every point read so far, cm (the active map of a search for several sources may
        leave some out)."""
        book = getattr(self, "book", None)
        return self.imaging.points if book is None else book.raw.points

    def _info_point(self, allowed: np.ndarray) -> tuple[np.ndarray | None, float]:
        """The ``"info"`` rule: the admissible lattice point of least expected entropy and
        the expected gain (nats); ``(None, 0)`` when the belief sits in one lattice cell or
        no lattice point is admissible."""
        lat = self._lattice
        mass = np.bincount(lat.anchor, self.imaging.weights(), minlength=len(lat.nodes))
        anchors, w = systematic_support(mass, INFO_SUPPORT, self.rng)
        cand = np.flatnonzero(allowed[lat.nodes])
        if anchors.size < 2 or cand.size == 0:
            return None, 0.0
        c = self.imaging.strength_map()[lat.nodes[anchors]]
        means = lat.columns(anchors)[cand] * c[None, :]               # c_i G(y, x_i), reciprocity
        if INFO_SCORE == "mi":
            gain = mutual_information(means, w, self.sigma_used / np.sqrt(2.0))
        else:
            gain = -w @ np.log(w) - expected_entropy(means, w, self.sigma_used / np.sqrt(2.0))
        best = int(np.argmax(gain))
        return lat.points[cand[best]].copy(), float(gain[best])

    def _axis_point(self, allowed: np.ndarray) -> np.ndarray | None:
        """The ``"axis"`` rule once the imaging mass is concentrated, else None."""
        return axis_point(self.space, self.imaging.values() * self._node_area, allowed, self.reach, self.d)

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
