"""arenas: the world of the source-search testbed.

Arena geometry (outer boundary and impassable obstacles, in cm), arena files (YAML),
arenas drawn as images, the built-in arenas (:func:`builtin_names`), and the simulated
testbed of Landa et al.: the painted floor (:func:`render_floor`), the reflectance
sensor and its calibration, the pymunk micro-car, the overhead ArUco camera, and
:class:`Testbed`, which puts them together.
"""

from .camera import Observation, OverheadCamera
from .car import Car, CarSpec, car_footprint
from .errors import ArenaError
from .floor import FLOOR_FORMAT, Floor, GreyMapping, render_floor
from .frames import pixel_to_world, world_to_pixel
from .geometry import DEFAULT_STRENGTH, Arena, as_points
from .image import from_image
from .io import builtin_description, builtin_names, from_dict, load, save, to_dict
from .sensor import ADC_MAX, CALIBRATION_GREYS, AdcCurve, Calibration, ReflectanceSensor
from .testbed import Measurement, Testbed, dead_reckon

__all__ = [
    "ADC_MAX", "CALIBRATION_GREYS", "DEFAULT_STRENGTH", "FLOOR_FORMAT", "AdcCurve", "Arena",
    "ArenaError", "Calibration", "Car", "CarSpec", "Floor", "GreyMapping", "Observation",
    "Measurement", "OverheadCamera", "ReflectanceSensor", "Testbed", "dead_reckon", "as_points", "builtin_description",
    "builtin_names", "car_footprint", "from_dict", "from_image", "load", "pixel_to_world",
    "render_floor", "save", "to_dict", "world_to_pixel",
]
