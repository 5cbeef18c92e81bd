"""Reciprocity on the random lattice: the discrete adjoint and the lattice-reciprocity searcher."""

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.sparse.csgraph import shortest_path

from reciprocity.api import run
from reciprocity.episode import SUMMARY_KEYS
from reciprocity.errors import SearchError
from reciprocity.spaces.lattice import CONTROLS
from reciprocity.models.lattice import LatticeGreen
from reciprocity.observations import Observation
from reciprocity.scenarios import load_scenario
from reciprocity.spaces.lattice import LatticeSpace
from reciprocity.strategies import STRATEGIES, SearchContext
from reciprocity.worlds.lattice import draw_links, green_row


#: World overrides of the runs here: the map told, source and entry connected (fast draws).
FAST = {"map": "known", "connectivity": "nodes"}


def _world(seed=1, **over):
    """A ristic-lattice world; source and entry connected (not every node: a
    fully connected draw takes ~10^3 redraws, seconds per world)."""
    return load_scenario("ristic-lattice").with_world({"map": "known", "connectivity": "nodes", **over}).build_world(seed)


def _strategy(world, **params):
    s = STRATEGIES["lattice-reciprocity"](**params)
    s.start(SearchContext("lattice", world.nominal(), np.array([[9.0, -4.0, 0.0]]), np.random.default_rng(0)))
    return s


def test_adjoint_column_equals_world_truth_to_machine_precision():
    w = _world(4)
    sp, g = w.space, LatticeGreen(w.space)
    t = np.flatnonzero(g.candidates)                   # inner nodes whose cluster reaches the ring
    assert w.source_node in t and t.size > 200
    cols = g.visits(t)                                 # F[:, z] for every inner z: one solve each
    rows = np.array([green_row(sp, x) for x in t])     # the world's truth, a row per source
    np.testing.assert_allclose(cols[t], rows[:, t], rtol=0, atol=1e-12 * rows.max())
    # reversibility of the absorbing walk: d_x F[x, z] = d_z F[z, x]
    f = rows[:, t]
    d = g.degree[t]
    np.testing.assert_allclose(d[:, None] * f, (d[:, None] * f).T, rtol=1e-12, atol=1e-13)
    assert not np.allclose(f, f.T)                     # F itself is not symmetric on a random lattice
    assert np.all(g.visits(np.flatnonzero(~sp.transient)) == 0)   # absorbing nodes: no counts


def test_adjoint_on_a_lattice_with_closed_clusters_and_weights():
    s = LatticeSpace(6)
    present, _ = draw_links(s, 0.45, np.random.default_rng(2), connectivity="nodes", keep=(0,))
    s = s.with_links(present)
    g = LatticeGreen(s)
    open_nodes = np.flatnonzero(g.candidates)
    closed = np.flatnonzero(s.transient & ~g.candidates)
    assert closed.size > 0                             # the draw has closed clusters / isolated nodes
    for x in open_nodes[::5]:
        np.testing.assert_allclose(g.visits(open_nodes)[x], green_row(s, x)[open_nodes], atol=1e-12)
    assert np.all(g.visits(closed)[open_nodes] == 0)
    # uniform conductances are the complete lattice; scaling them changes nothing
    full = LatticeGreen(s.with_links(np.ones(len(s.links), bool)))
    half = LatticeGreen(s, np.full(len(s.links), 0.5))
    z = open_nodes[:7]
    np.testing.assert_allclose(half.visits(z), full.visits(z), rtol=1e-12)
    with pytest.raises(ValueError, match="conductance"):
        LatticeGreen(s, -np.ones(len(s.links)))


def _walk_to(world, strat, goals, rng, stay=0):
    """Drive the strategy's filter along shortest true paths from (9, -4) through the
    nodes `goals`, `stay` more readings at each, readings drawn from the world (no slips)."""
    sp = world.space
    adj = sp.adjacency.tolil()
    adj[world.source_node, :] = 0                      # never through the source (the search would stop)
    adj[:, world.source_node] = 0
    path = [int(sp.index_of([9, -4])[0])]
    for goal in np.atleast_1d(goals):
        pred = shortest_path(adj.tocsr(), unweighted=True, directed=False, return_predecessors=True,
                             indices=[int(goal)])[1]
        while path[-1] != goal:
            path.append(int(pred[0, path[-1]]))
        path += [int(goal)] * stay
    for a, b in zip(path[:-1], path[1:]):
        u = (sp.points[b] - sp.points[a]).astype(int)
        k = int(np.flatnonzero(np.all(CONTROLS == u, axis=1))[0])
        strat.control = k
        r = world.read(sp.points[b], time=0.0, dwell=1.0, rng=rng)
        strat.observe([Observation(sp.points[b], r.value, 0.0, 1.0, "hits", False, 0, r.data)], None)
    return path


