"""The painted floor: grey mapping, rendering, sampling, files."""

import json

import cv2
import matplotlib
import numpy as np
import pytest

import arenas
from arenas import Arena, ArenaError
from arenas.floor import Floor, GreyMapping, render_floor

matplotlib.use("Agg")

SQUARE = [[0, 0], [20, 0], [20, 20], [0, 20]]
OBSTACLE = [[12, 4], [16, 4], [16, 8], [12, 8]]
PEAK = np.array([6.0, 14.0])


def bump(points):
    """An analytic signal peaked at PEAK (no NaNs: render_floor masks the free region)."""
    return 100.0 * np.exp(-np.sum((np.asarray(points) - PEAK) ** 2, axis=1) / 50.0)


@pytest.fixture(scope="module")
def arena():
    return Arena.from_polygons(SQUARE, [OBSTACLE], name="box")


@pytest.fixture(scope="module")
def floor(arena):
    return render_floor(arena, bump, px_per_mm=0.5, outline_width_mm=4.0)


# ---------------------------------------------------------------- grey mapping
def test_mapping_round_trip_and_monotone():
    m = GreyMapping(u_max=80.0)
    g = np.linspace(m.g_min, 255.0, 301)
    assert np.allclose(m.grey(m.signal(g)), g)
    u = np.linspace(0.0, m.signal(255.0), 301)
    assert np.allclose(m.signal(m.grey(u)), u)
    assert np.all(np.diff(m.grey(np.linspace(-10, 500, 500))) >= 0)
    assert m.grey(m.u_max) == pytest.approx(m.g_max)


def test_mapping_clips_and_handles_nan():
    m = GreyMapping(u_max=10.0, g_min=30.0)
    assert m.grey([np.nan, -5.0, 0.0, 1e6]).tolist() == [30.0, 30.0, 30.0, 255.0]
    assert m.signal([0.0, 29.0, 30.0]).tolist() == [0.0, 0.0, 0.0]


def test_mapping_u_max_is_the_quantile():
    values = np.r_[np.arange(100_000, dtype=float), np.nan]
    m = GreyMapping.for_values(values, saturated_fraction=1e-3)
    assert m.u_max == pytest.approx(np.quantile(values[:-1], 0.999))
    assert np.mean(values[:-1] > m.u_max) == pytest.approx(1e-3, abs=1e-5)
    assert GreyMapping.for_values(values, g_min=20.0).g_min == 20.0


@pytest.mark.parametrize("kw, match", [
    ({"u_max": 0.0}, "u_max"), ({"u_max": 1.0, "g_min": 200.0}, "g_min"),
    ({"u_max": 1.0, "g_max": 300.0}, "g_max")])
def test_mapping_rejects_bad_parameters(kw, match):
    with pytest.raises(ArenaError, match=match):
        GreyMapping(**kw)


def test_for_values_rejects_empty_or_non_positive():
    with pytest.raises(ArenaError, match="no finite values"):
        GreyMapping.for_values([np.nan, np.nan])
    with pytest.raises(ArenaError, match="no positive signal"):
        GreyMapping.for_values(-np.ones(10))
    with pytest.raises(ArenaError, match="saturated_fraction"):
        GreyMapping.for_values(np.ones(10), saturated_fraction=1.0)


# ---------------------------------------------------------------- rendering
def test_render_covers_the_bounds(floor):
    assert floor.image.shape == (100, 100) and floor.image.dtype == np.uint8
    assert floor.px_per_cm == 5.0 and floor.origin == (0.0, 0.0)
    assert floor.extent == (0.0, 20.0, 0.0, 20.0)
    assert floor.arena_name == "box"
    assert not floor.image.flags.writeable


def test_free_pixels_carry_the_mapped_signal(floor):
    pix = np.array([[30, 30], [50, 70], [80, 20]])  # (col, row), all away from walls
    g = floor.image[pix[:, 1], pix[:, 0]]
    assert np.array_equal(g, np.rint(floor.mapping.grey(bump(floor.to_world(pix)))))


