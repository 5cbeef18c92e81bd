"""Fixtures shared by the whole suite."""

import cv2
import numpy as np
import pytest


def _pixels_near(path, rgb, tol: int = 40) -> int:
    """Number of pixels of the PNG at `path` within `tol` (per channel) of colour `rgb`."""
    img = cv2.imread(str(path), cv2.IMREAD_COLOR)
    assert img is not None, f"{path} is not a readable image"
    bgr = np.array(rgb[::-1], dtype=int)
    return int(np.all(np.abs(img.astype(int) - bgr) <= tol, axis=2).sum())


def _video_frames(path) -> list:
    """Every frame (BGR) of the video at `path`, as OpenCV decodes it."""
    cap = cv2.VideoCapture(str(path))
    frames = []
    while True:
        ok, frame = cap.read()
        if not ok:
            break
        frames.append(frame)
    cap.release()
    return frames


@pytest.fixture
def video_frames():
    """``video_frames(path)``: the frames of a video, to count and compare them."""
    return _video_frames


@pytest.fixture(scope="session", autouse=True)
def _private_cache(tmp_path_factory):
    """Tests keep meshes in a cache of their own, never the user's."""
    import os
    old = os.environ.get("RECIPROCITY_CACHE")
    os.environ["RECIPROCITY_CACHE"] = str(tmp_path_factory.mktemp("cache"))
    yield
    if old is None:
        os.environ.pop("RECIPROCITY_CACHE", None)
    else:
        os.environ["RECIPROCITY_CACHE"] = old


@pytest.fixture
def pixels_near():
    """``pixels_near(path, (r, g, b), tol=40)``: how much of a figure shows a colour, so a
    test asserts what a figure shows (a marker, a path), not that a file exists."""
    return _pixels_near
