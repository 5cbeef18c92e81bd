"""Several sources: worlds that superpose them, the judgement by optimal assignment, the
Bayes factor of one more source, and a search that finds them all without being told K."""

import json

import numpy as np
import pytest
from scipy import integrate

import arenas
import reciprocity as r
from reciprocity.env import SearchEnv, rollout
from reciprocity.errors import SearchError
from reciprocity.outcome import MAX_SOURCES, match_sources
from reciprocity.scenarios import from_dict
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent

TWO = dict(world="poisson", arena="paper", sources=[[70.2, 70.2], [60.0, 125.0]], strengths=[850.0, 700.0])


def scenario(**over):
    return from_dict({**TWO, **over}, name="two")


# -- the judgement ---------------------------------------------------------------------
def test_optimal_assignment_matches_each_true_source_once():
    true = np.array([[0.0, 0.0], [10.0, 0.0]])
    # the greedy choice for the first source (the estimate at 9) would leave the second 11 away
    est = np.array([[9.0, 0.0], [21.0, 0.0]])
    assert match_sources(true, est) == pytest.approx([9.0, 11.0])
    assert match_sources(true, est[:1]) == [None, 1.0]           # one missed
    assert match_sources(true, np.empty((0, 2))) == [None, None]
    assert match_sources(true[:1], est) == [9.0]                  # an extra estimate stays unmatched


# -- the world -------------------------------------------------------------------------
def test_the_signal_of_several_sources_is_the_sum_of_their_fields():
    world = scenario().build_world(0)
    one = [r.worlds.poisson.truth_solver(world.true_arena.without_scenario(), world.h).field(s, c, cached=True)
           for s, c in zip(world.sources, world.strengths)]
    pts = np.array([[30.0, 60.0], [60.0, 120.0], [120.0, 70.0]])
    assert np.allclose(world.field(pts), one[0](pts) + one[1](pts))
    assert world.n_sources == 2 and world.strengths.tolist() == [850.0, 700.0]


def test_the_task_tells_the_bound_on_the_number_of_sources_never_the_sources():
    env = SearchEnv(scenario(max_sources=3))
    _, info = env.reset(seed=0)
    nominal = dict(info["task"].nominal)
    assert nominal["max_sources"] == 3
    assert not {"sources", "strengths", "n_sources", "source"} & set(nominal)
    assert nominal["strength"] == 850.0                          # the nominal, not the true strengths
    # the classic single-source task says nothing of several
    _, info = SearchEnv("paper").reset(seed=0)
    assert "max_sources" not in info["task"].nominal


@pytest.mark.parametrize("over, message", [
    (dict(sources=[[70.2, 70.2], [120.0, 120.0]]), "sources[1] (120, 120) cm is outside the free region"),
    (dict(sources=[]), "sources must be a list of 1 to"),
    (dict(sources=[[70.0, 70.0]] * (MAX_SOURCES + 1)), "sources must be a list of 1 to"),
    (dict(sources=[[70.0, 70.0], [70.5, 70.0]]), "sources must be at least 1 cm apart"),
    (dict(sources=[[70.0, 70.0], "a"]), "sources[1]"),
    (dict(strengths=[850.0]), "strengths must give one number per source (2)"),
    (dict(strengths=[850.0, -1.0]), "strengths[1]"),
    (dict(max_sources=1), "max_sources (1) is less than the number of sources (2)"),
    (dict(max_sources=9), "max_sources must be a whole number from 1 to"),
    (dict(source=[30.0, 60.0]), "give either source (one source) or sources (several), not both"),
])
def test_bad_sources_are_refused_naming_the_key(over, message):
    with pytest.raises(SearchError) as err:
        scenario(**over)
    assert message in str(err.value)


def test_strengths_without_sources_are_refused():
    with pytest.raises(SearchError, match="needs sources"):
        from_dict(dict(world="poisson", arena="paper", strengths=[850.0]), name="x")