def test_brightness_increases_toward_the_peak(floor):
    t = np.linspace(0.0, 1.0, 60)[:, None]
    ray = np.array([18.0, 17.0]) * (1 - t) + PEAK * t  # free of the obstacle
    g = floor.grey_at(ray)
    assert np.all(np.diff(g) >= -1e-9)
    assert g[-1] > g[0] + 50
    # the source is painted at or above g_max (saturated)
    assert floor.grey_at(PEAK)[0] >= floor.mapping.g_max


def test_outlines_and_off_free_pixels(floor, arena):
    m = floor.mapping
    # obstacle interior: outside the free region, painted g_min
    assert floor.grey_at([14.0, 6.0])[0] == m.g_min
    # the outline sits on the walls, in outline_grey, with no anti-aliasing
    for wall in ([14.0, 8.0], [12.0, 6.0], [10.0, 0.1], [19.9, 10.0]):
        assert floor.grey_at(wall)[0] == 215
    # 4 mm at 5 px/cm = 2 px: one pixel beyond the obstacle's outline is painted signal
    assert floor.grey_at([14.0, 8.5])[0] not in (m.g_min, 215)
    assert set(np.unique(floor.image)) <= set(range(int(m.g_min), 256))


def test_mapping_can_be_given(arena):
    m = GreyMapping(u_max=50.0, g_min=10.0)
    f = render_floor(arena, bump, px_per_mm=0.25, mapping=m, outline_grey=230)
    assert f.mapping is m
    assert f.grey_at([14.0, 6.0])[0] == 10.0
    near_wall = f.to_pixel([14.0, 8.0]).round().astype(int)[0]
    assert f.image[near_wall[1] - 1:near_wall[1] + 2, near_wall[0]].max() == 230
    assert f.grey_at(PEAK)[0] == 255  # u = 100 > u_max


def test_image_rows_grow_downwards():
    """A feature painted at high y appears in a low row (row 0 is the top)."""
    a = Arena.from_polygons(SQUARE)
    f = render_floor(a, lambda p: p[:, 1], px_per_mm=0.5, outline_width_mm=0.0)
    col = f.image[5:-5, 50].astype(int)
    assert np.all(np.diff(col) <= 0) and col[0] > col[-1] + 100
    img = np.zeros((10, 8), np.uint8)
    img[1, :] = 200  # near the top of the picture
    g = Floor(img, 1.0, (0.0, 0.0), GreyMapping(1.0)).grey_at([[4.0, 8.5], [4.0, 1.5]])
    assert g.tolist() == [200.0, 0.0]


@pytest.mark.parametrize("bad, match", [
    ({"px_per_mm": -1.0}, "px_per_mm"), ({"px_per_mm": np.nan}, "px_per_mm"),
    ({"outline_grey": 300}, "outline_grey"), ({"outline_width_mm": -1.0}, "outline_width"),
    ({"chunk": 0}, "chunk"), ({"mapping": "grey"}, "GreyMapping")])
def test_render_rejects_bad_arguments(arena, bad, match):
    with pytest.raises(ArenaError, match=match):
        render_floor(arena, bump, **{"px_per_mm": 0.25, **bad})


def test_render_rejects_bad_fields(arena):
    with pytest.raises(ArenaError, match=r"one value per point"):
        render_floor(arena, lambda p: np.ones((len(p), 2)), px_per_mm=0.25)
    with pytest.raises(ArenaError, match="one value per point"):
        render_floor(arena, lambda p: 1.0, px_per_mm=0.25)
    with pytest.raises(ArenaError, match="callable"):
        render_floor(arena, np.ones(3), px_per_mm=0.25)
    with pytest.raises(ArenaError, match="arenas.Arena"):
        render_floor("box", bump)


