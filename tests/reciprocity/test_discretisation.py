"""The discretisation error a strategy estimates from its own solver, against the exact one."""

import numpy as np
import pytest

import arenas
import reciprocity as r
from reciprocity.errors import ReciprocityError
from reciprocity.fem import discretisation as disc


def _true_relative(solver, coarse_h):
    """The QUANTILE of the true relative error of `solver`'s Green's functions on `disk`
    over the pairs the estimate uses."""
    coarse = r.GreenSolver(solver.arena, h=coarse_h)
    _, inside = coarse.probe_matrix(solver.nodes)
    src = disc._sample_sources(solver.nodes, solver._mesh1, inside, coarse.h, disc.SAMPLE_SOURCES)
    rel = []
    for j, z in enumerate(src):
        g = solver.greens(z[None])[:, 0]
        rr = np.hypot(*(solver.nodes - z).T)
        use = (rr >= disc.NEAR_CELLS * coarse.h) & (g > disc.FLOOR_SHARE * g.max()) & inside
        exact = r.disk_green(solver.nodes[use], z, (70, 70), 70)
        rel.append(np.abs(g[use] - exact) / g[use])
    return float(np.quantile(np.concatenate(rel), disc.QUANTILE))


@pytest.mark.parametrize("h", [2.0, 1.0])
def test_the_estimate_tracks_the_true_error_on_the_disk(h):
    solver = r.GreenSolver(arenas.load("disk"), h=h)
    est = disc.discretisation_error(solver)
    true = _true_relative(solver, 2 * h)
    # an upper estimate: the coarse field between its nodes is further off than at them
    assert true <= est.relative <= 4 * true
    assert disc.discretisation_error(solver) is est                  # kept on the solver
    assert est.h == h and est.pairs > 1000 and np.nanmax(est.profile) >= est.relative


def test_the_estimate_falls_with_the_mesh():
    arena = arenas.load("disk")
    e = [disc.discretisation_error(r.GreenSolver(arena, h=h)).relative for h in (4.0, 2.0, 1.0)]
    assert e[0] > 1.5 * e[1] > 2.25 * e[2] * 0.8


def test_p2_solvers_are_refused():
    with pytest.raises(ReciprocityError, match="P1"):
        disc.discretisation_error(r.GreenSolver(arenas.load("disk"), h=4.0, order=2))
