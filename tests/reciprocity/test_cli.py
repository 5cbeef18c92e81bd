"""The reciprocity command line."""

import json
from pathlib import Path

import pytest

import arenas

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
    out = capsys.readouterr().out.splitlines()
    assert "contacts" in out[0].split() and "hits" not in out[0].split()
    assert out[-2] == f"summary written to {js}"
    assert out[-1].startswith("success: ") and ("success: yes" in out[-1]) == s["success"]


def test_figures_are_drawn_from_the_episode_record(tmp_path):
    from reciprocity.api import run
    from reciprocity.viz.episode import episode_figures
    kw = dict(seed=1, params={"h": 4.0, "max_steps": 3})
    assert run("empty", "reciprocity", **kw).belief == {}          # kept only when asked for
    episode = run("empty", "reciprocity", figures=True, **kw)
    assert {"imaging", "steps", "eps", "within_reach"} <= set(episode.belief)
    assert {"field", "true_arena"} <= set(episode.truth)
    assert "trace" in json.loads(episode.to_json()) and "truth" not in json.loads(episode.to_json())
    arena = arenas.load("empty").with_scenario(start=episode.summary["start"])
    assert [name for name, _ in episode_figures(episode, arena)] == ["steps"]
    gradient = run("empty", "gradient", figures=True, **{**kw, "params": {"h": 4.0}})
    assert [name for name, _ in episode_figures(gradient, arena)] == ["path"]