def test_chunking_does_not_change_the_image(arena, floor):
    f = render_floor(arena, bump, px_per_mm=0.5, chunk=777)
    assert np.array_equal(f.image, floor.image)


# ---------------------------------------------------------------- sampling
def test_grey_at_pixel_centres_is_the_pixel(floor):
    rng = np.random.default_rng(1)
    pix = rng.integers(0, 100, size=(200, 2))
    assert np.array_equal(floor.grey_at(floor.to_world(pix)), floor.image[pix[:, 1], pix[:, 0]])


def test_grey_at_is_bilinear_and_nan_off_the_image():
    img = np.array([[0, 100], [50, 150]], np.uint8)
    f = Floor(img, 1.0, (10.0, 20.0), GreyMapping(1.0))
    # the image centre, between the four pixel centres
    assert f.grey_at([11.0, 21.0])[0] == pytest.approx(75.0)
    assert f.grey_at([10.0, 20.0])[0] == 50.0  # lower-left corner: edge pixel value
    assert np.isnan(f.grey_at([[9.9, 21.0], [11.0, 22.1]])).all()


def test_spot_grey(floor):
    c = floor.to_world([[30, 30], [60, 80]])
    assert np.allclose(floor.spot_grey(c, 0.0), floor.grey_at(c))
    half = np.zeros((40, 40), np.uint8)
    half[:, 20:] = 200
    f = Floor(half, 10.0, (0.0, 0.0), GreyMapping(1.0))
    g = f.spot_grey([[2.0, 2.0], [0.5, 2.0], [3.5, 2.0]], radius=0.5)
    assert g[0] == pytest.approx(100.0, abs=3.0)  # half the disk on each side
    assert g[1] == 0.0 and g[2] == 200.0
    assert np.isnan(f.spot_grey([[50.0, 50.0]], 0.3)[0])
    with pytest.raises(ArenaError, match="radius"):
        f.spot_grey([[2.0, 2.0]], -1.0)


# ---------------------------------------------------------------- files
def test_save_load_round_trip(floor, tmp_path):
    path = floor.save(tmp_path / "box.png")
    assert path == tmp_path / "box.png" and path.with_suffix(".json").is_file()
    back = Floor.load(path)
    assert np.array_equal(back.image, floor.image)
    assert (back.px_per_cm, back.origin, back.mapping, back.arena_name) == (
        floor.px_per_cm, floor.origin, floor.mapping, floor.arena_name)


