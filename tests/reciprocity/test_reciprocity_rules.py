"""The reciprocity strategy's presets and rules: the paper's settings, the expected-
information rule on hand-built beliefs, ambiguity and reachability stops, statistics."""

import re

import numpy as np
import pytest
from scipy.stats import binom

import arenas
import reciprocity as r
from reciprocity.env import SearchEnv, rollout
from reciprocity.observations import Observation
from reciprocity.scenarios import load_scenario
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.strategies.information import expected_entropy
from reciprocity.strategies.reciprocity import PRESETS
from reciprocity.models.green import cached_solver


@pytest.fixture(scope="module")
def empty():
    a = arenas.load("empty")
    return a, cached_solver(a.without_scenario(), 3.0)


def started(solver, arena, *, noise=12.0, start=(20.0, 20.0), **kw):
    s = r.ReciprocityStrategy(solver=solver, **kw)
    s.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=arena.strength,
                                            noise=noise),
                            np.array([[*start, 0.0]]), np.random.default_rng(0)))
    return s


def test_paper_preset_is_algorithm_1(empty):
    arena, solver = empty
    s = started(solver, arena, preset="paper")
    assert (s.rule, s.combine, s.sigma, s.eps, s.extent_tol, s.tail_tol) == (
        "nearest", "mean", "noise", 0.7, np.inf, np.inf)
    assert s.sigma_used == 12.0                      # eq. (7): sigma^2 is the noise variance
    assert PRESETS["paper"]["area_tol"] == s.area_tol and s.d == PRESETS["paper"]["d"]
    over = started(solver, arena, preset="paper", sigma=17.0, rule="axis")
    assert (over.sigma_used, over.rule, over.combine) == (17.0, "axis", "mean")
    default = started(solver, arena, noise=5.0)
    assert default.sigma_used == pytest.approx(5.0 * np.sqrt(2.0))   # likelihood-consistent
    told = started(solver, arena, noise=12.0)
    car_nominal = dict(arena=arena.without_scenario(), strength=850.0, noise=12.0, reading_noise=2.0)
    told_car = r.ReciprocityStrategy(solver=solver, sigma="calibrated")
    told_car.start(r.SearchContext("poisson", car_nominal, np.array([[20.0, 20.0, 0.0]]),
                                   np.random.default_rng(0)))
    assert told.sigma_used > told_car.sigma_used == pytest.approx(2.0 * np.sqrt(2.0))
    # the default uses the platform's own noise where it reports one, else the world's
    assert r.ReciprocityStrategy().reading_sigma(car_nominal) == pytest.approx(2.0 * np.sqrt(2.0))
    assert r.ReciprocityStrategy(sigma="auto").reading_sigma(car_nominal) == pytest.approx(12.0 * np.sqrt(2.0))
    # the shared part is imaged as one offset, the rest as independent noise
    biased = dict(car_nominal, reading_bias=1.2)
    assert r.ReciprocityStrategy().reading_sigma(biased) == pytest.approx(np.sqrt(2.0 ** 2 - 1.2 ** 2) * np.sqrt(2.0))
    assert r.ReciprocityStrategy().reading_bias(biased) == 1.2 and r.ReciprocityStrategy(sigma="auto").reading_bias(biased) == 0.0
    with pytest.raises(r.SearchError, match="preset"):
        r.ReciprocityStrategy(preset="landa")
    with pytest.raises(r.SearchError, match="sigma"):
        r.ReciprocityStrategy(sigma="wide")


def test_expected_entropy_prefers_the_point_that_separates_two_modes():
    """Two equally likely sources; a reading equal for both (a point on their bisector)
    leaves log 2 nats, one whose predictions differ by 10 noise std removes it."""
    w = np.array([0.5, 0.5])
    means = np.array([[40.0, 40.0], [40.0, 160.0]])   # candidate 0: bisector, 1: beside one
    h = expected_entropy(means, w, noise=12.0)
    assert h[0] == pytest.approx(np.log(2.0))
    assert h[1] < 1e-6


def test_info_rule_measures_where_two_modes_read_differently(empty):
    arena, solver = empty
    a, b = np.array([40.0, 70.0]), np.array([100.0, 70.0])
    s = started(solver, arena, rule="info")
    s.imaging.add((70.0, 20.0), 0.0)
    p = solver.nodes
    s.imaging._cache["P"] = np.exp(-np.sum((p - a) ** 2, 1) / 8.0) + np.exp(-np.sum((p - b) ** 2, 1) / 8.0)
    nxt = s.next_point()
    gap = abs(np.hypot(*(nxt - a)) - np.hypot(*(nxt - b)))
    assert gap > 20.0                                # far from the bisector x = 70
    assert min(np.hypot(*(nxt - a)), np.hypot(*(nxt - b))) < 25.0


