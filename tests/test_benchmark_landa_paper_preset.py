"""benchmarks/landa_paper_preset.py: the offline re-evaluation of the stop rule picks the
first reading whose region is below A_ε, and its report runs on recorded readings."""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "landa_paper_preset.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("landa_paper_preset", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_pair_stops_at_the_first_reading_below_its_tolerance(bench):
    # two runs, one threshold: areas per reading and the error then
    per_run = {0: [([900.0], 40.0), ([30.0], 3.0), ([10.0], 1.0)],
               1: [([900.0], 40.0), ([0.0], 60.0), ([5.0], 2.0)],
               2: [([900.0], 40.0), ([800.0], 20.0), ([700.0], 1.5)]}
    assert bench.stops(per_run, 0, 40.0) == [(2, 3.0, True, False), (2, 60.0, True, True), (3, 1.5, False, False)]
    assert bench.stops(per_run, 0, 8.0) == [(3, 1.0, False, False), (2, 60.0, True, True), (3, 1.5, False, False)]


def test_intervals(bench):
    p, lo, hi = bench.wilson(18, 30)
    assert p == 0.6 and lo == pytest.approx(0.423, abs=1e-3) and hi == pytest.approx(0.754, abs=1e-3)
    m, lo, hi = bench.t_interval([7, 8, 9, 10])
    assert m == 8.5 and hi - m == pytest.approx(m - lo) == pytest.approx(2.054, abs=1e-3)


def test_the_report_runs_on_recorded_readings(bench, tmp_path):
    """Three exact readings of the paper arena's source: every section is reported, and
    the product's region closes round the source."""
    import arenas
    from reciprocity.models.green import cached_solver
    arena = arenas.load("paper")
    solver = cached_solver(arena.without_scenario(), 1.0)
    field = solver.field(arena.source, strength=arena.strength)
    points = [[60.0, 60.0], [80.0, 75.0], [70.0, 85.0]]
    run = dict(seed=0, source=list(arena.source), sigma=3.0, strength=float(arena.strength), points=points,
               readings=[float(v) for v in field(np.array(points))], saturated=[False] * 3,
               stop_reason="step cap", sim_time_s=1.0)
    (tmp_path / "run-0.json").write_text(json.dumps(run))
    text = bench.evaluate(tmp_path)
    assert text.count("### ") == 4 and "1 runs, σ = 3.00" in text
    assert text.count("| 0.1 | 2000 |") == 2        # eq. (8) and the product
