"""The clear-arc bitmasks of the sweeps (``hjplanner._sweep.stencil_masks``) against what they
must mean: every arc whose samples are all certified is admitted, no arc with a sample surely
within the clearance of a wall is, and every admitted arc keeps the clearance from the walls as
the arena's exact ``wall_distance`` measures it."""

from __future__ import annotations

import numpy as np
import pytest

import arenas
from hjplanner import SolverOptions, _sweep, solver
from hjplanner._motion import arc_step

#: Headings checked per case (a spread over the turn; every heading would only repeat the work).
HEADINGS = (0, 5, 11, 17, 30)


def _sample_bounds(ws, k: int):
    """Lower and upper bounds of the wall distance at every clearance sample of the arcs of
    heading ``k`` from every node: (nc, nx, ny, m) each, -inf/-inf off the grid; and the
    certified distance each sample needs (nc,)."""
    g = ws.grid
    ci, cj, corner_dist, margin = solver.arc_sample_cells(ws.rho, g, ws.ctrl, ws.clearance)
    i = np.arange(g.nx)[None, :, None, None] + ci[k][:, None, None, :]
    j = np.arange(g.ny)[None, None, :, None] + cj[k][:, None, None, :]
    inside = (i >= 0) & (j >= 0) & (i <= g.nx - 2) & (j <= g.ny - 2)
    # a sample on a node of the grid's last line or column is on the grid: its own node's distance
    on_node = (corner_dist[k][:, None, None, :, 0] == 0) & (i >= 0) & (j >= 0) & (i < g.nx) & (j < g.ny)
    node = ws.distance[np.clip(i, 0, g.nx - 1), np.clip(j, 0, g.ny - 1)]
    i, j = np.clip(i, 0, g.nx - 2), np.clip(j, 0, g.ny - 2)
    corners = np.stack([ws.distance[i + a, j + b] for a, b in ((0, 0), (0, 1), (1, 0), (1, 1))], axis=-1)
    near = corner_dist[k][:, None, None, :, :]
    lower = np.where(inside, (corners - near).max(axis=-1), -np.inf)
    upper = np.where(inside, (corners + near).min(axis=-1), np.where(on_node, node, -np.inf))
    return lower, upper, margin


CASES = {
    "rectangle, no clearance": lambda: solver.prepare(((-1.0, 1.0), (-1.0, 1.0)), 0.3, 0.02, 64),
    "paper, the car's clearance, reverse": lambda: solver.prepare(arenas.load("paper"), 15.0, 1.5, 48,
                                                                  clearance=4.0, reverse=True),
    "maze, the car's clearance": lambda: solver.prepare(arenas.load("maze"), 15.0, 1.0, 48, clearance=4.0),
}

#: The cases whose checks of every arc take ten seconds or more: in the slow tier.
SLOW = {"maze, the car's clearance"}


def _cases(names):
    return [pytest.param(n, marks=pytest.mark.slow) if n in SLOW else n for n in names]


@pytest.mark.parametrize("case", _cases(sorted(CASES)))
def test_masks_admit_every_certified_arc_and_no_arc_surely_blocked(case):
    ws = CASES[case]()
    adm = ws.stencils["adm"]
    nc = len(ws.ctrl)
    bits = np.uint32(1) << np.arange(nc, dtype=np.uint32)
    extra = 0
    for k in HEADINGS:
        lower, upper, margin = _sample_bounds(ws, k)
        admitted = ((adm[k][None] & bits[:, None, None]) != 0) & ws.free[None]
        certified = (lower >= margin[:, None, None, None]).all(axis=-1) & ws.free[None]
        # a sample off the grid, or whose distance is below the clearance: the arc meets a wall
        surely_blocked = (upper < ws.clearance).any(axis=-1)
        assert certified.any() and surely_blocked.any() and not certified.all()
        assert not (certified & ~admitted).any(), "an arc with every sample certified is refused"
        assert not (admitted & surely_blocked).any(), "an arc with a point within the clearance is admitted"
        extra += int((admitted & ~certified).sum())
    if case != "rectangle, no clearance":
        assert extra > 0  # the certified disks admit arcs the plain rule refuses: that path is tested below


