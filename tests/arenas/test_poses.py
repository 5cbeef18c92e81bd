"""Headings are degrees where people write them and radians in the API: one conversion."""

import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import arenas
from arenas.poses import pose_from_degrees, pose_to_degrees

ROOT = Path(__file__).resolve().parents[2]
#: The modules that may turn degrees into radians: the pose conversion, and the plume kind's
#: turns and wind direction (angles of a world's parameters, not poses). Any other is a
#: second conversion of something a person wrote.
CONVERTERS = {"arenas/poses.py", "reciprocity/wiring/plume.py", "reciprocity/models/plume.py"}


def test_round_trip_and_shapes():
    assert pose_from_degrees([1, 2]).tolist() == [1.0, 2.0]
    np.testing.assert_allclose(pose_from_degrees([1, 2, 90]), [1, 2, np.pi / 2])
    many = pose_from_degrees([[0, 0, 180], [1, 1, -90]])
    np.testing.assert_allclose(many[:, 2], [np.pi, -np.pi / 2])
    assert pose_to_degrees(pose_from_degrees([3, 4, 37.5])) == pytest.approx([3, 4, 37.5])


def test_every_front_door_reads_degrees_the_same(tmp_path):
    """An arena file, a scenario file, a campaign spec's world override and --start all turn
    a 90 degree heading into pi/2."""
    from reciprocity.campaign.spec import world_overrides
    from reciprocity.cli import _world_overrides, build_parser
    from reciprocity.scenarios import load_scenario

    data = arenas.to_dict(arenas.load("paper"))
    data["start"] = [30.0, 30.0, 90.0]
    arena_file = tmp_path / "a.yaml"
    arena_file.write_text(yaml.safe_dump(data))
    assert arenas.load(arena_file).start[2] == pytest.approx(np.pi / 2)
    scenario_file = tmp_path / "s.yaml"
    scenario_file.write_text(yaml.safe_dump({"world": "poisson", "arena": "paper", "start": [30, 30, 90]}))
    assert load_scenario(str(scenario_file)).starts[0, 2] == pytest.approx(np.pi / 2)
    assert world_overrides({"start": [30, 30, 90]})["start"][2] == pytest.approx(np.pi / 2)
    args = build_parser().parse_args(["run", "--arena", "paper", "--strategy", "reciprocity", "--start", "30,30,90"])
    assert _world_overrides(args)["start"][2] == pytest.approx(np.pi / 2)
    assert arenas.to_dict(arenas.load(arena_file))["start"] == pytest.approx([30, 30, 90])


def test_no_other_module_converts_degrees():
    pattern = re.compile(r"\b(radians|deg2rad)\(|pi\s*/\s*180|180\s*/\s*(np\.)?pi")
    found = []
    for package in ("arenas", "reciprocity"):
        for path in sorted((ROOT / package).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            if rel not in CONVERTERS and pattern.search(path.read_text()):
                found.append(rel)
    assert not found, f"degrees converted outside arenas/poses.py: {found}"
