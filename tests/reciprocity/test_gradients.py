"""reciprocity.fem.gradients: the RMS slope of P1 fields around each node, exact for linear
fields and converging at first order for smooth ones."""

import numpy as np
import pytest

import arenas
from reciprocity.fem.gradients import NodalSlope
from reciprocity.models.green import cached_solver


@pytest.fixture(scope="module", params=[4.0, 2.0, 1.0])
def mesh(request):
    solver = cached_solver(arenas.load("empty").without_scenario(), request.param)
    return request.param, solver.nodes, solver.triangles


def test_a_linear_field_has_its_slope_at_every_node(mesh):
    _, nodes, tri = mesh
    v = 3.0 * nodes[:, 0] - 4.0 * nodes[:, 1] + 7.0
    assert np.allclose(NodalSlope(nodes, tri)(v[:, None])[:, 0], 5.0, rtol=1e-9)


def test_several_columns_at_once_equal_one_at_a_time(mesh):
    _, nodes, tri = mesh
    slope = NodalSlope(nodes, tri)
    v = np.stack([np.sin(nodes[:, 0] / 9.0), nodes[:, 1] ** 2 / 100.0], axis=1)
    both = slope(v)
    assert np.allclose(both[:, 0], slope(v[:, :1])[:, 0]) and np.allclose(both[:, 1], slope(v[:, 1:])[:, 0])


def test_a_smooth_field_converges_at_first_order():
    """|∇ sin(x/9) cos(y/13)| at interior nodes against the exact value, h = 4, 2, 1 cm."""
    errs = []
    for h in (4.0, 2.0, 1.0):
        solver = cached_solver(arenas.load("empty").without_scenario(), h)
        x, y = solver.nodes.T
        v = np.sin(x / 9.0) * np.cos(y / 13.0)
        exact = np.hypot(np.cos(x / 9.0) * np.cos(y / 13.0) / 9.0, -np.sin(x / 9.0) * np.sin(y / 13.0) / 13.0)
        inside = (x > 10) & (x < 130) & (y > 10) & (y < 130)
        got = NodalSlope(solver.nodes, solver.triangles)(v[:, None])[:, 0]
        errs.append(np.sqrt(np.mean((got[inside] - exact[inside]) ** 2)))
    order = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(order > 0.8), (errs, order)
