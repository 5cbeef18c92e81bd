"""arenas: the world of the source-search testbed.

Arena geometry (outer boundary and impassable obstacles, in cm), arena files (YAML),
arenas drawn as images, and the built-in arenas (:func:`builtin_names`).
"""

from .errors import ArenaError
from .frames import pixel_to_world, world_to_pixel
from .geometry import DEFAULT_STRENGTH, Arena, as_points
from .image import from_image
from .io import builtin_description, builtin_names, from_dict, load, save, to_dict

__all__ = [
    "Arena", "ArenaError", "DEFAULT_STRENGTH", "as_points", "builtin_description", "builtin_names",
    "from_dict", "from_image", "load", "pixel_to_world", "save", "to_dict", "world_to_pixel",
]
