"""The lattice world of Ristic et al. (2014) and its RBPF searcher."""

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.sparse import identity
from scipy.sparse.csgraph import connected_components

from reciprocity.api import run
from reciprocity.beliefs.rbpf import RBPFBelief
from reciprocity.episode import SUMMARY_KEYS
from reciprocity.errors import SearchError
from reciprocity.intents import Move, Stay
from reciprocity.platforms.lattice import LatticePlatform
from reciprocity.spaces.lattice import CONTROLS
from reciprocity.models.lattice import log_bhattacharyya, log_evidence, log_gain
from reciprocity.observations import Observation
from reciprocity.scenarios import load_scenario
from reciprocity.spaces.lattice import LatticeSpace
from reciprocity.worlds.lattice import LatticeWorld, draw_links, green_row


def _world(seed=1, **over):
    return load_scenario("ristic-lattice").with_world(over).build_world(seed)


def test_paper_lattice_has_572_links():
    s = LatticeSpace(9)
    assert (len(s), len(s.links), int(s.transient.sum())) == (305, 572, 253)
    i = s.index_of([0, 0])[0]
    assert sorted(s.points[s.neighbours(i)].tolist()) == [[-1, 0], [0, -1], [0, 1], [1, 0]]
    assert s.index_of([[0.5, 0], [0, 10]]).tolist() == [-1, -1]


def test_green_row_matches_dense_inverse():
    s = LatticeSpace(3)
    present, _ = draw_links(s, 0.2, np.random.default_rng(3))
    s = s.with_links(present)
    src = int(s.index_of([0, 1])[0])
    lab = connected_components(s.adjacency, directed=False)[1]
    t = np.flatnonzero(s.transient & (lab == lab[src]))
    a = s.adjacency.toarray()
    deg = a.sum(axis=1)
    q = (a / np.maximum(deg, 1)[:, None])[np.ix_(t, t)]
    dense = np.linalg.inv(np.eye(len(t)) - q)
    row = green_row(s, src)
    np.testing.assert_allclose(row[t], dense[list(t).index(src)], rtol=1e-10, atol=1e-12)
    assert np.all(row[~s.transient] == 0)


def test_green_row_on_ten_thousand_nodes_is_sparse_and_exact():
    s = LatticeSpace(56)
    assert len(s) > 9000
    src = int(s.index_of([0, 0])[0])
    present, _ = draw_links(s, 0.35, np.random.default_rng(0), connectivity="nodes", keep=(src,))
    s = s.with_links(present)
    row = green_row(s, src)
    lab = connected_components(s.adjacency, directed=False)[1]
    t = np.flatnonzero(s.transient & (lab == lab[src]))
    deg = np.asarray(s.adjacency.sum(axis=1)).ravel()
    q = (s.adjacency.multiply(1.0 / np.maximum(deg, 1)[:, None])).tocsr()[t][:, t]
    resid = (identity(len(t)) - q).T @ row[t]
    e = np.zeros(len(t))
    e[list(t).index(src)] = 1
    assert np.abs(resid - e).max() < 1e-8
    assert row[src] >= 1


def test_connectivity_redraw_connects_every_inner_node():
    s = LatticeSpace(9)
    start = int(s.index_of([9, -4])[0])
    present, draws = draw_links(s, 0.35, np.random.default_rng(5), keep=(start,))
    assert draws > 1                      # a random 35 % cut is almost never connected at once
    assert (~present).sum() == round(0.35 * 572)
    lab = connected_components(s.with_links(present).adjacency, directed=False)[1]
    assert len(set(lab[s.transient])) == 1 and lab[start] == lab[s.transient][0]


def test_same_seed_same_lattice_and_lattice_seed_fixes_it():
    a, b, c = _world(4), _world(4), _world(5)
    assert np.array_equal(a.space.present, b.space.present)
    assert not np.array_equal(a.space.present, c.space.present)
    d, e = _world(4, lattice_seed=7), _world(5, lattice_seed=7)
    assert np.array_equal(d.space.present, e.space.present)


def test_count_sensor_is_poisson_with_lattice_mean():
    w = _world(2)
    rng = np.random.default_rng(0)
    at = np.array([0.0, 6.0])
    lam = w.mean(at)
    n = 3000
    x = np.array([w.read(at, time=0, dwell=1, rng=rng).value for _ in range(n)])
    assert abs(x.mean() - lam) < 4 * np.sqrt(lam / n)
    assert abs(x.var() - lam) < 5 * lam * np.sqrt(2 / n) + 4 * np.sqrt(lam / n)
    assert w.mean([9, -4]) == 0.0           # absorbing ring