def test_unknown_strength_two_modes_are_reported(empty):
    """Readings on the mirror line x = 70 of a source at (50, 70) cannot tell it from
    (90, 70): at the step cap the search reports two modes instead of converging."""
    arena, solver = empty
    s = started(solver, arena, strength=None, max_steps=3, rule="nearest")
    u = solver.field((50.0, 70.0), strength=600.0)
    for z in [(70.0, 40.0), (70.0, 100.0), (70.0, 70.0)]:
        s.observe([Observation(np.array(z), float(u([z])[0]))], None)
    assert s.outcome.reason == r.StopReason.STEP_CAP and not s.outcome.reason.converged
    gap = float(re.search(r"2 modes, the two largest (\d+) cm apart", s.outcome.detail).group(1))
    assert abs(gap - 40.0) <= 2 * solver.h          # the mirror images, to the mesh size


def test_info_rule_gives_up_when_no_point_separates_the_modes(empty):
    """Two modes, and the observer may only measure along the bottom wall, where the
    signal of either is buried in the noise: the search says so instead of measuring."""
    arena, solver = empty
    s = started(solver, arena, rule="info", strength=None)
    s.imaging.add((70.0, 20.0), 0.0)
    p = solver.nodes
    s.imaging._cache["P"] = np.exp(-np.sum((p - [40.0, 110.0]) ** 2, 1) / 8.0) + \
        np.exp(-np.sum((p - [100.0, 110.0]) ** 2, 1) / 8.0)
    s.reachability.reachable &= p[:, 1] < 4.0
    assert s.next_point() is None
    assert s.outcome.reason == r.StopReason.GAVE_UP
    found = re.search(r"tells the modes apart; 2 modes, the two largest (\d+) cm apart", s.outcome.detail)
    assert abs(float(found.group(1)) - 60.0) <= 2 * solver.h


def test_unreachable_region_stops_at_once(empty):
    arena, solver = empty
    s = started(solver, arena)
    s.restrict(lambda pts: np.zeros(len(pts), dtype=bool))
    assert s.outcome.reason == r.StopReason.UNREACHABLE and "reachable" in s.outcome.detail
    s = started(solver, arena)
    s.imaging.add((20.0, 20.0), 0.0)
    s.imaging._cache["P"] = (solver.nodes[:, 0] > 110).astype(float)   # sources on the right
    s.restrict(lambda pts: pts[:, 0] < 60)          # observer on the left, out of reach
    assert s.outcome.reason == r.StopReason.UNREACHABLE and "out of reach" in s.outcome.detail


def test_belief_out_of_reach_stops_with_its_probability(empty):
    """A source behind a gap the observer cannot pass: the region still touches the
    reachable part (weak readings through the gap), but less than UNREACH_MASS of the
    belief lies within reach: the search stops and says how sure it is."""
    from reciprocity.strategies.imaging_search.stop_rule import UNREACH_MASS
    arena, solver = empty
    x = solver.nodes[:, 0]
    for strip, stops in ((0.2, True), (1.0, False)):
        s = started(solver, arena)
        s.restrict(lambda pts: pts[:, 0] < 50)      # the observer keeps to the left
        s.imaging.add((20.0, 20.0), 0.0)
        s.imaging.add((20.0, 60.0), 0.0)
        # most belief far right, a faint strip just beyond the reachable part
        s.imaging._cache["P"] = np.where(x > 110, 1.0, np.where((x > 55) & (x < 60), strip, 0.0))
        within = s.imaging.weights()[s.within_reach()].sum()
        assert (within < UNREACH_MASS) == stops and (s.region() & s.within_reach()).any()
        s._check_reachable()
        if stops:
            assert s.outcome.reason == r.StopReason.UNREACHABLE
            p = float(re.search(r"out of reach with probability ([0-9.]+)", s.outcome.detail).group(1))
            assert p == pytest.approx(1.0 - within, abs=1e-3)
        else:
            assert not s.done
    # one reading alone never triggers it (a single level set is a band)
    s = started(solver, arena)
    s.restrict(lambda pts: pts[:, 0] < 50)
    s.imaging.add((20.0, 20.0), 0.0)
    s.imaging._cache["P"] = np.where(x > 110, 1.0, np.where((x > 55) & (x < 60), 0.2, 0.0))
    s._check_reachable()
    assert not s.done


