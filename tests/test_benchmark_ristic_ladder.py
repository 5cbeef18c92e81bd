"""benchmarks/ristic_ladder.py: every rung on the reproduce table's episode seeds, rows
written as they finish and resumed, the intervals of its table, and its bad input."""

import csv
import importlib.util
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "ristic_ladder.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("ristic_ladder", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_two_runs_repeat_the_table_episodes_and_resume(bench, tmp_path, capsys):
    from reciprocity.campaign.reproduce import TABLES
    from reciprocity.campaign.worker import execute_task
    out = tmp_path / "ladder.csv"
    assert bench.main(["--runs", "2", "--rungs", "4", "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    tasks = [t for t in TABLES["ristic2014-table1"].protocol("paper").spec(2).tasks()
             if t.scenario.label == "source_0_7"]
    assert [int(r["seed"]) for r in rows] == [t.seed for t in tasks]
    s = execute_task(tasks[1])[0].summary          # the table's own episode, run as the campaign runs it
    assert (rows[1]["success"], int(rows[1]["steps"]), rows[1]["reached"]) == (
        str(s["success"]), s["steps"], str(s["reached"]))
    text = out.read_text()
    assert bench.main(["--runs", "2", "--rungs", "4", "--out", str(out)]) == 0
    assert out.read_text() == text                  # resumed: nothing run again
    assert "| 4. the paper: map unknown, eq. (25) | 2 |" in capsys.readouterr().out


def test_intervals(bench):
    d, lo, hi = bench.newcombe(56, 70, 48, 80)      # Newcombe (1998), Table II, method 10
    assert d == pytest.approx(0.2) and lo == pytest.approx(0.0524, abs=1e-4) and hi == pytest.approx(0.3339, abs=1e-4)
    p, lo, hi = bench.wilson(18, 30)
    assert p == 0.6 and lo == pytest.approx(0.423, abs=1e-3) and hi == pytest.approx(0.754, abs=1e-3)
    m, lo, hi = bench.t_interval([7, 8, 9, 10])
    assert m == 8.5 and hi - m == pytest.approx(m - lo) == pytest.approx(2.054, abs=1e-3)


def test_the_table_reads_the_rows_and_differences(bench, tmp_path):
    out = tmp_path / "ladder.csv"
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, bench.FIELDS)
        w.writeheader()
        for i in range(4):
            for rung, ok, hit in (("3", i < 3, i < 3), ("4", i < 1, i < 2)):
                w.writerow(dict(experiment="ladder", rung=rung, stream="campaign", source="0,7", seed_index=i,
                                seed=i, success=ok, reached=hit, steps=10 + i, wall_s=0.1))
    text = bench.table(out)
    assert "| 4. the paper: map unknown, eq. (25) | 4 | 25 % [5, 70] | 50 % [15, 85] | 25 % [5, 70] |" in text
    assert "| 3 − 4 | the position estimated instead of known | +50 [-14, +79] | +25 [-32, +66] |" in text


def test_the_streams_are_compared_rung_by_rung(bench, tmp_path):
    out = tmp_path / "ladder.csv"
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, bench.FIELDS)
        w.writeheader()
        for stream, ok in (("integers", (True, False, False, False)), ("campaign", (True, True, True, False))):
            for i, hit in enumerate(ok):
                w.writerow(dict(experiment="ladder", rung="4", stream=stream, source="0,7", seed_index=i,
                                seed=i, success=hit, reached=hit, steps=10, wall_s=0.1))
    text = bench.streams(out)
    assert "| 4 | 4, 25 %, 25 % | 4, 75 %, 75 % | -50 [-79, +14] | -50 [-79, +14] |" in text
    assert "| 3 |" not in text                     # a rung without both streams is left out


@pytest.mark.parametrize("args, key", [(["--runs", "0"], "--runs"), (["--rungs", "5"], "--rungs"),
                                       (["--stream", "odd"], "--stream"), (["--source", "0,10"], "--source"),
                                       (["--experiment", "x"], "--experiment"), (["--minutes", "-1"], "--minutes")])
def test_bad_input_is_one_error_line(bench, tmp_path, capsys, args, key):
    assert bench.main([*args, "--out", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {key} ")
    assert not (tmp_path / "x.csv").exists()
