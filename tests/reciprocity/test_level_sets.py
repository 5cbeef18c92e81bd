"""The geometry of a function on a P1 mesh (reciprocity.beliefs.level_sets)."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.level_sets import contour, refined_maximum, superlevel_area
from reciprocity.models.green import cached_solver


@pytest.fixture(scope="module")
def solver():
    return cached_solver(arenas.load("empty").without_scenario(), 4.0)


def test_refined_maximum_finds_a_quadratic_peak_below_the_mesh_size(solver):
    peak = np.array([71.3, 52.9])
    values = 1.0 - np.sum((solver.nodes - peak) ** 2, axis=1) / 400.0
    node = solver.nodes[np.argmax(values)]
    got = refined_maximum(solver, values)
    assert np.hypot(*(got - peak)) < 1e-6 < np.hypot(*(node - peak))


def test_a_vertex_far_off_keeps_the_node(solver):
    """The peak lies outside the free region, beyond 1.5 h of the best node (the corner)."""
    values = -np.sum((solver.nodes + 10.0) ** 2, axis=1)
    assert np.array_equal(refined_maximum(solver, values), solver.nodes[np.argmax(values)])


def test_contour_of_a_linear_function_is_its_line(solver):
    lines = contour(solver, solver.nodes[:, 0], 35.0)
    assert lines and all(np.allclose(line[:, 0], 35.0) for line in lines)
    assert contour(solver, solver.nodes[:, 0], 1e6) == []
    assert superlevel_area(solver.nodes, solver.triangles, solver.nodes[:, 0], 35.0) == pytest.approx(105 * 140)
