"""ROS map_server maps: read as arenas wherever an arena is taken, written from arenas, on
occupancy grids drawn here."""

import cv2
import numpy as np
import pytest
import yaml

import arenas
from arenas import ArenaError
from arenas.ros_map import free_cells

#: map_server's grey levels: free, occupied, unknown.
FREE, OCC, UNKNOWN = 254, 0, 205


def _grid() -> np.ndarray:
    """A 40 x 60 cell map (rows x cols): unknown around, a wall ring, free inside, a table
    (occupied) and a pillar of unknown cells in the room."""
    g = np.full((40, 60), UNKNOWN, np.uint8)
    g[2:38, 2:58] = OCC                 # the walls
    g[3:37, 3:57] = FREE                # the room: 34 x 54 cells
    g[10:16, 10:22] = OCC               # a table, 6 x 12 cells
    g[25:29, 40:44] = UNKNOWN           # a pillar nobody scanned, 4 x 4 cells
    return g


def _write(folder, grid, *, name="lab", image=None, **keys) -> str:
    meta = {"image": image or f"{name}.pgm", "resolution": 0.05, "origin": [-1.0, -0.5, 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196, **keys}
    if grid is not None:
        cv2.imwrite(str(folder / meta["image"]), grid)
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(meta))
    return str(path)


def test_a_drawn_map_reads_as_the_room_in_cm(tmp_path):
    a = arenas.load(_write(tmp_path, _grid()))
    # 5 cm cells; the image's lower-left corner at (-100, -50) cm; the room spans cols 3-56
    # and rows 3-36 (row 0 at the top: y from (40 - 37) * 5 - 50 = -35 to (40 - 3) * 5 - 50 = 135)
    lo, hi = a.boundary.min(axis=0), a.boundary.max(axis=0)
    assert np.allclose(lo, [-100 + 3 * 5, -35], atol=0.01) and np.allclose(hi, [-100 + 57 * 5, 135], atol=0.01)
    assert len(a.obstacles) == 2                                   # the table and the unknown pillar
    room, table, pillar = 34 * 54 * 25, 6 * 12 * 25, 4 * 4 * 25
    assert a.area == pytest.approx(room - table - pillar, rel=0.01)
    assert not a.contains([(-100 + 16 * 5, 135 - 10 * 5)])[0]     # inside the table
    assert a.name == "lab"


def test_negate_and_png_give_the_same_arena(tmp_path):
    a = arenas.load(_write(tmp_path, _grid()))
    b = arenas.load(_write(tmp_path, 255 - _grid(), name="neg", image="neg.png", negate=1))
    assert a.free_region.symmetric_difference(b.free_region).area < 1e-6


def test_the_thresholds_are_those_of_map_server():
    grey = np.array([[0, 100, 200, 254]], np.uint8)       # p = 1, 0.61, 0.22, 0.004
    assert free_cells(grey).tolist() == [[False, False, False, True]]
    assert free_cells(grey, free_thresh=0.3, occupied_thresh=0.9).tolist() == [[False, False, True, True]]
    assert free_cells(grey, negate=True).tolist() == [[True, False, False, False]]
    assert free_cells(np.array([[0, 10, 50, 100]], np.uint8), mode="raw").tolist() == [[True, True, False, False]]
    assert free_cells(grey, unknown="free").tolist() == [[False, True, True, True]]
    assert free_cells(grey, unknown="free", occupied_thresh=0.5).tolist() == [[False, False, True, True]]


def test_unknown_cells_may_be_taken_for_free_space(tmp_path):
    a = arenas.load(_write(tmp_path, _grid(), unknown="free"))
    assert len(a.obstacles) == 1                           # the table; the pillar is free
    assert a.area == pytest.approx((34 * 54 - 6 * 12) * 25, rel=0.01)


def test_grey_cells_between_the_thresholds_are_obstacles_unless_free(tmp_path):
    g = _grid()
    g[10:16, 10:22] = 100                                  # the table at p = 0.61: unknown
    assert len(arenas.load(_write(tmp_path, g)).obstacles) == 2
    loose = arenas.load(_write(tmp_path, g, name="loose", free_thresh=0.7, occupied_thresh=0.9))
    assert len(loose.obstacles) == 0                       # the table (0.61) and the pillar (0.2) free
    assert loose.area == pytest.approx(34 * 54 * 25)


@pytest.mark.parametrize("name", ["paper", "maze", "disk", "deep_u"])
def test_an_arena_written_as_a_map_reads_back_within_a_cell(name, tmp_path):
    arena = arenas.load(name)
    path = arenas.to_ros_map(arena, tmp_path / f"{name}.yaml", resolution=0.01)
    meta = yaml.safe_load(path.read_text())
    assert meta["image"] == f"{name}.pgm" and (tmp_path / f"{name}.pgm").is_file()
    assert {"resolution", "origin", "negate", "occupied_thresh", "free_thresh"} <= set(meta)
    back = arenas.load(path)
    assert back.free_region.hausdorff_distance(arena.free_region) <= 1.5        # cm: 1.5 cells
    assert back.area == pytest.approx(arena.area, rel=0.01)


