"""examples/planner_paths.py runs, draws its figure and its paths follow φ and keep the clearance."""

import importlib.util
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "planner_paths.py"


def test_planner_paths_example(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("planner_paths_example", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    worst, nearest = module.main(tmp_path, n_paths=2)
    assert (tmp_path / "planner_paths.png").read_bytes()[:4] == b"\x89PNG"
    # the arena's start pose and two random ones: path length within 4 grid spacings of φ(start)
    # (measured 0.0-1.3 h), never closer to a wall than the clearance of 4 cm
    assert 0.0 <= worst < 4.0
    assert nearest >= 4.0
    assert "largest |length - φ(start)|" in capsys.readouterr().out
