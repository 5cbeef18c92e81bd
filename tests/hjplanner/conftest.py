"""Shared fixtures of the hjplanner tests."""

import numpy as np
import pytest

import arenas
from hjplanner import point_distance, solve

REFERENCE_DOMAIN = ((-1.0, 1.0), (-1.0, 1.0))
RHO = 0.3


def _reference_poses(n: int = 3000, seed: int = 1, max_distance: float = 0.95):
    rng = np.random.default_rng(seed)
    poses = rng.uniform([-1, -1, 0], [1, 1, 2 * np.pi], (12 * n, 3))
    exact = point_distance(poses[:, 0], poses[:, 1], poses[:, 2], RHO)
    keep = exact < max_distance
    return poses[keep][:n], exact[keep][:n]


@pytest.fixture(scope="session")
def reference_sample():
    """Random poses (n, 3) of the reference setup with exact distance below 0.95, and those distances."""
    return _reference_poses()


@pytest.fixture(scope="session")
def reference_vf():
    """The reference setup at 101 x 101 x 64."""
    return solve(REFERENCE_DOMAIN, (0.0, 0.0), RHO, 0.02, 64)


@pytest.fixture(scope="session")
def coarse_vf():
    """A quick 41 x 41 x 32 solve of the reference setup."""
    return solve(REFERENCE_DOMAIN, (0.0, 0.0), RHO, 0.05, 32)


@pytest.fixture(scope="session")
def u_room():
    """A 4 x 3 arena with a U-shaped obstacle open at the top."""
    boundary = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
    u_shape = np.array([[1.5, 0.8], [2.5, 0.8], [2.5, 2.2], [2.3, 2.2], [2.3, 1.0], [1.7, 1.0], [1.7, 2.2],
                        [1.5, 2.2]])
    return arenas.Arena.from_polygons(boundary, [u_shape], name="u-room")


@pytest.fixture(scope="session")
def paper():
    """The built-in `paper` arena (cm) without its scenario, as the car platform passes it."""
    return arenas.load("paper").without_scenario()


@pytest.fixture(scope="session")
def u_room_vf(u_room):
    """Target behind the U, clearance 0.05, turning radius 0.25."""
    return solve(u_room, (3.3, 1.5), 0.25, 0.04, 48, clearance=0.05)

