"""The reciprocity command line."""

import json

import pytest

from reciprocity.cli import main


def test_arenas_lists_builtins(capsys):
    assert main(["arenas"]) == 0
    out = capsys.readouterr().out
    for name in ["paper", "empty", "disk", "maze", "deep_u"]:
        assert name in out


def test_run_writes_summary_json_and_figures(tmp_path, capsys):
    js = tmp_path / "s.json"
    rc = main(["run", "--arena", "empty", "--strategy", "reciprocity", "--seed", "1", "--h", "3",
               "--source", "100,50", "--start", "20,20,90", "--json", str(js),
               "--out", str(tmp_path / "out"), "--quiet", "--set", "max_steps=12"])
    assert rc == 0
    s = json.loads(js.read_text())
    assert s["source"] == [100.0, 50.0] and s["start"][:2] == [20.0, 20.0]
    assert s["params"]["max_steps"] == 12
    assert (tmp_path / "out" / "reciprocity_steps.png").stat().st_size > 10_000
    assert "reciprocity" in capsys.readouterr().out


@pytest.mark.parametrize("argv, match", [
    (["run", "--arena", "nowhere", "--strategy", "gradient"], "no built-in arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "70"], "--source needs 2"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "500,3"], "outside the arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--start", "a,b"], "comma-separated"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "eps"], "KEY=VALUE"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "colour=3", "--h", "5"], "bad parameter"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--platform", "car", "--car", "wheels=6"],
     "unknown car option"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--platform", "car", "--car", "planner=magic"],
     "planner must be one of"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--platform", "car", "--car", "rho=-3"], "rho"),
])
def test_bad_input_exits_2_with_a_message(argv, match, capsys):
    assert main(argv + ["--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and match in err and "Traceback" not in err
