"""Platforms: what turns a strategy's intents into motion and readings.

:mod:`~reciprocity.platforms.base` holds the :class:`Platform` interface;
:mod:`~reciprocity.platforms.point` the point observer (moves instantly along free paths);
:mod:`~reciprocity.platforms.walker` the walker (one move per time step on a lattice, a
grid or the plane, with slips); :mod:`~reciprocity.platforms.lattice` the lattice
searcher's relative controls (Ristic et al., eq. (45)); and :mod:`~reciprocity.platforms.car`
the simulated micro-car driven by Hamilton-Jacobi value functions. The car's names are
imported on first use: they pull in :mod:`hjplanner` and numba, which the other
platforms do not need.
"""

import lazy_loader as _lazy

from .base import Platform
from .lattice import CONTROLS, LatticePlatform
from .point import PointPlatform, gradient_sample_points
from .walker import WalkerPlatform

#: Names of :mod:`reciprocity.platforms.car`, imported on first access (lazy_loader, as
#: the other packages).
_CAR_NAMES = ("CAR_KEYS", "CarPlatform", "DrivingOptions", "PLANNERS", "check_car_options",
              "make_car_platform")

__all__ = [
    "CONTROLS", "LatticePlatform", "Platform", "PointPlatform", "WalkerPlatform",
    "gradient_sample_points", *_CAR_NAMES,
]

__getattr__, _, _ = _lazy.attach(__name__, submod_attrs={"car": list(_CAR_NAMES)})
