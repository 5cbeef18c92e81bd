"""Beyond the papers of issue 12: the look-ahead searcher and the arena infotaxis cross-run."""

from dataclasses import replace

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.errors import SearchError
from reciprocity.scenarios import load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.arena_infotaxis import gaussian_expected_entropy
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.infotaxis import candidate_moves
from reciprocity.strategies.lookahead import move_set

from plume_beliefs import hand_built

_strategy = hand_built


CLOUD = ([[12.5, 9.5], [13.5, 9.5], [12.5, 10.5], [6.5, 12.5], [9.5, 4.5]], [0.3, 0.2, 0.2, 0.2, 0.1])


# -- the look-ahead searcher ------------------------------------------------------------------
def test_depth_one_reproduces_infotaxis_and_space_aware_infotaxis():
    ref = _strategy("infotaxis", *CLOUD)
    mine = _strategy("lookahead", *CLOUD, cost="entropy")
    cands, _ = candidate_moves(ref.nominal, ref.pos, ref.heading)
    # infotaxis' score is the expected entropy minus the current entropy S
    assert np.allclose(mine.scores(cands) - ref.belief.entropy(), ref.scores(cands), atol=1e-12)
    ref = _strategy("space-aware-infotaxis", *CLOUD)
    mine = _strategy("lookahead", *CLOUD, cost="space-aware")
    assert np.allclose(mine.scores(cands), ref.scores(cands), atol=1e-12)


def _brute_second(s, cands):
    """Depth-two scores by explicit loops over outcomes and second moves."""
    b = s.belief
    joint, p_found, _ = b.outcomes(cands, eta=s.eta)
    P = joint.sum(axis=2)
    rho = P / P.sum(axis=0)
    _, hds = candidate_moves(s.nominal, s.pos, s.heading)
    out = []
    for v in range(len(cands)):
        total = 0.0
        for z in range(joint.shape[0]):
            if P[z, v] <= 0:
                continue
            post = joint[z, v] / P[z, v]
            keep = (b.x.copy(), b._w.copy())
            b._w = post
            pts2, _ = candidate_moves(s.nominal, cands[v], hds[v])
            inner = []
            for u in pts2:
                j2, pf2, _ = b.outcomes(u[None], eta=s.eta)
                P2 = j2.sum(axis=2)[:, 0]
                r2 = P2 / P2.sum()
                cost = s._cost(j2[:, 0][:, None, :], u[None])[:, 0]
                inner.append((1 - pf2[0]) * np.sum(np.where(P2 > 0, r2 * cost, 0.0)))
            b.x, b._w = keep
            total += rho[z, v] * min(inner)
        out.append((1 - p_found[v]) * total)
    return np.array(out)


@pytest.mark.parametrize("cost", ["entropy", "space-aware", "distance"])
def test_depth_two_matches_explicit_enumeration_on_the_grid(cost):
    s = _strategy("lookahead", *CLOUD, cost=cost, depth=2)
    cands, _ = candidate_moves(s.nominal, s.pos, s.heading)
    assert np.allclose(s.scores(cands), _brute_second(s, cands), rtol=1e-9, atol=1e-12)


def test_move_set_keeps_the_order_of_candidate_moves_and_masks_the_outside():
    nom = load_scenario("song-100").with_world({"max_turn": 30}).build_world(0).nominal()
    pts, hds, inside = move_set(nom, np.array([[0.0, 0.0], [49.5, 0.0]]), np.array([0.0, 0.0]))
    ref, ref_h = candidate_moves(nom, [0.0, 0.0], 0.0)
    assert np.allclose(pts[0], ref) and np.allclose(hds[0], ref_h) and inside[0].all()
    assert not inside[1].all() and np.allclose(pts[1][inside[1]], candidate_moves(nom, [49.5, 0.0], 0.0)[0])


@pytest.mark.parametrize("params", [{}, {"depth": 2}, {"cost": "entropy", "depth": 2}])
def test_lookahead_heads_for_a_belief_lying_east(params):
    s = _strategy("lookahead", [[12.5, 9.5], [13.5, 9.5], [12.5, 10.5]], [0.5, 0.3, 0.2], **params)
    assert np.allclose(s.propose().point, [10.5, 9.5])


