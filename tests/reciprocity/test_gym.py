"""The Gymnasium faces: every id passes check_env, renders, and with StrategyPolicy runs the
very episode `reciprocity run` runs."""

import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import reciprocity.gym as rg  # noqa: E402
from reciprocity.api import execute  # noqa: E402
from reciprocity.errors import SearchError  # noqa: E402

#: Cheap parameters of the lattice's RBPF (the equivalence does not depend on them).
RBPF = {"n_particles": 500, "n_gain": 50}


def drive(env, policy, seed):
    obs, info = env.reset(seed=seed)
    assert set(info) == {"task"}                 # nothing of the truth at reset
    policy.reset(seed)
    terminated = truncated = False
    steps = 0
    while not (terminated or truncated):
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        assert env.observation_space.contains(obs)
        steps += 1
    return info, steps


def same_summary(a: dict, b: dict) -> list:
    return sorted(k for k in set(a) | set(b) if k != "wall_time_s" and a.get(k) != b.get(k))


#: World keys that keep a test's truth cheap (the flow truth's 0.5 cm mesh takes seconds to build).
CHEAP = {"reciprocity/Flow-v0": {"truth_h": 2.0}}


@pytest.mark.parametrize("env_id", sorted(rg.IDS))
def test_check_env_passes(env_id):
    env = gymnasium.make(env_id, **CHEAP.get(env_id, {}))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # unbounded readings and cm-sized boxes are warned about
        check_env(env.unwrapped)


@pytest.mark.parametrize("env_id, scenario, strategy, params, world", [
    ("reciprocity/Poisson-v0", "paper", "reciprocity", {}, {"random_source": False}),
    ("reciprocity/Plume-v0", "otto-2d", "infotaxis", {}, {}),
    ("reciprocity/Plume-v0", "song-100", "infotaxis", {}, {"max_turn": 30}),
    ("reciprocity/Lattice-v0", "ristic-lattice", "rbpf", RBPF, {}),
    # the info rule with 32 posterior samples: the policy's mechanics at an eighth of the solves
    ("reciprocity/Flow-v0", "paper-wind", "reciprocity-wind", {"h": 2.0, "samples": 32}, {"truth_h": 2.0}),
])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_strategy_policy_runs_the_cli_episode(env_id, scenario, strategy, params, world, seed):
    """The same seed gives the same summary (estimate, readings, every key but the wall
    time) through Gymnasium as through `reciprocity run`."""
    env = gymnasium.make(env_id, scenario=scenario, **world)
    info, steps = drive(env, rg.StrategyPolicy(strategy, env, **params), seed)
    world = {k: v for k, v in world.items() if k != "random_source"}
    episode, _, _ = execute(scenario, strategy, seed=seed, params=params, world=world or None)
    assert same_summary(info["summary"], episode.summary) == []
    assert info["n_measurements"] == episode.summary["n_measurements"]
    assert {"success", "error", "estimate", "steps", "stop_reason"} <= set(info)


def test_the_car_runs_the_cli_episode():
    env = gymnasium.make("reciprocity/PoissonCar-v0")
    info, _ = drive(env, rg.StrategyPolicy("reciprocity", env), 0)
    episode, _, _ = execute("paper", "reciprocity", seed=0, platform="car")
    assert same_summary(info["summary"], episode.summary) == []


@pytest.mark.parametrize("env_id, strategy, params", [
    ("reciprocity/Poisson-v0", "reciprocity", {}), ("reciprocity/Plume-v0", "infotaxis", {}),
    ("reciprocity/Lattice-v0", "rbpf", RBPF), ("reciprocity/Filament-v0", "detection-infotaxis", {}),
    ("reciprocity/Flow-v0", "reciprocity-wind", {"h": 2.0})])
def test_rgb_frames_and_the_belief_image(env_id, strategy, params):
    env = rg.BeliefImage(gymnasium.make(env_id, render_mode="rgb_array", **CHEAP.get(env_id, {})), size=24)
    policy = rg.StrategyPolicy(strategy, env, **params)
    obs, _ = env.reset(seed=3)
    policy.reset(3)
    for _ in range(3):
        obs, _, terminated, truncated, _ = env.step(policy(obs))
        if terminated or truncated:
            break
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape[2] == 3 and frame.std() > 0
    assert env.observation_space.contains(obs) and obs.shape == (2, 24, 24)
    assert obs[1].sum() == 1.0                   # the observer's pixel
    assert obs[0].max() == pytest.approx(1.0)    # the belief, scaled to its peak


