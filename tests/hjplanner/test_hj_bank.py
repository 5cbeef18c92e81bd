"""ValueFunctionBank (lattice, disk cache, processes) and OnDemandPlanner (LRU)."""

import subprocess
import sys

import numpy as np
import pytest

import arenas
from hjplanner import (OnDemandPlanner, PlanningError, ValueFunctionBank, cache_info, clear_cache, default_cache_dir,
                       lattice_targets, solve)

#: A safety net against a hung subprocess, never the assertion (the work is bounded; minutes).
HANG_S = 300

SMALL = dict(rho=0.2, h=0.1, ntheta=16)


def test_lattice_skips_obstacles(u_room):
    targets = lattice_targets(u_room, 0.5, h=0.05, clearance=0.05)
    assert targets.ndim == 2 and targets.shape[1] == 2
    # centred lattice of 8 x 6 points 0.5 apart, minus those in the inflated U (arena geometry as the oracle)
    lattice = np.stack(np.meshgrid(0.25 + 0.5 * np.arange(8), 0.25 + 0.5 * np.arange(6), indexing="ij"), -1)
    expected = lattice.reshape(-1, 2)[u_room.contains(lattice.reshape(-1, 2), 0.05 + 0.05 * np.sqrt(2))]
    assert {tuple(t) for t in np.round(expected, 9)} <= {tuple(t) for t in np.round(targets, 9)}
    assert u_room.contains(targets, 0.05).all()
    assert len(targets) < 48
    with pytest.raises(PlanningError, match="spacing must be a positive"):
        lattice_targets(u_room, 0.0)


def test_bank_builds_caches_and_finds_nearest(tmp_path, u_room):
    bank = ValueFunctionBank(u_room, 1.0, clearance=0.05, cache_dir=tmp_path, **SMALL)
    assert len(bank) == len(bank.missing()) > 4
    bank.build(workers=1, progress=False)
    assert bank.missing() == []
    files = sorted(bank.directory.glob("*.npz"))
    assert len(files) == len(bank) and bank.directory.parent == tmp_path
    vf = bank.nearest((0.45, 0.55))
    assert np.allclose(vf.target, bank.targets[bank.nearest_index((0.45, 0.55))])
    assert np.hypot(*(vf.target - (0.45, 0.55))) <= 0.5 * np.sqrt(2) + 1e-9
    assert bank.nearest((0.45, 0.55)) is vf  # in-memory LRU
    # same geometry and parameters: the cache is reused
    again = ValueFunctionBank(u_room, 1.0, clearance=0.05, cache_dir=tmp_path, **SMALL)
    assert again.key == bank.key and again.missing() == []
    # any change of geometry or parameters changes the key
    moved = arenas.Arena.from_polygons(u_room.boundary, [u_room.obstacles[0] + 0.01], name="u-room")
    assert ValueFunctionBank(moved, 1.0, clearance=0.05, cache_dir=tmp_path, **SMALL).key != bank.key
    assert ValueFunctionBank(u_room, 1.0, clearance=0.05, cache_dir=tmp_path, **dict(SMALL, rho=0.21)).key != bank.key
    with pytest.raises(PlanningError):
        bank.nearest((1.0,))


def test_bank_in_parallel_processes(tmp_path):
    bank = ValueFunctionBank(((0, 1), (0, 1)), 0.5, cache_dir=tmp_path, **SMALL)
    assert len(bank) == 4
    bank.build(workers=2, progress=False)
    assert bank.missing() == []
    serial = ValueFunctionBank(((0, 1), (0, 1)), 0.5, cache_dir=tmp_path / "serial", **SMALL)
    serial.build(workers=1, progress=False)
    a, b = bank.nearest((0.2, 0.2)), serial.nearest((0.2, 0.2))
    direct = solve(((0, 1), (0, 1)), tuple(a.target), **SMALL)
    finite = np.isfinite(direct.values)
    for vf in (a, b):
        assert np.array_equal(finite, np.isfinite(vf.values))
        assert np.abs(vf.values[finite] - direct.values[finite]).max() < 1e-3


def test_cache_directory_info_and_clear(tmp_path, monkeypatch):
    monkeypatch.setenv("HJPLANNER_CACHE", str(tmp_path / "env-cache"))
    assert default_cache_dir() == tmp_path / "env-cache"
    bank = ValueFunctionBank(((0, 1), (0, 1)), 0.5, **SMALL)
    assert bank.directory.parent == tmp_path / "env-cache"
    bank.build(workers=1, progress=False)
    legacy = tmp_path / "env-cache" / ("0123456789abcdef0123" + "_0000_0.5_0.5.npz")
    legacy.write_bytes(b"x" * 100)
    (tmp_path / "env-cache" / "notes.txt").write_text("not ours")
    info = cache_info()
    banks = [entry for entry in info if entry["key"] == bank.key]
    assert len(banks) == 1 and banks[0]["files"] == banks[0]["targets"] == 4
    assert banks[0]["params"]["h"] == 0.1 and banks[0]["domain"] == "rect[0,1]x[0,1]"
    expected = sum(f.stat().st_size for f in bank.directory.iterdir())
    assert banks[0]["bytes"] == expected
    assert [entry["bytes"] for entry in info if entry["key"] == "legacy"] == [100]
    assert clear_cache() == expected + 100
    assert cache_info() == [] and not bank.directory.exists() and not legacy.exists()
    assert (tmp_path / "env-cache" / "notes.txt").exists()  # only hjplanner's own files go