def test_distance_cost_turns_toward_the_belief_in_the_plane():
    s = _strategy("lookahead", [[0, 30], [1, 30]], [0.5, 0.5], at=(0, 0), grid=False, heading=0.0)
    move = s.propose()
    assert move.point[1] > 0.05 and np.hypot(*move.point) == pytest.approx(1.0)


def test_lookahead_episodes_find_the_source():
    for seed in range(3):
        s = run("otto-2d", "lookahead", seed=seed, params={"cost": "entropy", "depth": 2}).summary
        assert s["stop"] == "found" and s["success"]
    # song-100 as song2019-table1 runs it: the power-mean distance rule in ~100-160 steps
    # (100 seeds: all found, 95 % of runs below 160); a cap of 250 steps fails only if lost
    sc = replace(load_scenario("song-100"), max_steps=250)
    s = run(sc, "lookahead", seed=0, world={"max_turn": 30}).summary
    assert s["stop"] == "found" and s["steps"] > 90       # at least the straight-line distance


@pytest.mark.parametrize("params, match", [({"cost": "speed"}, "cost must be one of"), ({"depth": 3}, "depth"),
                                           ({"kappa": 0}, "kappa"), ({"power": -1}, "power"),
                                           ({"second_kmax": 0.5}, "second_kmax")])
def test_bad_lookahead_parameters(params, match):
    with pytest.raises(SearchError, match=match) as exc:
        run("song-100", "lookahead", params=params)
    assert "\n" not in str(exc.value)


# -- infotaxis on the Poisson arena --------------------------------------------------------------
def test_gaussian_expected_entropy_limits():
    w = np.log(np.array([0.5, 0.5]))
    sup, sw = np.array([0, 1]), np.array([0.5, 0.5])
    same = np.array([[10.0, 10.0]])                 # a reading that cannot tell them apart
    apart = np.array([[0.0, 100.0]])                # 100 noise sd apart: the reading decides
    assert gaussian_expected_entropy(same, w, sup, sw, 1.0)[0] == pytest.approx(np.log(2))
    assert gaussian_expected_entropy(apart, w, sup, sw, 1.0)[0] == pytest.approx(0.0, abs=1e-9)
    # half a noise sd apart: in between, and the more apart the less entropy left
    e = gaussian_expected_entropy(np.array([[0.0, 0.5], [0.0, 2.0]]), w, sup, sw, 1.0)
    assert np.log(2) > e[0] > e[1] > 0


def test_arena_infotaxis_converges_on_the_empty_arena():
    params = {"spacing": 5.0, "h": 2.0, "step": 10.0, "support": 12}
    s = run("empty", "arena-infotaxis", seed=0, params=params).summary
    assert s["world"] == "poisson" and s["stop"] == "converged"
    assert s["error"] < 5.0 and s["success"]
    assert s["n_measurements"] >= 2


@pytest.mark.parametrize("params, match", [({"step": 0}, "step"), ({"confidence": 1.0}, "confidence"),
                                           ({"support": 0}, "support"), ({"sigma": -1}, "sigma")])
def test_bad_arena_infotaxis_parameters(params, match):
    with pytest.raises(SearchError, match=match):
        run("empty", "arena-infotaxis", params=params)


def test_arena_infotaxis_refuses_plume_worlds():
    with pytest.raises(SearchError, match="does not apply|applies to"):
        run("song-100", "arena-infotaxis")


# -- the reciprocity search's imaging on the plume (cross-run b adapter) --------------------------
def _imaging(at=(33.0, -33.0), **params):
    sc = load_scenario("song-100")
    nom = sc.build_world(0).nominal()
    s = STRATEGIES["plume-reciprocity"](**params)
    s.start(SearchContext("plume", nom, np.array([[at[0], at[1], np.pi / 2]]), np.random.default_rng(0)))
    return s, nom


