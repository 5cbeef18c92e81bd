"""The compiled first hits of a disk target (``hjplanner._motion.first_hits``) against the
array computation they replaced, and the process-wide memo of prepared workspaces."""

from __future__ import annotations

import numpy as np
import pytest

import arenas
from hjplanner import solver
from hjplanner._motion import arc_step


def first_hits_by_arrays(ws, gx, gy, dist, target, radius):
    """The boundary data of a disk target as ``solver._first_hits`` computed it with NumPy
    arrays, heading by heading (the reference for the compiled kernel)."""
    grid, free = ws.grid, ws.free
    bc = np.full((grid.ntheta, grid.nx, grid.ny), np.inf)
    v, u, s = (np.array(column, dtype=float) for column in zip(*ws.ctrl))
    near = np.nonzero(free & (dist <= radius + s.max() + grid.h))
    bc[:, free & (dist <= radius)] = 0.0
    fractions = np.linspace(0.0, 1.0, 33)
    bit = np.uint32(1) << np.arange(len(s), dtype=np.uint32)
    origins = np.column_stack([np.zeros(grid.ntheta), np.zeros(grid.ntheta), grid.theta])
    shapes = arc_step(origins[:, None, None, :], u[None, :, None], v[None, :, None], s[None, :, None] * fractions,
                      ws.rho)
    rx, ry = gx[near] - target[0], gy[near] - target[1]
    for k in range(grid.ntheta):
        outside = np.hypot(rx[:, None, None] + shapes[k, :, :, 0], ry[:, None, None] + shapes[k, :, :, 1]) - radius
        hit = outside <= 0
        m = np.argmax(hit, axis=-1)
        before = np.take_along_axis(outside, np.maximum(m - 1, 0)[..., None], -1)[..., 0]
        after = np.take_along_axis(outside, m[..., None], -1)[..., 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            step = np.where(m > 0, before / (before - after), 0.0)
        first = s * (fractions[np.maximum(m - 1, 0)] + step * (fractions[1] - fractions[0]) * (m > 0))
        clear = (ws.stencils["adm"][k][near][:, None] & bit) != 0
        first = np.where(hit.any(axis=-1) & clear, first, np.inf).min(axis=1)
        bc[k][near] = np.minimum(bc[k][near], first)
    bc[:, ~free] = np.inf
    return bc


@pytest.fixture(scope="module")
def workspace():
    arena = arenas.load("paper").without_scenario()
    return solver.prepare(arena, 10.0, 2.0, 32, clearance=4.0, reverse=True)


@pytest.mark.parametrize("target,radius", [((30.0, 30.0), 2.0), ((61.3, 17.9), 1.0), ((78.7, 54.3), 0.5)])
def test_first_hits_equal_the_array_computation_bit_for_bit(workspace, target, radius):
    g = workspace.grid
    gx, gy = np.meshgrid(g.x, g.y, indexing="ij")
    dist = np.hypot(gx - target[0], gy - target[1])
    new = solver._first_hits(workspace, gx, gy, dist, target, radius)
    old = first_hits_by_arrays(workspace, gx, gy, dist, target, radius)
    assert np.isfinite(new).sum() > 0
    np.testing.assert_array_equal(new, old)


def test_prepared_workspaces_are_shared_per_walls_and_arguments():
    arena = arenas.load("paper")
    a = solver.prepared(arena.without_scenario(), 10.0, 2.0, 16, clearance=4.0, reverse=True)
    b = solver.prepared(arena.with_scenario(source=(30.0, 30.0)).without_scenario(), 10.0, 2.0, 16,
                        clearance=4.0, reverse=True)
    assert a is b
    assert solver.prepared(arena.without_scenario(), 10.0, 2.0, 16, clearance=3.0, reverse=True) is not a
    ref = solver.prepare(arena.without_scenario(), 10.0, 2.0, 16, clearance=4.0, reverse=True)
    np.testing.assert_array_equal(a.free, ref.free)
    np.testing.assert_array_equal(a.stencils["adm"], ref.stencils["adm"])