@pytest.mark.parametrize("case", _cases(["paper, the car's clearance, reverse", "maze, the car's clearance"]))
def test_every_admitted_arc_keeps_the_clearance_from_the_true_walls(case):
    """Arcs admitted through certified disks (not every sample certified on its own) are
    sampled densely and measured with the arena's exact wall distance."""
    ws = CASES[case]()
    arena = arenas.load(case.split(",")[0])
    g, adm = ws.grid, ws.stencils["adm"]
    v, u, s = (np.array(column, dtype=float) for column in zip(*ws.ctrl))
    rng = np.random.default_rng(5)
    checked = 0
    for k in HEADINGS:
        lower, _, margin = _sample_bounds(ws, k)
        certified = (lower >= margin[:, None, None, None]).all(axis=-1)
        for c in range(len(ws.ctrl)):
            admitted = ((adm[k] >> np.uint32(c)) & 1).astype(bool) & ws.free
            ii, jj = np.nonzero(admitted & ~certified[c])
            if not len(ii):
                continue
            pick = rng.choice(len(ii), min(len(ii), 60), replace=False)
            poses = np.column_stack([g.x[ii[pick]], g.y[jj[pick]], np.full(len(pick), g.theta[k])])
            fractions = np.linspace(0.0, 1.0, 65)
            points = arc_step(poses[:, None, :], u[c], v[c], s[c] * fractions[None, :], ws.rho)[..., :2]
            distance = np.asarray(arena.wall_distance(points.reshape(-1, 2)))
            inside = np.asarray(arena.contains(points.reshape(-1, 2)))
            assert inside.all() and distance.min() >= ws.clearance - 1e-9
            checked += len(pick)
    assert checked > 100


@pytest.mark.parametrize("case", sorted(CASES))
def test_masks_are_the_same_bits_on_one_thread_and_on_two(case):
    """The masks are computed row by row, each node's bits its own: two threads taking
    alternate rows give every bit one thread gives, on every case."""
    ws = CASES[case]()
    ci, cj, corner_dist, margin = solver.arc_sample_cells(ws.rho, ws.grid, ws.ctrl, ws.clearance)
    reach = np.array([s for _, _, s in ws.ctrl], dtype=float)
    one, two = (_sweep.stencil_masks(ws.distance, ws.free, ws.clearance, ci, cj, corner_dist, margin, reach, t)
                for t in (1, 2))
    assert one.dtype == two.dtype == np.uint32 and one.any()
    np.testing.assert_array_equal(one, two)
    np.testing.assert_array_equal(one, ws.stencils["adm"])


def test_mask_threads_follow_the_options(monkeypatch):
    assert solver.mask_threads(SolverOptions(threads=1)) == 1
    assert solver.mask_threads(SolverOptions(threads=2)) == 2
    for cores, threads in ((1, 1), (2, 2), (8, _sweep.GROUPS), (None, 1)):
        monkeypatch.setattr(solver.os, "cpu_count", lambda cores=cores: cores)
        assert solver.mask_threads(SolverOptions()) == threads


# ------------------------------------------------- masks of another map, from the last one's
def _maps():
    """`paper`, the same with a box added in one corner, and with one of its obstacles gone:
    the maps a car that scans its walls goes through."""
    base = arenas.load("paper")
    box = np.array([[10.0, 10.0], [16.0, 10.0], [16.0, 14.0], [10.0, 14.0]])
    added = arenas.Arena.from_polygons(base.boundary, [*base.obstacles, box], name="paper")
    fewer = arenas.Arena.from_polygons(base.boundary, base.obstacles[1:], name="paper")
    return base, added, fewer


