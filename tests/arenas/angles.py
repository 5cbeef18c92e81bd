"""Angle arithmetic for the arenas tests."""

import math


def angle_diff(a, b):
    """Signed difference of two angles, wrapped to [-pi, pi)."""
    return (a - b + math.pi) % (2 * math.pi) - math.pi
