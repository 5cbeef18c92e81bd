"""benchmarks/farrell_figures.py: the paper-against-ours table of Farrell et al.'s Figs. 5–8
on a tiny run, and its refusal of bad arguments."""

import importlib.util
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "farrell_figures.py"


@pytest.fixture(scope="module")
def bench():
    if str(SCRIPT.parent) not in sys.path:
        sys.path.insert(0, str(SCRIPT.parent))      # its `arguments` helper
    spec = importlib.util.spec_from_file_location("farrell_figures", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_two_seeds_print_a_row_per_quantity_with_its_verdict(bench, capsys):
    rows = bench.main(["--seeds", "2", "--figure-seed", "0"])
    out = capsys.readouterr().out.splitlines()
    assert len(out) == len(rows) + 2 and out[0].startswith("| Fig. |")
    assert {r[0] for r in rows} == {"5", "6", "7", "8"} and all(len(r) == 6 and r[5] for r in rows)
    by = {(r[0], r[1]): r for r in rows}
    assert by[("7", "ends and times")][5].startswith("agrees") and "C388 at 44 s" in by[("7", "ends and times")][3]
    assert by[("8", "distinct from Fig. 7's path")][5] == "agrees"


@pytest.mark.parametrize("argv", [["--seeds", "1"], ["--seeds", "x"], ["--figure-seed", "-1"], ["--frobnicate"]])
def test_a_bad_argument_is_one_error_line_and_exit_2(bench, argv, capsys):
    with pytest.raises(SystemExit) as exc:
        bench.parse(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
