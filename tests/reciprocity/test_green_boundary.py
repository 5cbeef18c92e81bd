"""The Dirichlet nodes of a P1 solver, found from the edges only one triangle has, are those
scikit-fem's facet tables give, on built-in and generated arenas; the facets are classified
(outer boundary, obstacles) when first asked for, as before."""

import numpy as np
import pytest

import arenas
from reciprocity.fem.green import GreenSolver, boundary_nodes


@pytest.mark.parametrize("arena", [arenas.load("paper"), arenas.load("maze"), arenas.load("disk"),
                                   arenas.generate("rooms", 1), arenas.generate("ring", 0)],
                         ids=lambda a: a.name)
def test_p1_dirichlet_nodes_are_scikit_fems(arena):
    solver = GreenSolver(arena, h=4.0)
    mesh = solver._mesh1
    facets = mesh.boundary_facets()
    reference = solver.basis.get_dofs(facets).all()
    got = boundary_nodes(mesh.t, mesh.p.shape[1])
    assert got.dtype == reference.dtype and np.array_equal(got, reference)
    assert np.array_equal(solver._dirichlet, reference)
    # the facets, classified on first use: together the boundary, in scikit-fem's numbering
    assert np.array_equal(np.sort(np.concatenate([solver.outer_facets, solver.obstacle_facets])), facets)
    assert (solver.obstacle_facets.size > 0) == bool(arena.obstacles)


@pytest.mark.parametrize("order, walls", [(1, "neumann"), (2, "dirichlet"), (2, "neumann")])
def test_other_solvers_take_scikit_fems_facets(order, walls):
    solver = GreenSolver(arenas.load("paper"), h=6.0, order=order, walls=walls)
    dir_facets = solver.outer_facets if walls == "neumann" else solver._mesh1.boundary_facets()
    assert np.array_equal(solver._dirichlet, solver.basis.get_dofs(dir_facets).all())
