"""benchmarks/bench_locate.py: its refusals, and a coarse run whose two paths agree."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "benchmarks" / "bench_locate.py"


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


@pytest.mark.parametrize("args, key", [(["--h", "0"], "--h 0.0"), (["--px-per-cm", "-1"], "--px-per-cm -1.0")])
def test_bad_arguments_fail_with_one_error_line(args, key):
    r = run(*args)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {key}")


def test_a_coarse_run_prints_a_row_per_arena():
    r = run("--h", "8", "--px-per-cm", "1")
    assert r.returncode == 0, r.stderr
    rows = [line for line in r.stdout.splitlines() if line.startswith("| ") and "x |" in line]
    assert [row.split(" | ")[0] for row in rows] == ["| paper", "| maze", "| pillars-1", "| rooms-2"]
