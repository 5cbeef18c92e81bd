"""The Song et al. (2019) scripts of benchmarks/ (song_fig5, song_fig67, song_circling,
song_temperature, song_gap): tiny runs, their resumption, their refusal of bad arguments
and the commands their documents show."""

import csv
import importlib.util
import re
import shlex
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"


def _load(name):
    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))              # their `arguments`, `resumable` helpers
    if name not in sys.modules:                     # registered: a worker pool pickles its functions
        spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
    return sys.modules[name]


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def test_fig5_writes_one_row_per_step_and_the_figure(tmp_path, capsys):
    rows = _load("song_fig5").main(["--seeds", "1", "--max-steps", "25", "--out", str(tmp_path)])
    assert (tmp_path / "fig5.png").stat().st_size > 0
    written = _rows(tmp_path / "fig5.csv")
    assert len(written) == len(rows) == 2 * 25                     # two strategies, 25 steps each
    assert {r["strategy"] for r in written} == {"infotaxis", "free-energy"}
    first = [r for r in rows if r["strategy"] == "infotaxis"][0]
    # the paper's Fig. 5 start (200, -100), source (-250, 0): one step from the start
    assert first["sensor_distance"] == pytest.approx(np.hypot(450, 100), abs=1.5)
    assert all(r["spread"] > 0 for r in rows)
    assert "free-energy: found 0/1" in capsys.readouterr().out


def test_fig67_runs_both_temperatures_and_draws_seed_zero(tmp_path):
    bench = _load("song_fig67")
    rows = bench.main(["--seeds", "1", "--max-steps", "20", "--last", "10", "--out", str(tmp_path)])
    assert (tmp_path / "fig67.png").stat().st_size > 0
    assert [r["temperature"] for r in rows] == list(bench.TEMPERATURES)
    assert rows[0]["decided_by_T"] == 0.0                            # T = 0 never differs from itself
    assert all(r["steps"] == 20 and not r["success"] for r in rows)
    assert len(_rows(tmp_path / "fig67.csv")) == 2


def test_circling_measures_a_walker_at_the_turn_limit():
    bench = _load("song_circling")
    # a unit step turning 3 degrees each time: the circle of radius 1 / (2 sin 1.5 deg)
    turn = np.radians(3.0)
    radius = 1 / (2 * np.sin(turn / 2))
    heading = np.arange(400) * turn
    centre = np.array([10.0, 0.0])
    xy = centre + radius * np.column_stack([np.sin(heading), -np.cos(heading)])
    trace = [{"pose": [x, y, h % (2 * np.pi)], "estimate": centre} for (x, y), h in zip(xy, heading)]
    m = bench.circling(trace, source=[0.0, 0.0], max_turn_deg=3.0, last=240, radius=25.0)
    assert m["at_max_turn"] == 1.0 and m["near_estimate"] == 1.0
    assert m["orbit_radius"] == pytest.approx(radius, rel=1e-3) and radius == pytest.approx(19.1, abs=0.05)
    assert m["orbit_to_source"] == pytest.approx(10.0, abs=0.5)
    assert m["closest_approach"] == pytest.approx(radius - 10.0, abs=0.1)


def _count_runs(monkeypatch, bench):
    """Count the calls of `bench.run` (one per run) from now on."""
    calls = []
    real = bench.run

    def counted(*args, **kwargs):
        calls.append(args[:2])
        return real(*args, **kwargs)
    monkeypatch.setattr(bench, "run", counted)
    return calls


def test_fig5_resumes_from_its_csv(tmp_path, monkeypatch, capsys):
    bench = _load("song_fig5")
    argv = ["--max-steps", "10", "--out", str(tmp_path)]
    calls = _count_runs(monkeypatch, bench)
    first = bench.main(["--seeds", "1", *argv])
    assert sorted(calls) == [("free-energy", 0), ("infotaxis", 0)]
    again = bench.main(["--seeds", "1", *argv])                    # all written: nothing runs
    assert len(calls) == 2 and again == first
    more = bench.main(["--seeds", "2", *argv])                     # only seed 1 runs
    assert sorted(calls[2:]) == [("free-energy", 1), ("infotaxis", 1)]
    assert len(more) == len(_rows(tmp_path / "fig5.csv")) == 4 * 10
    assert more[:len(first)] == first
    assert "infotaxis: found 0/2" in capsys.readouterr().out


