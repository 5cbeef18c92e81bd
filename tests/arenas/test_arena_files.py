"""Arena files: YAML round trip and malformed-file messages; image import."""

import cv2
import numpy as np
import pytest

import arenas
from arenas import ArenaError


def test_yaml_round_trip(tmp_path):
    for name in arenas.builtin_names():
        a = arenas.load(name)
        path = arenas.save(a, tmp_path / f"{name}.yaml")
        b = arenas.load(path)
        assert np.allclose(a.boundary, b.boundary)
        assert all(np.allclose(o, p) for o, p in zip(a.obstacles, b.obstacles))
        assert np.allclose(a.source, b.source) and np.allclose(a.start, b.start)
        assert a.circle == b.circle and a.strength == b.strength


def _write(tmp_path, text):
    p = tmp_path / "a.yaml"
    p.write_text(text)
    return p


@pytest.mark.parametrize("text, match", [
    ("obstacles: []\n", "exactly one of 'boundary'"),
    ("boundary: [[0, 0], [1, 0], [1, 1]]\nwalls: 3\n", "unknown key"),
    ("boundary: [[0, 0], [1, 0], [1, one]]\n", "must be a number"),
    ("boundary: [[0, 0], [1, 0], [1, .nan]]\n", "must be a number in \\[-100000, 100000\\]"),
    ("boundary: [[0, 0], [1, 0], [1, 1]]\nsource: [0.5]\n", "'source' must be"),
    ("boundary: [[0, 0], [1, 0], [1, 1]]\nstrength: true\n", "must be a number"),
    ("boundary: [[0, 0], [10, 0], [10, 10]]\nstart: [1, 2, 3, 4]\n", "'start' must be"),
    ("disk: {center: [0, 0]}\n", "'disk' must be"),
    ("- 1\n- 2\n", "must hold a mapping"),
    ("boundary: [[0, 0], [1, 0]\n", "not valid YAML"),
    ("!!python/object/apply:os.system ['true']\n", "not valid YAML"),
])
def test_malformed_files_are_explained(tmp_path, text, match):
    with pytest.raises(ArenaError, match=match):
        arenas.load(_write(tmp_path, text))


def test_unknown_name():
    with pytest.raises(ArenaError, match="built-ins are"):
        arenas.load("no-such-arena")


def test_start_heading_in_file_is_degrees(tmp_path):
    a = arenas.load(_write(tmp_path, "boundary: [[0, 0], [10, 0], [10, 10], [0, 10]]\nstart: [1, 2, 90]\n"))
    assert a.start[2] == pytest.approx(np.pi / 2)


def test_from_image_recovers_drawn_obstacles(tmp_path):
    img = np.full((280, 280), 255, np.uint8)  # 0.5 cm per pixel: a 140 cm floor
    cv2.rectangle(img, (40, 40), (99, 79), 0, -1)            # 30 x 20 cm block
    cv2.fillPoly(img, [np.array([[150, 150], [250, 150], [250, 250], [230, 250],
                                 [230, 170], [150, 170]])], 0)  # an L
    cv2.rectangle(img, (0, 200), (59, 209), 0, -1)          # a wall on the left edge
    path = tmp_path / "plan.png"
    cv2.imwrite(str(path), img)
    a = arenas.from_image(path, cm_per_px=0.5, source=(100, 100))
    assert a.name == "plan" and len(a.obstacles) == 3
    dark = (img < 128).sum() * 0.25
    assert a.area == pytest.approx(140 * 140 - dark, rel=0.02)
    # pixel rows run downward, y upward: the block (rows 40-79) sits near the top
    block = min(a.obstacles, key=lambda o: abs(o[:, 0].mean() - 35))
    assert 100 < block[:, 1].mean() < 125


def test_from_image_rejects_bad_input():
    with pytest.raises(ArenaError, match=r"cm_per_px must be a number in \(0, 100000\]"):
        arenas.from_image(np.zeros((10, 10)), cm_per_px=0)
    with pytest.raises(ArenaError, match="cannot read image"):
        arenas.from_image("missing.png", cm_per_px=1)