def test_info_rule_statistics_on_empty(empty):
    """12 seeded episodes at h = 3 cm, noise 12, known strength: at least 10 succeed (at
    the measured rate of about 0.99 this fails with probability below 0.01; a rate of
    0.8 would pass with probability 0.28) and the median needs at most 7 readings (6
    without the likelihood's position term, which at h = 3 cm stands for a source up to
    1.1 cm RMS from its node: 12 of 12 succeed with it, 11 without)."""
    arena, solver = empty
    rng = np.random.default_rng(11)
    ok, counts = 0, []
    for seed in range(12):
        src = arena.random_free_points(1, rng, clearance=8.0)[0]
        start = np.append(arena.random_free_points(1, rng, clearance=5.0)[0], 0.0)
        sc = load_scenario(arena.with_scenario(source=src, start=start)).with_world(dict(noise=12.0, truth_h=2.1))
        env = SearchEnv(sc, platform_options={"route_h": 3.0})
        ep = rollout(env, StrategyAgent(r.ReciprocityStrategy(solver=solver, rule="info")), seed)
        ok += ep.summary["success"]
        counts.append(ep.summary["n_measurements"])
    assert binom.cdf(9, 12, 0.99) < 0.01
    assert ok >= 10
    assert np.median(counts) <= 7


def test_the_likelihood_adds_its_error_terms_in_quadrature(empty):
    arena, solver = empty
    from reciprocity.fem.discretisation import discretisation_error
    from reciprocity.strategies.imaging_search.likelihood import CALIBRATED_MODEL_ERROR
    disc = discretisation_error(solver).relative
    s = started(solver, arena)
    assert s.error_terms["discretisation"] == disc > 0 and s.error_terms["noise"] == pytest.approx(12.0)
    assert s.imaging.model_error == pytest.approx(disc)
    strong = started(solver, arena, strength_error=0.2)
    assert strong.imaging.model_error == pytest.approx(np.hypot(disc, 0.2))
    car = r.ReciprocityStrategy(solver=solver)
    car.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=850.0, noise=12.0,
                                              reading_noise=2.0), np.array([[20.0, 20.0, 0.0]]),
                              np.random.default_rng(0)))
    assert car.imaging.model_error == pytest.approx(np.hypot(disc, CALIBRATED_MODEL_ERROR))
    fixed = started(solver, arena, model_error=0.03)
    assert fixed.imaging.model_error == pytest.approx(0.03) and "discretisation" not in fixed.error_terms
    assert fixed.params()["model_error_used"] == pytest.approx(0.03)
    assert started(solver, arena, preset="paper").imaging.model_error == 0.0    # eq. (8) has none
    for bad in (dict(model_error=1.5), dict(model_error="guess"), dict(strength_error=-0.1),
                dict(strength_error=True), dict(credible_mass=1.0), dict(credible_radius=0.0)):
        with pytest.raises(r.SearchError, match=next(iter(bad))):
            r.ReciprocityStrategy(**bad)


def test_the_credible_rule_holds_a_search_whose_belief_has_a_near_second_mode():
    """Two modes 8 cm apart, the second holding about a sixth of the belief: the tail rule
    (10 cm) would stop; the credible rule (95 % within 3 cm) does not, until it goes."""
    arena = arenas.load("empty")
    solver = cached_solver(arena.without_scenario(), 1.5)
    s = started(solver, arena)
    nodes = s.imaging.nodes
    a, b = np.array([70.0, 70.0]), np.array([78.0, 70.0])

    def belief(second):
        im = s.imaging
        if not im.n:
            im.add((30.0, 30.0), 1.0)
        P = np.exp(-np.sum((nodes - a) ** 2, axis=1) / 2.0) + second * np.exp(-np.sum((nodes - b) ** 2, axis=1) / 2.0)
        im._cache.clear()
        im._cache["P"] = P / P.max()
        return im

    im = belief(0.18)
    est = im.estimate()
    assert np.hypot(*(est - a)) < 1.0
    assert 0.7 < im.weights()[np.hypot(*(nodes - est).T) <= 3.0].sum() < 0.95
    loose = started(solver, arena, credible_radius=float("inf"))
    assert loose.stop_rule.tail_within(est, im) and not s.stop_rule.tail_within(est, im)
    im = belief(0.0)
    assert s.stop_rule.tail_within(im.estimate(), im)


def test_an_empty_region_is_not_a_found_source(empty):
    """Eq. (8)'s mean after one reading far below every prediction (noise can make a
    reading negative) is below eps everywhere: the region is empty, its area 0 < A_eps,
    and the search must go on rather than stop (it stopped 92-99 cm off before)."""
    arena, solver = empty
    s = started(solver, arena, preset="paper", start=(70.0, 70.0))
    s.observe([Observation(np.array([70.0, 70.0]), -200.0)], None)
    assert s.imaging.values().max() < s.eps and s.imaging.area(s.eps) == 0.0
    assert not s.done


