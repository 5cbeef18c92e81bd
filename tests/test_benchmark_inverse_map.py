"""benchmarks/bench_inverse_map.py: its refusals, and a coarse run (in this process, whose
modules are loaded already) whose two paths agree."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "benchmarks" / "bench_inverse_map.py"


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


@pytest.mark.parametrize("args, key", [(["--h", "0"], "--h 0.0"), (["--px-per-cm", "-1"], "--px-per-cm -1.0")])
def test_bad_arguments_fail_with_one_error_line(args, key):
    r = run(*args)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {key}")


def test_a_coarse_run_prints_a_row_per_arena(capsys):
    spec = importlib.util.spec_from_file_location("bench_inverse_map", SCRIPT)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    assert bench.main(["--h", "10", "--px-per-cm", "1"]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| ") and "x |" in line]
    assert [row.split(" | ")[0] for row in rows] == ["| ring-1", "| disk", "| paper"]
