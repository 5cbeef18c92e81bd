"""The flow world (issue 38): scenario keys, truth against model, and reciprocity in wind end to end."""

import json

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.cli import main
from reciprocity.env import SearchEnv
from reciprocity.errors import SearchError
from reciprocity.observations import Observation
from reciprocity.scenarios import from_dict, load_scenario
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.reciprocity_wind import ArenaCounts, WindReciprocity

#: A 60 x 40 cm duct with one pillar, the wind in on the left and out on the right:
#: meshes of a few thousand nodes, so an episode takes about a second.
DUCT = {"name": "duct", "boundary": [[0, 0], [60, 0], [60, 40], [0, 40]],
        "obstacles": [[[28, 12], [34, 12], [34, 28], [28, 28]]]}
SCENARIO = {"world": "flow", "arena": DUCT, "source": [18, 22], "start": [52, 8, 90],
            "inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]], "speed": 1, "D": 5, "tau": 60,
            "strength": 100, "detector": 1, "truth_h": 1, "max_steps": 60}
#: The strategy's mesh size in these tests, cm (twice the truth's).
MODEL_H = 2.0
#: A seed on which reciprocity in wind converges within the success radius (seeds 0-2 all do).
SEED = 0


def _scenario(**over):
    return from_dict({**SCENARIO, **over}, "duct-wind")


def _told(world) -> dict:
    """A world's nominal description with its arena as geometry (comparable)."""
    nominal = dict(world.nominal())
    arena = nominal.pop("arena")
    return dict(nominal, boundary=arena.boundary.tolist(), obstacles=[o.tolist() for o in arena.obstacles],
                source=arena.source)


def _file(tmp_path, **over):
    import yaml
    path = tmp_path / "duct-wind.yaml"
    path.write_text(yaml.safe_dump({**SCENARIO, **over}))
    return path


@pytest.mark.parametrize("over, match", [
    ({"wind": 3}, "unknown flow world parameter"),
    ({"inflow": None}, "a flow scenario needs inflow"),
    ({"inflow": [[[10, 10], [10, 30]]]}, "does not lie along one edge of the boundary"),
    ({"inflow": [[0, 0], [0, 40]]}, "inflow must be a list of segments"),
    ({"outflow": [[[0, 10], [0, 20]]]}, "overlaps outflow segment"),
    ({"speed": 0}, r"speed must be a number in \(0, 1000\] cm/s"),
    ({"D": -1}, r"D must be a number in \[0.001, 10000\] cm²/s"),
    ({"tau": "long"}, "tau must be a number"),
    ({"strength": 0}, r"strength must be a number in \(0, 1e\+09\] particles/s"),
    ({"detector": [1]}, "detector must be a number"),
    ({"walls": "leaky"}, "walls must be one of impermeable, absorbing"),
    ({"truth_h": 0.01}, r"truth_h must be a number in \[0.1, 10\] cm"),
    ({"mismatch": {"wind_turn": 10}}, "unknown flow mismatch option"),
    ({"mismatch": {"wind_factor": 0}}, "mismatch wind_factor must be a number"),
    ({"mismatch": {"inflow": [[[30, 0], [31, 5]]]}}, "mismatch inflow segment"),
    ({"mismatch": [1.2]}, "flow mismatch must be a mapping"),
    ({"source": [31, 20]}, r"source \(31, 20\) cm is inside an obstacle"),
    ({"start": [31, 20]}, "outside the free region"),
])
def test_bad_flow_keys_are_refused_with_one_line(over, match):
    with pytest.raises(SearchError, match=match) as exc:
        _scenario(**over)
    assert "\n" not in str(exc.value)