def test_mutual_information_of_a_reading_against_closed_forms():
    from reciprocity.strategies.information import mutual_information
    two = np.array([[0.0, 100.0], [0.0, 0.0]])
    mi = mutual_information(two, np.array([0.5, 0.5]), 1.0)
    assert mi[0] == pytest.approx(np.log(2.0), abs=1e-3) and mi[1] == pytest.approx(0.0, abs=1e-9)
    # means drawn from N(0, a^2): the reading is N(0, 1 + a^2), I = log(1 + a^2) / 2
    rng = np.random.default_rng(0)
    a, k = 3.0, 20000
    mi = mutual_information(rng.normal(0.0, a, (1, k)), np.full(k, 1.0 / k), 1.0)
    assert mi[0] == pytest.approx(0.5 * np.log(1.0 + a * a), abs=3 * a / np.sqrt(k) + 0.01)


@pytest.fixture(scope="module")
def slit():
    """A wall across the arena with a 3 cm slit at its top: a car keeps 4 cm from the
    walls, so it cannot pass."""
    a = arenas.Arena.from_polygons([(0, 0), (140, 0), (140, 140), (0, 140)],
                                   [[(60, 0), (64, 0), (64, 137), (60, 137)]], name="slit", strength=850.0)
    return a, cached_solver(a, 2.0)


def test_possible_sources_behind_a_slit_are_out_of_reach(slit):
    """Within `reach` of the reachable part, as the crow flies and along the free region,
    but seen from nowhere the observer can go: a unit source just behind the slit reads
    below DETECT_SNR x the noise on the whole edge of the reachable part, so it is not
    within reach; the same distance in the open is."""
    from reciprocity.strategies.imaging_search.reachability import DETECT_SNR
    from reciprocity.strategies.reach import edge_nodes
    arena, solver = slit
    s = started(solver, arena, noise=12.0, start=(30.0, 120.0), model_error=0.0, clearance=4.0)
    s.restrict(lambda pts: pts[:, 0] < 56)          # the car's side, 4 cm from the wall
    s.imaging.add((30.0, 120.0), 0.0)               # the test applies from the first reading
    p, near = solver.nodes, s.within_reach()
    behind = (p[:, 0] > 66) & (p[:, 0] < 70) & (p[:, 1] > 131) & (np.hypot(p[:, 0] - 56, p[:, 1] - 136) < 11)
    assert behind.sum() >= 5
    # within reach by distance and by path (through the slit): the old test let them in
    assert s.reachability._near[behind].all()
    assert not near[behind].any()
    # the adjoint fields of the whole edge agree: none of them sees these nodes
    edge = edge_nodes(s.space.edges, s.reachability.reachable)
    edge = edge[p[edge, 1] > 100]                   # the rest lies farther from them
    g = solver.greens(p[edge])[behind]
    noise = s.sigma_used / np.sqrt(2.0)
    assert arena.strength * g.max() < DETECT_SNR * noise
    # open space at the same distance on the car's side is seen
    s2 = started(solver, arena, noise=12.0, start=(30.0, 120.0), model_error=0.0, clearance=4.0)
    s2.restrict(lambda pts: pts[:, 0] < 40)
    s2.imaging.add((30.0, 120.0), 0.0)
    open_strip = (p[:, 0] > 46) & (p[:, 0] < 50) & (p[:, 1] > 20) & (p[:, 1] < 120)
    assert s2.within_reach()[open_strip].all()


def test_mostly_out_of_reach_reads_where_the_reachable_belief_lies(empty):
    """92 % of the belief out of reach, the rest in one blob the observer can reach: the
    next reading goes to the blob (to find the source there or rule it out), and the
    summary keys say how much lies out of reach and how large the reachable part is."""
    from reciprocity.strategies.imaging_search.stop_rule import TEST_REACH_ABOVE
    arena, solver = empty
    s = started(solver, arena, model_error=0.0)
    s.restrict(lambda pts: pts[:, 0] < 50)
    s.imaging.add((20.0, 20.0), 0.0)
    s.imaging.add((20.0, 60.0), 0.0)
    x, y = solver.nodes.T
    blob = np.hypot(x - 40.0, y - 110.0) < 6.0
    s.imaging._cache["P"] = np.where(x > 110, 1.0, 0.0) + np.where(blob, 3.0, 0.0)
    s._check_reachable()
    assert not s.done
    assert TEST_REACH_ABOVE < s.notes["mass_out_of_reach"] < 0.95
    reachable = s.space.cell_areas[s.reachability.reachable].sum()
    assert s.notes["reachable_area"] == pytest.approx(reachable, abs=0.1)
    nxt = s.next_point()
    assert np.hypot(*(nxt - [40.0, 110.0])) < s.reach
    within = s.within_reach()
    assert within[blob].all() and not within[x > 110].any()
