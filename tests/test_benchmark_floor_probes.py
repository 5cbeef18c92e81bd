"""benchmarks/bench_locate.py and bench_inverse_map.py (a floor's pixels: located, then mapped
into their cells): their refusals, and coarse runs whose two paths agree."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


def run(script, *args):
    return subprocess.run([sys.executable, str(BENCHMARKS / script), *args], capture_output=True, text=True)


@pytest.mark.parametrize("script", ["bench_locate.py", "bench_inverse_map.py"])
@pytest.mark.parametrize("args, key", [(["--h", "0"], "--h 0.0"), (["--px-per-cm", "-1"], "--px-per-cm -1.0")])
def test_bad_arguments_fail_with_one_error_line(script, args, key):
    r = run(script, *args)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {key}")


def _rows(out):
    return [line.split(" | ")[0] for line in out.splitlines() if line.startswith("| ") and "x |" in line]


def test_a_coarse_location_run_prints_a_row_per_arena():
    r = run("bench_locate.py", "--h", "8", "--px-per-cm", "1")
    assert r.returncode == 0, r.stderr
    assert _rows(r.stdout) == ["| paper", "| maze", "| pillars-1", "| rooms-2"]


def test_a_coarse_inverse_map_run_prints_a_row_per_arena(capsys):
    """In this process, whose modules are loaded already."""
    spec = importlib.util.spec_from_file_location("bench_inverse_map", BENCHMARKS / "bench_inverse_map.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    assert bench.main(["--h", "10", "--px-per-cm", "1"]) == 0
    assert _rows(capsys.readouterr().out) == ["| ring-1", "| disk", "| paper"]