def test_one_source_given_replaces_several_and_several_replace_one():
    one = scenario().with_world({"source": [30.0, 60.0]})
    assert one.params["sources"] is None and one.params["source"] == [30.0, 60.0]
    several = from_dict(dict(world="poisson", arena="paper"), name="p").with_world(
        {"sources": [[30.0, 60.0], [70.2, 70.2]]})
    assert several.params["sources"] == [[30.0, 60.0], [70.2, 70.2]]
    assert several.build_world(0).max_sources == MAX_SOURCES


# -- the Bayes factor of one more source -------------------------------------------------
def test_log_evidence_ratio_is_the_integral_over_the_strength_prior():
    solver = r.GreenSolver(arenas.load("empty"), h=4.0)
    lo, hi, sigma = 300.0, 1200.0, 12.0 * np.sqrt(2.0)
    im = r.ImagingMap(solver, sigma, strength=None, combine="product", strength_range=(lo, hi))
    z = [(30.0, 30.0), (90.0, 40.0), (60.0, 100.0)]
    readings = [40.0, 5.0, 120.0]
    for p, v in zip(z, readings):
        im.add(p, v)
    b = im.log_evidence_ratio()
    g = im._g
    rr = np.array(readings)
    for node in (10, len(im.nodes) // 2, len(im.nodes) - 7):
        def integrand(c):
            return np.exp(-(np.sum((c * g[node] - rr) ** 2) - rr @ rr) / sigma ** 2) / c
        quad = integrate.quad(integrand, lo, hi, limit=200, points=[lo * 1.5, hi / 1.5])[0] / np.log(hi / lo)
        assert b[node] == pytest.approx(np.log(quad), abs=0.03)


def test_log_evidence_ratio_is_zero_where_no_reading_sees_and_excludes_where_readings_are_quiet():
    solver = r.GreenSolver(arenas.load("paper"), h=3.0)
    im = r.ImagingMap(solver, 12.0 * np.sqrt(2.0), strength=None, combine="product",
                      strength_range=(425.0, 1700.0))
    for p in [(66.0, 80.0), (75.0, 60.0)]:
        im.add(p, 0.0)                                         # quiet: no source near
    b = im.log_evidence_ratio()
    unseen = 1700.0 * np.abs(im._g).max(axis=1) < 1e-3         # no strength of the prior shows there
    loud = 425.0 * im._g.max(axis=1) > 60.0                    # any source there would have shown
    assert unseen.sum() > 100 and np.all(np.abs(b[unseen]) < 1e-3)
    assert loud.sum() > 50 and np.all(b[loud] < np.log(0.05))
    # a reading of the true source's field: decisive evidence for a source beside it
    u = solver.field((70.2, 70.2), 850.0)
    im.add((70.0, 66.0), float(u([(70.0, 66.0)])[0]))
    near = np.argmin(np.hypot(*(im.nodes - (70.2, 70.2)).T))
    assert im.log_evidence_ratio()[near] > np.log(100.0)
    with pytest.raises(r.ReciprocityError, match="strength_range"):
        r.ImagingMap(solver, 12.0, strength=850.0, combine="product").log_evidence_ratio()


def test_restrict_zeroes_the_map_outside_the_allowed_nodes():
    solver = r.GreenSolver(arenas.load("empty"), h=4.0)
    im = r.ImagingMap(solver, 12.0, strength=600.0, combine="product")
    im.add((30.0, 30.0), 50.0)
    allowed = im.nodes[:, 0] > 70.0
    im.restrict(allowed)
    assert np.all(im.values()[~allowed] == 0.0) and im.values()[allowed].max() == 1.0
    assert im.estimate()[0] > 65.0
    with pytest.raises(r.ReciprocityError, match="at least one True"):
        im.restrict(np.zeros(len(im.nodes), dtype=bool))


# -- the search ------------------------------------------------------------------------
@pytest.mark.slow
def test_the_search_finds_two_sources_without_being_told_how_many():
    env = SearchEnv(scenario())
    episode = rollout(env, StrategyAgent(STRATEGIES["reciprocity"]), 0)
    s = episode.summary
    assert s["n_sources_estimated"] == 2 and s["success"], s["stop_reason"]
    assert max(s["errors"]) < 5.0 and s["error"] == max(s["errors"])
    assert len(s["estimates"]) == 2 and len(s["estimates_sd"]) == 2
    assert s["sources"] == TWO["sources"] and s["max_sources"] == MAX_SOURCES
    assert "probability of one more" in s["stop_reason"]
    json.dumps(s)


def test_one_source_found_of_two_is_not_a_success():
    env = SearchEnv(scenario())
    episode = rollout(env, StrategyAgent(STRATEGIES["reciprocity"], {"max_sources": 1}), 0)
    s = episode.summary
    assert s["converged"] and s["n_sources_estimated"] == 1
    assert s["errors"][1] is None and s["error"] is None and not s["success"]


def test_the_classic_single_source_search_is_unchanged():
    """A task with one source: no book, no extra keys, the readings of the single search."""
    env = SearchEnv("paper")
    episode = rollout(env, StrategyAgent(STRATEGIES["reciprocity"]), 3)
    s = episode.summary
    assert "estimates" not in s and "n_sources_estimated" not in s
    assert s["params"]["max_sources"] == 1 and s["params"]["max_steps"] == 30


@pytest.mark.parametrize("params, message", [
    ({"max_sources": 0}, "max_sources must be a whole number from 1 to"),
    ({"max_sources": 2.5}, "max_sources must be a whole number"),
    ({"more_tol": 1.0}, "more_tol must be a probability in (0, 1)"),
    ({"max_steps": 0}, "max_steps must be a whole number >= 1"),
    ({"survey_reach": -1.0}, "survey_reach must be a positive length in cm or 'reach'"),
    ({"survey_travel": 0.0}, "survey_travel must be a positive length in cm, or None"),
])
def test_bad_search_parameters_are_refused(params, message):
    with pytest.raises(SearchError) as err:
        STRATEGIES["reciprocity"](**params)
    assert message in str(err.value)


# -- files, campaigns and the command line ---------------------------------------------
def test_a_plain_arena_file_takes_several_sources_and_the_run_draws_them(tmp_path):
    from reciprocity.cli import main
    arena = tmp_path / "box2.yaml"
    arena.write_text("name: box2\nboundary: [[0, 0], [100, 0], [100, 80], [0, 80]]\n"
                     "obstacles:\n  - [[40, 20], [60, 20], [60, 40], [40, 40]]\n"
                     "sources: [[20, 20], [80, 60]]\nstrengths: [600, 600]\nstrength: 600\nstart: [50, 70, 0]\n")
    out = tmp_path / "out"
    assert main(["run", "--arena", str(arena), "--strategy", "reciprocity", "--out", str(out),
                 "--json", str(tmp_path / "s.json"), "--quiet"]) == 0
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["n_sources_estimated"] == 2 and s["success"] and len(s["errors"]) == 2
    assert (out / "reciprocity_sources.png").stat().st_size > 10_000
    assert (out / "reciprocity_steps.png").exists()


def test_a_campaign_draws_as_many_sources_as_the_scenario_has_well_apart():
    from reciprocity.campaign.spec import SOURCE_CLEARANCE, SOURCE_SEPARATION
    from reciprocity.campaign.worker import world_draw
    sc = from_dict({**TWO, "sources": [[70.2, 70.2], [60.0, 125.0], [120.0, 10.0]], "strengths": None}, name="k3")
    arena = sc.arena
    for seed in range(20):
        draw = world_draw(sc, seed)
        pts = np.array(draw["sources"])
        assert pts.shape == (3, 2) and "source" not in draw
        assert np.all(arena.contains(pts, clearance=SOURCE_CLEARANCE))
        gaps = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))[np.triu_indices(3, 1)]
        assert gaps.min() >= SOURCE_SEPARATION
    assert world_draw(sc, 3) == world_draw(sc, 3)                  # the seed decides
    world = sc.with_world(world_draw(sc, 3)).build_world(3)
    assert world.n_sources == 3 and world.max_sources == MAX_SOURCES


