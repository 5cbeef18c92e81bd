"""Search strategies and episodes: hand-built cases and seeded statistics."""

import json

import numpy as np
import pytest
from scipy.stats import binom

import arenas
import reciprocity as r
from reciprocity.env import SearchEnv, rollout
from reciprocity.scenarios import load_scenario
from reciprocity.spaces import mesh_space
from reciprocity.strategies.agent import StrategyAgent


@pytest.fixture(scope="module")
def empty():
    a = arenas.load("empty")
    return a, r.GreenSolver(a, h=2.0), 1.4


def episode(arena, strategy, *, source=None, start=None, seed=0, noise=12.0, truth_h=1.4, **world):
    """One point-observer episode in the Poisson world of `arena` (truth on a finer mesh)."""
    arena = arena.with_scenario(source=source, start=start)
    sc = load_scenario(arena).with_world(dict(noise=noise, truth_h=truth_h, **world))
    return rollout(SearchEnv(sc, platform_options={"route_h": 3.0}), StrategyAgent(strategy), seed)


def test_three_point_gradient_is_exact_for_planes():
    pts = np.array([[1.0, 2.0], [-1.0, 2.5], [3.0, -1.0]])
    g = np.array([0.7, -1.3])
    assert np.allclose(r.three_point_gradient(pts, pts @ g + 5.0), g)
    with pytest.raises(r.SearchError, match="collinear"):
        r.three_point_gradient(np.array([[0, 0], [1, 1], [2, 2.0]]), np.zeros(3))


def test_strategy_never_sees_the_source(empty):
    arena, solver, truth = empty
    seen = []

    class Spy(r.ReciprocityStrategy):
        def start(self, ctx):
            seen.append((ctx.arena.source, sorted(ctx.nominal)))
            super().start(ctx)

    episode(arena, Spy(solver=solver))
    assert seen == [(None, ["arena", "noise", "strength"])]


def test_nearest_rule_follows_step_13(empty):
    arena, solver, truth = empty
    s = r.ReciprocityStrategy(solver=solver, rule="nearest", d=10.0, area_tol=1.0, max_steps=4)
    ep = episode(arena, s, noise=0.0)
    pts = np.array([rec["points"][0] for rec in ep.trace])
    for k in range(1, len(pts)):
        # at least d from every earlier point, and as near as that allows (within a mesh size)
        dist = np.hypot(*(pts[:k] - pts[k]).T)
        assert dist.min() >= 10.0 - 1e-9
        assert np.hypot(*(pts[k] - pts[k - 1])) <= 10.0 + 2 * solver.h
        # inside {v_k > I_k} of the previous measurement
        v = arena.strength * solver.green(pts[k - 1])(pts[k][None])[0]
        assert v > ep.trace[k - 1]["readings"][0]


def test_reciprocity_search_statistics_on_empty(empty):
    """12 seeded episodes, noise sigma = 12: at least 10 succeed (if the true success rate
    were only 0.8, 10 or more successes would have probability 0.28; at the measured rate
    of about 0.98 the bound holds with probability 0.99)."""
    arena, solver, truth = empty
    rng = np.random.default_rng(7)
    ok, errors, counts = 0, [], []
    for seed in range(12):
        src = arena.random_free_points(1, rng, clearance=8.0)[0]
        start = np.append(arena.random_free_points(1, rng, clearance=5.0)[0], 0.0)
        ep = episode(arena, r.ReciprocityStrategy(solver=solver), source=src, start=start, seed=seed)
        ok += ep.summary["success"]
        errors.append(ep.summary["error"])
        counts.append(ep.summary["n_measurements"])
    assert binom.sf(9, 12, 0.98) > 0.99
    assert ok >= 10
    assert np.median(errors) < 1.5 * solver.h  # a coarse 2 cm mesh here; 1 cm halves it
    assert np.median(counts) <= 8


def test_gradient_ascent_reaches_the_source_without_noise(empty):
    arena, solver, truth = empty
    s = r.GradientStrategy(h=2.0)
    ep = episode(arena, s, noise=0.0)
    S = ep.summary
    assert S["stop_reason"] == "converged: gradient puts the source within stop_radius" and S["success"]
    assert S["converged"] and S["error"] < s.stop_radius
    paper_rule = episode(arena, r.GradientStrategy(h=2.0, i_max=300.0, stop_radius=0.0), noise=0.0)
    assert paper_rule.summary["stop_reason"] == "converged: signal above i_max"
    n_gradients = sum(rec["kind"] == "gradient" for rec in ep.trace)
    assert S["n_samples"] == S["n_measurements"] + 2 * n_gradients
    assert len(s.gradients) == n_gradients


