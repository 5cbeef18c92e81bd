"""Potential-flow wind through an arena: no flow through walls, flux conserved, bad segments refused."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import arenas
from reciprocity.errors import ReciprocityError
from reciprocity.fem import WindField

#: Inflow speed, cm/s.
U = 10.0
#: The maze's serpentine: wind enters the bottom corridor on the left, leaves the top one on the right.
MAZE_IN, MAZE_OUT = [((0.0, 4.0), (0.0, 28.0))], [((140.0, 112.0), (140.0, 136.0))]
#: Inflow flux U × length, cm²/s.
MAZE_FLUX = U * 24.0
#: Points this far (cm) inside a wall stand for the wall.
INSIDE = 1e-3
#: Cross-section fluxes match the inflow to this relative error (mesh 2 cm).
FLUX_REL = 1e-3
#: |u·n| / U at wall midpoints on a 2 cm mesh ...
WALL_NORMAL_REL = 5e-3
#: ... and the inflow's normal speed at its middle, relative to U.
INFLOW_SPEED_REL = 2e-2
#: The flux read pointwise along the inflow segment, relative to U × length (2 cm mesh).
INFLOW_FLUX_REL = 3e-2


@pytest.fixture(scope="module")
def maze_winds():
    maze = arenas.load("maze")
    return {h: WindField.potential(maze, MAZE_IN, MAZE_OUT, speed=U, h=h) for h in (4.0, 2.0)}


def _flux(wind, a, b, n=4000):
    """Flux of `wind` through the segment a -> b (cm²/s), positive to its left."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    t = (np.arange(n) + 0.5) / n
    pts = a + t[:, None] * (b - a)
    d = b - a
    normal = np.array([-d[1], d[0]])
    return float(np.sum(wind(pts) @ normal) / n)


def test_every_cross_section_carries_the_inflow(maze_winds):
    """Divergence free: all the inflow passes each corridor and each gap of the serpentine."""
    w = maze_winds[2.0]
    sections = [((5.0, 32.0), (5.0, 0.0)),          # the inflow corridor, left to right
                ((108.0, 35.0), (140.0, 35.0)),      # the gap round the first wall, upward
                ((70.0, 38.0), (70.0, 68.0)),        # the second corridor, right to left
                ((0.0, 71.0), (32.0, 71.0))]         # the gap round the second wall, upward
    for a, b in sections:
        assert _flux(w, a, b) == pytest.approx(MAZE_FLUX, rel=FLUX_REL)


def test_no_flow_through_the_walls_and_it_converges(maze_winds):
    x = np.linspace(10.0, 100.0, 10)
    # midpoints along the faces of the first and second walls (y = 32 below, y = 74 above)
    pts = np.vstack([np.column_stack([x, np.full(10, 32.0 - INSIDE)]),
                     np.column_stack([x + 30.0, np.full(10, 74.0 + INSIDE)])])
    normal = {h: np.abs(w(pts)[:, 1]).max() / U for h, w in maze_winds.items()}
    assert normal[2.0] < WALL_NORMAL_REL
    assert normal[2.0] < 0.7 * normal[4.0]
    # the wind along the same walls is of the order of the inflow
    assert np.abs(maze_winds[2.0](pts)[:, 0]).mean() > 0.3 * U


def test_the_inflow_is_the_speed_times_the_length(maze_winds):
    w = maze_winds[2.0]
    assert _flux(w, (5.0, 32.0), (5.0, 0.0)) == pytest.approx(MAZE_FLUX, rel=FLUX_REL)
    assert w([[INSIDE, 16.0]])[0] == pytest.approx([U, 0.0], abs=INFLOW_SPEED_REL * U)
    assert w([[140.0 - INSIDE, 124.0]])[0, 0] == pytest.approx(U, rel=INFLOW_SPEED_REL)  # same length out
    # the flux through the segment itself, read pointwise, converges to U × length (the weak
    # form imposes it exactly; the jump of u·n at the segment's ends is smeared over a cell)
    miss = {h: abs(_flux(w, (INSIDE, 28.0), (INSIDE, 4.0)) / MAZE_FLUX - 1) for h, w in maze_winds.items()}
    assert miss[2.0] < INFLOW_FLUX_REL and miss[2.0] < 0.6 * miss[4.0]


def test_unequal_segments_keep_the_flux_and_speed_and_peclet_are_reported():
    arena = arenas.load("empty")
    w = WindField.potential(arena, [((0.0, 40.0), (0.0, 100.0))], [((140.0, 60.0), (140.0, 80.0))],
                            speed=U, h=6.0)
    assert _flux(w, (70.0, 140.0), (70.0, 0.0)) == pytest.approx(60.0 * U, rel=FLUX_REL)
    assert w.max_speed > 60.0 * U / 20.0 * 0.9        # the outflow is three times faster
    assert w.peclet(1.0, 5.0) == pytest.approx(w.max_speed / 10.0)
    assert np.isnan(w([[-5.0, 70.0]])).all()
    assert w.node_velocity(w.solver.mesh).shape == (w.solver.mesh.p.shape[1], 2)
    assert w.element_velocity(w.solver.mesh).shape == (w.solver.mesh.t.shape[1], 2)


def test_uniform_wind():
    w = WindField.uniform((3.0, 4.0), 5.0)
    assert w([[1.0, 2.0], [3.0, 4.0]]).tolist() == [[3.0, 4.0], [3.0, 4.0]]
    assert WindField.uniform(np.pi / 2, 2.0)([[0.0, 0.0]])[0] == pytest.approx([0.0, 2.0])
    assert w.max_speed == 5.0 and w.peclet(2.0, 5.0) == 1.0


@pytest.mark.parametrize("inflow, outflow, message", [
    ([((10.0, 40.0), (10.0, 60.0))], MAZE_OUT, "inflow segment .* does not lie along one edge of the boundary"),
    ([((0.0, 20.0), (0.0, 50.0))], MAZE_OUT, "inflow segment .* runs along an obstacle attached to the boundary"),
    (MAZE_IN, [((140.0, 100.0), (140.0, 100.0))], "outflow segment .* has zero length"),
    ("left", MAZE_OUT, "inflow must be a list of segments"),
    (MAZE_IN, MAZE_IN, "overlaps outflow segment"),
])
def test_bad_segments_are_refused_with_one_line(inflow, outflow, message):
    with pytest.raises(ReciprocityError, match=message) as info:
        WindField.potential(arenas.load("maze"), inflow, outflow, speed=U, h=8.0)
    assert "\n" not in str(info.value)


def test_bad_speeds_and_directions():
    arena = arenas.load("empty")
    with pytest.raises(ReciprocityError, match="inflow speed must be a positive number"):
        WindField.potential(arena, MAZE_IN, MAZE_OUT, speed=0.0, h=8.0)
    with pytest.raises(ReciprocityError, match="wind direction must be a non-zero vector"):
        WindField.uniform((0.0, 0.0), 1.0)


def test_wind_figure(tmp_path, pixels_near):
    """examples/wind_figure.py draws both arenas' winds and the plumes at two Péclet numbers."""
    path = Path(__file__).resolve().parents[2] / "examples" / "wind_figure.py"
    spec = importlib.util.spec_from_file_location("wind_figure", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    pngs = mod.main(["--out", str(tmp_path), "--h", "4"])
    assert [p.name for p in pngs] == ["wind_paper.png", "wind_maze.png"]
    for png in pngs:
        assert png.stat().st_size > 20_000
        assert pixels_near(png, (255, 0, 0), 60) > 10      # the source's red star
