"""Plume world, particle belief and infotaxis-type strategies (papers/001, 002; otto)."""

from dataclasses import replace

import numpy as np
import pytest
from scipy.special import k0

from reciprocity import SUMMARY_KEYS
from reciprocity.api import run
from reciprocity.beliefs.particles import ParticleBelief, grid_particles
from reciprocity.errors import SearchError
from reciprocity.observations import Observation
from reciprocity.scenarios import load_scenario
from reciprocity.models.plume import PlumeParams, plume_length, plume_rate
from reciprocity.worlds.plume import PlumeWorld
from reciprocity.wiring.plume import otto_initial_hit_probabilities, otto_max_hits

from plume_beliefs import hand_built

SONG = PlumeParams(rate=2.0, a=1.0, D=1.0, tau=400.0, V=0.5, wind_direction=0.0, form="wind")


# -- the hit rate -----------------------------------------------------------------------
def test_rate_matches_a_direct_evaluation_of_each_form():
    lam = np.sqrt(1.0 * 400.0 / (1 + 0.25 * 400.0 / 4.0))
    assert plume_length(1.0, 400.0, 0.5) == pytest.approx(lam)
    r, r0 = np.array([7.0, -2.0]), np.array([-3.0, 4.0])
    d = np.hypot(*(r - r0))
    wind_x = 2.0 / np.log(lam) * np.exp((r[0] - r0[0]) * 0.5 / 2.0) * k0(d / lam)
    assert plume_rate(r, r0, SONG)[0, 0] == pytest.approx(wind_x, rel=1e-12)
    # Vergassola's wind along -y: exp((y0 - y) V / (2D))
    verg = replace(SONG, wind_direction=270.0)
    assert plume_rate(r, r0, verg)[0, 0] == pytest.approx(
        2.0 / np.log(lam) * np.exp((r0[1] - r[1]) * 0.25) * k0(d / lam), rel=1e-9)
    iso = replace(SONG, form="isotropic")                      # papers/001, Section 2
    assert plume_rate(r, r0, iso)[0, 0] == pytest.approx(2.0 / np.log(lam) * np.exp(0.25 * d) * k0(d / lam))


def test_rate_limits():
    calm = PlumeParams(rate=2.0, a=0.5, D=1.0, tau=1.0, V=0.0)
    d = np.arange(1, 6, dtype=float)
    # otto: mu(d) = R dt K0(d / lambda) / ln(2 lambda / dx), lambda = dx = 1
    assert np.allclose(plume_rate(np.column_stack([d, 0 * d]), [[0, 0]], calm)[:, 0], 2 * k0(d) / np.log(2))
    # no wind: isotropic; wind: downwind above upwind; far away: vanishing
    ring = 5 * np.column_stack([np.cos(np.linspace(0, 6, 9)), np.sin(np.linspace(0, 6, 9))])
    assert np.ptp(plume_rate(ring, [[0, 0]], calm)) < 1e-12
    down, up = plume_rate([[20, 0], [-20, 0]], [[0, 0]], SONG)[:, 0]
    assert down > 100 * up
    assert plume_rate([[1e4, 3e3]], [[0, 0]], SONG)[0, 0] < 1e-12
    # inside the sensor radius the rate is that at the radius
    assert plume_rate([[0.2, 0]], [[0, 0]], calm)[0, 0] == pytest.approx(plume_rate([[0, 0.5]], [[0, 0]], calm)[0, 0])
    # the isotropic form still decays since 1/lambda > V / (2D)
    iso = replace(SONG, form="isotropic")
    assert plume_rate([[400, 0]], [[0, 0]], iso)[0, 0] < plume_rate([[100, 0]], [[0, 0]], iso)[0, 0]


def test_poisson_hits_have_the_rate_as_mean_and_variance():
    w = PlumeWorld(((-50, 50), (-50, 50)), [0, 0], SONG, found_radius=3)
    rng = np.random.default_rng(7)
    n, p = 4000, np.array([15.0, 2.0])
    z = np.array([w.read(p, time=0, dwell=1.0, rng=rng).value for _ in range(n)])
    mu = w.rate(p[None])[0]
    assert 0.1 < mu < 10
    assert abs(z.mean() - mu) < 4 * np.sqrt(mu / n)
    # variance of a Poisson sample: sd(s^2) ~ sqrt((mu + 2 mu^2) / n)
    assert abs(z.var(ddof=1) - mu) < 4 * np.sqrt((mu + 2 * mu * mu) / n)