@pytest.mark.slow
def test_an_unknown_map_and_two_sources_run_end_to_end():
    """Both extensions at once: the strategy meshes what its range sensor saw, and looks for
    the sources it is not told of; the walls and the sources stay on the truth's side."""
    sc = from_dict(dict(world="poisson", arena={"name": "box2", "boundary": [[0, 0], [100, 0], [100, 80], [0, 80]],
                                                "obstacles": [[[40, 20], [60, 20], [60, 40], [40, 40]]],
                                                "strength": 600, "start": [50, 70, 0]},
                        sources=[[20, 20], [80, 60]], map="unknown", lidar={"beams": 32, "range": 40, "noise": 0.5}),
                   name="both")
    env = SearchEnv(sc)
    _, info = env.reset(seed=0)
    assert not info["task"].nominal["arena"].obstacles                # only the boundary is told
    agent = StrategyAgent(STRATEGIES["reciprocity"])
    s = rollout(env, agent, 0).summary
    assert len(agent.strategy.solver.arena.obstacles) >= 1            # the wall it saw, meshed
    assert s["n_sources_estimated"] == 2 and s["n_sources_right"], s["stop_reason"]
    assert max(s["errors"]) < 5.0


def test_a_saturated_reading_is_evidence_of_a_source_and_is_kept_by_the_residual_maps():
    """A reading at the sensor's ceiling says "a source is near": the Bayes factor counts
    it (censored, under the null too), and the maps of further sources keep it, so a
    search never asks for the same point again because its reading was dropped."""
    solver = r.GreenSolver(arenas.load("paper"), h=3.0)
    im = r.ImagingMap(solver, 12.0 * np.sqrt(2.0), strength=None, combine="product",
                      strength_range=(425.0, 1700.0))
    im.add((66.0, 80.0), 0.0)
    im.add((70.0, 66.0), 300.0, saturated=True)
    b = im.log_evidence_ratio()
    unseen = 1700.0 * np.abs(im._g).max(axis=1) < 1e-3
    near = np.hypot(*(im.nodes - (70.0, 66.0)).T) < 3.0
    assert np.all(np.abs(b[unseen]) < 1e-3) and b[near].max() > np.log(100.0)

    from reciprocity.observations import Observation
    from reciprocity.strategies.multi_source import SourceBook
    raw = r.ImagingMap(solver, 12.0 * np.sqrt(2.0), strength=850.0, combine="product")
    book = SourceBook(raw, 850.0, 4, np.full(len(raw.nodes), 10.0))
    book.add(Observation((70.0, 66.0), 400.0))
    book.accept(np.array([70.0, 66.0]), 1.0)
    active = book.add(Observation((120.0, 20.0), 374.6, saturated=True))
    assert active.n == 2 and active.saturated.tolist() == [False, True]


