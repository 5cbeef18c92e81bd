"""benchmarks/reach_certify.py: its refusals, and a tiny run that writes its rows and table."""

import csv
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "benchmarks" / "reach_certify.py"


def run(*args, cwd=None):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, cwd=cwd)


@pytest.mark.parametrize("args, key", [(["--draws", "0"], "--draws 0"), (["--points", "-3"], "--points -3"),
                                       (["--arenas", "atlantis"], "--arenas 'atlantis'"),
                                       (["--table", "nowhere.csv"], "--table 'nowhere.csv'")])
def test_bad_arguments_exit_2_with_one_error_line(tmp_path, args, key):
    res = run(*args, "--out", str(tmp_path / "r.csv"))
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and lines[0].startswith("error: ") and key in lines[0]
    assert not (tmp_path / "r.csv").exists()


def test_a_tiny_run_writes_rows_resumes_and_prints_its_table(tmp_path):
    out = tmp_path / "r.csv"
    res = run("--arenas", "rooms", "--draws", "1", "--starts", "1", "--points", "20", "--out", str(out))
    assert res.returncode == 0, res.stderr
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 1 and rows[0]["arena"] == "rooms" and int(rows[0]["points"]) == 21   # and the source
    assert int(rows[0]["flood"]) >= int(rows[0]["hj"]) - int(rows[0]["hj_only"])
    assert "| rooms | 1 |" in res.stdout
    again = run("--arenas", "rooms", "--draws", "1", "--starts", "1", "--points", "20", "--out", str(out))
    assert again.returncode == 0 and len(list(csv.DictReader(out.open()))) == 1      # resumed: nothing new