@pytest.mark.parametrize("strength", [None, 12.0])
def test_posterior_concentrates_on_the_true_source(strength):
    """Readings on a tour of the nodes at graph distance 2 of the source (3 readings
    each, the source itself never visited): the posterior's mode is the source."""
    hits, mass = 0, []
    for seed in range(6):
        w = _world(seed)
        s = _strategy(w, strength=strength)
        d = shortest_path(w.space.adjacency, unweighted=True, directed=False, indices=[w.source_node])[0]
        ring = np.flatnonzero((d == 2) & w.space.transient)
        ring = ring[np.argsort(np.arctan2(*(w.space.points[ring] - w.source).T))]   # a tour around it
        _walk_to(w, s, ring, np.random.default_rng(seed), stay=3)
        assert s.pos.max() > 0.99                      # known map, no slips: the position is certain
        hits += int(np.argmax(s.post) == w.source_node)
        mass.append(s.post[d <= 1].sum())
    # 6 lattices, deterministic (seeded); the mode may miss by a node on one of them
    assert hits >= 5, (hits, mass)
    assert np.mean(mass) > 0.9, mass


def test_negative_binomial_marginal_matches_quadrature():
    w = _world(3)
    s = _strategy(w)                                   # A0 unknown, Gamma(15, 1)
    _walk_to(w, s, [int(w.space.index_of([3, 3])[0])], np.random.default_rng(1), stay=3)
    counts = np.array([h[2] for h in s.history])
    fb = np.column_stack([s._fbar(h[0], h[1]) for h in s.history])
    xs = np.flatnonzero(s.post > 1e-3)[:4]
    logml = []
    grid = np.linspace(1e-6, 100, 20001)
    for x in xs:
        def logf(a, x=x):
            a = np.atleast_1d(a)[:, None]
            return (stats.poisson.logpmf(counts, a * fb[x]).sum(axis=1)
                    + stats.gamma.logpdf(a[:, 0], 15.0, scale=1.0))
        lf = logf(grid)
        off = lf.max()
        logml.append(np.log(integrate.simpson(np.exp(lf - off), x=grid)) + off)
    logml = np.array(logml)
    exact = s.logpost[xs] - s.not_here[xs]            # posterior up to a constant, the 'not found' term removed
    np.testing.assert_allclose(exact - exact[0], logml - logml[0], atol=1e-6)


def test_position_filter_moves_slips_and_stays_at_missing_links():
    w = _world(2)
    sp = w.space
    s = _strategy(w, slip=0.2)
    s.pos[:] = 0
    i = int(np.flatnonzero(sp.transient & (np.asarray(sp.adjacency.sum(1)).ravel() == 2))[0])
    s.pos[i] = 1.0
    s._predict_position(1)                             # east
    assert s.pos.sum() == pytest.approx(1.0)
    lid = sp.link_of[i]
    ok = (lid >= 0) & sp.present[np.maximum(lid, 0)]
    east = int(sp.step_of[i, 0]) if ok[0] else i
    assert s.pos[east] >= 0.8 - 1e-12
    stays = 0.2 / 4 * (1 + int((~ok).sum()))          # the "stay" slip and every slip into a wall
    assert s.pos[i] == pytest.approx(stays + (0.8 if not ok[0] else 0.0))


def test_episode_through_api_contract_and_success_definition():
    s = run("ristic-lattice", "lattice-reciprocity", seed=1, world=FAST).summary
    assert set(SUMMARY_KEYS) <= set(s)
    assert s["strategy"] == "lattice-reciprocity" and 1 <= s["steps"] <= 100
    assert s["success"] == (s["reached"] and s["self_localised"])
    assert s["reached"] == (s["stop"] == "found")


def test_map_rbpf_mode_runs_with_a_small_filter():
    s = run("ristic-lattice", "lattice-reciprocity", seed=2, params={"map": "rbpf", "n_particles": 200},
            world={**FAST, "source": [2, -5]}).summary
    assert set(SUMMARY_KEYS) <= set(s) and s["success"] == (s["reached"] and s["self_localised"])


@pytest.mark.parametrize("params", [{"green": "complete"}, {"green": "sampled", "n_maps": 3, "unseen": "nominal"}])
def test_map_rbpf_variants_keep_a_proper_posterior(params):
    w = _world(3, map="unknown")
    s = _strategy(w, map="rbpf", n_particles=200, **params)
    _walk_to(w, s, [int(w.space.index_of([4, 0])[0])], np.random.default_rng(2), stay=2)
    assert s.post.sum() == pytest.approx(1.0) and np.all(s.post[~w.space.transient] == 0)
    assert s.propose() is not None