@pytest.mark.parametrize("fault, mean", [
    ({"gain": 0.0}, lambda mu, t: 0.0),
    ({"gain": 0.5, "false_rate": 0.3}, lambda mu, t: 0.5 * mu + 0.3),
    ({"fails_at": 10.0}, lambda mu, t: mu if t < 10 else 0.0),
])
def test_a_faulty_sensor_counts_gain_times_the_hits_plus_false_alarms(fault, mean):
    from reciprocity.worlds.plume import SensorFault
    w = PlumeWorld(((-50, 50), (-50, 50)), [0, 0], SONG, sensors=[SensorFault(), SensorFault.from_dict(fault)])
    rng = np.random.default_rng(11)
    n, p = 4000, np.array([15.0, 2.0])
    mu = w.rate(p[None])[0]
    for t in (0.0, 20.0):
        healthy = np.array([w.read(p, time=t, dwell=1.0, rng=rng, observer=0).value for _ in range(n)])
        faulty = np.array([w.read(p, time=t, dwell=1.0, rng=rng, observer=1).value for _ in range(n)])
        beyond = np.array([w.read(p, time=t, dwell=1.0, rng=rng, observer=2).value for _ in range(n)])
        for z, m in ((healthy, mu), (faulty, mean(mu, t)), (beyond, mu)):
            # the sample mean of n Poisson(m) counts: sd sqrt(m / n)
            assert abs(z.mean() - m) < 4 * np.sqrt(max(m, 1e-12) / n) + 1e-12
    assert w.nominal() == PlumeWorld(((-50, 50), (-50, 50)), [0, 0], SONG).nominal()
    assert w.describe()["sensors"][1] == {**SensorFault().as_dict(), **fault}


def test_mismatch_changes_the_truth_not_the_nominal_model():
    from reciprocity.worlds.plume import PlumeMismatch
    w = PlumeWorld(((-50, 50), (-50, 50)), [0, 0], SONG, mismatch=PlumeMismatch(rate_factor=3.0))
    assert w.nominal()["plume"] == SONG
    assert w.rate([[10, 0]])[0] == pytest.approx(3 * plume_rate([[10, 0]], [[0, 0]], SONG)[0, 0])


# -- the particle belief ------------------------------------------------------------------
def _belief(points, **kw):
    kw.setdefault("resample_below", None)
    return ParticleBelief(SONG, np.asarray(points, float), ((-50, 50), (-50, 50)), np.random.default_rng(0), **kw)


def test_a_hit_reweights_particles_by_the_poisson_likelihood():
    b = _belief([[-10, 0], [10, 0], [0, 30]])
    r = np.array([5.0, 0.0])
    b.update(Observation(r, 2.0, 0.0, 1.0, "hits"))
    mu = plume_rate(r, b.support(), SONG)[0]
    lik = mu ** 2 * np.exp(-mu)
    assert np.allclose(b.weights(), lik / lik.sum())
    # the particle upwind of the sensor (the wind blows along +x) gains the most
    assert np.argmax(b.weights()) == 0


def test_no_hit_far_from_the_plume_barely_moves_the_belief_and_the_found_zone_is_ruled_out():
    b = _belief([[-10, 0], [10, 0], [40, 40]], found_radius=3.0)
    b.update(Observation([40, 41], 0.0, 0.0, 1.0, "hits"))
    w = b.weights()
    assert w[2] == 0.0                     # within the found radius of the reading
    assert w[0] == pytest.approx(0.5, abs=5e-3)


def test_resampling_below_a_third_keeps_the_cloud_inside_and_resets_weights():
    pts = grid_particles(((-50, 50), (-50, 50)), 200)
    assert len(pts) == 200
    b = ParticleBelief(SONG, pts, ((-50, 50), (-50, 50)), np.random.default_rng(1), resample_below=1 / 3)
    for _ in range(3):
        b.update(Observation([0, 10], 3.0, 0.0, 1.0, "hits"))
    assert b.n_resampled >= 1
    b.resample()
    assert np.all(np.abs(b.support()) <= 50)
    assert np.allclose(b.weights(), 1 / 200)
    assert b.n_eff() == pytest.approx(200)
    # the cloud moved upwind of the sensor (sources at x < 0 send hits to x = 0)
    assert b.estimate()[0] < 0
    pred = b.predictive(np.array([[0.0, 10.0], [20.0, 10.0]]))
    assert pred.means.shape == (2, 200) and pred.expected_entropy().shape == (2,)


# -- policies on hand-built beliefs (as otto's tests) ---------------------------------------
_strategy = hand_built


