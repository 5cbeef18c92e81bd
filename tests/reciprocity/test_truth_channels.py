"""Truth stays on the truth's side: each test fails if a channel to the strategy reopens."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from reciprocity.api import execute
from reciprocity.worlds.poisson import TRUTH_H, TRUTH_ORDER, truth_solver

ROOT = Path(__file__).resolve().parents[2]


def test_the_truth_never_shares_a_solver_with_a_strategy():
    """Even at the truth's own mesh size the strategy's solver, mesh, elements and
    factorization are its own: the data never come from the very model that inverts them."""
    h = 3.0
    episode, strategy, _ = execute("paper", "reciprocity", seed=1, params={"h": h, "max_steps": 2},
                                   world={"truth_h": h})
    truth = truth_solver(strategy.solver.arena.without_scenario(), h)
    assert truth.arena.boundary.tolist() == strategy.solver.arena.boundary.tolist()   # the same walls, and yet
    assert strategy.solver is not truth
    assert strategy.solver.mesh is not truth.mesh
    # the truth may have read its field from the disk cache without factorizing: make it
    # factorize, so that the two factorizations are compared and not two Nones
    assert strategy.solver._lu is not None and truth.factorize()._lu is not None
    assert strategy.solver._lu is not truth._lu
    assert (truth.order, strategy.solver.order) == (TRUTH_ORDER, 1)
    assert truth.n_unknowns != strategy.solver.n_unknowns


@pytest.mark.parametrize("h", ["0.7", "2.5"])
def test_the_truths_discretisation_does_not_follow_the_strategys_h(h):
    """`--h` sets the strategy's mesh only: the world's mesh size and elements stay its own."""
    from reciprocity.cli import _plan, build_parser
    from reciprocity.env import SearchEnv
    args = build_parser().parse_args(["run", "--arena", "paper", "--strategy", "reciprocity", "--h", h])
    plan = _plan(args, "paper", "reciprocity", {})
    assert plan.spec.params["h"] == float(h)
    env = SearchEnv(plan.spec)
    env.reset(seed=0)
    assert env.world.h == TRUTH_H
    assert env.world.describe()["truth_h"] == TRUTH_H


def test_the_layer_contracts_hold_without_exceptions():
    """import-linter's contracts (pyproject.toml): belief never imports truth, truth never
    imports belief, numerics at the bottom; none may list an ignored import."""
    text = (ROOT / "pyproject.toml").read_text()
    assert "ignore_imports" not in text, "a contract has an exception again"
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    assert exe is not None, "import-linter (the test extra) is not installed"
    done = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:]
    assert "0 broken" in done.stdout


#: Per world kind: a scenario and two true sources. Whatever the true source, the agent's
#: first action must be the same: before its first reading it knows only the public task.
MOVES = {
    "poisson": ("paper", [70.21, 70.21], [110.0, 110.0]),
    "lattice": ("ristic-lattice", [0, 7], [3, -2]),
    "plume": ("song-100", None, [20.0, 40.0]),
    "filament": ("farrell", [20.0, 0.0], [40.0, 10.0]),
    "flow": ("paper-wind", [70.21, 70.21], [120.0, 80.0]),
}
#: Parameters that keep a strategy's start-up cheap (the first action does not depend on them).
CHEAP = {"h": 4.0, "n_particles": 200, "particles": 500}


def _first_action(scenario, strategy, source, seed):
    from reciprocity.env import SearchEnv
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    from reciprocity.api import strategy_parameters
    accepted = strategy_parameters(strategy)
    params = {k: v for k, v in CHEAP.items() if k in accepted}
    env = SearchEnv(scenario, world=None if source is None else {"source": source})
    agent = StrategyAgent(STRATEGIES[strategy], params)
    _, info = env.reset(seed=seed)
    agent.reset(info["task"], info["agent_seed"])
    return agent.act(), env.world.source, info["task"]


def _pairs():
    from reciprocity.strategies import STRATEGIES
    return [pytest.param(kind, name, id=f"{kind}-{name}") for kind in MOVES
            for name, cls in STRATEGIES.items() if kind in cls.worlds]


def _public(task) -> dict:
    """Everything a Task tells, as plain values (arenas as their file mapping)."""
    import dataclasses
    from collections.abc import Mapping

    import arenas
    import numpy as np

    def plain(v):
        if isinstance(v, arenas.Arena):
            return arenas.to_dict(v)
        if isinstance(v, Mapping):
            return {k: plain(x) for k, x in v.items()}
        if isinstance(v, np.ndarray):
            return (np.round(v, 9) if v.dtype.kind == "f" else v).tolist()
        if isinstance(v, (int, float, str, bool, type(None))):
            return v
        if isinstance(v, (tuple, list)):
            return [plain(x) for x in v]
        if dataclasses.is_dataclass(v):
            return plain(dataclasses.asdict(v))
        if hasattr(v, "points") and hasattr(v, "links"):        # a lattice (search space)
            return plain({"points": v.points, "links": np.asarray(v.links),
                          "present": getattr(v, "present", None)})
        raise AssertionError(f"a Task value of unexpected type {type(v).__name__}: compare it here")
    return {f: plain(getattr(task, f)) for f in task.__dataclass_fields__ if f != "reachable"}


def _same(a, b) -> bool:
    import numpy as np
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    return type(a) is type(b) and all(
        np.allclose(getattr(a, f), getattr(b, f)) if getattr(a, f) is not None else getattr(b, f) is None
        for f in a.__dataclass_fields__)


@pytest.mark.parametrize("kind, strategy", _pairs())
def test_the_first_action_does_not_depend_on_the_true_source(kind, strategy):
    import numpy as np
    scenario, here, there = MOVES[kind]
    a, src_a, task_a = _first_action(scenario, strategy, here, seed=5)
    b, src_b, task_b = _first_action(scenario, strategy, there, seed=5)
    assert not np.allclose(src_a, src_b), "the two worlds must differ in their source"
    assert _public(task_a) == _public(task_b), "the task told to the agent depends on the true source"
    assert _same(a, b), f"{strategy} acts differently when only the true source moved: {a} vs {b}"


def test_the_car_plans_on_the_map_not_on_the_true_walls():
    """Under ``wall_shift`` the testbed's physics has the true (grown) walls and the car's
    planner, reachability and standable targets have the map the strategy was given."""
    import arenas
    import numpy as np
    from reciprocity.env import SearchEnv
    small = arenas.Arena.from_polygons([[0, 0], [60, 0], [60, 60], [0, 60]],
                                       [[[24, 24], [32, 24], [32, 32], [24, 32]]], name="small",
                                       source=(42.0, 15.0), strength=500.0, start=(10.0, 10.0, 0.0))
    env = SearchEnv(small, platform="car", world={"mismatch": {"wall_shift": 3.0}, "truth_h": 2.0},
                    platform_options={"px_per_mm": 0.5, "h": 2.0, "ntheta": 24})
    env.reset(seed=1)
    car, world = env.platforms[0], env.world
    believed, true = car.arena, car.testbed.arena
    assert np.allclose(believed.obstacles[0], world.arena.obstacles[0])          # the map
    # a point inside the grown wall but outside the mapped one: the map says free
    p = np.array([[33.5, 28.0]])
    assert believed.contains(p)[0] and not true.contains(p)[0]
    assert np.allclose(car.planner.workspace.geometry["obstacles"][0], believed.obstacles[0])


def test_the_evaluator_classifies_the_source_on_the_true_walls():
    """A source in a pocket whose mouth the true (grown) walls close: the car's map says
    reachable, the environment's verdict ``source_reachable`` says not."""
    import arenas
    import numpy as np
    from reciprocity.env import SearchEnv
    pocket = arenas.Arena.from_polygons(
        [[0, 0], [60, 0], [60, 60], [0, 60]],
        [[[30, 20], [58, 20], [58, 40], [30, 40], [30, 33], [32, 33], [32, 38], [56, 38], [56, 22],
          [32, 22], [32, 27], [30, 27]]],                     # a room whose door is 6 cm wide
        name="pocket", source=(48.0, 30.0), strength=500.0, start=(10.0, 10.0, 0.0))
    opts = {"px_per_mm": 0.5, "h": 1.0, "ntheta": 24, "clearance": 2.0}
    src = np.array([[48.0, 30.0]])
    open_env = SearchEnv(pocket, platform="car", world={"truth_h": 2.0}, platform_options=opts)
    open_env.reset(seed=1)
    shut = SearchEnv(pocket, platform="car", world={"truth_h": 2.0, "mismatch": {"wall_shift": 2.0}},
                     platform_options=opts)
    shut.reset(seed=1)
    assert open_env.platforms[0].reachable(src)[0] and shut.platforms[0].reachable(src)[0]   # the map
    assert open_env._source_reachable is True
    assert shut._source_reachable is False                                                # the walls


@pytest.mark.parametrize("faulty", ["hajieghrary-dead-sensor", "hajieghrary-false-alarms"])
def test_a_faulty_sensor_is_told_to_no_strategy(faulty):
    """The sensor faults are truth: the task of a faulty world is the matched world's, and
    the team's first moves are the same (they differ only once a faulty reading arrives)."""
    from reciprocity.env import SearchEnv
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    tasks, actions = [], []
    for scenario in ("hajieghrary", faulty):
        env = SearchEnv(scenario)
        _, info = env.reset(seed=3)
        agent = StrategyAgent(STRATEGIES["voi"], {"particles": 200, "share": "all"})
        agent.reset(info["task"], info["agent_seed"])
        # the scenario's name is a label, the same for every world it names
        tasks.append({k: v for k, v in _public(info["task"]).items() if k != "scenario"})
        actions.append(agent.act())
    assert tasks[0] == tasks[1], "the task tells the strategy about the sensor faults"
    assert _same(actions[0], actions[1])