def test_plume_imaging_is_the_poisson_posterior_on_its_lattice():
    from scipy.stats import poisson
    from reciprocity.observations import Observation
    from reciprocity.models.plume import plume_rate
    s, nom = _imaging()
    r = np.array([10.0, 20.0])
    s.observe([Observation(r, 2.0, 0.0, 1.0, "hits")], None)
    lik = poisson.pmf(2, plume_rate(r[None], s.nodes, nom["plume"])[0] * nom["dt"])
    lik[np.hypot(*(s.nodes - r).T) <= nom["found_radius"]] = 0.0
    assert np.allclose(s.weights(), lik / lik.sum(), rtol=1e-9, atol=1e-15)


def test_plume_imaging_reach_rule_picks_the_mass_within_reach_away_from_places_read():
    s, _ = _imaging(reach=3.0)
    # two clusters: the heavier one wins; once every point near it has been read from,
    # the lighter one
    w = np.full(len(s.nodes), 1e-30)
    a = np.hypot(*(s.nodes - [-21.0, 21.0]).T) <= 4.0
    b = np.hypot(*(s.nodes - [21.0, 21.0]).T) <= 4.0
    w[a], w[b] = 2.0, 1.0
    s.logp = np.log(w)
    assert np.hypot(*(s.target() - [-21.0, 21.0])) <= 2.0
    s.far &= np.hypot(*(s.nodes - [-21.0, 21.0]).T) >= 6.0
    assert np.hypot(*(s.target() - [21.0, 21.0])) <= 2.0


def test_plume_imaging_episodes_find_the_source():
    for seed in range(3):
        s = run("otto-2d", "plume-reciprocity", seed=seed).summary
        assert s["stop"] == "found" and s["success"]
    sc = replace(load_scenario("song-100"), max_steps=300)
    s = run(sc, "plume-reciprocity", seed=0, world={"max_turn": 30}).summary
    assert s["stop"] == "found" and s["steps"] > 90


@pytest.mark.parametrize("params, match", [({"h": 0}, "h must"), ({"reach": -1}, "reach"), ({"d": 0}, "d must")])
def test_bad_plume_imaging_parameters(params, match):
    with pytest.raises(SearchError, match=match):
        run("song-100", "plume-reciprocity", params=params)


# -- the bound of benchmarks/plume_phases.py -----------------------------------------------------
def _phases_module(monkeypatch):
    import importlib.util
    import sys
    from pathlib import Path
    bench = Path(__file__).resolve().parents[2] / "benchmarks"
    monkeypatch.syspath_prepend(str(bench))          # its shared helpers (plume_bench)
    spec = importlib.util.spec_from_file_location("plume_phases", bench / "plume_phases.py")
    mod = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "plume_phases", mod)     # its workers unpickle by name
    spec.loader.exec_module(mod)
    return mod


def test_phase_bound_is_the_straight_walk_and_grows_with_the_turn_limit(monkeypatch):
    oracle = _phases_module(monkeypatch).oracle_steps
    # heading already at the source: ceil(d - R) unit steps
    assert oracle([0, 0], 0.0, [10, 0], step=1.0, max_turn_deg=30, radius=3.0) == 7
    # facing away: the U-turn costs steps; a tighter turn limit costs more
    wide = oracle([0, 0], 180.0, [10, 0], step=1.0, max_turn_deg=30, radius=3.0)
    tight = oracle([0, 0], 180.0, [10, 0], step=1.0, max_turn_deg=3, radius=3.0)
    assert 7 + 5 <= wide < tight
    # song-100 with 30 degree turns: 94.3 apart, start heading 90 degrees, 45 off the line
    assert oracle([33.33, -33.33], 90.0, [-33.33, 33.33], step=1.0, max_turn_deg=30, radius=3.0) == 92


def test_phase_report_takes_a_start_override_in_radians(monkeypatch, tmp_path, capsys):
    mod = _phases_module(monkeypatch)
    # facing away from the source (-45 degrees, given in radians like every world override)
    mod.main(["--scenario", "song-100", "--world", "max_turn=30", "--world", f"start=[33.33,-33.33,{-np.pi / 4}]",
              "--strategy", "lookahead", "--seeds", "1", "--out", str(tmp_path)])
    away = mod.oracle_steps([33.33, -33.33], -45.0, [-33.33, 33.33], step=1.0, max_turn_deg=30, radius=3.0)
    out = capsys.readouterr().out
    assert f"bound (knows the source) {away} steps" in out and away > 92
    assert "| lookahead |" in out