@pytest.mark.parametrize("name", ["infotaxis", "space-aware-infotaxis", "free-energy", "mapless-infotaxis"])
def test_policies_head_for_a_belief_lying_east(name):
    params = {"extent": 2.0} if name == "mapless-infotaxis" else {}
    s = _strategy(name, [[12.5, 9.5], [13.5, 9.5], [12.5, 10.5]], [0.5, 0.3, 0.2], **params)
    move = s.propose()
    assert np.allclose(move.point, [10.5, 9.5])


def test_infotaxis_steps_onto_a_near_certain_source():
    s = _strategy("infotaxis", [[9.5, 10.5], [3.5, 3.5]], [0.999, 0.001])
    assert np.allclose(s.propose().point, [9.5, 10.5])


def test_entrotaxis_prefers_the_most_uncertain_reading():
    # two equally likely sources far apart: the reading between them is the least certain
    s = _strategy("entrotaxis", [[9.5, 13.5], [9.5, 1.5]], [0.5, 0.5], at=(9.5, 12.5))
    assert s.propose().point[1] < 13.5        # not onto the found zone of one hypothesis


def test_free_energy_turns_toward_a_concentrated_belief_in_the_plane():
    s = _strategy("free-energy", [[0, 30], [1, 30]], [0.5, 0.5], at=(0, 0), grid=False)
    s.heading = 0.0                            # facing +x; the belief lies to the north
    move = s.propose()
    assert move.point[1] > 0.05                # the largest left turn (+3 degrees)
    assert np.hypot(*move.point) == pytest.approx(1.0)


# -- episodes through the API -----------------------------------------------------------
QUICK = {"particles": 100}


@pytest.mark.parametrize("name", ["infotaxis", "free-energy", "mapless-infotaxis", "entrotaxis"])
def test_short_song_episode(name):
    sc = replace(load_scenario("song-100"), max_steps=15)
    s = run(sc, name, seed=3, params=QUICK).summary
    assert set(SUMMARY_KEYS) <= set(s)
    assert s["world"] == "plume" and s["steps"] <= 15 and s["n_measurements"] == s["steps"]
    assert s["path_length"] == pytest.approx(s["steps"], rel=1e-6)      # unit speed


@pytest.mark.parametrize("name", ["infotaxis", "space-aware-infotaxis"])
def test_otto_episodes_reach_the_drawn_source(name):
    for seed in range(3):
        s = run("otto-2d", name, seed=seed).summary
        assert s["stop"] == "found" and s["success"] and s["error"] is not None
        assert s["initial_hit"] >= 1


def test_otto_first_hit_law_and_hit_cap():
    calm = PlumeParams(rate=2.0, a=0.5, D=1.0, tau=1.0, V=0.0)
    assert otto_max_hits(calm, 1.0, 1.0) == 3               # otto's Nhits = 4
    p = otto_initial_hit_probabilities(calm, 1.0, 1.0, 3)
    assert p[0] == 0 and p.sum() == pytest.approx(1) and p[1] > p[2] > p[3] > 0


def test_voi_team_shares_messages_and_voi_sends_fewer():
    sc = replace(load_scenario("hajieghrary"), max_steps=8)
    every = run(sc, "voi", seed=1, params=dict(QUICK, share="all"))
    some = run(sc, "voi", seed=1, params=dict(QUICK, share="voi"))
    assert every.summary["n_agents"] == 3 and every.summary["steps"] == 8
    assert every.summary["messages"] == 3 * 8
    assert all(len(m.receivers) == 2 for m in every.messages.messages)
    assert some.summary["messages"] <= every.summary["messages"]
    solo = run(sc, "voi", seed=1, agents=1, params=QUICK).summary
    assert solo["messages"] == 0
    alone = run(sc, "voi", seed=1, params=dict(QUICK, share="none"))
    assert alone.summary["n_agents"] == 3 and alone.summary["messages"] == 0


@pytest.mark.parametrize("strategy, agents", [("infotaxis", None), ("voi", 2)])
def test_a_fault_given_to_an_observer_the_run_lacks_is_refused(strategy, agents):
    with pytest.raises(SearchError, match=r"sensors\[2\] is a fault of observer 3, but the run has") as exc:
        run("hajieghrary-dead-sensor", strategy, agents=agents, params=QUICK)
    assert "\n" not in str(exc.value)


def test_a_dead_sensor_reads_nothing_in_a_team_run():
    sc = replace(load_scenario("hajieghrary-dead-sensor"), max_steps=300)
    ep = run(sc, "voi", seed=2, params=dict(QUICK, share="none"))
    reads = [(o.agent, o.value) for rec in ep.records for o in rec.observations]
    assert {a for a, _ in reads} == {0, 1, 2}
    assert all(v == 0 for a, v in reads if a == 2)
    assert ep.summary["sensors"][2]["gain"] == 0