def test_gradient_ascent_stops_when_it_stalls(empty):
    """Gradient steps that keep starting from the same few centimetres (a car circling
    the saturated disk) end the search at the strongest sample, not at the step cap."""
    from reciprocity.intents import Measure, SampleGradient
    arena, solver, truth = empty
    s = r.GradientStrategy(h=2.0, stop_radius=0.0)
    s.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=arena.strength, noise=0.0),
                            np.array([[70.0, 70.0, 0.0]]), np.random.default_rng(0)))
    centre = np.array([70.0, 70.0])
    for k in range(6):
        p = centre + 2.0 * np.array([np.cos(k), np.sin(k)])
        s.observe([r.Observation(p, 100.0 + k)], Measure(p))
        assert isinstance(s.propose(), SampleGradient)
        # a weak, turning gradient: the source looks far (no radius stop), the steps go round
        s.observe([r.Observation(p + [5.0, 0.0], 100.0 + k), r.Observation(p + [0.0, 5.0], 100.5 + k)],
                  SampleGradient(p, 5.0))
        if s.done:
            break
    assert s.done and s.outcome.reason == r.StopReason.CONVERGED and "stalled" in s.outcome.detail
    assert len(s.gradients) == s.stall_steps
    assert np.allclose(s.estimate, centre + 2.0 * np.array([np.cos(2), np.sin(2)]) + [0.0, 5.0])
    # with i_max, stalling far below it is a wall, not the source: the search goes on
    far = r.GradientStrategy(h=2.0, stop_radius=0.0, i_max=1000.0)
    far.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=arena.strength, noise=0.0),
                              np.array([[70.0, 70.0, 0.0]]), np.random.default_rng(0)))
    far.gradients = list(s.gradients)
    far._best = (100.0, centre)
    assert not far._stalled()
    far._best = (0.7 * 1000.0, centre)
    assert far._stalled()
    with pytest.raises(r.SearchError, match="stall_steps"):
        r.GradientStrategy(stall_steps=1)
    with pytest.raises(r.SearchError, match="stop_radius"):
        r.GradientStrategy(stop_radius=-1.0)


def test_episode_summary_and_trace_serialise(tmp_path):
    ep, strat, plat = r.execute(arenas.load("empty"), "reciprocity", seed=2, params={"h": 3.0})
    data = json.loads(ep.to_json(tmp_path / "ep.json"))
    assert set(r.SUMMARY_KEYS) <= set(data)
    assert data["n_measurements"] == len(data["trace"])
    assert data["error"] == pytest.approx(np.hypot(*(np.subtract(data["estimate"], data["source"]))))
    again, _, _ = r.execute(arenas.load("empty"), "reciprocity", seed=2, params={"h": 3.0})
    assert again.summary["estimate"] == ep.summary["estimate"]  # same seed, same result


def test_point_platform_path_goes_around_obstacles():
    arena = arenas.load("deep_u")
    p = r.PointPlatform(mesh_space(arena.without_scenario(), 3.0))
    straight = np.hypot(*(arena.source - arena.start[:2]))
    assert p.distance(arena.start[:2], arena.source) > straight + 20


@pytest.mark.parametrize("kwargs, match", [
    (dict(eps=1.5), "eps"), (dict(d=-1), "d must be"), (dict(rule="random"), "rule"),
    (dict(max_steps=0), "max_steps"), (dict(extent_tol=0), "extent_tol"),
])
def test_bad_reciprocity_parameters(kwargs, match):
    with pytest.raises(r.SearchError, match=match):
        r.ReciprocityStrategy(**kwargs)


def test_bad_gradient_parameters():
    with pytest.raises(r.SearchError, match="i_min < i_max"):
        r.GradientStrategy(i_min=50, i_max=20)
    with pytest.raises(r.SearchError, match="unknown strategy"):
        r.execute(arenas.load("empty"), "spiral")
    with pytest.raises(r.SearchError, match="unknown car option"):
        r.execute(arenas.load("empty"), "gradient", platform="car", platform_options={"wheels": 6})
    with pytest.raises(r.SearchError, match="unknown point-observer option"):
        r.execute(arenas.load("empty"), "gradient", platform_options={"rho": 12})


