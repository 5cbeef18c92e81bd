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


def test_the_estimate_is_kept_on_disk_and_read_back_to_the_bit(monkeypatch):
    """A second solver of the same mesh (another process, as far as the estimate can tell)
    reads the estimate from the disk cache instead of solving on the coarse mesh; a
    solver of another mesh size, or another number of sample sources, computes its own."""
    arena = arenas.load("disk")
    first = disc.discretisation_error(r.GreenSolver(arena, h=4.0))
    computed = []
    original = disc._estimate
    monkeypatch.setattr(disc, "_estimate", lambda *a: computed.append(a[1:]) or original(*a))
    again = disc.discretisation_error(r.GreenSolver(arena, h=4.0))
    assert computed == []
    assert again is not first and again.relative == first.relative and again.pairs == first.pairs
    np.testing.assert_array_equal(again.profile, first.profile)
    np.testing.assert_array_equal(again.distances, first.distances)
    disc.discretisation_error(r.GreenSolver(arena, h=4.0), sources=6)
    disc.discretisation_error(r.GreenSolver(arena, h=3.0))
    assert [c[0] for c in computed] == [6, disc.SAMPLE_SOURCES]


def test_an_entry_for_other_bins_or_another_h_is_refused():
    edges = np.array([0.0, 5.0, 10.0, 20.0, 40.0, 80.0, np.inf])
    good = dict(relative=np.array([0.01]), distances=edges[1:].copy(), profile=np.full(6, 0.01),
                h=np.array([2.0]), pairs=np.array([500], dtype=np.int64))
    disc._check_entry(good, 2.0, edges)
    for change in (dict(relative=np.array([np.nan])), dict(relative=np.array(0.01)),
                   dict(distances=edges[1:][::-1].copy()), dict(profile=np.full(5, 0.01)),
                   dict(profile=np.full(6, -1.0)), dict(h=np.array([1.0])), dict(pairs=np.array([0])),
                   dict(pairs=np.array([1.5]))):
        with pytest.raises(ValueError):
            disc._check_entry({**good, **change}, 2.0, edges)
