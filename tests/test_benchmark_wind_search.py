"""benchmarks/wind_search.py: flow scenarios on generated arenas, the table and the resume."""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "wind_search.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("wind_search", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_generated_arena_takes_the_wind_on_the_open_parts_of_its_side_edges(bench):
    sc = bench.scenario_of("generate:rooms:1")
    assert sc.world == "flow" and sc.name == "rooms-1-wind" and sc.params["speed"] == 1.0
    inflow = np.array(sc.params["inflow"])
    assert len(inflow) > 1 and np.all(inflow[:, :, 0] == 0.0)       # walls meet the left edge: cut there
    assert np.all(np.array(sc.params["outflow"])[:, :, 0] == 140.0)
    with pytest.raises(ValueError, match="no rectangular boundary"):
        bench.generated_flow("ring", 1)


def test_the_table_and_the_resume_read_the_results_lines(bench, tmp_path):
    rows = [dict(scenario="s-wind", speed=1.0, strategy="a", seed=i, h=2.0, set={}, success=i < 3,
                 converged=i < 3, error=1.0 if i < 3 else None, n_measurements=10, path_length=100.0,
                 wall_s=1.0, wall_distance=5.0 if i < 2 else 20.0) for i in range(4)]
    results = tmp_path / "r.jsonl"
    results.write_text("".join(json.dumps(r) + "\n" for r in rows))
    done = bench._done(results)
    assert ("s-wind", 1.0, "a", 3, 2.0, "{}") in done and len(done) == 4
    table = bench.table(list(done.values()), {"s-wind": 28.0})
    assert "| s-wind | 1 (28) | a | 75% [30, 95] | 75% | 10.0 | 100 | 1.00 | 1.00 | 1.0 |" in table
    assert "| s-wind | a | 2/2 (100%) | 1/2 (50%) |" in bench.near_walls(rows, 10.0)
