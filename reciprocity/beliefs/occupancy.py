"""The occupancy map of a strategy told only part of the walls (``map: unknown``).

The grid itself lives in :mod:`reciprocity.spaces.occupancy`, where a platform's own
controller may use it too (the car maps the walls it meets with its own range sensor, as a
robot's navigation stack does) without importing any belief.
"""

from ..spaces.occupancy import OccupancyGrid

__all__ = ["OccupancyGrid"]
