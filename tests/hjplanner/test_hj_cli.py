"""The hjplanner command line: round trips and clear error messages (exit code 2, no traceback)."""

import re
import json

import numpy as np
import pytest

from hjplanner import ValueFunction
from hjplanner.cli import main


@pytest.mark.slow
def test_solve_then_path(tmp_path, capsys):
    out = tmp_path / "v.npz"
    assert main(["solve", "--bounds=-1,1,-1,1", "--target", "0,0", "--rho", "0.3", "--h", "0.05",
                 "--ntheta", "32", "--out", str(out)]) == 0
    assert "solved" in capsys.readouterr().out
    vf = ValueFunction.load(out)
    assert vf.grid.nx == 41 and vf.grid.ntheta == 32
    plot = tmp_path / "p.png"
    assert main(["path", "--value", str(out), "--start=-0.7,0.2,10", "--plot", str(plot)]) == 0
    summary = json.loads(capsys.readouterr().out.splitlines()[0])
    assert summary["reached"] and abs(summary["length"] - summary["phi_start"]) < 0.15
    assert summary["phi_start"] == pytest.approx(float(vf(-0.7, 0.2, np.radians(10))))
    lengths = [float(word[1:]) for word in summary["controls"].split()]
    assert sum(lengths) == pytest.approx(summary["length"], abs=0.01)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bank_command_and_cache(tmp_path, monkeypatch, capsys):
    argv = ["bank", "--bounds", "0,1,0,1", "--spacing", "0.5", "--rho", "0.2", "--h", "0.1", "--ntheta", "16",
            "--workers", "1", "--quiet"]
    assert main(argv + ["--cache", str(tmp_path)]) == 0
    assert "bank of 4 targets" in capsys.readouterr().out
    assert len(list(tmp_path.glob("*/*.npz"))) == 4
    monkeypatch.setenv("HJPLANNER_CACHE", str(tmp_path))  # the same cache through the environment
    assert main(argv) == 0
    assert "0 solved" in capsys.readouterr().out
    size = sum(f.stat().st_size for f in tmp_path.glob("*/*"))
    assert main(["cache", "--info"]) == 0
    out = capsys.readouterr().out
    assert "1 bank" in out and f"{size / 1e6:.2f} MB" in out and "rect[0,1]x[0,1]" in out
    assert main(["cache", "--clear", "--cache", str(tmp_path)]) == 0
    assert "freed" in capsys.readouterr().out
    assert list(tmp_path.glob("*/*.npz")) == []


@pytest.mark.parametrize("argv, message", [
    (["solve", "--bounds", "0,1,0,1", "--target", "2,2", "--rho", "0.1", "--out", "v.npz"], "outside the domain"),
    (["solve", "--bounds", "0,1,0,1", "--target", "0.5,0.5", "--rho", "-1", "--out", "v.npz"],
     r"rho must be a number in \(0, 100000\]"),
    (["solve", "--bounds", "0,1,0,1", "--target", "0.5,0.5", "--rho", "0.2", "--h", "0", "--out", "v.npz"],
     r"h must be a number in \(0, 100000\]"),
    (["solve", "--bounds", "0,1,0,1", "--target", "0.5,0.5", "--rho", "0.2", "--ntheta", "4", "--out", "v.npz"],
     "ntheta must be a whole number from 8 to 720"),
    (["solve", "--bounds", "0,1,0", "--target", "0.5,0.5", "--rho", "0.2", "--out", "v.npz"], "--bounds X0,X1,Y0,Y1"),
    (["solve", "--target", "0.5,0.5", "--rho", "0.2", "--out", "v.npz"], "a domain is needed"),
    (["solve", "--bounds", "0,1,0,1", "--target", "a,b", "--rho", "0.2", "--out", "v.npz"], "--target X,Y"),
    (["solve", "--arena", "no-such-arena", "--target", "1,1", "--rho", "10", "--out", "v.npz"],
     "cannot load arena 'no-such-arena'"),
    (["solve", "--bounds", "0,1,0,1", "--rho", "0.2", "--out", "v.npz"], "required: --target"),
    (["path", "--value", "missing.npz", "--start", "1,2,3"], "does not exist"),
    (["frobnicate"], "invalid choice"),
    (["cache", "--info", "--clear"], "not allowed with argument"),
    ([], "a command is needed"),
])
def test_errors_are_messages(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert re.search(message, captured.err) and not captured.out
    assert "Traceback" not in captured.err


def test_path_errors(tmp_path, capsys):
    out = tmp_path / "v.npz"
    assert main(["solve", "--bounds", "0,1,0,1", "--target", "0.5,0.5", "--rho", "0.3", "--h", "0.05", "--ntheta",
                 "16", "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["path", "--value", str(out), "--start", "0.97,0.5,0"]) == 2  # facing the wall, 3 cm away
    assert "cannot reach the target" in capsys.readouterr().err
    assert main(["path", "--value", str(out), "--start", "0.1,0.2"]) == 2
    assert "--start X,Y,DEG" in capsys.readouterr().err
    assert np.isfinite(ValueFunction.load(out)(0.2, 0.2, 0.0))


@pytest.mark.parametrize("command", ["solve", "bank"])
def test_a_plain_arena_file_is_a_domain(command, tmp_path, monkeypatch, capsys):
    """``--arena FILE`` takes the README's arena file, for every subcommand with a domain."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "room.yaml").write_text("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\n"
                                        "obstacles: [[[20, 10], [30, 10], [30, 30], [20, 30]]]\n"
                                        "source: [50, 20]\nstrength: 850\nstart: [5, 5, 0]\n")
    common = ["--arena", "room.yaml", "--rho", "5", "--h", "2", "--ntheta", "16"]
    if command == "solve":
        argv = ["solve", *common, "--target", "50,20", "--out", "v.npz"]
    else:
        argv = ["bank", *common, "--spacing", "30", "--cache", "cache", "--workers", "1", "--quiet"]
    assert main(argv) == 0, capsys.readouterr().err
    assert (tmp_path / ("v.npz" if command == "solve" else "cache")).exists()
