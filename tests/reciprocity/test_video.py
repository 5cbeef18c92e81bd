"""The episode video: frame count and size, the car where it is, both layouts, bad input."""

import json

import cv2
import numpy as np
import pytest
from matplotlib.tri import LinearTriInterpolator, Triangulation

import arenas
from reciprocity.episode import Episode
from reciprocity.errors import SearchError
from reciprocity.viz.video import GAP_PX, _Canvas, _ImagingRaster, write_video

SOURCE = [30.0, 22.0]
FPS, SPEEDUP, PX = 10, 2.0, 4


@pytest.fixture(scope="module")
def arena():
    return arenas.Arena.from_polygons([[0, 0], [40, 0], [40, 30], [0, 30]],
                                      [[[15, 10], [25, 10], [25, 20], [15, 20]]], name="box")


@pytest.fixture(scope="module")
def floor():
    """A grey ramp at 2 px/cm (resized by the writer): darker toward the source."""
    x = np.linspace(0.0, 1.0, 80)
    return np.tile(np.round(60 + 150 * x[::-1]).astype(np.uint8), (60, 1))


def _poses(times, start, end, heading):
    s = (times - times[0]) / (times[-1] - times[0])
    xy = np.asarray(start) + s[:, None] * (np.asarray(end) - np.asarray(start))
    return np.column_stack([xy, np.full(len(times), heading)])


def _measurement(point, time):
    return {"point": list(point), "true_point": list(point), "counts": [500, 502],
            "intensity": 80.0, "saturated": False, "time": time}


@pytest.fixture(scope="module")
def episode():
    """Along the bottom (2 s), up the right side (2 s, a re-plan and a bump), a refusal."""
    t1 = np.linspace(0.05, 2.0, 40)
    p1 = _poses(t1, [5.0, 5.0], [33.0, 5.0], 0.0)
    t2 = np.linspace(2.05, 4.0, 40)
    p2 = _poses(t2, [34.0, 6.0], [34.0, 24.0], np.pi / 2)
    rec1 = {"step": 1, "kind": "signal", "times": t1, "true_poses": p1,
            "estimated_poses": p1 + 0.3, "replans": [list(p1[0] + 0.3)],
            "plans": [[[5, 5], [20, 5], [33, 5]]],
            "measurements": [_measurement(p1[-1, :2], 2.0)], "collisions": [],
            "estimate": np.array([20.0, 15.0]), "next": [34.0, 24.0],
            "targets": np.array([[33.0, 5.0]])}
    rec2 = {"step": 2, "kind": "signal", "times": t2, "true_poses": p2,
            "estimated_poses": p2 - 0.2, "replans": np.array([p2[0] - 0.2, p2[20] - 0.2]),
            "plans": [[[34, 6], [34, 24]], [[34, 15], [34, 24]]],
            "measurements": [_measurement(p2[-1, :2], 4.0)],
            "collisions": [{"time": 3.0, "x": 36.0, "y": 15.0}],
            "estimate": [31.0, 21.0], "next": [10.0, 25.0], "targets": [[34.0, 24.0]]}
    rec3 = {"step": 3, "kind": "unreachable", "times": np.empty(0),
            "true_poses": np.empty((0, 3)), "estimated_poses": np.empty((0, 3)), "replans": [],
            "plans": [], "measurements": [], "collisions": [], "targets": [[20.0, 15.0]]}
    summary = {"strategy": "reciprocity", "source": SOURCE, "estimate": [31.0, 21.0],
               "error": 1.4, "n_measurements": 2, "n_samples": 2, "path_length": 46.0}
    return Episode(summary, [rec1, rec2, rec3])