@pytest.mark.parametrize("scenario, strategy", [("song-100", "free-energy"), ("farrell", "hmm")])
def test_a_plume_or_filament_run_draws_its_search_from_the_record(tmp_path, scenario, strategy):
    import reciprocity
    builtin = Path(reciprocity.__file__).parent / "data" / "scenarios" / f"{scenario}.yaml"
    (tmp_path / "short.yaml").write_text(builtin.read_text().replace("max_steps:", "max_steps: 20  #"))
    out = tmp_path / "out"
    cheap = ["--set", "particles=100"] if strategy == "free-energy" else []
    assert main(["run", "--scenario", str(tmp_path / "short.yaml"), "--strategy", strategy, "--quiet", *cheap,
                 "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == [f"{strategy}_episode.json", f"{strategy}_walker_search.png"]


def test_a_strategy_that_records_nothing_gets_no_figures(tmp_path):
    assert main(["run", "--arena", "empty", "--strategy", "random-walk", "--h", "4", "--quiet",
                 "--set", "n_steps=2", "--out", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["random-walk_episode.json"]


def _summary(**over) -> dict:
    s = dict(world="poisson", success=False, converged=False, stop="step cap",
             stop_reason="step cap: max_steps = 30 measurements", error=0.5)
    return {**s, **over}


@pytest.mark.parametrize("summary, line", [
    (_summary(), "success: no — step cap reached (max_steps = 30 measurements)"),
    (_summary(stop="gave up", stop_reason="gave up"), "success: no — gave up"),
    (_summary(converged=True, stop="converged", stop_reason="converged: map mass 0.31", error=5.94,
              world="filament"),
     "success: no — converged (map mass 0.31), error 5.94 > success radius 5"),
    (_summary(converged=True, success=True, stop="converged", stop_reason="converged: region small", error=1.04),
     "success: yes — converged (region small), error 1.04 cm <= success radius 5 cm"),
    (_summary(converged=True, success=True, stop="found", stop_reason="found: observer 0 reached the source",
              world="plume"),
     "success: yes — observer 0 reached the source"),
    (_summary(converged=True, stop="found", stop_reason="found: observer 0 reached the source", world="lattice",
              self_localised=False),
     "success: no — observer 0 reached the source, but the searcher's own position was not localised"),
    (_summary(converged=True, stop="converged", stop_reason="converged", errors=[1.0, None],
              n_sources_estimated=1),
     "success: no — converged, 1 sources found of 2, worst error 1.00 cm (success radius 5 cm)"),
])
def test_the_last_line_says_whether_the_run_succeeded_and_why_it_stopped(summary, line):
    from reciprocity.cli import _verdict
    assert _verdict(summary, 5.0) == line


def test_a_run_that_reaches_its_step_cap_says_so(capsys):
    assert main(["run", "--scenario", "ristic-lattice", "--strategy", "random-walk", "--set", "n_steps=3",
                 "--quiet"]) == 0
    last = capsys.readouterr().out.splitlines()[-1]
    assert last.startswith("success: no — step cap reached ("), last


@pytest.mark.parametrize("argv, match", [
    (["run", "--arena", "nowhere", "--strategy", "gradient"], "no built-in arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "70"], "--source needs 2"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--source", "500,3"], "outside the arena"),
    (["run", "--arena", "paper", "--strategy", "gradient", "--start", "a,b"], "comma-separated"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "eps"], "KEY=VALUE"),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--set", "colour=3", "--h", "5"],
     "unknown parameter(s) colour for strategy 'reciprocity'; valid: "),
    (["run", "--arena", "paper", "--strategy", "reciprocity", "--seed", "-1"], "--seed must be a whole number from 0"),
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
    assert "eps must be a number in (0, 1); got 3" in capsys.readouterr().err


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


#: Safety net against a hung subprocess (seconds), never an assertion: a listing takes well under one.
HANG_S = 600

README_ARENA = """\
boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]
obstacles:
  - [[40, 50], [46, 50], [46, 96], [94, 96], [94, 76], [100, 76], [100, 102], [40, 102]]
source: [70.21, 70.21]
strength: 850
start: [128, 12, 135]
"""


@pytest.mark.parametrize("flag", ["--arena", "--scenario"])
def test_a_plain_arena_file_runs(flag, tmp_path, monkeypatch, capsys):
    """The README's arena file (no ``world:`` key) is a poisson scenario, by either flag;
    its source and start are the episode's."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_arena.yaml").write_text(README_ARENA)
    rc = main(["run", flag, "my_arena.yaml", "--strategy", "reciprocity", "--h", "3", "--quiet",
               "--set", "max_steps=3", "--json", "s.json"])
    assert rc == 0, capsys.readouterr().err
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["arena"] == "my_arena" and s["world"] == "poisson"
    assert s["source"] == [70.21, 70.21]
    assert s["start"][:2] == [128.0, 12.0] and s["start"][2] == pytest.approx(3 * 3.141592653589793 / 4)


def test_arena_flag_refuses_a_scenario_of_another_world(tmp_path, capsys):
    from importlib import resources
    song = tmp_path / "song.yaml"
    song.write_text((resources.files("reciprocity") / "data" / "scenarios" / "song-100.yaml").read_text())
    assert main(["run", "--arena", str(song), "--strategy", "infotaxis", "--quiet"]) == 2
    assert "give it with --scenario" in capsys.readouterr().err
    assert main(["run", "--arena", "song-100", "--strategy", "infotaxis", "--quiet"]) == 2
    assert "no built-in arena or file named 'song-100'" in capsys.readouterr().err


def test_comma_joined_options_equal_repeated_flags():
    from reciprocity.cli import _params
    assert _params(["strength_factor=1.2,wall_shift=0.3"], "--mismatch") == \
        _params(["strength_factor=1.2", "wall_shift=0.3"], "--mismatch") == \
        {"strength_factor": 1.2, "wall_shift": 0.3}
    assert _params(["start=[1, 2]"]) == {"start": [1, 2]}
    assert _params(["target=1,2"]) == {"target": "1,2"}  # a value with a comma stays whole


@pytest.mark.parametrize("items, match", [
    (["a=1", "a=2"], "given twice"),
    (["=3"], "with a key"),
    (["a={b: 1, b: 2}"], "duplicate key"),
])
def test_bad_key_value_flags(items, match):
    from reciprocity.cli import _params
    from reciprocity.errors import ReciprocityError
    with pytest.raises(ReciprocityError, match=match):
        _params(items)


_BAD_OUT = [(["--out", "{tmp}/afile"], "is a file; give a folder"),
            (["--out", "/proc/forbidden"], "cannot write into")]
_BAD_JSON = [(["--json", "{tmp}"], "is a folder; give a file name"),
             (["--json", "{tmp}/afile/x.json"], "is a file, so no folder can be made there")]


@pytest.mark.parametrize("command, extra, match", [("run", *c) for c in _BAD_OUT + _BAD_JSON]
                         + [("demo", *c) for c in _BAD_OUT])
def test_outputs_are_checked_before_any_work(command, extra, match, tmp_path, monkeypatch, capsys):
    """A bad output path is refused before the episode runs, and nothing is written."""
    monkeypatch.setattr("reciprocity.api.execute", lambda *a, **k: (_ for _ in ()).throw(AssertionError("ran")))
    (tmp_path / "afile").write_text("x")
    before = sorted(tmp_path.rglob("*"))
    argv = [a.format(tmp=tmp_path) for a in extra]
    if command == "run":
        argv = ["run", "--arena", "paper", "--strategy", "reciprocity"] + argv
    else:
        argv = ["demo", "--platform", "point"] + argv
    assert main(argv + ["--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: ") and match in err
    assert sorted(tmp_path.rglob("*")) == before


def test_json_folder_is_created_when_missing(tmp_path, capsys):
    js = tmp_path / "new" / "deeper" / "s.json"
    assert main(["run", "--arena", "empty", "--strategy", "reciprocity", "--h", "4", "--quiet",
                 "--set", "max_steps=2", "--json", str(js)]) == 0
    assert json.loads(js.read_text())["strategy"] == "reciprocity"


def test_the_demo_takes_a_plain_arena_file(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_arena.yaml").write_text(README_ARENA)
    rc = main(["demo", "--arena", "my_arena.yaml", "--platform", "point", "--h", "4", "--quiet", "--out", "d"])
    out = capsys.readouterr()
    assert rc == 0, out.err
    assert "arena 'my_arena'" in out.out and "paper's own testbed" not in out.out
    rows = json.loads((tmp_path / "d" / "summary.json").read_text())
    assert [r["strategy"] for r in rows] == ["reciprocity", "gradient"]
    assert all(r["source"] == [70.21, 70.21] for r in rows)


def test_the_demo_says_what_it_does_before_and_while_it_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["demo", "--arena", "empty", "--platform", "point", "--h", "5", "--out", "d"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("demo: the point observer searches arena 'empty' with reciprocity and then gradient")
    assert lines[1].startswith("  reciprocity: done in ") and lines[2].startswith("  gradient: done in ")
    assert lines[-3].startswith("reciprocity: success: ") and lines[-2].startswith("gradient: success: ")


@pytest.mark.parametrize("command", ["scenarios", "strategies", "arenas"])
def test_a_reader_that_leaves_early_gets_no_traceback(command):
    """`reciprocity scenarios | head -2`: the listing meets a closed pipe and exits quietly."""
    import os
    import subprocess
    import sys
    r, w = os.pipe()
    os.close(r)                                   # the reader is already gone
    try:
        done = subprocess.run([sys.executable, "-c", f"import sys, reciprocity.cli as c; sys.exit(c.main([{command!r}]))"],
                              stdout=w, stderr=subprocess.PIPE, text=True, timeout=HANG_S)
    finally:
        os.close(w)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr


def test_a_generated_arena_runs_from_the_command_line_and_a_scenario_file(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert main(["run", "--arena", "generate:maze:4:cols=3", "--strategy", "reciprocity", "--h", "5",
                 "--set", "max_steps=2", "--quiet", "--json", str(out)]) == 0
    summary = json.loads(out.read_text())
    assert summary["arena"] == "maze-4-cols3"
    assert summary["source"] == arenas.generate("maze", 4, cols=3).source.tolist()
    scenario = tmp_path / "gen.yaml"
    scenario.write_text("world: poisson\narena: {generate: maze, seed: 4, cols: 3}\nmax_steps: 2\n")
    assert main(["run", "--scenario", str(scenario), "--strategy", "reciprocity", "--h", "5", "--quiet",
                 "--json", str(out)]) == 0
    assert json.loads(out.read_text())["source"] == summary["source"]