def test_link_sensor_detection_rates():
    w = _world(3)
    sp = w.space
    rng = np.random.default_rng(1)
    sec = sp.second_link_of
    n = 4000
    hits = {(1, 1): [0, 0], (1, 0): [0, 0]}
    for node in rng.choice(np.flatnonzero(sp.transient), n):
        z1, z2 = w.links_seen(int(node), rng)
        lid = sp.link_of[node]
        np.testing.assert_array_equal(z1, (lid >= 0) & sp.present[np.maximum(lid, 0)])   # p_d 1, p_fa 0
        for d in range(4):
            if z2[d] < 0:
                assert z1[d] == 0
                continue
            m = int(sec[node, d] >= 0 and sp.present[sec[node, d]])
            hits[(1, m)][0] += z2[d]
            hits[(1, m)][1] += 1
    for m, p in ((1, 0.8), (0, 0.1)):
        k, tot = hits[(1, m)]
        assert abs(k / tot - p) < 4 * np.sqrt(p * (1 - p) / tot)


def test_platform_moves_stays_at_missing_links_and_slips_at_rate():
    w = _world(1)
    sp = w.space
    p = LatticePlatform(sp, slip=0.0)
    p.reset([9, -4, 0], w, np.random.default_rng(0))
    here = int(sp.index_of([9, -4])[0])
    for d in range(4):
        lid = sp.link_of[here, d]
        p.reset([9, -4, 0], w, np.random.default_rng(0))
        p.execute(Move(p.pose[:2] + CONTROLS[d + 1]))
        moved = lid >= 0 and sp.present[lid]
        assert np.array_equal(p.true_position, sp.points[sp.step_of[here, d]] if moved else [9, -4])
        assert np.array_equal(p.pose[:2], [9, -4] + CONTROLS[d + 1])   # dead reckoning
    q = LatticePlatform(sp, slip=0.04)
    q.reset([0, 0, 0], w, np.random.default_rng(2))
    n = 5000
    for _ in range(n):
        q.execute(Stay(q.pose[:2]))
    assert abs(q.slips / n - 0.04) < 4 * np.sqrt(0.04 * 0.96 / n)
    with pytest.raises(SearchError, match="one unit"):
        q.execute(Move(q.pose[:2] + [2, 0]))


def test_closed_forms_match_numerical_integrals():
    eta, theta, c = 7.0, 0.8, 0.6
    g = stats.gamma(eta, scale=theta)
    for n in (0, 3, 11):
        num_i = integrate.quad(lambda a: stats.poisson.pmf(n, c * a) * g.pdf(a), 0, 80)[0]
        num_j = integrate.quad(lambda a: np.sqrt(stats.poisson.pmf(n, c * a)) * g.pdf(a), 0, 80)[0]
        assert np.isclose(np.exp(log_evidence(n, eta, theta, c)), num_i, rtol=1e-7)
        assert np.isclose(np.exp(log_bhattacharyya(n, eta, theta, c)), num_j, rtol=1e-7)


def test_log_model_is_zero_on_the_rim_and_symmetric():
    s = np.array([[0.0, 0.0]])
    assert np.isclose(log_gain(np.array([[9.0, 0.0]]), s, 9.0)[0], 0.0)
    assert np.isclose(log_gain(np.array([[3.0, 0.0]]), s, 9.0)[0], np.log(3.0))
    a, b = np.array([[1.0, 2.0]]), np.array([[-3.0, 4.0]])
    assert np.isclose(log_gain(a, b, 9.0), log_gain(b, a, 9.0))


def _belief(n=400, seed=0):
    return RBPFBelief(LatticeSpace(9), [0, 0], np.random.default_rng(seed), n_particles=n, regularise=False)


def test_rbpf_links_seen_set_link_probabilities():
    b = _belief()
    here = int(b.space.index_of([0, 0])[0])
    b.update(Observation([0, 0], 0, kind="hits", data={"primary": [1, 0, 1, 1], "secondary": [1, -1, 0, 1]}))
    q = b.link_probability()
    lid = b.space.link_of[here]
    np.testing.assert_allclose(q[lid], [1, 0, 1, 1], atol=1e-6)
    sec = b.space.second_link_of[here]
    np.testing.assert_allclose(q[sec[[0, 2]]], [0.8 * 0.5 / (0.8 * 0.5 + 0.1 * 0.5), 0.2 * 0.5 / (0.2 * 0.5 + 0.9 * 0.5)],
                               rtol=1e-5)
    assert np.isclose(q[sec[1]], 0.5)               # not observable: unchanged


def test_rbpf_zero_counts_push_the_source_away_and_counts_pull_it_close():
    b = _belief(2000)
    near0 = np.mean(np.hypot(*b.source.T) < 3)
    for _ in range(5):
        b.predict(0)
        b.update(Observation([0, 0], 0, kind="hits", data={"primary": [1, 1, 1, 1], "secondary": [-1] * 4}))
    assert np.mean(np.hypot(*b.source.T) < 3) < near0 / 3
    assert b.eta == 15.0 and np.all(b.theta < 1.0)
    c = _belief(2000, seed=1)
    for _ in range(5):
        c.predict(0)
        c.update(Observation([0, 0], 30, kind="hits", data={"primary": [1, 1, 1, 1], "secondary": [-1] * 4}))
    assert np.mean(np.hypot(*c.source.T) < 3) > 0.9
    assert c.eta == 15.0 + 150