def test_fig67_resumes_and_draws_seed_zero_from_its_record(tmp_path, monkeypatch):
    bench = _load("song_fig67")
    argv = ["--max-steps", "10", "--last", "5", "--temperatures", "0", "--out", str(tmp_path)]
    calls = _count_runs(monkeypatch, bench)
    bench.main(["--seeds", "1", *argv])
    assert (tmp_path / "fig67_seed0_T0.json").exists()
    (tmp_path / "fig67.png").unlink()
    rows = bench.main(["--seeds", "2", *argv])
    assert calls == [(0.0, 0), (0.0, 1)]                           # seed 0 is not run again ...
    assert (tmp_path / "fig67.png").stat().st_size > 0             # ... yet drawn, from its record
    assert [(r["temperature"], r["seed"]) for r in rows] == [(0.0, 0), (0.0, 1)]


def test_circling_resumes_from_its_csv(tmp_path, monkeypatch):
    bench = _load("song_circling")
    argv = ["--strategies", "infotaxis", "--max-steps", "10", "--last", "5", "--out", str(tmp_path)]
    calls = _count_runs(monkeypatch, bench)
    first = bench.main(["--seeds", "1", *argv])
    assert first[0]["steps"] == 10 and first[0]["side"] == 100
    rows = bench.main(["--seeds", "2", *argv])
    assert calls == [("infotaxis", 100), ("infotaxis", 100)]       # seed 0, then seed 1 only
    assert [r["seed"] for r in rows] == [0, 1] and rows[0] == first[0]


def test_a_time_budget_stops_before_the_next_run(tmp_path, monkeypatch, capsys):
    bench = _load("song_circling")
    monkeypatch.setattr(sys.modules["resumable"], "deadline", lambda minutes: lambda: True)  # spent at once
    rows = bench.main(["--seeds", "3", "--strategies", "infotaxis", "--max-steps", "5", "--last", "5",
                       "--minutes", "1", "--out", str(tmp_path)])
    assert len(rows) == len(_rows(tmp_path / "circling.csv")) == 1
    assert "2 runs left" in capsys.readouterr().out


def test_temperature_writes_each_step_and_resumes(tmp_path, capsys):
    bench = _load("song_temperature")
    argv = ["--sides", "100", "--workers", "1", "--out", str(tmp_path)]
    first = bench.main(["--seeds", "1", *argv])
    assert first and [r["step"] for r in first] == list(range(1, first[0]["steps"] + 1))
    assert {(r["alpha"], r["area_exponent"], r["seed"]) for r in first} == {(0.01, 0.0, 0)}
    assert bench.main(["--seeds", "1", *argv]) == first            # nothing run again
    assert len(_rows(tmp_path / "temperature.csv")) == len(first)
    assert "| 100² | 1/1 |" in capsys.readouterr().out


#: A bad argument of each script: (script, argv, the option the error line names).
BAD = [
    ("song_fig5", ["--seeds", "0"], "--seeds"),
    ("song_fig5", ["--seeds", "two"], "--seeds"),
    ("song_fig5", ["--max-steps", "-5"], "--max-steps"),
    ("song_fig5", ["--max-steps", "10000000"], "--max-steps"),
    ("song_fig5", ["--minutes", "0"], "--minutes"),
    ("song_fig5", ["--minutes", "inf"], "--minutes"),
    ("song_fig67", ["--temperatures", "0,hot"], "--temperatures"),
    ("song_fig67", ["--temperatures", "-1"], "--temperatures"),
    ("song_fig67", ["--radius", "0"], "--radius"),
    ("song_fig67", ["--last", "0"], "--last"),
    ("song_circling", ["--sides", "100,120"], "--sides"),
    ("song_circling", ["--strategies", "infotaxis,reciprocity"], "--strategies"),
    ("song_circling", ["--radius", "nan"], "--radius"),
    ("song_temperature", ["--sides", "99"], "--sides"),
    ("song_temperature", ["--workers", "0"], "--workers"),
    ("song_temperature", ["--alpha", "-0.1"], "--alpha"),
    ("song_gap", ["--variant", "base", "--side", "120"], "--side"),
    ("song_gap", ["--variant", "no_such_variant"], "--variant"),
    ("song_gap", ["--variant", "base+rate=[1,"], "--variant"),
    ("song_gap", ["--variant", "base+colour=1"], "--variant"),
    ("song_gap", ["--variant", "base", "--baseline", "basis"], "--baseline"),
    ("song_gap", ["--variant", "base", "--strategy", "reciprocity"], "--strategy"),
    ("song_gap", ["--variant", "base", "--seeds", "0"], "--seeds"),
    ("song_gap", ["--variant", "base", "--first-seed", "-1"], "--first-seed"),
]