def _strategy_with_belief(solver, arena, belief, **kw):
    s = r.ReciprocityStrategy(solver=solver, **kw)
    s.start(r.SearchContext("poisson", dict(arena=arena.without_scenario(), strength=arena.strength),
                            np.array([[20.0, 20.0, 0.0]]), np.random.default_rng(0)))
    s.imaging.add((20.0, 20.0), 0.0)
    s.imaging._cache["P"] = belief(solver.nodes)
    return s


def test_axis_rule_measures_across_an_elongated_belief(empty):
    arena, solver, _ = empty
    # a belief stretched along x (std 5 cm) and thin in y (std 1.4 cm), centred at (70, 70)
    s = _strategy_with_belief(solver, arena, lambda p: np.exp(-((p[:, 0] - 70) / 7.0) ** 2
                                                                - ((p[:, 1] - 70) / 2.0) ** 2))
    nxt = s.next_point()
    assert abs(nxt[1] - 70) <= solver.h            # on the major axis
    assert abs(abs(nxt[0] - 70) - 10) <= solver.h  # 2 std = 10 cm beyond the centre


def test_reach_rule_goes_where_the_mass_is(empty):
    arena, solver, _ = empty
    # a broad belief: everything but the lower-left quarter
    s = _strategy_with_belief(solver, arena, lambda p: ((p[:, 0] > 70) | (p[:, 1] > 70)).astype(float),
                              rule="reach")
    nxt = s.next_point()
    assert nxt[0] > 70 or nxt[1] > 70


def test_giving_up_near_the_source_is_not_a_success(empty):
    """A run whose estimate lands near the source but that stops on its step cap (or for
    want of targets) has not converged, so it is not a success."""
    arena, solver, _ = empty
    ep = episode(arena, r.ReciprocityStrategy(solver=solver, max_steps=2, area_tol=1.0), noise=0.0)
    S = ep.summary
    assert S["stop"] == "step cap" and not S["converged"] and not S["success"]
    near = r.RandomWalkStrategy(n_steps=3)
    S = episode(arena, near, start=[88.0, 60.0, 0.0], noise=0.0).summary
    assert S["error"] < 10 and not S["converged"] and not S["success"]


def test_saturated_readings_are_censored(empty):
    """A saturated reading says "at least I": every node whose prediction exceeds I keeps
    p = 1; an exact reading of the same value would rule them out."""
    arena, solver, _ = empty
    z = np.array([40.0, 40.0])
    exact, censored = (r.ImagingMap(solver, 12.0, strength=850.0) for _ in range(2))
    exact.add(z, 150.0)
    censored.update(r.Observation(z, 150.0, saturated=True))
    above = censored.model()[:, 0] > 150.0 + 3 * 12.0
    assert above.sum() > 10
    assert np.all(censored.p_maps()[above, 0] == 1.0)
    assert np.all(exact.p_maps()[above, 0] < np.exp(-9))


def test_model_mismatch_changes_the_truth_not_the_strategy(empty):
    """A 30 % stronger true source: the strategy is told the nominal strength; the world
    reads 1.3 times the nominal field (noise-free)."""
    arena, solver, _ = empty
    told = []

    class Spy(r.RandomWalkStrategy):
        def start(self, ctx):
            told.append(ctx.nominal["strength"])
            super().start(ctx)

    a = episode(arena, Spy(n_steps=3), noise=0.0)
    b = episode(arena, Spy(n_steps=3), noise=0.0, mismatch=r.Mismatch(strength_factor=1.3))
    assert told == [arena.strength, arena.strength]
    ra = np.concatenate([rec["readings"] for rec in a.trace])
    rb = np.concatenate([rec["readings"] for rec in b.trace])
    assert np.allclose(rb, 1.3 * ra, rtol=1e-9)
    assert b.summary["mismatch"]["strength_factor"] == 1.3


def test_shifted_walls_move_the_truth(empty):
    arena = arenas.load("paper")
    w = r.PoissonWorld(arena, mismatch=r.Mismatch(wall_shift=1.0), h=3.0)
    # a point 0.5 cm off an obstacle edge is free for the strategy, inside the true wall
    p = np.array([[40.0, 70.0 + 0.0]]) + np.array([[-0.5, 0.0]])
    assert arena.contains(p)[0] and not w.contains(p)[0]
    assert w.true_arena.area < arena.area


def test_trace_records_refuse_colliding_keys(empty):
    rec = r.StepRecord(1, 0, "measure", "signal", np.zeros(2), [], np.zeros(3), np.zeros((1, 2)), 0.0,
                       0.0, belief={"next": [1, 2]}, platform={"next": [3, 4]})
    with pytest.raises(r.SearchError, match="clash"):
        rec.as_dict()