def test_rbpf_links_localise_the_searcher():
    b = _belief(400)
    sp = b.space
    rim = int(sp.index_of([9, -4])[0])            # no potential link east or south
    b.node[:200] = rim
    b.update(Observation([0, 0], 0, kind="hits", data={"primary": [1, 1, 1, 1], "secondary": [-1] * 4}))
    assert np.all(b.node == sp.index_of([0, 0])[0])


def test_episode_through_api_has_contract_keys():
    for name in ("rbpf", "rbpf-infotaxis"):
        s = run("ristic-lattice", name, seed=3, params={"n_particles": 200, "n_gain": 50},
                world={"source": [2, -5]}).summary
        assert set(SUMMARY_KEYS) <= set(s)
        assert s["world"] == "lattice" and s["arena"] == "ristic-lattice" and s["strategy"] == name
        assert s["steps"] >= 1 and s["steps"] <= 100
        assert s["success"] == (s["stop"] == "found")


@pytest.mark.parametrize("world, match", [
    ({"p": 0.5}, "percolation"),
    ({"p": 0.7}, "percolation"),
    ({"source": [0, 9.5]}, "not a node"),
    ({"source": [9, -4]}, "not a node"),            # on the absorbing ring
    ({"source": [0.5, 1]}, "not a node"),
    ({"strength": 0}, "release rate A0 in \\(0, 1e\\+06\\]"),
    ({"strength": -3}, "release rate A0 in \\(0, 1e\\+06\\]"),
    ({"start": [0.5, 0]}, "not a lattice node"),
    ({"lattice_seed": -1}, "lattice_seed"),
    ({"localisation": "gps"}, "localisation must be 'unknown'"),
])
def test_bad_world_input_is_one_line_error(world, match):
    with pytest.raises(SearchError, match=match) as exc:
        run("ristic-lattice", "rbpf", seed=0, params={"n_particles": 20, "n_gain": 5}, world=world)
    assert "\n" not in str(exc.value)


def test_start_cut_off_from_the_source_is_an_error():
    sc = load_scenario("ristic-lattice").with_world({"connectivity": "nodes", "entry": None})
    w = sc.build_world(0)
    lab = connected_components(w.space.adjacency, directed=False)[1]
    cut = w.space.points[lab != lab[w.source_node]][0]
    with pytest.raises(SearchError, match="cut off"):
        run(sc.with_world({"start": cut.tolist()}), "rbpf", seed=0, params={"n_particles": 20, "n_gain": 5})


@pytest.mark.parametrize("params, match", [({"n_particles": 5}, "n_particles"), ({"n_gain": 0}, "n_gain"),
                                           ({"ideal": "mode"}, "ideal"), ({"eta0": 0}, "eta0")])
def test_bad_strategy_parameters(params, match):
    with pytest.raises(SearchError, match=match):
        run("ristic-lattice", "rbpf", seed=0, params=params)


def test_world_without_map_knowledge_in_nominal():
    w = _world(1)
    nom = w.nominal()
    assert nom["space"].present.all() and "source" not in nom
    assert isinstance(w, LatticeWorld)


def test_the_papers_lattice_is_shipped_with_its_shortest_paths():
    """ristic-lattice-paper: one lattice from its data file, 200 of 572 links missing, every
    node connected, shortest paths 20, 14 and 8 links from the entry (the paper's Fig. 2),
    reported in the summary as `shortest_path`."""
    from reciprocity.api import execute
    from reciprocity.scenarios import load_scenario
    sc = load_scenario("ristic-lattice-paper")
    worlds = [sc.build_world(seed) for seed in (0, 1)]
    assert np.array_equal(worlds[0].space.present, worlds[1].space.present)     # one lattice for every run
    assert (~worlds[0].space.present).sum() == 200 and worlds[0].space.present.size == 572
    for source, links in (([0, 7], 20), ([0, 1], 14), ([2, -5], 8)):
        w = sc.with_world({"source": source}).build_world(0)
        assert w.describe_start([9, -4])["shortest_path"] == links
    ep, _, _ = execute("ristic-lattice-paper", "rbpf", seed=0, params={"n_particles": 200, "n_gain": 20},
                       world={"source": [2, -5]})
    assert ep.summary["shortest_path"] == 8 and ep.summary["lattice_draws"] == 0


