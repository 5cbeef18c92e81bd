"""The compiled kernels of the path search against their numpy definitions."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hjplanner import _search, dubins
from hjplanner._grid import lower_wall_distance
from hjplanner._motion import arc_samples, arc_step, arcs_are_clear, arcs_from, drive_runs, sample_spacing

RHO = 0.3
finite = st.floats(-2.0, 2.0, allow_nan=False)
angle = st.floats(-7.0, 7.0, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(finite, finite, angle, finite, finite)
def test_point_distance_matches_numpy(x, y, theta, tx, ty):
    """Operation for operation the closed forms of dubins.point_distance: equal to round-off
    (numpy's arctan2 and arccos are its own vectorised versions, libm's are compiled here)."""
    ref = float(dubins.point_distance(x, y, theta, RHO, (tx, ty)))
    got = _search.point_distance(x, y, theta, RHO, tx, ty)
    assert got == ref or abs(got - ref) <= 1e-12 * max(1.0, abs(ref))


@settings(max_examples=300, deadline=None)
@given(finite, finite, angle, st.booleans(), st.floats(0.05, 1.5))
def test_local_exact_matches_numpy(x, y, theta, reverse, r0):
    ref = float(dubins.local_exact(x, y, theta, (0.1, -0.2), RHO, r0, reverse))
    got = _search.local_exact(x, y, theta, 0.1, -0.2, RHO, r0, reverse)
    if np.isfinite(ref) != np.isfinite(got):  # only a value within round-off of r0 may differ
        value = dubins.point_distance(x, y, theta, RHO, (0.1, -0.2))
        if reverse:
            value = min(value, dubins.point_distance(x, y, theta + np.pi, RHO, (0.1, -0.2)))
        assert abs(float(value) - r0) < 1e-9
        return
    assert got == ref or abs(got - ref) <= 1e-12


def test_local_exact_only_solves_near_the_target():
    """The straight-line prefilter changes no value: every finite value is within r0."""
    rng = np.random.default_rng(0)
    x, y, t = rng.uniform(-3, 3, (3, 50_000))
    for reverse in (False, True):
        values = dubins.local_exact(x, y, 2 * t, (0.1, -0.2), RHO, 1.5, reverse)
        full = dubins.point_distance(x, y, 2 * t, RHO, (0.1, -0.2))
        if reverse:
            full = np.minimum(full, dubins.point_distance(x, y, 2 * t + np.pi, RHO, (0.1, -0.2)))
        np.testing.assert_array_equal(values, np.where(full <= 1.5, full, np.inf))


def _clear_reference(vf, poses, u, v, s):
    """arcs_are_clear as it was written in numpy: every sample's certified distance."""
    points = arc_samples(poses, u.astype(float), v.astype(float), s, vf.rho, sample_spacing(vf.grid.h))
    step = s / (points.shape[1] - 1)
    bound = lower_wall_distance(vf.distance, vf.grid.x0, vf.grid.y0, vf.grid.h,
                                np.ascontiguousarray(points[..., 0].ravel()),
                                np.ascontiguousarray(points[..., 1].ravel())).reshape(points.shape[:2])
    return (bound >= vf.clearance + 0.5 * step[:, None]).all(axis=1)


def test_arc_kernels_match_numpy(u_room_vf):
    vf = u_room_vf
    rng = np.random.default_rng(3)
    g = vf.grid
    poses = np.column_stack([rng.uniform(g.x0, g.x0 + (g.nx - 1) * g.h, 400),
                             rng.uniform(g.y0, g.y0 + (g.ny - 1) * g.h, 400), rng.uniform(0, 2 * np.pi, 400)])
    u = rng.integers(-1, 2, 400)
    v = rng.choice([-1, 1], 400)
    s = rng.uniform(0.0, 0.4, 400)
    expected = _clear_reference(vf, poses, u, v, s)
    assert 0 < expected.sum() < len(expected)  # both outcomes occur
    np.testing.assert_array_equal(arcs_are_clear(vf.distance, g, vf.clearance, poses, u, v, s, vf.rho), expected)
    for pose in poses[:40]:
        ends, clear = arcs_from(pose, u[:12], v[:12], s[:12], vf.rho, vf.distance, g.x0, g.y0, g.h, vf.clearance)
        np.testing.assert_array_equal(ends, arc_step(np.repeat(pose[None], 12, axis=0), u[:12], v[:12], s[:12],
                                                     vf.rho))
        np.testing.assert_array_equal(clear, _clear_reference(vf, np.repeat(pose[None], 12, axis=0), u[:12],
                                                              v[:12], s[:12]))


def test_drive_runs_matches_arc_step():
    start = np.array([0.2, -0.1, 1.0])
    runs = [(1, 1, 0.33), (0, 1, 0.1), (-1, -1, 0.07), (0, -1, 0.0)]
    poses, steps = drive_runs(start, *(np.array([r[i] for r in runs], float) for i in range(3)), 0.02, RHO)
    expected, at = [start[None]], start
    for u, v, length in runs:
        n = max(1, int(np.ceil(length / 0.02 - 1e-9)))
        part = arc_step(at, u, v, length * np.arange(1, n + 1) / n, RHO)
        expected.append(part)
        at = part[-1]
    np.testing.assert_array_equal(poses, np.concatenate(expected))
    assert steps.tolist() == [17, 5, 4, 1]
