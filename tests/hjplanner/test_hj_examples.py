"""examples/planner_paths.py runs and produces its figure and a sane number."""

import importlib.util
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "planner_paths.py"


def test_planner_paths_example(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("planner_paths_example", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    worst = module.main(tmp_path, n_paths=2)
    assert (tmp_path / "planner_paths.png").stat().st_size > 10_000
    # the arena's start pose and two random ones reach the target; at this coarse resolution
    # (h = 2 cm, 36 headings) a path may detour by up to ~40% of φ(start) near a discontinuity of φ
    assert 0.0 <= worst < 0.5
    assert "largest relative length" in capsys.readouterr().out
