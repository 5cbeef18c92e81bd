"""The closed-form references of hjplanner.dubins, checked independently."""

import numpy as np
import pytest

from hjplanner import half_plane_distance, point_distance, reeds_shepp_line_distance

RHO = 0.3


def _brute_force(x, y, theta, rho, n=721, lateral=2e-3):
    """Shortest path of type C C S to the origin by exhaustive search over the two arc angles.

    CS and CC are special cases (zero-length arcs or segment); the final
    segment must pass within ``lateral`` of the target.
    """
    t = np.linspace(0.0, 2 * np.pi, n)
    best = np.inf
    for d1 in (1, -1):
        x1 = x + d1 * rho * (np.sin(theta + d1 * t) - np.sin(theta))
        y1 = y - d1 * rho * (np.cos(theta + d1 * t) - np.cos(theta))
        h1 = theta + d1 * t
        for d2 in (1, -1):
            x2 = x1[:, None] + d2 * rho * (np.sin(h1[:, None] + d2 * t) - np.sin(h1[:, None]))
            y2 = y1[:, None] - d2 * rho * (np.cos(h1[:, None] + d2 * t) - np.cos(h1[:, None]))
            h2 = h1[:, None] + d2 * t
            ahead = -np.cos(h2) * x2 - np.sin(h2) * y2
            side = np.sin(h2) * x2 - np.cos(h2) * y2
            total = rho * (t[:, None] + t[None, :]) + np.where((ahead >= 0) & (np.abs(side) < lateral), ahead, np.inf)
            best = min(best, float(total.min()))
    return best


def _simulate_greedy_half_plane(x, theta, rho, x0, ds=1e-4):
    """Time for the car turning towards +x at the maximal rate to reach x >= x0 (numerical integration)."""
    s = 0.0
    psi = np.mod(theta + np.pi, 2 * np.pi) - np.pi
    while x < x0:
        step = min(ds, abs(psi) * rho) if psi != 0 else ds
        if psi == 0:
            return s + (x0 - x)
        new_psi = psi - np.sign(psi) * step / rho
        x += rho * (np.sin(abs(psi)) - np.sin(abs(new_psi)))
        psi, s = new_psi, s + step
    return s


def test_simple_exact_values():
    assert point_distance(-1.0, 0.0, 0.0, RHO) == pytest.approx(1.0)
    assert point_distance(0.0, 0.0, 1.0, RHO) == 0.0
    # target on the left turning circle, a quarter turn away
    assert point_distance(-RHO, -RHO, 0.0, RHO) == pytest.approx(0.5 * np.pi * RHO)
    # target straight behind at distance d < 2 rho: CC path (Bui et al.)
    assert point_distance(0.1, 0.0, 0.0, RHO) > 2 * np.pi * RHO * 0.9


def test_matches_brute_force_search():
    rng = np.random.default_rng(0)
    poses = rng.uniform([-0.8, -0.8, 0], [0.8, 0.8, 2 * np.pi], (8, 3))
    exact = point_distance(poses[:, 0], poses[:, 1], poses[:, 2], RHO)
    brute = np.array([_brute_force(*p, RHO) for p in poses])
    # the brute force samples arcs every 2π/720 and accepts a lateral miss of 2e-3
    np.testing.assert_allclose(exact, brute, atol=4e-3)


def test_symmetries_and_vectorisation():
    rng = np.random.default_rng(1)
    x, y, th = rng.uniform(-1, 1, (3, 500))
    th = th * np.pi
    d = point_distance(x, y, th, RHO)
    assert d.shape == (500,) and np.isfinite(d).all() and (d >= np.hypot(x, y) - 1e-12).all()
    np.testing.assert_allclose(point_distance(x, -y, -th, RHO), d, atol=1e-12)  # mirror
    rot = 0.7
    xr, yr = np.cos(rot) * x - np.sin(rot) * y, np.sin(rot) * x + np.cos(rot) * y
    np.testing.assert_allclose(point_distance(xr, yr, th + rot, RHO), d, atol=1e-9)  # rotation
    np.testing.assert_allclose(point_distance(x + 2, y - 1, th, RHO, target=(2, -1)), d, atol=1e-9)
    assert point_distance(x[:, None], y[:, None], np.linspace(0, 6, 7), RHO).shape == (500, 7)


