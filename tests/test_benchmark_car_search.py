"""benchmarks/car_search.py: its draws state how their sources were drawn, its options and its table."""

import csv
from contextlib import nullcontext
import importlib.util
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "car_search.py"


@pytest.fixture(scope="module")
def bench():
    sys.path.insert(0, str(SCRIPT.parent))          # its `resumable` helper
    spec = importlib.util.spec_from_file_location("car_search", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_paper_draw_is_the_campaign_s_and_states_its_source_clearance(bench):
    from reciprocity.campaign.spec import SOURCE_CLEARANCE
    sc = bench.scenario_of("paper", 0)
    assert sc.params["source_clearance"] == SOURCE_CLEARANCE
    assert sc.arena.wall_distance([sc.params["source"]])[0] >= SOURCE_CLEARANCE


@pytest.mark.parametrize("argv", [["--set", "source_clearance"], ["--set", "=3"], ["--only", "some"],
                                  ["--arenas", "paper", "--world", "map=sometimes"],
                                  ["--arenas", "paper", "--world", "colour=3"]])
def test_bad_options_exit_2(bench, argv, capsys):
    # argparse refuses a bad choice itself (SystemExit 2); the script refuses a bad --set
    with pytest.raises(SystemExit, match="2") if "--only" in argv else nullcontext():
        assert bench.main(argv) == 2
    assert "error:" in capsys.readouterr().err


def test_the_table_counts_unreachable_stops_within_ten_readings(bench, tmp_path):
    rows = [dict(arena="paper", draw=0, success=False, source_reachable=False, stop="unreachable", error=90,
                 n_measurements=7, collisions=0, sim_time_s=100, wall_time_s=10, speed=10, mass_out_of_reach=1),
            dict(arena="paper", draw=1, success=False, source_reachable=False, stop="unreachable", error=80,
                 n_measurements=12, collisions=0, sim_time_s=100, wall_time_s=10, speed=10, mass_out_of_reach=1),
            dict(arena="paper", draw=2, success=True, source_reachable=True, stop="converged", error=1,
                 n_measurements=4, collisions=1, sim_time_s=50, wall_time_s=10, speed=5, mass_out_of_reach=0)]
    path = tmp_path / "runs.csv"
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, bench.FIELDS)
        w.writeheader()
        w.writerows(rows)
    table = bench.table([path])
    assert "| paper | 3 | 1/1 = 100% [21%, 100%] | 4 | 2/2 (1) | 1 | 8.3x / 5.0x |" in table