# -- settling the found sources ----------------------------------------------------------
def _two_source_book():
    """A book with readings of two sources of 850 (on the strategy's own solver, so the
    readings are exact and only the estimates can be wrong)."""
    from reciprocity.observations import Observation
    from reciprocity.strategies.multi_source import SourceBook
    solver = r.GreenSolver(arenas.load("paper"), h=3.0)
    truth = np.array([[52.3, 32.5], [124.6, 21.0]])
    u = [solver.field(s, 850.0) for s in truth]
    raw = r.ImagingMap(solver, 2.5 * np.sqrt(2.0), strength=850.0, combine="product")
    book = SourceBook(raw, 850.0, 4, solver.arena.wall_distance(raw.nodes))
    points = [(69.0, 23.0), (52.0, 36.0), (45.0, 35.0), (121.0, 15.0), (114.0, 14.0), (126.0, 26.0),
              (118.0, 30.0), (60.0, 40.0)]
    return book, truth, [Observation(p, float(u[0]([p])[0] + u[1]([p])[0])) for p in points]


def test_settling_corrects_a_position_found_before_the_readings_that_show_it_wrong():
    """A source accepted 5 cm off (its region converged on readings the other source
    distorted) is moved back by the readings taken since: the search does not stop on a
    stale estimate."""
    book, truth, obs = _two_source_book()
    for o in obs[:3]:
        book.add(o)
    book.accept(truth[0] + (0.5, 0.0), 1.0)
    for o in obs[3:5]:
        book.add(o)
    book.accept(truth[1] + (3.0, 4.0), 1.0)                  # 5 cm off
    assert np.hypot(*(book.found[1] - truth[1])) < 1.5       # settled at once
    book.found[1] = truth[1] + (3.0, 4.0)                    # and stale again ...
    book.add(obs[5])                                         # ... until the next reading
    err = [float(np.min(np.hypot(*(truth - f).T))) for f in book.found]
    assert len(book.found) == 2 and max(err) < 1.5, err
    assert book.strengths == pytest.approx([850.0, 850.0], rel=0.1)


