"""The video of a search on hit counts (``flow`` worlds): frames per reading, both layouts,
the observer moving, the command line, bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.cli import main
from reciprocity.errors import SearchError
from reciprocity.scenarios import from_dict
from reciprocity.viz.count_video import write_count_video

DUCT = {"name": "duct", "boundary": [[0, 0], [60, 0], [60, 40], [0, 40]],
        "obstacles": [[[28, 12], [34, 12], [34, 28], [28, 28]]]}
SCENARIO = {"world": "flow", "arena": DUCT, "source": [18, 22], "start": [50, 20, 90],
            "inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]], "speed": 1, "D": 5, "tau": 60,
            "strength": 100, "detector": 1, "truth_h": 1, "max_steps": 4}


@pytest.fixture(scope="module")
def scenario():
    return from_dict(SCENARIO, "duct-wind")


@pytest.fixture(scope="module")
def episodes(scenario):
    """A search with a posterior and one without, four readings each, with their records."""
    return {name: run(scenario, name, seed=1, params={"h": 2.0}, figures=True)
            for name in ("reciprocity-wind", "surge-cast-wind")}


@pytest.mark.parametrize("name", ["reciprocity-wind", "surge-cast-wind"])
def test_frames_per_reading_and_the_layouts(name, episodes, scenario, tmp_path, video_frames):
    episode = episodes[name]
    n = episode.summary["n_measurements"]
    path = write_count_video(tmp_path / "sub" / "search.mp4", episode, scenario.arena, fps=5, move_frames=2,
                             hold_frames=3, dpi=50)
    frames = video_frames(path)
    assert n >= 2 and len(frames) == n * (2 + 3)
    h, w = frames[0].shape[:2]
    two_panels = name == "reciprocity-wind"                 # the right panel is the posterior
    assert (w > 1.5 * h) == two_panels
    # the second reading: the observer moves while it travels (frames 5-6), and holds still
    # at the reading (frames 7-9, up to coding noise)
    def change(i):
        return np.abs(frames[i + 1].astype(int) - frames[i].astype(int)).mean()
    assert change(5) > 4 * max(change(7), change(8))


def test_the_command_line_writes_the_video_unless_told_not_to(tmp_path, capsys, video_frames):
    (tmp_path / "wind.yaml").write_text(
        "world: flow\narena: {name: duct, boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]}\n"
        "inflow: [[[0, 0], [0, 40]]]\noutflow: [[[60, 0], [60, 40]]]\nspeed: 1\nD: 5\ntau: 60\n"
        "truth_h: 1\nsource: [18, 22]\nstart: [50, 20, 90]\n")
    for flag, out in (([], "with"), (["--no-video"], "without")):
        code = main(["run", "--scenario", str(tmp_path / "wind.yaml"), "--strategy", "gradient-wind", "--seed", "0",
                     "--set", "max_steps=3", "--quiet", "--out", str(tmp_path / out), *flag])
        assert code in (0, 1)
    capsys.readouterr()
    assert len(video_frames(tmp_path / "with" / "gradient-wind.mp4")) == 3 * 6
    assert not list((tmp_path / "without").glob("*.mp4"))


@pytest.mark.parametrize("kwargs, words", [
    (dict(path="search.avi"), "must end in .mp4"),
    (dict(fps=0), "fps must be an integer from 1 to 60"),
    (dict(move_frames=2.5), "move_frames must be an integer"),
    (dict(hold_frames=True), "hold_frames must be an integer"),
    (dict(dpi=1000), "dpi must be an integer from 40 to 200"),
])
def test_bad_video_arguments_are_refused(kwargs, words, episodes, scenario, tmp_path):
    path = tmp_path / kwargs.pop("path", "search.mp4")
    with pytest.raises(SearchError, match=words):
        write_count_video(path, episodes["reciprocity-wind"], scenario.arena, **kwargs)
    assert not path.exists()


def test_an_episode_without_readings_is_refused(episodes, scenario, tmp_path):
    episode = dataclasses.replace(episodes["reciprocity-wind"], records=[])
    with pytest.raises(SearchError, match="no readings"):
        write_count_video(tmp_path / "x.mp4", episode, scenario.arena)