def _refused(name, argv, capsys) -> str:
    with pytest.raises(SystemExit) as exc:
        _load(name).main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
    return err


@pytest.mark.parametrize("name, argv, option", BAD, ids=lambda x: x if isinstance(x, str) else " ".join(x))
def test_a_bad_argument_exits_2_with_one_error_line(name, argv, option, tmp_path, capsys):
    out = tmp_path / "new" / "out"
    err = _refused(name, [*argv, "--out", str(out)], capsys)
    assert option in err and argv[-1] in err
    assert not (tmp_path / "new").exists()                       # refused before any work


@pytest.mark.parametrize("name", ["song_fig5", "song_fig67", "song_circling", "song_temperature", "song_gap"])
def test_an_output_folder_that_is_a_file_is_refused(name, tmp_path, capsys):
    (tmp_path / "taken").write_text("")
    argv = ["--variant", "base"] if name == "song_gap" else []
    err = _refused(name, [*argv, "--out", str(tmp_path / "taken")], capsys)
    assert "--out" in err and "is a file" in err


@pytest.mark.parametrize("name, csv_name", [("song_fig5", "fig5.csv"), ("song_fig67", "fig67.csv"),
                                            ("song_circling", "circling.csv"),
                                            ("song_temperature", "temperature.csv")])
def test_a_csv_that_cannot_be_resumed_is_refused(name, csv_name, tmp_path, capsys):
    bench = _load(name)
    header = ",".join(bench.COLUMNS) + "\r\n"
    cases = {
        "is a symbolic link": lambda p: p.symlink_to(tmp_path / "elsewhere.csv"),
        "has the columns": lambda p: p.write_text("a,b\r\n1,2\r\n"),
        "cut-off row": lambda p: p.write_text(header + "infotaxis,1"),
    }
    for i, (says, make) in enumerate(cases.items()):
        out = tmp_path / str(i)
        out.mkdir()
        make(out / csv_name)
        assert says in _refused(name, ["--out", str(out)], capsys)
    assert not (tmp_path / "elsewhere.csv").exists()


def _documented(script: str) -> list[list[str]]:
    """The argument lists of every command of `script` the documents show."""
    found = []
    for doc in ("docs/papers/song2019.md", "benchmarks/song_figures.md", "benchmarks/song_gap.md"):
        text = (ROOT / doc).read_text().replace("\\\n", " ")
        found += re.findall(rf"`benchmarks/{script}\.py([^`]*)`", text)                  # inline
        found += re.findall(rf"^ +(?:nice -n 10 )?python benchmarks/{script}\.py( --.*)$", text, re.M)
        if script == "song_gap":                     # its P() shorthand; a bare name is a mention
            found = [a for a in found if a.strip()] + re.findall(r"^ +\$P (.*)$", text, re.M)
    return [shlex.split(args.replace("\n", " ")) for args in found]


@pytest.mark.parametrize("script, at_least", [("song_fig5", 2), ("song_fig67", 2), ("song_circling", 1),
                                              ("song_temperature", 2), ("song_gap", 12)])
def test_the_documented_commands_are_accepted(script, at_least, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    commands = _documented(script)
    assert len(commands) >= at_least
    for argv in commands:
        _load(script).parse(argv)
    assert list(tmp_path.iterdir()) == []                          # parsing writes nothing
