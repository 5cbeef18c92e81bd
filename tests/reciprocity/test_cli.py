"""The reciprocity command line."""

import json

import pytest

from reciprocity.cli import main


def test_arenas_lists_builtins(capsys):
    assert main(["arenas"]) == 0
    out = capsys.readouterr().out
    for name in ["paper", "empty", "disk", "maze", "deep_u"]:
        assert name in out


def test_run_writes_summary_json_and_figures(tmp_path, capsys, pixels_near):
    js = tmp_path / "s.json"
    rc = main(["run", "--arena", "empty", "--strategy", "reciprocity", "--seed", "1", "--h", "3",
               "--source", "100,50", "--start", "20,20,90", "--json", str(js),
               "--out", str(tmp_path / "out"), "--quiet", "--set", "max_steps=12"])
    assert rc == 0
    s = json.loads(js.read_text())
    assert s["source"] == [100.0, 50.0] and s["start"][:2] == [20.0, 20.0]
    assert s["params"]["max_steps"] == 12
    png = tmp_path / "out" / "reciprocity_steps.png"
    assert pixels_near(png, (0, 255, 0), 60) > 20 and pixels_near(png, (255, 0, 0), 60) > 20
    assert "reciprocity" in capsys.readouterr().out


@pytest.mark.parametrize("argv, match", [
    (["run", "--arena", "nowhere", "--strategy", "gradient"], "no built-in arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "70"], "--source needs 2"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "500,3"], "outside the arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--start", "a,b"], "comma-separated"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "eps"], "KEY=VALUE"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "colour=3", "--h", "5"],
     "unknown parameter(s) colour for strategy 'reciprocity'; valid: "),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--seed", "-1"], "--seed must be a non-negative"),
    (["run", "--arena", "paper", "--strategy", "spiral"], "unknown strategy 'spiral'; choose one of"),
    (["run", "--scenario", "nowhere", "--strategy", "gradient"], "no built-in scenario or file"),
    (["run", "--strategy", "gradient"], "give exactly one of --arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--platform", "walker"],
     "platform 'walker' does not apply to poisson worlds"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--mismatch", "wall_shift=9"], "wall_shift"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--mismatch", "colour=1"],
     "unknown mismatch option(s) colour"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--agents", "3"], "directs 1 observer"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--h", "0"], "--h must be"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--car", "rho=12"], "--car options need"),
    (["run", "--arena"], "expected one argument"),
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


def test_bad_input_is_refused_before_any_heavy_work(monkeypatch, capsys):
    """An invalid strategy parameter is reported before the arena is meshed."""
    import reciprocity.spaces.mesh as mesh_mod
    def boom(*a, **k):
        raise AssertionError("meshed before validating")
    monkeypatch.setattr(mesh_mod, "cached_mesh", boom)
    assert main(["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "eps=3", "--quiet"]) == 2
    assert "eps must lie strictly between 0 and 1" in capsys.readouterr().err


def test_scenarios_and_strategies_are_listed(capsys):
    assert main(["scenarios"]) == 0
    out = capsys.readouterr().out
    assert "paper" in out and "poisson" in out
    assert main(["strategies"]) == 0
    out = capsys.readouterr().out
    rows = {line.split()[0]: line for line in out.splitlines()[1:]}
    assert {"reciprocity", "gradient", "random-walk"} <= set(rows)
    assert "poisson" in rows["reciprocity"] and "lattice" in rows["random-walk"]


def test_run_by_scenario_with_mismatch(tmp_path):
    js = tmp_path / "s.json"
    rc = main(["run", "--scenario", "empty", "--strategy", "reciprocity", "--h", "4", "--quiet",
               "--mismatch", "strength_factor=1.25", "--json", str(js)])
    assert rc == 0
    s = json.loads(js.read_text())
    assert s["world"] == "poisson" and s["mismatch"]["strength_factor"] == 1.25
    assert s["stop"] in ("converged", "step cap", "no target") and "converged" in s