# -- bad input ----------------------------------------------------------------------------
@pytest.mark.parametrize("override, match", [
    ({"D": 0}, r"plume D must be a number in \[1e-09, 1e\+06\]"), ({"tau": -1}, "plume tau must be a number in"),
    ({"V": -0.1}, r"plume V must be a number in \[0, 10000\]"), ({"a": 0}, "plume a must be a number in"),
    ({"rate": 0}, "plume rate must be a number in"), ({"source": [90, 0]}, "outside the area"),
    ({"form": "gauss"}, "form must be one of"), ({"mismatch": {"rate_factor": 0}}, r"in \(0, 1000\]"),
    ({"mismatch": {"speed": 2}}, "unknown plume mismatch"), ({"a": 10}, "must exceed the sensor radius"),
    ({"sensors": {"gain": 0}}, "plume sensors must be a list"), ({"sensors": [{}] * 65}, "at most 64"),
    ({"sensors": [{"gain": -1}]}, r"plume sensors\[0\] gain must be a number in \[0, 1e\+06\]"),
    ({"sensors": [{}, {"drift": 1}]}, r"unknown plume sensors\[1\] option\(s\) drift"),
    ({"sensors": [7]}, r"plume sensors\[0\] must be a mapping"),
    ({"sensors": [{"fails_at": "soon"}]}, "fails_at must be a number"),
])
def test_bad_world_parameters_raise_one_line_errors(override, match):
    with pytest.raises(SearchError, match=match) as exc:
        load_scenario("song-100").with_world(override)
    assert "\n" not in str(exc.value)


def test_start_on_the_source_is_refused():
    with pytest.raises(SearchError, match="on the source") as exc:
        run("song-100", "infotaxis", world={"start": [-33.0, 33.0]}, params=QUICK)
    assert "\n" not in str(exc.value)


def test_free_energys_temperature_factor_grows_with_the_area_only_when_asked():
    from reciprocity.env import SearchEnv
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    used = {}
    for side in (100, 300):
        for k in (0.0, 2.35):
            _, info = SearchEnv(f"song-{side}").reset(seed=0)
            agent = StrategyAgent(STRATEGIES["free-energy"], dict(QUICK, alpha=5.3, area_exponent=k))
            agent.reset(info["task"], info["agent_seed"])
            used[side, k] = agent.strategy.alpha_used
    assert used[100, 0.0] == used[300, 0.0] == used[100, 2.35] == pytest.approx(5.3)
    assert used[300, 2.35] == pytest.approx(5.3 * 3 ** 2.35)
    with pytest.raises(SearchError, match="area_exponent"):
        run("song-100", "free-energy", params={"area_exponent": -1})


@pytest.mark.parametrize("params, match", [({"particles": 0}, "particles"), ({"particles": 9}, "from 10 to 100000"),
                                           ({"share": "some"}, "share"),
                                           ({"alpha": -1}, "alpha")])
def test_bad_strategy_parameters(params, match):
    name = "voi" if "share" in params else ("free-energy" if "alpha" in params else "infotaxis")
    with pytest.raises(SearchError, match=match):
        run("song-100", name, params=params)


def test_search_figure_draws_the_path_hits_and_clouds():
    from reciprocity.viz.plume import search_figure
    sc = replace(load_scenario("song-100"), max_steps=25)
    ep = run(sc, "free-energy", seed=2, params=QUICK, figures=True)
    assert ep.summary == {**run(sc, "free-energy", seed=2, params=QUICK).summary,
                          "wall_time_s": ep.summary["wall_time_s"]}       # the records change no episode
    fig = search_figure(ep)
    path_ax = fig.axes[0]
    assert len(path_ax.lines[1].get_xdata()) == ep.summary["steps"] + 1   # start + one point a step
    assert [step for step, _, _ in ep.belief["particles"]] == [0, 10, 20]
    assert ep.truth["mean_hits"].shape == (200, 200) and ep.truth["form"] == "wind"
    assert ep.truth["source"].tolist() == ep.summary["source"]


def test_plume_figures_need_the_episodes_record():
    from reciprocity.viz.plume import search_figure
    sc = replace(load_scenario("song-100"), max_steps=2)
    with pytest.raises(SearchError, match="figures=True"):
        search_figure(run(sc, "free-energy", seed=2, params=QUICK))
