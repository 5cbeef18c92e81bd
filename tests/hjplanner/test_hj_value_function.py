"""ValueFunction: interpolation, .npz files, plots."""

import json
import types

import matplotlib
import numpy as np
import pytest

from hjplanner import PlanningError, ValueFunction, solve

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
    np.testing.assert_array_equal(loaded.values, u_room_vf.values)
    np.testing.assert_array_equal(loaded.free, u_room_vf.free)
    assert loaded.grid == u_room_vf.grid
    assert loaded.meta == json.loads(json.dumps(u_room_vf.meta))
    assert loaded.meta["domain"] == "u-room" and loaded.rho == 0.25 and loaded.meta["clearance"] == 0.05
    np.testing.assert_array_equal(loaded.geometry["obstacles"][0], u_room_vf.geometry["obstacles"][0])
    pose = (0.5, 1.5, 0.3)
    assert loaded(*pose) == u_room_vf(*pose)
    with np.load(path, allow_pickle=False) as data:  # plain arrays only
        assert data["phi"].dtype == np.float64


def test_load_errors(tmp_path):
    with pytest.raises(PlanningError, match="does not exist"):
        ValueFunction.load(tmp_path / "missing.npz")
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a zip file")
    with pytest.raises(PlanningError, match="cannot read"):
        ValueFunction.load(bad)
    other = tmp_path / "other.npz"
    np.savez(other, meta=np.array(json.dumps({"format": "something else"})))
    with pytest.raises(PlanningError, match="not an hjplanner value function"):
        ValueFunction.load(other)


def test_plot_slice(tmp_path, u_room_vf, coarse_vf):
    import matplotlib.pyplot as plt
    ax = u_room_vf.plot_slice(np.pi / 2)
    ax.figure.savefig(tmp_path / "slice.png")
    plt.close(ax.figure)
    assert (tmp_path / "slice.png").stat().st_size > 1000
    fig, ax = plt.subplots()
    assert coarse_vf.plot_slice(0.0, ax=ax) is ax
    plt.close(fig)
    assert "41x41x32" in repr(coarse_vf)


def test_arena_duck_typing_only_reads_three_attributes():
    class Minimal:
        boundary = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
        obstacles = [np.array([[0.8, 0.8], [1.2, 0.8], [1.2, 1.2], [0.8, 1.2]])]
        name = "minimal"

    vf = solve(Minimal(), (0.3, 0.3), 0.2, 0.05, 16)
    assert vf.meta["domain"] == "minimal"
    assert np.isinf(vf(1.0, 1.0, 0.0))
    with pytest.raises(PlanningError, match="arena obstacle"):
        solve(types.SimpleNamespace(boundary=Minimal.boundary, obstacles=[np.zeros((2, 2))], name="x"),
              (0.3, 0.3), 0.2, 0.05, 16)