def test_load_errors(floor, tmp_path):
    path = floor.save(tmp_path / "f.png")
    with pytest.raises(ArenaError, match="does not exist"):
        Floor.load(tmp_path / "nope.png")
    with pytest.raises(ArenaError, match="not a .png"):
        Floor.load(tmp_path / "f.jpg")
    with pytest.raises(ArenaError, match="saved as PNG"):
        floor.save(tmp_path / "f.jpg")
    (tmp_path / "text.png").write_text("not an image")
    with pytest.raises(ArenaError, match="corrupt or not a PNG"):
        Floor.load(tmp_path / "text.png")
    cv2.imwrite(str(tmp_path / "colour.png"), np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(ArenaError, match="not an 8-bit grey"):
        Floor.load(tmp_path / "colour.png")
    cv2.imwrite(str(tmp_path / "alone.png"), np.zeros((4, 4), np.uint8))
    with pytest.raises(ArenaError, match="sidecar .* is missing"):
        Floor.load(tmp_path / "alone.png")
    path.with_suffix(".json").write_text("{broken")
    with pytest.raises(ArenaError, match="corrupt"):
        Floor.load(path)
    meta = {"format": "arenas.floor/1", "px_per_cm": 5.0, "origin": [0, 0],
            "mapping": {"u_max": 1.0}, "arena_name": "box", "shape": [3, 3]}
    path.with_suffix(".json").write_text(json.dumps(meta))
    with pytest.raises(ArenaError, match="do not belong together"):
        Floor.load(path)


def test_floor_validates_its_fields():
    with pytest.raises(ArenaError, match="uint8"):
        Floor(np.zeros((3, 3)), 1.0, (0, 0), GreyMapping(1.0))
    with pytest.raises(ArenaError, match="px_per_cm"):
        Floor(np.zeros((3, 3), np.uint8), 0.0, (0, 0), GreyMapping(1.0))


def test_plot_uses_world_extent(floor):
    import matplotlib.pyplot as plt

    ax = floor.plot()
    im = ax.get_images()[0]
    assert tuple(im.get_extent()) == floor.extent
    assert im.get_clim() == (0, 255)
    plt.close(ax.figure)


def test_floors_of_one_arena_share_their_free_pixels(arena):
    """Two fields painted on one arena (a campaign's episodes) find the free pixels once, and
    the shared grid is the arena's own ``contains`` at the pixel centres."""
    from arenas.floor import free_pixels
    from arenas.frames import pixel_to_world

    free_pixels.cache_clear()
    a = render_floor(arena, lambda p: 100 - p[:, 0], px_per_mm=0.5)
    b = render_floor(arena.with_scenario(source=(5.0, 5.0)), lambda p: 1 + p[:, 1], px_per_mm=0.5)
    info = free_pixels.cache_info()
    assert (info.hits, info.misses) == (1, 1)
    free, centres = free_pixels(arena.without_scenario(), 5.0)
    h, w = a.image.shape
    rows, cols = np.mgrid[0:h, 0:w]
    origin = (arena.bounds[0][0], arena.bounds[1][0])
    every = pixel_to_world(np.column_stack([cols.ravel(), rows.ravel()]), 0.2, h, origin)
    np.testing.assert_array_equal(free, arena.contains(every))
    np.testing.assert_array_equal(centres, every[free])
    assert not free.flags.writeable and not centres.flags.writeable
    assert b.image.shape == a.image.shape


def _centres(arena, px_per_cm):
    import math
    from arenas.frames import pixel_to_world
    (x0, x1), (y0, y1) = arena.bounds
    w = max(1, math.ceil((x1 - x0) * px_per_cm - 1e-6))
    h = max(1, math.ceil((y1 - y0) * px_per_cm - 1e-6))
    rows, cols = np.mgrid[0:h, 0:w]
    return (h, w), pixel_to_world(np.column_stack([cols.ravel(), rows.ravel()]), 1.0 / px_per_cm, h, (x0, y0))


@pytest.mark.parametrize("which", ["paper", "maze", "disk", "deep_u", "rooms", "spiral", "ring",
                                   "pillars", "office", "specks"])
@pytest.mark.parametrize("px_per_cm", [1.7, 3.0])
def test_free_pixels_are_those_the_arena_contains(which, px_per_cm):
    """The rasterised free region, with the band along the walls asked of the arena itself,
    gives arena.contains to the pixel: built-in and generated arenas, and obstacles
    smaller than a pixel or thinner than one; and the free centres are those of every
    pixel, to the bit."""
    from arenas.floor import _free_centres, free_pixels
    if which == "specks":
        arena = Arena.from_polygons(
            [(0, 0), (50, 0), (50, 40), (0, 40)],
            [[(10, 10), (10.2, 10), (10.2, 10.2), (10, 10.2)],          # under a pixel
             [(20, 5), (20.1, 5), (20.1, 35), (20, 35)],                 # a wall thinner than one
             [(30, 10), (40, 10), (40, 30), (30, 30)]])
    elif which in ("paper", "maze", "disk", "deep_u"):
        arena = arenas.load(which)
    else:
        arena = arenas.generate(which, 2)
    shape, centres = _centres(arena, px_per_cm)
    truth = arena.contains(centres)
    assert np.array_equal(_free_centres(arena, px_per_cm, shape, lambda idx: centres[idx]), truth)
    free, inside = free_pixels(arena, px_per_cm)
    assert np.array_equal(free, truth) and np.array_equal(inside, centres[truth])
