"""Every example runs and produces the number it promises."""

import importlib.util
from pathlib import Path

import pytest


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_imaging_figure(tmp_path, pixels_near):
    assert load("imaging_figure").main(tmp_path) < 5.0
    png = tmp_path / "imaging_steps.png"
    assert pixels_near(png, (0, 255, 0), 60) > 20      # the lime star of the true source
    assert pixels_near(png, (255, 0, 255), 60) > 10    # the magenta estimate
    assert pixels_near(png, (255, 0, 0), 60) > 20      # red rings of the measurements


def test_custom_arena(tmp_path):
    assert load("custom_arena").main(tmp_path) < 5.0
    import arenas
    back = arenas.load(tmp_path / "floor_plan.yaml")
    assert len(back.obstacles) == 3 and back.strength == 500.0  # two drawn bars touch: one obstacle


def test_green_convergence(tmp_path):
    orders = load("green_convergence").main(tmp_path)
    assert orders[1] > 1.7 and orders[2] > 2.5


def test_every_example_is_run_by_a_test():
    """Examples never rot: each one is run by a test of this folder."""
    tested = set()
    for path in Path(__file__).parent.rglob("test_*.py"):
        text = path.read_text()
        tested |= {p.stem for p in EXAMPLES.glob("*.py") if f'load("{p.stem}")' in text
                   or f"examples/{p.stem}.py" in text or f'"{p.stem}"' in text}
    assert tested == {p.stem for p in EXAMPLES.glob("*.py")}


def test_lattice_figures(tmp_path, pixels_near):
    load("lattice_figures").main(["--out", str(tmp_path), "--steps", "5", "--seed", "1"])
    for name in ("lattice.png", "search.png"):
        assert pixels_near(tmp_path / name, (255, 0, 0), 60) > 20           # the true source's star
    assert pixels_near(tmp_path / "search.png", (255, 127, 14), 50) > 200   # the source particle cloud


def test_ppo_plume_environment_and_evaluation(tmp_path):
    """The PPO example's environment, evaluation and figure (the training needs PyTorch)."""
    mod = load("ppo_plume")
    rows = [dict(timesteps=t, ppo_steps=s, infotaxis_steps=14.2, random_steps=68.4) for t, s in ((0, 80), (10, 20))]
    mod.plot_curve(rows, 3, tmp_path / "curve.png")
    assert (tmp_path / "curve.png").stat().st_size > 10_000
    mod.write_results(rows[:1], 3, tmp_path)                # after each evaluation: the curve so far
    assert (tmp_path / "learning_curve.csv").read_text().splitlines()[1].startswith("0,80,")
    assert (tmp_path / "learning_curve.png").exists()
    env = mod.make_env()
    obs, _ = env.reset(seed=0)
    assert obs.shape == (1, 37, 37) and env.action_space.n == 4
    steps, rate = mod.evaluate(None, [0, 1, 2], strategy="infotaxis")
    walk_steps, _ = mod.evaluate(mod.random_walk(0), [0, 1, 2])
    assert rate == 1.0 and steps < walk_steps <= mod.MAX_STEPS


def test_ppo_plume_trains_when_stable_baselines3_is_installed(tmp_path):
    import pytest
    pytest.importorskip("stable_baselines3")
    rows = load("ppo_plume").main(["--timesteps", "512", "--eval-every", "512", "--eval-seeds", "3",
                                   "--out", str(tmp_path)])
    assert len(rows) == 2 and (tmp_path / "learning_curve.png").exists()
    assert len((tmp_path / "learning_curve.csv").read_text().splitlines()) == 3