def test_lattice_links_files_are_checked(tmp_path):
    from reciprocity.scenarios import load_scenario
    sc = load_scenario("ristic-lattice")
    with pytest.raises(SearchError, match="neither a built-in lattice"):
        sc.with_world({"links": "nope"})
    bad = tmp_path / "bad.npz"
    np.savez(bad, present=np.ones(10, dtype=bool))
    with pytest.raises(SearchError, match="572 booleans"):
        sc.with_world({"links": str(bad)})
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip")
    with pytest.raises(SearchError, match="not an .npz"):
        sc.with_world({"links": str(junk)})
    with pytest.raises(SearchError, match="not both"):
        sc.with_world({"links": "ristic-fig2", "lattice_seed": 3})
    cut = tmp_path / "cut.npz"
    np.savez(cut, present=np.zeros(572, dtype=bool))
    with pytest.raises(SearchError, match="not connected"):
        sc.with_world({"links": str(cut)})


def test_rbpf_oracle_rungs_use_the_map_and_the_lattice_field():
    """The oracle ladder's rungs: map='known' holds the true links with certainty, and
    field='lattice' gives the truth's own mean count A0 F[x, z] per unit A0."""
    from reciprocity.env import SearchEnv
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    with pytest.raises(SearchError, match="needs map='known'"):
        STRATEGIES["rbpf"](field="lattice")
    env = SearchEnv("ristic-lattice-paper", world={"map": "known"})
    _, info = env.reset(seed=0)
    agent = StrategyAgent(STRATEGIES["rbpf"], {"map": "known", "field": "lattice", "n_particles": 50})
    agent.reset(info["task"], info["agent_seed"])
    b, world = agent.strategy.belief, env.world
    assert np.array_equal(b.q[0] == 1.0, world.space.present) and np.all((b.q == 0) | (b.q == 1))
    at_source = np.tile(world.source, (3, 1)).astype(float)
    nodes = np.array([world.space.index_of([9, -4])[0], world.space.index_of([5, 0])[0], world.source_node])
    c = b.gain(nodes, at_source)
    assert np.allclose(c, world.lam[nodes] / world.strength + 1e-9)
    plain = SearchEnv("ristic-lattice-paper")
    _, info = plain.reset(seed=0)
    with pytest.raises(SearchError, match="tells the map"):
        StrategyAgent(STRATEGIES["rbpf"], {"map": "known"}).reset(info["task"], info["agent_seed"])


def test_rbpf_can_score_the_five_controls_of_algorithm_2():
    from reciprocity.env import SearchEnv
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    with pytest.raises(SearchError, match="controls must be"):
        STRATEGIES["rbpf"](controls="some")
    env = SearchEnv("ristic-lattice-paper")
    _, info = env.reset(seed=0)
    for controls, scored in (("all", 5), ("believed", None)):
        agent = StrategyAgent(STRATEGIES["rbpf"], {"controls": controls, "n_particles": 200, "n_gain": 20})
        agent.reset(info["task"], info["agent_seed"])
        agent.act()
        finite = int(np.isfinite(agent.strategy.gains).sum())
        if scored is not None:
            assert finite == scored
        else:
            assert finite == int(agent.strategy.admissible().sum())


def test_a_position_fix_is_an_oracle_the_scenario_must_ask_for():
    """localisation: known (rung 3 of the ladder): every reading carries the true node, and
    the RBPF puts every searcher-node particle there; without it no reading carries one."""
    plain, fixed = _world(1), _world(1, localisation="known")
    rng = np.random.default_rng(0)
    node = [2.0, -1.0]
    assert "fix" not in plain.read(node, time=0, dwell=1, rng=rng).data
    assert plain.nominal()["localisation"] == "unknown" and fixed.nominal()["localisation"] == "known"
    r = fixed.read(node, time=0, dwell=1, rng=rng)
    assert r.data["fix"] == node
    b = _belief(400)
    b.node[:200] = int(b.space.index_of(node)[0])               # where the fix says
    b.node[200:] = int(b.space.index_of([0, 0])[0])             # where slips or a wrong map put them
    b.source[:200], b.source[200:] = [3.0, 3.0], [-3.0, -3.0]
    b.update(Observation([0, 0], 0.0, kind="hits", data={"fix": node, "primary": [-1] * 4, "secondary": [-1] * 4}))
    assert np.all(b.node == b.space.index_of(node)[0])
    assert np.allclose(b.source, [3.0, 3.0]), "particles off the fix must lose their weight"
    with pytest.raises(SearchError, match="must be a lattice node"):
        b.update(Observation([0, 0], 0.0, kind="hits", data={"fix": [0.5, 0.0]}))
    s = run("ristic-lattice-paper", "rbpf", seed=2, params={"n_particles": 200, "n_gain": 20},
            world={"localisation": "known", "source": [2, -5]}).summary
    assert s["localisation_known"] is True