def test_on_demand_planner_lru():
    planner = OnDemandPlanner(((-1, 1), (-1, 1)), maxsize=2, **SMALL)
    a = planner.get((0.0, 0.0))
    assert planner.get((0.001, 0.0)) is a  # within h/10: same entry
    planner.get((0.5, 0.5))
    planner.get((-0.5, 0.5))  # evicts (0, 0)
    assert planner.get((0.0, 0.0)) is not a
    assert planner.hits == 1 and planner.misses == 4
    with pytest.raises(PlanningError):
        planner.get((5.0, 5.0))


def test_on_demand_window(paper):
    """A window solve is an upper bound of the whole-map φ, equal to it (within the sweeps'
    stopping tolerance) where the optimal path keeps inside, and cheaper; a window covering
    most of the grid is the whole grid."""
    planner = OnDemandPlanner(paper, rho=15.0, h=3.0, ntheta=24, clearance=4.0, reverse=True, maxsize=8)
    target, car = (70.0, 30.0), (40.0, 40.0)
    full = planner.get(target)
    win = planner.get(target, near=car, margin=30.0)
    x0, x1, y0, y1 = win.meta["window"]
    assert (x0, y0) == (9.0, 0.0) and x1 < 110 and y1 < 80
    assert win.values.size < 0.5 * full.values.size
    rng = np.random.default_rng(0)
    x, y, th = rng.uniform(x0, x1, 5000), rng.uniform(y0, y1, 5000), rng.uniform(0, 2 * np.pi, 5000)
    a, b = full(x, y, th), win(x, y, th)
    tol = 0.05 * 3.0 * full.meta["sweeps"]          # sweep_tol * h per sweep, at most
    assert not (np.isfinite(b) & ~np.isfinite(a)).any()
    assert (b[np.isfinite(b)] >= a[np.isfinite(b)] - tol).all()
    assert abs(float(win(*car, 0.3)) - float(full(*car, 0.3))) < tol
    assert planner.get(target, near=(70.0, 130.0), margin=70.0) is full   # all of the grid: the whole
    assert "window" not in full.meta
    with pytest.raises(PlanningError, match="near"):
        planner.get(target, near=(np.nan, 1.0), margin=30.0)
    with pytest.raises(PlanningError, match="margin"):
        planner.get(target, near=car, margin=-1.0)


def test_readme_bank_command_is_the_car_platforms_bank(tmp_path, paper):
    """`hjplanner bank` as in the README and the car platform's planner=bank find the same folder."""
    from hjplanner.cli import _domain, build_parser
    args = build_parser().parse_args(["bank", "--arena", "paper", "--spacing", "12.7", "--rho", "15", "--h", "1.5",
                                      "--ntheta", "48", "--clearance", "4", "--reverse"])
    from_cli = ValueFunctionBank(_domain(args), args.spacing, rho=args.rho, h=args.h, ntheta=args.ntheta,
                                 clearance=args.clearance, reverse=args.reverse, cache_dir=tmp_path)
    # reciprocity.platforms.car: DrivingOptions defaults, arenas.CarSpec.rho, the arena without its scenario
    from_car = ValueFunctionBank(paper, 12.7, cache_dir=tmp_path, rho=15.0, h=1.5, ntheta=48, clearance=4.0,
                                 reverse=True)
    assert from_cli.directory == from_car.directory
    np.testing.assert_array_equal(from_cli.targets, from_car.targets)


UNGUARDED = """
import arenas
from hjplanner import ValueFunctionBank

bank = ValueFunctionBank(arenas.load("paper"), 40.0, rho=15, h=3.0, ntheta=16, clearance=4, cache_dir={cache!r})
bank.build(workers=2, progress=False)
print("built", len(bank.missing()))
"""


def test_bank_from_an_unguarded_script_is_built_here_not_hung(tmp_path):
    """A script that builds a bank without ``if __name__ == "__main__":`` makes every spawned
    worker fail; the build then runs in the calling process instead of waiting for ever (it
    used to block on the dead worker's start-up pipe)."""
    script = tmp_path / "unguarded.py"
    script.write_text(UNGUARDED.format(cache=str(tmp_path / "cache")))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=HANG_S,
                          cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.splitlines()[-1] == "built 0"
    assert "could not start" in done.stderr
    assert not list((tmp_path / "cache").rglob("*.workspace"))  # the scratch file is removed
