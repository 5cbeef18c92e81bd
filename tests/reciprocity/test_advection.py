"""Advection-diffusion-decay: observed orders against the free-space solution, and reciprocity."""

import numpy as np
import pytest
from fem_error import l2_error_away, observed_order

import arenas
from reciprocity.errors import ReciprocityError
from reciprocity.fem import AdvectionSolver, WindField, free_space_advection_green

#: Diffusivity, cm²/s.
D = 1.0
#: P1 with SUPG keeps at least this observed L2 order away from the source.
RATE_P1 = 1.9
#: Forward and adjoint agree to this relative error (round-off of the LU solves).
RECIPROCITY_REL = 1e-10
#: The exact solution on the disk's boundary, relative to its largest value in the annulus:
#: the absorbing wall truncates a solution that has decayed.
DECAYED_AT_WALL = 1e-3


def _plume_problem(pe, h0, radius):
    """Uniform wind along +x whose cell Péclet number on the coarsest mesh `h0` is `pe`, and
    a lifetime giving a downwind decay length of radius / 6 (so ``1/λ - |u|/(2D) = 6/radius``)."""
    speed = 2.0 * pe * D / h0
    inv_lambda = 6.0 / radius + speed / (2.0 * D)
    tau = 1.0 / (D * (inv_lambda**2 - speed**2 / (4.0 * D**2)))
    return speed, tau


def _observed_order(pe, hs, radius):
    """Observed L2 order of the forward field over the annulus radius/6 <= |x - z| <= 2 radius/3
    around a source z = (-radius/3, 0), on a disk with absorbing walls."""
    speed, tau = _plume_problem(pe, hs[0], radius)
    disk = arenas.Arena.disk((0.0, 0.0), radius)
    z = np.array([-radius / 3.0, 0.0])
    r_in, r_out = radius / 6.0, 2.0 * radius / 3.0

    def exact(x, y):
        pts = np.column_stack([x.ravel(), y.ravel()])
        return free_space_advection_green(pts, z, (speed, 0.0), D, tau).reshape(x.shape)

    wall = disk.boundary
    ring = z + r_in * np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 64)), np.sin(np.linspace(0, 2 * np.pi, 64))])
    assert exact(*wall.T).max() < DECAYED_AT_WALL * exact(*ring.T).max()
    errs = []
    for h in hs:
        s = AdvectionSolver(disk, WindField.uniform((1.0, 0.0), speed), D, tau, h=h, walls="absorbing")
        c = s.forward(z).dofs
        # the annulus: the error beyond r_in less the error beyond r_out
        beyond_in, beyond_out = (l2_error_away(s.space, c, exact, z, r)[0] for r in (r_in, r_out))
        errs.append(np.sqrt(beyond_in**2 - beyond_out**2))
    order = observed_order(hs, errs)
    # shown with -s: the table of benchmarks/advection.md
    print(f"\nradius {radius:g} cm, cell Péclet {pe:g} on h = {hs[0]:g} cm: L2 errors "
          f"{', '.join(f'{e:.3g}' for e in errs)}, observed order {order:.2f}")
    return order


@pytest.mark.parametrize("pe", [1.0, 10.0])
def test_p1_supg_keeps_second_order_up_to_cell_peclet_10(pe):
    """Cell Péclet number |u| h / (2D) on the coarsest of the three meshes (h/2, h/4: pe/2, pe/4)."""
    assert _observed_order(pe, [1.0, 0.5, 0.25], radius=30.0) >= RATE_P1


@pytest.mark.slow
@pytest.mark.parametrize("pe", [0.5, 1.0, 2.0, 5.0, 10.0])
def test_p1_supg_order_sweep_on_a_wider_disk(pe):
    """The same on a disk twice as wide in cells (an annulus of 10 to 40 coarse cells)."""
    assert _observed_order(pe, [1.0, 0.5, 0.25], radius=60.0) >= RATE_P1


@pytest.fixture(scope="module")
def maze_wind():
    return WindField.potential(arenas.load("maze"), [((0.0, 4.0), (0.0, 28.0))],
                               [((140.0, 112.0), (140.0, 136.0))], speed=5.0, h=3.0)


@pytest.mark.parametrize("walls", ["impermeable", "absorbing"])
def test_reciprocity_forward_equals_adjoint_in_a_potential_flow(maze_wind, walls):
    """c(z; x) = v(x; z): the reading at z of a source at x is the adjoint of z read at x,
    with SUPG at a cell Péclet number above 1 and walls of either kind."""
    maze = arenas.load("maze")
    s = AdvectionSolver(maze, maze_wind, D=1.0, tau=40.0, walls=walls)
    assert maze_wind.peclet(s.h, s.D) > 1.0
    pts = maze.random_free_points(6, np.random.default_rng(3), clearance=1.0)
    forward = np.array([s.forward(x)(pts) for x in pts])       # [i, j]: source x_i, reading x_j
    adjoint = np.array([s.adjoint(z)(pts) for z in pts])       # [j, i]: reading x_j, source x_i
    assert np.abs(forward - adjoint.T).max() <= RECIPROCITY_REL * np.abs(forward).max()
    assert not np.allclose(forward, forward.T, rtol=1e-2)    # the wind breaks the symmetry
    # all readings from all candidate sources at once: one adjoint solve per reading
    batch = s.source_matrix(pts) @ s.adjoints(pts)            # [i, j]: source x_i, reading x_j
    assert np.abs(batch - forward).max() <= RECIPROCITY_REL * np.abs(forward).max()
    assert np.allclose(s.forwards(pts), np.column_stack([s.forward(x).dofs for x in pts]))


def test_the_plume_goes_downwind_and_impermeable_walls_keep_the_substance():
    arena = arenas.load("empty")
    source = np.array([50.0, 70.0])
    still = AdvectionSolver(arena, WindField.uniform((1.0, 0.0), 0.0), D=2.0, tau=30.0, h=5.0)
    c = still.forward(source)
    basis = still.space.basis
    # no wind, no flux through the walls: all that is released decays inside, ∫ c = τ
    assert float(np.sum(basis.interpolate(c.dofs) * basis.dx)) == pytest.approx(30.0, rel=1e-10)
    windy = AdvectionSolver(arena, WindField.uniform((1.0, 0.0), 3.0), D=2.0, tau=30.0, h=5.0)
    c = windy.forward(source)
    assert c([[80.0, 70.0]])[0] > 10 * c([[20.0, 70.0]])[0]
    assert windy.adjoint((80.0, 70.0))([source])[0] == pytest.approx(c([[80.0, 70.0]])[0], rel=1e-10)


def test_bad_input_messages():
    arena = arenas.load("empty")
    wind = WindField.uniform((1.0, 0.0), 1.0)
    with pytest.raises(ReciprocityError, match="walls must be one of"):
        AdvectionSolver(arena, wind, D=1.0, tau=10.0, h=10.0, walls="leaky")
    with pytest.raises(ReciprocityError, match="diffusivity D .* must be a positive number"):
        AdvectionSolver(arena, wind, D=0.0, tau=10.0, h=10.0)
    with pytest.raises(ReciprocityError, match="wind must be a WindField"):
        AdvectionSolver(arena, (1.0, 0.0), D=1.0, tau=10.0, h=10.0)
    s = AdvectionSolver(arena, wind, D=1.0, tau=10.0, h=10.0)
    with pytest.raises(ReciprocityError, match="outside the meshed free region"):
        s.forward((150.0, 70.0))
    with pytest.raises(ReciprocityError, match="outside the meshed free region"):
        s.adjoint((-1.0, 70.0))