def test_a_bad_flow_file_exits_2_with_one_line(tmp_path, capsys):
    rc = main(["run", "--scenario", str(_file(tmp_path, walls="leaky")), "--strategy", "reciprocity-wind",
               "--quiet"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "walls must be one of" in err and "\n" not in err


def test_the_builtin_wind_scenarios_load():
    for name in ("paper-wind", "maze-wind"):
        sc = load_scenario(name)
        assert sc.world == "flow" and sc.params["inflow"][0][0][0] == 0.0 and sc.params["outflow"][0][0][0] == 140.0


def test_the_truth_differs_from_the_model_under_mismatch():
    """Every mismatch key moves the true counts away from the told ones; without one the
    truth (its own finer mesh) and the strategy's model agree within 3 % but are not the
    same numbers."""
    points = np.array([[24.0, 22.0], [40.0, 30.0], [12.0, 22.0], [50.0, 8.0]])       # down, down, up, far
    told = _scenario().build_world(SEED)
    base = told.mean_count(points, 1.0)
    model = ArenaCounts(told.nominal(), MODEL_H)
    # what the strategy's model reads at the points from the true source (one forward solve)
    predicted = model.solver.forward(told.source)(points) * told.params.detector * told.params.strength
    assert np.allclose(predicted, base, rtol=0.03) and not np.allclose(predicted, base, rtol=1e-6)
    for mismatch in ({"wind_factor": 2.0}, {"diffusivity_factor": 0.5}, {"tau_factor": 0.2},
                     {"strength_factor": 1.5}, {"inflow": [[[60, 0], [60, 40]]], "outflow": [[[0, 0], [0, 40]]]}):
        world = _scenario(mismatch=mismatch).build_world(SEED)
        assert _told(world) == _told(told)
        assert np.abs(world.mean_count(points, 1.0) / base - 1).max() > 0.1, mismatch
    reversed_ = _scenario(mismatch={"inflow": [[[60, 0], [60, 40]]], "outflow": [[[0, 0], [0, 40]]]})
    counts = reversed_.build_world(SEED).mean_count(points[:3], 1.0)
    assert counts[2] > counts[0] and base[0] > base[2]         # the true wind blows the other way


def test_reciprocity_in_wind_runs_end_to_end_from_the_command_line(tmp_path, capsys):
    js = tmp_path / "s.json"
    rc = main(["run", "--scenario", str(_file(tmp_path)), "--strategy", "reciprocity-wind", "--seed", str(SEED),
               "--h", str(MODEL_H), "--quiet", "--json", str(js)])
    s = json.loads(js.read_text())
    assert rc == 0 and s["world"] == "flow" and s["strategy"] == "reciprocity-wind"
    assert s["converged"] and s["success"] and s["error"] < 5.0 and 1 < s["n_measurements"] < 60
    assert capsys.readouterr().out.splitlines()[-1].startswith("success: yes")


@pytest.mark.parametrize("strategy", ["reciprocity-wind", "free-space-wind"])
def test_the_same_seed_gives_the_same_episode(strategy):
    a, b = (run(_scenario(max_steps=12), strategy, seed=SEED, params=dict(h=MODEL_H)) for _ in range(2))
    drop = ("wall_time_s",)
    assert {k: v for k, v in a.summary.items() if k not in drop} == {k: v for k, v in b.summary.items()
                                                                     if k not in drop}
    assert len(a.trace) == len(b.trace) == a.summary["n_measurements"]
    assert all(np.array_equal(x[key], y[key]) for x, y in zip(a.trace, b.trace) for key in ("points", "readings"))


def test_the_task_and_the_actions_do_not_depend_on_the_true_source():
    """Two worlds that differ only in the true source tell the strategy the same, and the
    same readings lead it to the same points: the truth stays behind the task."""
    paths, tasks = [], []
    readings = [0.0, 2.0, 5.0, 1.0, 0.0, 3.0]
    for source in ([18.0, 22.0], [45.0, 30.0]):
        env = SearchEnv(_scenario(source=source))
        _, info = env.reset(seed=SEED)
        task = info["task"]
        tasks.append(_told(env.world))
        strat = WindReciprocity(h=MODEL_H)
        strat.start(SearchContext(task.world, task.nominal, np.array(task.starts), np.random.default_rng(0)))
        path = []
        for value in readings:
            intent = strat.propose()
            path.append(intent.point.tolist())
            strat.observe([Observation(intent.point, value, 0.0, 1.0, "hits")], intent)
        paths.append(path)
    assert tasks[0]["source"] is None and tasks[0] == tasks[1]
    assert paths[0] == paths[1] and len({tuple(p) for p in paths[0]}) == len(readings)


def test_the_figures_replay_the_posterior_from_the_episode_record():
    """figures=True keeps the count posterior (each step replayed by ``first``) and the true
    wind; ``episode_figures`` draws the steps from them alone."""
    from reciprocity.viz.episode import episode_figures
    episode = run(_scenario(max_steps=5), "reciprocity-wind", seed=SEED, params={"h": MODEL_H}, figures=True)
    post = episode.belief["posterior"]
    assert post.n == episode.summary["n_measurements"] == len(post.readings)
    assert np.allclose(post.first(post.n).weights(), post.weights())
    assert np.allclose(post.first(0).weights(), post.areas / post.areas.sum())    # the prior: uniform in area
    assert np.all(np.isfinite(episode.truth["wind"](np.array([[10.0, 20.0]]))))
    arena = _scenario().arena.with_scenario(start=episode.summary["start"])
    assert [name for name, _ in episode_figures(episode, arena)] == ["steps"]


def test_a_count_posterior_restricted_to_some_candidates_gives_the_rest_no_mass():
    from reciprocity.beliefs.counts import CountPosterior
    nodes = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]])
    post = CountPosterior(nodes, np.ones(3), (1.0, 100.0), background=0.0)
    post.add(np.array([0.3, 0.2, 0.001]), count=5, dwell=1.0)
    before = post.weights().copy()
    post.restrict(np.array([False, True, True]))
    w = post.weights()
    assert w[0] == 0 and np.isclose(w.sum(), 1) and np.isclose(w[1] / w[2], before[1] / before[2])
    assert np.array_equal(post.first(0).weights(), [0.0, 0.5, 0.5])     # the replayed steps keep the prior
    with pytest.raises(ValueError, match="keeps at least one"):
        post.restrict(np.array([True, False, False]))


@pytest.mark.parametrize("param, used", [("task", 6.0), (0.0, 0.0), (3.0, 3.0)])
def test_reciprocity_in_wind_keeps_its_prior_off_the_walls_the_task_names(param, used):
    """The task's public ``source_clearance`` (or the parameter) empties the prior nearer the
    walls than it, less one mesh size; 0 leaves every node."""
    env = SearchEnv(_scenario(source_clearance=6))
    _, info = env.reset(seed=SEED)
    task = info["task"]
    assert task.nominal["source_clearance"] == 6
    strat = WindReciprocity(h=MODEL_H, source_clearance=param)
    strat.start(SearchContext(task.world, task.nominal, np.array(task.starts), np.random.default_rng(0)))
    assert strat.params()["source_clearance_used"] == used
    w, wall = strat.belief.weights(), strat.space.wall_distance
    assert np.all(w[wall < used - MODEL_H] == 0) and np.all(w[wall >= used - MODEL_H] > 0)


def test_a_bad_source_clearance_of_the_wind_search_is_refused():
    with pytest.raises(SearchError, match="source_clearance must be a number"):
        WindReciprocity(source_clearance="far")
