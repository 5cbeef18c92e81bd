"""benchmarks/song_fig5.py, song_fig67.py and song_circling.py on tiny runs."""

import csv
import importlib.util
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def test_fig5_writes_one_row_per_step_and_the_figure(tmp_path, capsys):
    rows = _load("song_fig5").main(["--seeds", "1", "--max-steps", "25", "--out", str(tmp_path)])
    assert (tmp_path / "fig5.png").stat().st_size > 0
    written = _rows(tmp_path / "fig5.csv")
    assert len(written) == len(rows) == 2 * 25                     # two strategies, 25 steps each
    assert {r["strategy"] for r in written} == {"infotaxis", "free-energy"}
    first = [r for r in rows if r["strategy"] == "infotaxis"][0]
    # the paper's Fig. 5 start (200, -100), source (-250, 0): one step from the start
    assert first["sensor_distance"] == pytest.approx(np.hypot(450, 100), abs=1.5)
    assert all(r["spread"] > 0 for r in rows)
    assert "free-energy: found 0/1" in capsys.readouterr().out


def test_fig67_runs_both_temperatures_and_draws_seed_zero(tmp_path):
    bench = _load("song_fig67")
    rows = bench.main(["--seeds", "1", "--max-steps", "20", "--last", "10", "--out", str(tmp_path)])
    assert (tmp_path / "fig67.png").stat().st_size > 0
    assert [r["temperature"] for r in rows] == list(bench.TEMPERATURES)
    assert rows[0]["decided_by_T"] == 0.0                            # T = 0 never differs from itself
    assert all(r["steps"] == 20 and not r["success"] for r in rows)
    assert len(_rows(tmp_path / "fig67.csv")) == 2


def test_circling_measures_a_walker_at_the_turn_limit():
    bench = _load("song_circling")
    # a unit step turning 3 degrees each time: the circle of radius 1 / (2 sin 1.5 deg)
    turn = np.radians(3.0)
    radius = 1 / (2 * np.sin(turn / 2))
    heading = np.arange(400) * turn
    centre = np.array([10.0, 0.0])
    xy = centre + radius * np.column_stack([np.sin(heading), -np.cos(heading)])
    trace = [{"pose": [x, y, h % (2 * np.pi)], "estimate": centre} for (x, y), h in zip(xy, heading)]
    m = bench.circling(trace, source=[0.0, 0.0], max_turn_deg=3.0, last=240, radius=25.0)
    assert m["at_max_turn"] == 1.0 and m["near_estimate"] == 1.0
    assert m["orbit_radius"] == pytest.approx(radius, rel=1e-3) and radius == pytest.approx(19.1, abs=0.05)
    assert m["orbit_to_source"] == pytest.approx(10.0, abs=0.5)
    assert m["closest_approach"] == pytest.approx(radius - 10.0, abs=0.1)