def test_settling_drops_a_found_source_that_explains_no_reading():
    """A phantom third source (weak, beside a wall, where no reading needs it) is dropped;
    a real one never is: removing it would raise the readings' chi2 by thousands."""
    book, truth, obs = _two_source_book()
    for o in obs:
        book.add(o)
    book.found = [truth[0].copy(), truth[1].copy(), np.array([100.0, 90.0])]
    book.anchors = [f.copy() for f in book.found]
    book.spread = [1.0, 1.0, 1.0]
    book._fit_strengths()
    assert book.settle() == 1 and book.dropped == 1
    assert len(book.found) == 2 and len(book.spread) == 2 and len(book.strengths) == 2
    assert book.chi2(book.found[:1]) - book.chi2(book.found) > 100.0
    assert book.settle() == 0                                  # the real ones stay
    single = book.found[:1]
    book.found, book.anchors, book.spread = [single[0]], [single[0].copy()], [1.0]
    book._fit_strengths()
    assert book.settle() == 0 and len(book.found) == 1         # one source is always kept


def test_one_source_found_of_two_stays_where_its_region_converged():
    """Alone, a found source is not settled: on readings the second source also explains
    it would drift toward that one (and the search would never look for it)."""
    book, truth, obs = _two_source_book()
    for o in obs[:3]:
        book.add(o)
    book.accept(truth[0] + (0.5, 0.0), 1.0)
    for o in obs[3:]:
        book.add(o)                                          # readings of the second source
    assert len(book.found) == 1 and np.hypot(*(book.found[0] - truth[0] - (0.5, 0.0))) < 1e-9


def test_a_source_found_where_the_readings_do_not_put_it_is_moved_and_confirmed_again():
    """A source accepted 17 cm from where it is (beyond the window of settling), where the
    readings' chi2 says decisively that it lies elsewhere, moves there and loses its
    confirmation; sources where the readings put them never move."""
    book, truth, obs = _two_source_book()
    for o in obs:
        book.add(o)
    book.found = [truth[0] + (0.0, 17.0), truth[1].copy()]
    book.anchors = [f.copy() for f in book.found]
    book.spread = [1.0, 1.0]
    book.confirmed = {0, 1}
    book._fit_strengths()
    book.settle()
    err = [float(np.min(np.hypot(*(truth - f).T))) for f in book.found]
    assert book.relocated == 1 and max(err) < 1.5, err
    assert book.confirmed == {1}
    book.settle()
    assert book.relocated == 1                                  # settled: nothing moves again
