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


def test_imaging_figure(tmp_path):
    assert load("imaging_figure").main(tmp_path) < 5.0
    assert (tmp_path / "imaging_steps.png").stat().st_size > 20_000


def test_custom_arena(tmp_path):
    assert load("custom_arena").main(tmp_path) < 5.0
    assert (tmp_path / "floor_plan.yaml").exists()


def test_green_convergence(tmp_path):
    orders = load("green_convergence").main(tmp_path)
    assert orders[1] > 1.7 and orders[2] > 2.5


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.py")))
def test_every_example_has_a_main(name):
    assert callable(getattr(load(name), "main", None))