class BumpImaging:
    """An imaging-map stand-in: a Gaussian bump at the source that sharpens with k."""

    def __init__(self, n=2):
        x, y = np.meshgrid(np.linspace(0, 40, 21), np.linspace(0, 30, 16))
        self.nodes = np.column_stack([x.ravel(), y.ravel()])
        self.triangles = Triangulation(self.nodes[:, 0], self.nodes[:, 1]).triangles
        self.n, self.k, self.asked = n, n, []

    def first(self, k):
        self.asked.append(k)
        other = BumpImaging(self.n)
        other.k = k
        return other

    def values(self):
        d2 = np.sum((self.nodes - SOURCE) ** 2, axis=1)
        return np.exp(-d2 / (200.0 / self.k))


def _expected_frames(end=4.0):
    return int(np.floor(end * FPS / SPEEDUP + 1e-9)) + 1 + FPS


def _car_pixel(frame_height, pose):
    """Pixel (row, col) in the left panel 1.5 cm behind the car's centre (inside the body;
    the heading mark runs forward from the centre)."""
    behind = np.asarray(pose[:2]) - 1.5 * np.array([np.cos(pose[2]), np.sin(pose[2])])
    col, row = arenas.world_to_pixel(behind, 1 / PX, 30 * PX)[0]
    header = frame_height - 30 * PX - frame_height % 2
    return round(row) + header, round(col)


def test_floor_video_has_the_frames_and_shows_the_car(tmp_path, arena, floor, episode, video_frames):
    out = write_video(tmp_path / "run.mp4", episode, arena, floor, fps=FPS, speedup=SPEEDUP,
                      px_per_cm=PX)
    assert out == tmp_path / "run.mp4"
    frames = video_frames(out)
    assert len(frames) == _expected_frames()
    h, w = frames[0].shape[:2]
    assert w == 40 * PX and h % 2 == 0 and h > 30 * PX
    last = frames[-1].astype(int)
    r, c = _car_pixel(h, episode.trace[1]["true_poses"][-1])
    # amber car body (B ~ 0, R ~ 255) over a grey floor (B = R)
    assert last[r, c, 2] - last[r, c, 0] > 100
    # the car has left its first position: the floor there is grey again
    r0, c0 = _car_pixel(h, episode.trace[0]["true_poses"][0])
    assert abs(last[r0, c0, 2] - last[r0, c0, 0]) < 40
    assert abs(frames[0][r0, c0, 2].astype(int) - frames[0][r0, c0, 0]) > 100


def test_imaging_panel_is_drawn_beside_the_floor(tmp_path, arena, floor, episode, video_frames):
    imaging = BumpImaging()
    out = write_video(tmp_path / "run.mp4", episode, arena, floor, imaging=imaging, fps=FPS,
                      speedup=SPEEDUP, px_per_cm=PX)
    frames = video_frames(out)
    assert len(frames) == _expected_frames()
    h, w = frames[0].shape[:2]
    assert w == 2 * 40 * PX + GAP_PX and h % 2 == 0
    assert set(imaging.asked) == {1, 2}
    header = h - 30 * PX
    right = slice(40 * PX + GAP_PX, w)
    # no measurement yet: the imaging panel is dark; at the end the bump is hot (red)
    assert frames[0][header:, right].mean() < 60
    col, row = arenas.world_to_pixel([SOURCE[0] + 3, SOURCE[1]], 1 / PX, 30 * PX)[0]
    hot = frames[-1][header + int(row), 40 * PX + GAP_PX + int(col)].astype(int)
    assert hot[2] > 150 and hot[0] < 100


def test_raster_matches_linear_interpolation(arena):
    imaging = BumpImaging()
    canvas = _Canvas(arena, 2.0)
    img = _ImagingRaster(imaging, canvas).colours(2)
    rows, cols = np.mgrid[0:canvas.height, 0:canvas.width]
    xy = arenas.pixel_to_world(np.column_stack([cols.ravel(), rows.ravel()]), 0.5,
                               canvas.height)
    tri = Triangulation(imaging.nodes[:, 0], imaging.nodes[:, 1], imaging.triangles)
    P = LinearTriInterpolator(tri, imaging.values())(xy[:, 0], xy[:, 1]).filled(np.nan)
    grey = np.round(np.clip(np.nan_to_num(P), 0, 1) * 255).astype(np.uint8)
    expected = cv2.applyColorMap(grey.reshape(img.shape[:2]), cv2.COLORMAP_JET)
    expected[np.isnan(P).reshape(img.shape[:2])] = 0
    assert np.abs(img.astype(int) - expected).max() <= 4  # rounding at .5 only