def test_the_centred_belief_image_puts_the_observer_in_the_middle():
    env = rg.BeliefImage(gymnasium.make("reciprocity/Plume-v0"), size=19, centred=True)
    plain = rg.BeliefImage(gymnasium.make("reciprocity/Plume-v0"), size=19)
    obs, _ = env.reset(seed=4)
    ref, _ = plain.reset(seed=4)
    for action in (1, 3, 3):
        obs, *_ = env.step(action)
        ref, *_ = plain.step(action)
    assert obs.shape == (1, 37, 37) and env.observation_space.contains(obs)
    r, c = np.argwhere(ref[1] == 1.0)[0]
    window = obs[0, 18 - r:18 - r + 19, 18 - c:18 - c + 19]
    assert np.array_equal(window, ref[0]) and obs[0].sum() == pytest.approx(ref[0].sum())


def test_frames_and_first_actions_do_not_depend_on_the_true_source():
    """What the policy and a viewer get before the first reading is the same wherever the
    source is: the truth stays behind the face."""
    outs = []
    for source in ([70.21, 70.21], [110.0, 110.0]):
        env = gymnasium.make("reciprocity/Poisson-v0", render_mode="rgb_array", source=source, random_source=False)
        policy = rg.StrategyPolicy("reciprocity", env, h=4.0)
        obs, info = env.reset(seed=5)
        policy.reset(5)
        outs.append((env.render(), policy(obs), obs["position"]))
    assert np.array_equal(outs[0][0], outs[1][0])
    assert np.array_equal(outs[0][1], outs[1][1]) and np.array_equal(outs[0][2], outs[1][2])


def test_an_outside_policy_declares_its_estimate_by_stopping():
    env = gymnasium.make("reciprocity/Poisson-v0", source=[70.0, 70.0], random_source=False)
    obs, _ = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(np.array([30.0, 30.0, 0.0]))
    assert not (terminated or truncated) and reward == -1.0 and obs["reading"][0] != 0.0
    obs, reward, terminated, truncated, info = env.step(np.array([71.0, 70.0, 1.0]))
    assert terminated and not truncated and info["success"] and info["n_measurements"] == 1
    assert info["estimate"] == [71.0, 70.0] and reward == rg.SUCCESS_REWARD     # stopping is no round
    with pytest.raises(SearchError, match="episode is over"):
        env.step(np.array([1.0, 1.0, 0.0]))


def test_a_plume_walker_is_truncated_at_the_budget():
    env = gymnasium.make("reciprocity/Plume-v0", scenario="otto-2d", max_steps=4)
    env.reset(seed=0)
    stay = env.unwrapped.face.n
    out = [env.step(stay) for _ in range(4)]
    assert [o[3] for o in out] == [False, False, False, True] and not out[-1][2]
    assert out[-1][4]["stop_reason"].startswith("step cap") and [o[1] for o in out] == [-1.0] * 4


def test_giving_up_early_never_pays_better_than_searching_on():
    """A failed episode's return is minus the whole budget, however early it stopped."""
    env = gymnasium.make("reciprocity/Plume-v0", scenario="otto-2d", max_steps=10)
    env.reset(seed=0)
    stop = env.unwrapped.face.n + 1
    _, first, _, _, _ = env.step(env.unwrapped.face.n)         # stay once
    _, last, terminated, _, info = env.step(stop)
    assert terminated and not info["success"] and first + last == -10.0


def test_bad_arguments_fail_cleanly():
    with pytest.raises(SearchError, match="render_mode"):
        rg.SearchGymEnv("otto-2d", render_mode="human")     # (gymnasium.make wraps 'human' itself)
    with pytest.raises(SearchError, match="max_steps"):
        gymnasium.make("reciprocity/Plume-v0", max_steps=0)
    with pytest.raises(SearchError, match="pettingzoo"):
        gymnasium.make("reciprocity/Plume-v0", scenario="hajieghrary")
    env = gymnasium.make("reciprocity/Plume-v0")
    with pytest.raises(SearchError, match="unknown strategy"):
        rg.StrategyPolicy("nope", env)
    # checked by api.check when the policy is made, as on every front door: the world,
    # then the parameters (name, value and what is allowed)
    with pytest.raises(SearchError, match="does not apply to scenario .otto-2d."):
        rg.StrategyPolicy("reciprocity", env)
    with pytest.raises(SearchError, match=r"unknown parameter\(s\) nope for strategy 'infotaxis'"):
        rg.StrategyPolicy("infotaxis", env, nope=1)
    with pytest.raises(SearchError, match="particles must be a whole number from 10 to 100000; got -3"):
        rg.StrategyPolicy("infotaxis", env, particles=-3)
    with pytest.raises(SearchError, match="unknown parameter"):
        rg.BeliefImage(env, nope=1)
    policy = rg.StrategyPolicy("infotaxis", env)
    env.reset(seed=1)
    with pytest.raises(SearchError, match="seed 1, not 2"):
        policy.reset(2)
    with pytest.raises(SearchError, match="size"):
        rg.BeliefImage(env, size=4)


