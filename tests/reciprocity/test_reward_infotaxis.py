"""Infotaxis II and III (reward_infotaxis.py) and the song2019-table1 protocols."""

from dataclasses import replace

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.beliefs.base import posterior_entropies, shannon_entropy
from reciprocity.errors import SearchError
from reciprocity.scenarios import load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.reward_infotaxis import expected_posterior_spread, expected_renyi_divergence

from plume_beliefs import hand_built


def _cloud(seed=0):
    """A hand-built belief on song-100 and the outcome table of three candidate moves."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-20, 20, size=(60, 2))
    pts[:3] = [[0.0, 2.5], [2.0, 1.0], [-3.0, -1.0]]        # within the found radius of a move
    w = rng.dirichlet(np.ones(60))
    s = hand_built("infotaxis-ii", pts, w, at=(0.0, 0.0), grid=False)
    cands = np.array([[0.0, 1.0], [1.0, 0.0], [-1.0, 0.0]])
    joint, _, dist = s.belief.outcomes(cands)
    return s, cands, joint, s.belief.weights(), dist <= s.belief.found_radius


def test_renyi_divergence_of_order_near_one_is_the_expected_kullback_leibler_gain():
    # E_o KL(post_o || prior) over the outcomes: found (the belief restricted to the found
    # zone, KL = -ln P_f) or z hits; with counts summed to z_max this is infotaxis' expected
    # entropy drop up to the truncation
    s, cands, joint, w, near = _cloud()
    assert near.any()
    rho, H, P = posterior_entropies(joint)
    p_f = np.where(near, w, 0.0).sum(axis=1)
    q = joint / np.maximum(P, 1e-300)[..., None]
    kl = np.sum(np.where(q > 0, q * np.log(np.where(q > 0, q, 1.0) / w), 0.0), axis=-1)
    direct = p_f * -np.log(np.maximum(p_f, 1e-300)) + (1 - p_f) * np.sum(rho * kl, axis=0)
    assert np.allclose(expected_renyi_divergence(joint, w, near, alpha=1 - 1e-7), direct, rtol=1e-5)
    h_found = np.array([shannon_entropy(np.where(n, w, 0.0)) for n in near])
    mi = shannon_entropy(w) - (p_f * h_found + (1 - p_f) * np.sum(rho * H, axis=0))
    assert np.allclose(direct, mi, rtol=0.02)
    # Rényi divergences grow with their order
    d = [expected_renyi_divergence(joint, w, near, alpha=a) for a in (0.3, 0.5, 0.9)]
    assert np.all(d[0] <= d[1]) and np.all(d[1] <= d[2])


def test_expected_posterior_spread_matches_a_direct_sum():
    s, cands, joint, w, near = _cloud(1)
    x = s.belief.support()

    def trace(q):
        q = q / q.sum()
        m = q @ x
        return float(q @ np.sum((x - m) ** 2, axis=1))

    rho, _, P = posterior_entropies(joint)
    for m in range(len(cands)):
        p_f = w[near[m]].sum()
        direct = (p_f * trace(np.where(near[m], w, 0.0)) if p_f > 0 else 0.0) + (1 - p_f) * sum(
            rho[z, m] * trace(joint[z, m]) for z in range(joint.shape[0]) if P[z, m] > 0)
        assert expected_posterior_spread(joint, w, near, x)[m] == pytest.approx(direct, rel=1e-9)


@pytest.mark.parametrize("name", ["infotaxis-ii", "infotaxis-iii"])
def test_rewards_head_for_a_belief_lying_east(name):
    s = hand_built(name, [[12.5, 9.5], [13.5, 9.5], [12.5, 10.5]], [0.5, 0.3, 0.2])
    assert np.allclose(s.propose().point, [10.5, 9.5])


@pytest.mark.parametrize("name", ["infotaxis-ii", "infotaxis-iii"])
def test_registered_and_run_a_short_song_episode(name):
    assert STRATEGIES[name].name == name and "plume" in STRATEGIES[name].worlds
    sc = replace(load_scenario("song-100").with_world({"max_turn": 3}), max_steps=12)
    s = run(sc, name, seed=2, params={"particles": 100}).summary
    assert s["strategy"] == name and s["steps"] <= 12 and s["n_measurements"] == s["steps"]


def test_infotaxis_ii_refuses_order_one():
    with pytest.raises(SearchError, match="alpha must differ from 1"):
        STRATEGIES["infotaxis-ii"](alpha=1.0)
    assert STRATEGIES["infotaxis-ii"](alpha=0.7).params()["alpha"] == 0.7


def test_song_protocols_build_the_printed_and_the_named_turns():
    from reciprocity.campaign.reproduce import TABLES
    table = TABLES["song2019-table1"]
    default, turn30, balanced = (table.protocol(p).spec(1) for p in (None, "turn30", "balanced"))
    assert [s.world for s in default.scenarios] == [{"max_turn": 3}] * 6         # as printed
    assert [s.world for s in turn30.scenarios] == [{"max_turn": 30}] * 6
    assert [s.world for s in balanced.scenarios] == [{"max_turn": 30}] * 6
    names = ["infotaxis", "free-energy", "mapless-infotaxis", "infotaxis-ii", "infotaxis-iii", "entrotaxis"]
    for spec in (default, turn30, balanced):
        assert [v.label for v in spec.variants] == names
    fe = {v.label: v.params for v in balanced.variants}["free-energy"]
    assert fe == {"alpha": 5.3, "area_exponent": 2.35}
    assert {v.label: v.params for v in default.variants}["free-energy"] == {}
    rows = {pv.row: pv.value for pv in table.paper if pv.metric == "steps"}
    assert rows["infotaxis-ii 300²"] == 2389.9 and rows["infotaxis-iii 350²"] == 2372.9
    assert "±3°" in table.note and "±30°" in table.protocol("turn30").note
    assert default.name == "song2019-table1" and turn30.name == "song2019-table1-turn30"
