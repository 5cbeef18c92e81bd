"""ValueFunctionBank (lattice, disk cache, processes) and OnDemandPlanner (LRU)."""

import types

import numpy as np
import pytest

from hjplanner import OnDemandPlanner, PlanningError, ValueFunctionBank, lattice_targets

SMALL = dict(rho=0.2, h=0.1, ntheta=16)


def test_lattice_skips_obstacles(u_room):
    targets = lattice_targets(u_room, 0.5, h=0.05, clearance=0.05)
    assert targets.ndim == 2 and targets.shape[1] == 2
    # centred lattice: 8 x 6 nodes, minus those in the inflated U
    assert 30 < len(targets) < 48
    from hjplanner._grid import free_space
    assert free_space(targets, u_room.boundary, u_room.obstacles, 0.05).all()
    with pytest.raises(PlanningError, match="spacing must be positive"):
        lattice_targets(u_room, 0.0)


def test_bank_builds_caches_and_finds_nearest(tmp_path, u_room):
    bank = ValueFunctionBank(u_room, 1.0, clearance=0.05, cache_dir=tmp_path, **SMALL)
    assert len(bank) == len(bank.missing()) > 4
    bank.build(workers=1, progress=False)
    assert bank.missing() == []
    files = sorted(tmp_path.glob("*.npz"))
    assert len(files) == len(bank)
    vf = bank.nearest((0.45, 0.55))
    assert np.allclose(vf.target, bank.targets[bank.nearest_index((0.45, 0.55))])
    assert np.hypot(*(vf.target - (0.45, 0.55))) <= 0.5 * np.sqrt(2) + 1e-9
    assert bank.nearest((0.45, 0.55)) is vf  # in-memory LRU
    # same geometry and parameters: the cache is reused
    again = ValueFunctionBank(u_room, 1.0, clearance=0.05, cache_dir=tmp_path, **SMALL)
    assert again.key == bank.key and again.missing() == []
    # any change of geometry or parameters changes the key
    moved = types.SimpleNamespace(boundary=u_room.boundary, obstacles=[u_room.obstacles[0] + 0.01], name="u-room")
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
    finite = np.isfinite(a.values)
    assert np.array_equal(finite, np.isfinite(b.values))
    assert np.abs(a.values[finite] - b.values[finite]).max() < 0.02


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
