"""Search strategies and episodes: hand-built cases and seeded statistics."""

import json

import numpy as np
import pytest
from scipy.stats import binom

import arenas
import reciprocity as r
from reciprocity.runner import search

CONTRACT = {"strategy", "arena", "seed", "source", "estimate", "error", "n_measurements",
            "n_samples", "path_length", "success", "region_area", "wall_time_s"}


@pytest.fixture(scope="module")
def empty():
    a = arenas.load("empty")
    return a, r.GreenSolver(a, h=2.0), r.GreenSolver(a, h=1.4)


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
        def start(self, arena, pose, rng):
            seen.append(arena.source)
            super().start(arena, pose, rng)

    platform = r.PointPlatform(truth, arena.source, arena.strength, noise=12.0)
    r.run_episode(arena, Spy(solver=solver), platform, seed=0)
    assert seen == [None]


def test_nearest_rule_follows_step_13(empty):
    arena, solver, truth = empty
    s = r.ReciprocityStrategy(solver=solver, rule="nearest", d=10.0, area_tol=1.0, max_steps=4)
    platform = r.PointPlatform(truth, arena.source, arena.strength, noise=0.0)
    ep = r.run_episode(arena, s, platform, seed=0)
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
        platform = r.PointPlatform(truth, src, arena.strength, noise=12.0)
        ep = r.run_episode(arena, r.ReciprocityStrategy(solver=solver), platform, start=start, seed=seed)
        ok += ep.summary["success"]
        errors.append(ep.summary["error"])
        counts.append(ep.summary["n_measurements"])
    assert binom.sf(9, 12, 0.98) > 0.99
    assert ok >= 10
    assert np.median(errors) < 1.5 * solver.h  # a coarse 2 cm mesh here; 1 cm halves it
    assert np.median(counts) <= 8


def test_gradient_ascent_reaches_the_source_without_noise(empty):
    arena, solver, truth = empty
    s = r.GradientStrategy(solver=solver)
    platform = r.PointPlatform(truth, arena.source, arena.strength, noise=0.0)
    ep = r.run_episode(arena, s, platform, seed=0)
    S = ep.summary
    assert S["stop_reason"].startswith("gradient puts the source") and S["success"]
    assert S["error"] < s.stop_radius
    paper_rule = r.run_episode(arena, r.GradientStrategy(solver=solver, i_max=300.0), platform, seed=0)
    assert paper_rule.summary["stop_reason"] == "signal above i_max"
    n_gradients = sum(rec["kind"] == "gradient" for rec in ep.trace)
    assert S["n_samples"] == S["n_measurements"] + 2 * n_gradients
    assert len(s.gradients) == n_gradients


def test_episode_summary_and_trace_serialise(tmp_path):
    ep, strat, plat = search(arenas.load("empty"), "reciprocity", seed=2, h=3.0)
    data = json.loads(ep.to_json(tmp_path / "ep.json"))
    assert CONTRACT <= set(data)
    assert data["n_measurements"] == len(data["trace"])
    assert data["error"] == pytest.approx(np.hypot(*(np.subtract(data["estimate"], data["source"]))))
    again, _, _ = search(arenas.load("empty"), "reciprocity", seed=2, h=3.0)
    assert again.summary["estimate"] == ep.summary["estimate"]  # same seed, same result


def test_point_platform_path_goes_around_obstacles():
    arena = arenas.load("deep_u")
    solver = r.GreenSolver(arena, h=3.0)
    p = r.PointPlatform(solver, arena.source, arena.strength)
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
        search(arenas.load("empty"), "spiral")
    with pytest.raises(r.SearchError, match="unknown car option"):
        search(arenas.load("empty"), "gradient", platform="car", car={"wheels": 6})
    with pytest.raises(r.SearchError, match="need platform='car'"):
        search(arenas.load("empty"), "gradient", car={"rho": 12})


def _strategy_with_belief(solver, arena, belief, **kw):
    s = r.ReciprocityStrategy(solver=solver, **kw)
    s.start(arena.without_scenario(), np.array([20.0, 20.0, 0.0]), np.random.default_rng(0))
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