def test_json_roundtripped_trace_gives_the_same_video_length(tmp_path, arena, floor, episode, video_frames):
    data = json.loads(episode.to_json())
    trace = data.pop("trace")
    assert isinstance(trace[0]["true_poses"], list)
    out = write_video(tmp_path / "json.mp4", Episode(data, trace), arena, floor,
                      imaging=BumpImaging(), fps=FPS, speedup=SPEEDUP, px_per_cm=PX,
                      progress=True)
    assert len(video_frames(out)) == _expected_frames()


def test_bad_inputs_raise(tmp_path, arena, floor, episode):
    with pytest.raises(SearchError, match=r"\.mp4"):
        write_video(tmp_path / "run.avi", episode, arena, floor)
    record = {"step": 1, "kind": "signal", "points": [[1.0, 2.0]], "readings": [3.0],
              "estimate": None}
    point = Episode(episode.summary, [record])
    with pytest.raises(SearchError, match="no car trace"):
        write_video(tmp_path / "run.mp4", point, arena, floor)
    with pytest.raises(SearchError, match="floor_image"):
        write_video(tmp_path / "run.mp4", episode, arena, floor.astype(float))
    with pytest.raises(SearchError, match="speedup"):
        write_video(tmp_path / "run.mp4", episode, arena, floor, speedup=0.0)
    (tmp_path / "taken.mp4").mkdir()
    with pytest.raises(SearchError, match="cannot open"):
        write_video(tmp_path / "taken.mp4", episode, arena, floor)


def test_the_walls_the_car_plans_on_are_drawn_from_the_time_they_became_current(tmp_path, arena, floor, episode,
                                                                                 video_frames):
    """An unknown map: the trace's ``maps`` (believed walls from 1 s, scanned walls from
    3 s) are drawn over the floor from their time on; the true walls stay as they were."""
    believed = [[2.0, 20.0], [10.0, 20.0], [10.0, 28.0], [2.0, 28.0]]
    scanned = [[28.0, 12.0], [32.0, 12.0], [32.0, 16.0], [28.0, 16.0]]
    trace = [dict(r) for r in episode.trace]
    trace[0]["maps"] = [{"time": 1.0, "walls": "believed", "obstacles": [believed]}]
    trace[1]["maps"] = [{"time": 3.0, "walls": "scanned", "obstacles": [scanned]}]
    mapped = Episode(episode.summary, trace)
    out = write_video(tmp_path / "map.mp4", mapped, arena, floor, fps=FPS, speedup=SPEEDUP, px_per_cm=PX)
    frames = [f.astype(int) for f in video_frames(out)]
    h = frames[0].shape[0]
    header = h - 30 * PX - h % 2

    def pixel(frame, x, y):
        col, row = arenas.world_to_pixel([x, y], 1 / PX, 30 * PX)[0]
        return frame[header + int(row), int(col)]

    def tinted(p, kind):                       # towards the kind's colour from a grey floor
        b, g, r = p
        return b - g > 25 and r - g > 10 if kind == "believed" else b - r > 25 and g - r > 25

    at = {t: int(round(t * FPS / SPEEDUP)) for t in (0.5, 1.5, 3.5)}
    assert not tinted(pixel(frames[at[0.5]], 6, 24), "believed")           # not yet current
    assert tinted(pixel(frames[at[1.5]], 6, 24), "believed")
    assert not tinted(pixel(frames[at[1.5]], 30, 14), "scanned")
    assert tinted(pixel(frames[at[3.5]], 30, 14), "scanned")
    assert not tinted(pixel(frames[at[3.5]], 6, 24), "believed")           # replaced by the scanned walls
    cv2.imwrite(str(tmp_path / "frame.png"), frames[at[3.5]].astype(np.uint8))
