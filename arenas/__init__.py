"""arenas: the world of the source-search testbed.

Arena geometry (outer boundary and impassable obstacles, in cm), arena files (YAML),
ROS ``map_server`` maps (YAML + PGM), arenas drawn as images, the built-in arenas (:func:`builtin_names`), and the simulated
testbed of Landa et al.: the painted floor (:func:`render_floor`), the reflectance
sensor and its calibration, the pymunk micro-car, the overhead ArUco camera, and
:class:`Testbed`, which puts them together.
"""

# The names below are imported on first use (PEP 562, via lazy_loader as in
# scikit-image): the camera pulls in OpenCV, the car pymunk and the sensor
# scipy.interpolate, and a command that only lists arenas needs none of them.
import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "camera": ["Observation", "OverheadCamera"],
    "car": ["Car", "CarSpec", "car_footprint"],
    "errors": ["ArenaError"],
    "families": ["FAMILIES", "generate"],
    "floor": ["FLOOR_FORMAT", "Floor", "GreyMapping", "render_floor"],
    "frames": ["pixel_to_world", "world_to_pixel"],
    "geometry": ["DEFAULT_STRENGTH", "Arena", "as_points"],
    "image": ["from_image"],
    "io": ["builtin_description", "builtin_names", "from_dict", "load", "save", "to_dict"],
    "ros_map": ["from_ros_map", "is_ros_map", "to_ros_map"],
    "sensor": ["ADC_MAX", "CALIBRATION_GREYS", "AdcCurve", "Calibration", "ReflectanceSensor"],
    "testbed": ["Measurement", "Testbed", "dead_reckon"],
})