def test_a_written_map_has_map_savers_grey_levels(tmp_path):
    path = arenas.to_ros_map(arenas.load("paper"), tmp_path / "p.yaml", resolution=0.02)
    grey = cv2.imread(str(tmp_path / "p.pgm"), cv2.IMREAD_UNCHANGED)
    assert grey.shape == (70, 70) and set(np.unique(grey)) == {OCC, FREE}
    assert yaml.safe_load(path.read_text())["origin"] == [0.0, 0.0, 0.0]


def test_the_simplification_keeps_the_arena_limits(tmp_path, monkeypatch):
    import arenas.ros_map as rm
    g = np.full((60, 60), FREE, np.uint8)
    g[5:55:4, 5:55:4] = OCC                                # 169 one-cell specks
    g[30:34, 30:34] = OCC                                  # and one block of 16 cells
    assert len(arenas.load(_write(tmp_path, g)).obstacles) > 150
    monkeypatch.setattr(rm, "MAX_OBSTACLES", 50)
    a = arenas.load(_write(tmp_path, g))
    assert len(a.obstacles) in range(1, 51)                # the specks go first, the block stays
    assert not a.contains([a.obstacles[0].mean(axis=0)])[0]


@pytest.mark.parametrize("change, words", [
    ({"image": "nowhere.pgm"}, "cannot read image"),
    ({"free_thresh": 0.7}, "'free_thresh' (0.7) must be below 'occupied_thresh' (0.65)"),
    ({"occupied_thresh": 1.5}, "'occupied_thresh' must be a number in [0, 1]; got 1.5"),
    ({"negate": 2}, "'negate' must be 0 or 1; got 2"),
    ({"resolution": -0.05}, "'resolution' (m per pixel) must be a number in (0, 1000]"),
    ({"origin": [0, 0, 7]}, "'origin' yaw (rad) must be a number in [-6.28319, 6.28319]; got 7"),
    ({"origin": "here"}, "'origin' must be [x, y, yaw]"),
    ({"mode": "fuzzy"}, "'mode' must be one of trinary, scale, raw; got 'fuzzy'"),
    ({"colour": "red"}, "unknown key(s) ['colour']"),
    ({"unknown": "maybe"}, "'unknown' must be one of obstacle, free; got 'maybe'"),
])
def test_bad_maps_fail_with_one_line(change, words, tmp_path):
    path = _write(tmp_path, None if "image" in change else _grid(), **change)
    with pytest.raises(ArenaError) as e:
        arenas.load(path)
    assert words in str(e.value) and "\n" not in str(e.value)


def test_a_map_with_no_free_cell_or_a_huge_image_is_refused(tmp_path):
    with pytest.raises(ArenaError, match="no free cell"):
        arenas.load(_write(tmp_path, np.full((20, 20), OCC, np.uint8)))
    with pytest.raises(ArenaError, match="more than 16777216 pixels"):
        arenas.load(_write(tmp_path, np.full((4097, 4097), FREE, np.uint8), name="huge"))


@pytest.mark.parametrize("flag", ["--arena", "--scenario"])
def test_the_command_line_takes_a_map(flag, tmp_path, monkeypatch, capsys):
    from reciprocity.cli import main
    monkeypatch.chdir(tmp_path)
    path = _write(tmp_path, _grid())
    assert main(["run", flag, path, "--strategy", "random-walk", "--source", "150,60", "--start=-50,20",
                 "--h", "5", "--set", "n_steps=2", "--quiet"]) == 0
    assert capsys.readouterr().out.splitlines()[-1].startswith("success: no — step cap reached")
    for bad, words in ((_write(tmp_path, _grid(), name="bad", free_thresh=0.9), "free_thresh"),
                       (_write(tmp_path, None, name="lost", image="lost.pgm"), "cannot read image")):
        assert main(["run", flag, bad, "--strategy", "random-walk", "--source", "150,60"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error: ") and words in err[0], err


def test_a_map_file_may_carry_the_source_and_the_start(tmp_path):
    a = arenas.load(_write(tmp_path, _grid(), source=[150, 60], strength=600, start=[-50, 20, 90]))
    assert a.source.tolist() == [150.0, 60.0] and a.strength == 600.0
    assert np.allclose(a.start, [-50.0, 20.0, np.pi / 2])
    for bad, words in (({"source": "here"}, "'source' must be [x, y]"), ({"start": [1, 2, 3, 4]}, "'start' must be"),
                       ({"strength": -1}, "strength must be a number in (0"),
                       ({"source": [-99, -40]}, "source (-99, -40) cm is outside the arena")):
        with pytest.raises(ArenaError) as e:
            arenas.load(_write(tmp_path, _grid(), name="bad", **bad))
        assert words in str(e.value) and "\n" not in str(e.value), str(e.value)


def test_a_yaw_turns_the_map_about_its_origin(tmp_path):
    """The ROS spec: origin is the pose of the lower-left pixel; yaw turns the image about it."""
    flat = arenas.load(_write(tmp_path, _grid(), origin=[1.0, 2.0, 0.0]))
    turned = arenas.load(_write(tmp_path, _grid(), name="turned", origin=[1.0, 2.0, np.pi / 2]))
    x, y = (flat.boundary - [100.0, 200.0]).T                  # about the origin, in cm
    expect = np.column_stack([100.0 - y, 200.0 + x])           # a quarter turn counter-clockwise
    assert turned.area == pytest.approx(flat.area)
    assert np.allclose(np.sort(turned.boundary, axis=0), np.sort(expect, axis=0), atol=1e-6)
