"""benchmarks/detection_bound.py: its refusals, its coverage bounds against hand sums, and
its table from rows."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "benchmarks" / "detection_bound.py"
sys.path.insert(0, str(SCRIPT.parent))
import detection_bound  # noqa: E402


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


@pytest.mark.parametrize("args, key", [(["--draws", "0"], "--draws"), (["--noise", "-1"], "--noise"),
                                       (["--families", "atlantis"], "--families"),
                                       (["--table", "nowhere.jsonl"], "--table")])
def test_bad_arguments_exit_2_with_one_error_line(tmp_path, args, key):
    res = run(*args, "--out", str(tmp_path / "r.jsonl"))
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and lines[0].startswith("error: ") and key in lines[0]
    assert not (tmp_path / "r.jsonl").exists()


def test_a_symlinked_output_is_refused(tmp_path):
    (tmp_path / "elsewhere.jsonl").write_text("")
    (tmp_path / "r.jsonl").symlink_to(tmp_path / "elsewhere.jsonl")
    res = run("--out", str(tmp_path / "r.jsonl"))
    assert res.returncode == 2 and "symbolic link" in res.stderr


def test_coverage_bounds_against_hand_sums():
    # three readers over four sources: footprints {0, 1}, {2}, {2, 3}; source 4 undetectable
    d = np.array([[1, 1, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 1, 1, 0]], dtype=bool)
    f_max, lower, greedy = detection_bound.coverage_bounds(d)
    assert f_max == 0.5
    assert lower == 1.0 + 0.5                      # two disjoint halves: 1 + P(miss the first)
    assert greedy == 1.0 + 0.5                     # greedy takes {0, 1} then {2, 3}
    # footprints that overlap: greedy pays for it, the bound does not
    d = np.array([[1, 1, 0], [0, 1, 1], [1, 0, 0], [0, 0, 1]], dtype=bool)
    f_max, lower, greedy = detection_bound.coverage_bounds(d)
    assert np.isclose(f_max, 2 / 3) and np.isclose(lower, 1 + 1 / 3)
    assert np.isclose(greedy, 1 + 1 / 3)           # {0, 1} then {2}: 1 + 1/3


def test_the_table_splits_the_readings_at_the_first_detection(tmp_path):
    rows = [dict(family="rooms", draw=i, noise=12.0, kappa=2.0, f_max=0.2, lower=3.0, greedy=4.0, never=0.0,
                 n=n, first_detection=k, success=True, error=0.5) for i, (n, k) in enumerate([(8, 5), (6, 2)])]
    path = tmp_path / "r.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    res = run("--table", str(path))
    assert res.returncode == 0, res.stderr
    assert "| 12 | rooms | 2 | 0.2 | 3 / 4 / 3.5 | 3.5 | 7 | 0.000 |" in res.stdout