def test_ppo_poisson_environment_and_evaluation(tmp_path):
    """The Poisson PPO example's environment, references and figure (training needs PyTorch)."""
    mod = load("ppo_poisson")
    rows = [dict(timesteps=t, ppo_success=s, ppo_low=max(s - 0.1, 0), ppo_high=min(s + 0.1, 1), ppo_steps=9.0,
                 strategy_success=1.0, strategy_steps=6.0, random_success=0.0, random_steps=1.0, wall_s=1.0)
            for t, s in ((0, 0.0), (10, 0.5))]
    mod.write_results(rows, 3, tmp_path)
    assert (tmp_path / "learning_curve.png").stat().st_size > 10_000
    assert len((tmp_path / "learning_curve.csv").read_text().splitlines()) == 3
    env = mod.make_env()
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs) and env.action_space.shape == (3,)
    ref = mod.evaluate(None, [10_000, 10_001], strategy="reciprocity")
    rnd = mod.evaluate(mod.random_actions(0), [10_000, 10_001])
    assert ref["success"] == 1.0 and ref["low"] < 1.0 and rnd["success"] <= ref["success"]


@pytest.mark.slow
def test_ppo_poisson_trains_and_goes_on_when_stable_baselines3_is_installed(tmp_path):
    """Two rollouts of SB3's default 2048 steps, the second continuing the saved model;
    the curve is labelled with the steps actually trained."""
    pytest.importorskip("stable_baselines3")
    mod = load("ppo_poisson")
    rows = mod.main(["--timesteps", "256", "--eval-every", "256", "--eval-seeds", "2", "--envs", "1",
                     "--out", str(tmp_path)])
    assert [r["timesteps"] for r in rows] == [0, 2048] and (tmp_path / "ppo_poisson.zip").exists()
    more = mod.main(["--timesteps", "4096", "--eval-every", "256", "--eval-seeds", "2", "--envs", "1",
                     "--out", str(tmp_path), "--init", str(tmp_path / "ppo_poisson.zip")])
    assert [int(float(r["timesteps"])) for r in more] == [0, 2048, 4096]
    assert len((tmp_path / "learning_curve.csv").read_text().splitlines()) == 4


def test_every_example_takes_an_output_folder():
    """The gallery's contract: ``python examples/NAME.py --out DIR`` writes its figures in DIR."""
    missing = [p.name for p in EXAMPLES.glob("*.py")
               if 'add_argument("--out"' not in p.read_text() and "training_parser(" not in p.read_text()]
    from reciprocity.gym.training import training_parser
    assert training_parser("x", "y").parse_args(["--out", "z"]).out.name == "z"     # the training examples' --out
    assert not missing


def test_arenas_figure(tmp_path, pixels_near):
    import arenas
    titles = load("arenas_figure").main(["--out", str(tmp_path)])
    assert len(titles) == len(arenas.builtin_names()) + 2
    assert pixels_near(tmp_path / "arenas.png", (255, 0, 0), 60) > 50      # the sources' stars


def test_planner_convergence(tmp_path):
    order = load("planner_convergence").main(["--out", str(tmp_path), "--quick"])
    assert order > 0.8 and (tmp_path / "planner_convergence.png").stat().st_size > 10_000


def test_world_figures(tmp_path):
    paths = load("world_figures").main(["--out", str(tmp_path), "--quick"])
    assert [p.name for p in paths] == list(load("world_figures").FIGURES)
    assert all(p.stat().st_size > 10_000 for p in paths)


def test_plume_figures(tmp_path, pixels_near):
    paths = load("plume_figures").main(["--out", str(tmp_path), "--quick"])
    assert [p.name for p in paths] == list(load("plume_figures").FIGURES)
    assert all(p.stat().st_size > 10_000 for p in paths)
    assert pixels_near(tmp_path / "rate_song-100.png", (255, 0, 0), 60) > 20    # the true source's red star


@pytest.mark.slow
def test_wind_search_figure(tmp_path, pixels_near):
    s = load("wind_search_figure").main(["--out", str(tmp_path), "--h", "3", "--truth-h", "2", "--max-steps", "6",
                                         "--video"])
    assert s["n_measurements"] == 6
    assert (tmp_path / "wind_search.mp4").stat().st_size > 10_000
    png = tmp_path / "wind_search_steps.png"
    assert pixels_near(png, (255, 0, 0), 60) > 20        # the true source's red star
    assert pixels_near(png, (255, 0, 255), 60) > 10      # the magenta estimate