@pytest.mark.parametrize("reverse", [False, True])
def test_a_map_prepared_like_the_last_has_the_bits_of_one_prepared_alone(reverse):
    """Only the nodes within the reach of a changed wall distance or free node are computed
    again; the others keep the last map's bits, and every bit is the one a full computation
    gives (walls added, and walls taken away)."""
    base, added, fewer = _maps()
    settings = dict(rho=15.0, h=1.5, ntheta=48, clearance=4.0, reverse=reverse)
    last = solver.prepare(base, **settings)
    for new in (added, fewer):
        alone = solver.prepare(new, **settings)
        like = solver.prepare(new, **settings, like=last)
        assert not np.array_equal(alone.distance, last.distance)
        np.testing.assert_array_equal(like.stencils["adm"], alone.stencils["adm"])
        for key in ("off_i", "w", "kk", "cost", "inv_self"):
            np.testing.assert_array_equal(like.stencils[key], alone.stencils[key])
        changed = (alone.distance != last.distance) | (alone.free != last.free)
        kept = ~_sweep.mask_reach(changed, *solver.arc_sample_cells(15.0, alone.grid, alone.ctrl, 4.0)[:2])
        assert kept.any() and (~kept).any()                  # some bits were kept, some computed
        last = alone


def test_a_workspace_of_other_settings_lends_no_bits():
    base, added, _ = _maps()
    last = solver.prepare(base, 15.0, 1.5, 48, clearance=4.0)
    for other in (dict(clearance=3.0), dict(reverse=True)):
        settings = dict(clearance=4.0) | other
        alone = solver.prepare(added, 15.0, 1.5, 48, **settings)
        np.testing.assert_array_equal(solver.prepare(added, 15.0, 1.5, 48, **settings, like=last).stencils["adm"],
                                      alone.stencils["adm"])


def test_the_reach_of_a_change_covers_every_node_whose_bits_read_it():
    """A node's bits read its own node and the corners of its arcs' sample cells: a change
    at one node reaches back over exactly those offsets."""
    ci = np.array([[[0, 2, -3]]])
    cj = np.array([[[0, -1, 1]]])
    changed = np.zeros((12, 12), bool)
    changed[6, 6] = True
    reach = _sweep.mask_reach(changed, ci, cj)
    # node (i, j) reads (i + a, j + b), a in [-3, 3], b in [-1, 2]: it is reached when
    # (6 - i, 6 - j) is such an offset
    i, j = np.nonzero(reach)
    assert set(zip((6 - i).tolist(), (6 - j).tolist())) == {(a, b) for a in range(-3, 4) for b in range(-1, 3)}


def test_the_bits_out_of_reach_are_taken_from_the_last_map():
    """Flip the last map's bits everywhere: the nodes out of the changes' reach carry the
    flipped bits (taken, not computed), the others the computed ones."""
    from dataclasses import replace
    base, added, _ = _maps()
    last = solver.prepare(base, 15.0, 1.5, 48, clearance=4.0)
    flipped = replace(last, stencils=dict(last.stencils, adm=~last.stencils["adm"]))
    alone = solver.prepare(added, 15.0, 1.5, 48, clearance=4.0)
    like = solver.prepare(added, 15.0, 1.5, 48, clearance=4.0, like=flipped)
    changed = (alone.distance != last.distance) | (alone.free != last.free)
    computed = _sweep.mask_reach(changed, *solver.arc_sample_cells(15.0, alone.grid, alone.ctrl, 4.0)[:2])
    np.testing.assert_array_equal(like.stencils["adm"][:, computed], alone.stencils["adm"][:, computed])
    np.testing.assert_array_equal(like.stencils["adm"][:, ~computed], ~last.stencils["adm"][:, ~computed])


def test_prepared_prepares_a_new_map_like_the_latest_of_its_settings(monkeypatch):
    from collections import OrderedDict
    monkeypatch.setattr(solver, "_PREPARED", OrderedDict())
    base, added, _ = _maps()
    seen = []
    real = solver.prepare
    monkeypatch.setattr(solver, "prepare", lambda *a, **k: seen.append(k.get("like")) or real(*a, **k))
    first = solver.prepared(base, 15.0, 1.5, 48, clearance=4.0)
    solver.prepared(base, 15.0, 1.5, 48, clearance=3.0)              # other settings: not a model
    second = solver.prepared(added, 15.0, 1.5, 48, clearance=4.0)
    assert seen[0] is None and seen[1] is None and seen[2] is first
    np.testing.assert_array_equal(second.stencils["adm"], real(added, 15.0, 1.5, 48, clearance=4.0).stencils["adm"])