@pytest.mark.parametrize("env_id", sorted(rg.IDS))
def test_observations_and_infos_pickle(env_id):
    """What a subprocess vector environment sends back (observations, reset and step
    infos, the final summary) pickles; the task arrives read-only, without the platform."""
    import pickle
    env = gymnasium.make(env_id, **CHEAP.get(env_id, {}))
    obs, info = env.reset(seed=0)
    sent = [obs, info]
    env.action_space.seed(0)
    for action in [*(env.action_space.sample() for _ in range(2)), env.unwrapped.face.stop_action()]:
        obs, _, terminated, truncated, info = env.step(action)
        sent += [obs, info]
        if terminated or truncated:
            break
    assert terminated or truncated
    back = pickle.loads(pickle.dumps(sent))
    task = back[1]["task"]
    sent_task = sent[1]["task"]
    assert (task.world, task.scenario, set(task.world_nominal)) == (sent_task.world, sent_task.scenario,
                                                                    set(sent_task.world_nominal))
    assert (task.starts == sent_task.starts).all() and task.max_steps == sent_task.max_steps
    with pytest.raises(TypeError):
        task.world_nominal["arena"] = None            # still read-only
    if task.reachable is not None:
        with pytest.raises(SearchError, match="another process"):
            task.reachable(np.zeros((1, 2)))
    import copy
    assert copy.deepcopy(sent_task).reachable == sent_task.reachable      # in-process copies keep it
    assert back[-1]["success"] == sent[-1]["success"]


def test_an_async_vector_environment_runs():
    """gymnasium.make_vec(..., vectorization_mode="async"): two lattice searches in
    subprocesses, a few steps (SB3's SubprocVecEnv sends the same things)."""
    envs = gymnasium.make_vec("reciprocity/Lattice-v0", num_envs=2, vectorization_mode="async")
    try:
        obs, infos = envs.reset(seed=[0, 1])
        assert infos["task"][0].world == "lattice"
        for _ in range(3):
            obs, reward, terminated, truncated, infos = envs.step(np.array([1, 2]))
            assert envs.observation_space.contains(obs) and reward.shape == (2,)
        envs.step(np.array([5, 5]))                  # both stop: the final infos come back too
    finally:
        envs.close()


@pytest.mark.parametrize("seed", [0, 3])
def test_poisson_v0_draws_its_source_and_start_as_the_command_line_does(seed, tmp_path):
    """Poisson-v0 draws the source and the start from the reset seed; StrategyPolicy runs the
    episode of `reciprocity run --arena paper --random-source --seed s`."""
    import json
    from reciprocity.cli import main
    env = gymnasium.make("reciprocity/Poisson-v0")
    info, _ = drive(env, rg.StrategyPolicy("reciprocity", env), seed)
    assert main(["run", "--arena", "paper", "--strategy", "reciprocity", "--random-source", "--seed", str(seed),
                 "--quiet", "--json", str(tmp_path / "s.json")]) == 0
    summary = json.loads((tmp_path / "s.json").read_text())
    assert same_summary(info["summary"], summary) == [] and info["success"]


def test_poisson_v0_ends_its_budget_as_a_terminal_state():
    """The budget is part of Poisson-v0's task: spent, it terminates (no bootstrapping
    past it); the other ids keep Gymnasium's time limit."""
    env = gymnasium.make("reciprocity/Poisson-v0", max_steps=2)
    env.reset(seed=0)
    out = [env.step(np.array([20.0 + 30 * k, 30.0, 0.0])) for k in range(2)]
    assert [(o[2], o[3]) for o in out] == [(False, False), (True, False)]
    assert out[-1][4]["stop_reason"].startswith("step cap") and not out[-1][4]["success"]
    with pytest.raises(SearchError, match="cap_terminates"):
        gymnasium.make("reciprocity/Poisson-v0", cap_terminates="yes")