def test_sampled_maps_follow_the_rbpf_links_and_unseen_prior():
    w = _world(1, map="unknown")
    s = _strategy(w, map="rbpf", n_particles=100, green="sampled", n_maps=3, unseen="nominal")
    _walk_to(w, s, [int(w.space.index_of([5, -4])[0])], np.random.default_rng(0))
    assert len(s.maps) == 3
    q = s._links_believed()
    seen = np.abs(q - 0.5) >= 1e-3
    assert seen.sum() >= 4
    # the drawn link frequency is q where seen and 1 - p (0.65) where unseen, within 4.5 binomial sigmas
    u = np.random.default_rng(5).random((400, len(q)))
    drawn = (u < s._links_unseen(q)).mean(axis=0)
    target = np.clip(np.where(seen, q, 0.65), 0, 1)
    assert np.all(np.abs(drawn - target) <= 4.5 * np.sqrt(target * (1 - target) / 400) + 1e-6)
    assert abs(drawn[~seen].mean() - 0.65) < 0.02       # 1 - p, not the RBPF prior 1/2


def test_rbpf_path_planner_steps_along_the_believed_map():
    """With every source particle on one node, the path planner's move is one link closer
    to it over the links the searcher believes present (the gain planner need not be)."""
    from reciprocity.api import execute
    from scipy.sparse import coo_matrix
    ep, s, _ = execute("ristic-lattice", "rbpf", seed=1, world=FAST,
                       params={"n_particles": 200, "n_gain": 20, "planner": "path"})
    assert ep.summary["params"]["planner"] == "path"
    b, sp = s.belief, s.space
    here = int(np.argmax(b.node_weights()))
    goal = int(sp.index_of(sp.points[here] + [0.0, 6.0])[0])
    assert goal >= 0
    b.source = np.repeat(sp.points[goal][None], len(b.source), axis=0)
    q = b.w @ b.q.astype(float)
    a, c = sp.links[q >= 0.5 - 1e-6].T
    n = len(sp.points)
    adj = coo_matrix((np.ones(2 * a.size), (np.r_[a, c], np.r_[c, a])), shape=(n, n)).tocsr()
    dist = shortest_path(adj, unweighted=True, directed=False, indices=[goal])[0]
    assert np.isfinite(dist[here]) and dist[here] >= 1
    ok = s.admissible()
    s.gains = s.gains_of(ok)
    k = s._path_control(ok, here)
    assert ok[k]
    after = here if k == 0 else int(sp.step_of[here, k - 1])
    assert dist[after] == dist[here] - 1

def test_rbpf_planner_is_validated():
    with pytest.raises(SearchError, match="planner must be") as exc:
        run("ristic-lattice", "rbpf", seed=0, params={"planner": "astar"}, world=FAST)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("params, match", [
    ({"map": "maybe"}, "map must be"), ({"rule": "greedy"}, "rule must be"),
    ({"strength": -1.0}, "strength must be"), ({"eta0": 0}, "eta0 must be"),
    ({"slip": 1.5}, "slip must be"), ({"n_particles": 5}, "n_particles"),
    ({"green": "dense"}, "green must be"), ({"support": 0}, "support must be"),
    ({"n_maps": 0}, "n_maps must be"), ({"unseen": "half"}, "unseen must be")])
def test_bad_strategy_parameters_are_one_line_errors(params, match):
    with pytest.raises(SearchError, match=match) as exc:
        run("ristic-lattice", "lattice-reciprocity", seed=0, params=params, world=FAST)
    assert "\n" not in str(exc.value)


def test_known_map_needs_the_world_to_tell_it_and_map_values_are_checked():
    with pytest.raises(SearchError, match="map: known") as exc:
        run("ristic-lattice", "lattice-reciprocity", seed=0, params={"map": "known"}, world={"connectivity": "nodes"})
    assert "\n" not in str(exc.value)
    with pytest.raises(SearchError, match="map must be 'unknown'"):
        run("ristic-lattice", "rbpf", seed=0, world={"map": "yes", "connectivity": "nodes"})
    assert "links" not in _world(1, map="unknown").nominal()
    w = _world(1, map="unknown")
    assert _strategy(w, n_particles=20).mode == "rbpf" and _strategy(_world(1)).mode == "known"   # map: auto
    nom = _world(1).nominal()
    assert "source" not in nom and nom["links"].dtype == bool and not nom["links"].all()


def test_posterior_figure_draws(tmp_path):
    from reciprocity.viz.lattice import posterior_figure
    w = _world(1)
    s = _strategy(w)
    path = _walk_to(w, s, [int(w.space.index_of([4, 0])[0])], np.random.default_rng(0))
    fig = posterior_figure(w.figure_record(), s.figure_record(), w.space.points[path])
    fig.savefig(tmp_path / "post.png")
    assert (tmp_path / "post.png").stat().st_size > 1000 and len(fig.axes) == 2