def test_satisfies_the_hj_equation_where_smooth():
    """-1 = cosθ φ_x + sinθ φ_y - |φ_θ|/ρ (eq. (13)) by central differences at random smooth points."""
    rng = np.random.default_rng(2)
    x, y, th = rng.uniform(-1, 1, (3, 400))
    th = th * np.pi
    e = 1e-6
    phi = lambda a, b, c: point_distance(a, b, c, RHO)  # noqa: E731
    px = (phi(x + e, y, th) - phi(x - e, y, th)) / (2 * e)
    py = (phi(x, y + e, th) - phi(x, y - e, th)) / (2 * e)
    pt = (phi(x, y, th + e) - phi(x, y, th - e)) / (2 * e)
    residual = np.cos(th) * px + np.sin(th) * py - np.abs(pt) / RHO + 1
    smooth = (np.abs(px) < 10) & (np.abs(py) < 10) & (np.abs(pt) < 10)
    assert smooth.mean() > 0.9
    assert np.median(np.abs(residual[smooth])) < 1e-6
    assert np.percentile(np.abs(residual[smooth]), 95) < 1e-4


def test_half_plane_matches_integration():
    for x, th in [(-0.5, 0.0), (-0.5, 0.4), (-0.05, 1.4), (-0.2, 2.5), (-0.01, np.pi), (-0.7, -2.0)]:
        assert half_plane_distance(x, th, RHO) == pytest.approx(_simulate_greedy_half_plane(x, th, RHO, 0.0),
                                                                 abs=2e-4)
    assert half_plane_distance(0.3, 2.0, RHO) == 0.0


def test_reeds_shepp_line_is_the_better_direction():
    assert reeds_shepp_line_distance(-0.4, np.pi, RHO) == pytest.approx(0.4)  # backing up
    th = np.linspace(0, 2 * np.pi, 50)
    np.testing.assert_allclose(reeds_shepp_line_distance(-0.4, th, RHO), reeds_shepp_line_distance(-0.4, th + np.pi,
                                                                                                     RHO))


def test_target_dead_ahead_is_robust_to_round_off():
    # psi = -π/2 - 1e-17 must mean "no turn", not a full loop
    assert point_distance(-0.07999999999999999, 0.0, 0.0, RHO) == pytest.approx(0.08, abs=1e-12)
    assert point_distance(-0.3 + 1e-16, 1e-17, 0.0, RHO) == pytest.approx(0.3, abs=1e-12)


@pytest.mark.parametrize("reverse", [False, True])
@pytest.mark.parametrize("r0", [0.25, 0.6])   # below and above πρ/2, where poses are ruled out unsolved
def test_compiled_exact_layer_matches_numpy(reverse, r0):
    """The solver's exact initial layer and the value function's reads near the target use
    the compiled kernels; they agree with the numpy reference to round-off, +inf alike."""
    from hjplanner._search import exact_layer, local_exact_many
    from hjplanner.dubins import local_exact

    rng = np.random.default_rng(7)
    x, y = rng.uniform(-0.7, 0.7, 3000), rng.uniform(-0.7, 0.7, 3000)
    theta = rng.uniform(-np.pi, 3 * np.pi, 3000)
    rho, target = 0.3, (0.03, -0.02)
    want = local_exact(x, y, theta, target, rho, r0, reverse)
    got = local_exact_many(x, y, theta, *target, rho, r0, reverse)
    assert np.array_equal(np.isinf(got), np.isinf(want)) and np.isinf(want).any() and np.isfinite(want).any()
    np.testing.assert_allclose(got[np.isfinite(want)], want[np.isfinite(want)], rtol=0, atol=1e-12)
    headings = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
    ii, jj = np.arange(50), np.arange(50)[::-1].copy()
    bc = np.full((16, 50, 50), np.inf)
    exact_layer(bc, ii, jj, x[:50], y[:50], headings, *target, rho, r0, reverse)
    layer = local_exact(x[:50][None, :], y[:50][None, :], headings[:, None], target, rho, r0, reverse)
    finite = np.isfinite(layer)
    assert np.array_equal(np.isfinite(bc[:, ii, jj]), finite)
    np.testing.assert_allclose(bc[:, ii, jj][finite], layer[finite], rtol=0, atol=1e-12)
    assert np.isinf(np.delete(bc.reshape(16, -1), ii * 50 + jj, axis=1)).all()