def test_poisson_v0_is_a_new_search_at_every_seed_and_a_failed_stop_costs_the_budget():
    env = gymnasium.make("reciprocity/Poisson-v0")
    starts = {tuple(env.reset(seed=s)[1]["task"].starts[0][:2].round(6)) for s in range(5)}
    assert len(starts) == 5                                          # a new start at every seed
    assert tuple(env.reset(seed=2)[1]["task"].starts[0][:2].round(6)) in starts   # the seed decides
    sources = set()
    for s in range(5):
        env.reset(seed=s)
        _, reward, terminated, _, info = env.step(np.array([70.21, 70.21, 1.0]))   # stop at once
        sources.add(tuple(np.round(info["source"], 6)))
        assert terminated and (info["success"] or reward == -40.0)  # -1 for each of the 40 rounds
    assert len(sources) == 5
    env.reset()                                                      # no seed: the env's own generator
    with pytest.raises(SearchError, match="random_source"):
        gymnasium.make("reciprocity/Poisson-v0", source=[30.0, 30.0])


def test_belief_stop_maps_actions_onto_the_arena_and_stops_at_the_beliefs_estimate():
    env = rg.BeliefStop(rg.BeliefImage(gymnasium.make("reciprocity/Poisson-v0", source=[70.0, 70.0],
                                                     random_source=False), size=16), frame="arena")
    assert env.action_space.shape == (3,) and env.action_space.low.min() == -1.0 == -env.action_space.high.max()
    assert env.observation_space.shape == (2, 16, 16) and env.observation_space.high.max() == 1.0
    obs, _ = env.reset(seed=0)
    lo, hi = env.unwrapped.face.bounds()
    assert np.allclose(env.action(np.array([-1.0, 1.0, -1.0]))[:2], [lo[0], hi[1]])
    assert np.allclose(env.action(np.array([0.0, 0.0, -0.2])), [*(lo + hi) / 2, 0.0])
    for point in ([-0.4, -0.4], [0.4, -0.4], [-0.4, 0.4], [0.3, 0.2]):
        obs, reward, terminated, truncated, info = env.step(np.array([*point, -1.0]))
        assert env.observation_space.contains(obs) and not terminated
    estimate = env.get_wrapper_attr("estimate")()
    obs, reward, terminated, truncated, info = env.step(np.array([-1.0, -1.0, 0.0]))
    assert terminated and np.allclose(info["estimate"], estimate)   # the belief's, not the corner's


def test_the_spread_frame_reads_in_the_beliefs_own_axes_and_the_spread_is_its_log_sd():
    env = rg.BeliefStop(rg.BeliefImage(gymnasium.make("reciprocity/Poisson-v0"), size=16, features=True))
    obs, _ = env.reset(seed=3)
    assert set(obs) == {"image", "spread", "budget"} and env.observation_space.contains(obs)
    image = env.get_wrapper_attr("moments").__self__
    for k in range(8):                          # around the belief's mean, in its own axes
        mean, axes, sd = image.moments()
        assert sd[0] >= sd[1] and np.allclose(axes.T @ axes, np.eye(2))
        lo, hi = env.unwrapped.face.bounds()
        a = np.array([0.5 * np.cos(k * np.pi / 2), 0.5 * np.sin(k * np.pi / 2), -1.0])
        assert np.allclose(env.action(a)[:2], np.clip(mean + axes @ (a[:2] * 2 * sd), lo, hi))
        obs, reward, terminated, truncated, info = env.step(a)
        assert env.observation_space.contains(obs)
        sd = image.moments()[2]
        assert np.allclose(obs["spread"], np.log1p(sd) / np.log1p(np.hypot(*(hi - lo))), atol=1e-6)
        assert obs["budget"][0] == pytest.approx((k + 1) / 40)


def test_check_env_passes_on_the_learning_stack():
    """Bounded, normalised spaces: only check_env's note that the env is wrapped remains."""
    env = rg.BeliefStop(rg.BeliefImage(gymnasium.make("reciprocity/Poisson-v0"), size=16, h=4.0, features=True))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=True)
    assert [str(w.message) for w in caught if "different from the unwrapped" not in str(w.message)] == []


def test_belief_stop_takes_only_point_worlds_over_a_belief_image():
    with pytest.raises(SearchError, match="point world"):
        rg.BeliefStop(rg.BeliefImage(gymnasium.make("reciprocity/Plume-v0"), size=16))
    with pytest.raises(SearchError, match="BeliefImage"):
        rg.BeliefStop(gymnasium.make("reciprocity/Poisson-v0"))
    with pytest.raises(SearchError, match="frame"):
        rg.BeliefStop(rg.BeliefImage(gymnasium.make("reciprocity/Poisson-v0"), size=16), frame="nope")
