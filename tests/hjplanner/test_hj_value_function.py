"""ValueFunction: interpolation, .npz files, plots."""

import json
import types

import matplotlib
import numpy as np
import pytest

from hjplanner import PlanningError, ValueFunction, solve
from hjplanner.value_function import QUANTUM_STEPS

matplotlib.use("Agg")


def test_evaluation_is_vectorised_periodic_and_nan_free(coarse_vf):
    x = np.linspace(-0.9, 0.9, 7)
    values = coarse_vf(x[:, None], x[None, :], 1.0)
    assert values.shape == (7, 7)
    np.testing.assert_allclose(coarse_vf(0.3, 0.2, 1.0 + 2 * np.pi), coarse_vf(0.3, 0.2, 1.0), atol=1e-12)
    np.testing.assert_allclose(coarse_vf(0.3, 0.2, -1.0), coarse_vf(0.3, 0.2, 2 * np.pi - 1.0), atol=1e-12)
    # outside the grid: +inf, never NaN
    assert np.isinf(coarse_vf(5.0, 0.0, 0.0))
    rng = np.random.default_rng(0)
    poses = rng.uniform([-1.2, -1.2, -10], [1.2, 1.2, 10], (5000, 3))
    assert not np.isnan(coarse_vf(poses[:, 0], poses[:, 1], poses[:, 2])).any()
    # at nodes, the cubic and linear interpolants reproduce the node values
    g = coarse_vf.grid
    node = coarse_vf.values[10, 30, 5]
    assert coarse_vf(g.x[10], g.y[30], g.theta[5]) == pytest.approx(node)
    assert coarse_vf(g.x[10], g.y[30], g.theta[5], cubic=False) == pytest.approx(node)


def test_infinite_neighbours_do_not_poison_interpolation(u_room_vf):
    vf = u_room_vf
    finite = np.isfinite(vf.values)
    assert 0.3 < finite.mean() < 1.0
    rng = np.random.default_rng(1)
    poses = rng.uniform([0, 0, 0], [4, 3, 2 * np.pi], (20000, 3))
    values = vf(poses[:, 0], poses[:, 1], poses[:, 2])
    assert not np.isnan(values).any()
    assert (values[np.isfinite(values)] >= 0).all()
    assert np.isfinite(values).mean() > 0.3


def test_save_load_round_trip(tmp_path, u_room_vf):
    path = u_room_vf.save(tmp_path / "v.npz")
    loaded = ValueFunction.load(path)
    finite = np.isfinite(u_room_vf.values)
    np.testing.assert_array_equal(np.isfinite(loaded.values), finite)
    # values are stored as uint16 multiples of max(h/64, max φ/65534): error at most half a step
    step = max(u_room_vf.grid.h / 64, u_room_vf.values[finite].max() / QUANTUM_STEPS)
    assert np.abs(loaded.values[finite] - u_room_vf.values[finite]).max() <= 0.5 * step + 1e-12
    np.testing.assert_array_equal(loaded.free, u_room_vf.free)
    np.testing.assert_allclose(loaded.distance, u_room_vf.distance, atol=1e-6)
    assert loaded.grid == u_room_vf.grid
    assert loaded.meta == json.loads(json.dumps(u_room_vf.meta))
    assert loaded.meta["domain"] == "u-room" and loaded.rho == 0.25 and loaded.meta["clearance"] == 0.05
    np.testing.assert_array_equal(loaded.geometry["obstacles"][0], u_room_vf.geometry["obstacles"][0])
    pose = (0.5, 1.5, 0.3)
    assert loaded(*pose) == pytest.approx(float(u_room_vf(*pose)), abs=step)
    with np.load(path, allow_pickle=False) as data:  # plain arrays only, 2 bytes per value
        assert data["phi_high"].dtype == data["phi_low"].dtype == np.uint8
        assert data["phi_high"].shape == (u_room_vf.grid.ntheta, u_room_vf.grid.nx, u_room_vf.grid.ny)
    # a loaded value function plans as well (near-ties may break the other way)
    start = (0.5, 1.5, 0.0)
    before, after = u_room_vf.path(start), loaded.path(start)
    assert after.reached and abs(after.length - before.length) < 2 * u_room_vf.grid.h


def test_load_errors(tmp_path):
    with pytest.raises(PlanningError, match="does not exist"):
        ValueFunction.load(tmp_path / "missing.npz")
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a zip file")
    with pytest.raises(PlanningError, match="not an .npz archive"):
        ValueFunction.load(bad)
    other = tmp_path / "other.npz"
    np.savez(other, meta=np.array(json.dumps({"format": "something else"})))
    with pytest.raises(PlanningError, match="not an hjplanner value function"):
        ValueFunction.load(other)


def test_plot_slice(u_room_vf, coarse_vf):
    import matplotlib.pyplot as plt
    ax = u_room_vf.plot_slice(np.pi / 2)
    # the filled contours span the finite values of the slice, the obstacle is drawn, the target marked
    levels = next(c for c in ax.collections if hasattr(c, "levels")).levels
    values = u_room_vf(*np.meshgrid(u_room_vf.grid.x, u_room_vf.grid.y, indexing="ij"), np.pi / 2, cubic=False)
    finite = values[np.isfinite(values)]
    assert levels.min() <= finite.min() and levels.max() >= finite.max()
    lines = [line.get_xydata() for line in ax.get_lines()]
    assert any(np.allclose(xy[:-1], u_room_vf.geometry["obstacles"][0]) for xy in lines if len(xy) == 9)
    assert any(np.allclose(xy, [u_room_vf.target]) for xy in lines)
    plt.close(ax.figure)
    fig, ax = plt.subplots()
    assert coarse_vf.plot_slice(0.0, ax=ax) is ax
    plt.close(fig)
    assert repr(coarse_vf) == ("ValueFunction(domain='rect[-1,1]x[-1,1]', target=(0.0, 0.0), rho=0.3, "
                               "grid=41x41x32, h=0.05)")


def test_domain_without_arena_geometry_is_rejected():
    polygons_only = types.SimpleNamespace(boundary=np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float), obstacles=[],
                                          name="polygons")
    with pytest.raises(PlanningError, match="Arena.from_polygons"):
        solve(polygons_only, (0.3, 0.3), 0.2, 0.05, 16)
