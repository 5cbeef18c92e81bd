"""Search strategies, selectable by name (:data:`STRATEGIES`)."""

from .base import Request, Status, Strategy
from .gradient import GradientStrategy, three_point_gradient
from .reciprocal import ReciprocityStrategy

#: Strategy classes by the name used on the command line.
STRATEGIES = {"reciprocity": ReciprocityStrategy, "gradient": GradientStrategy}

__all__ = ["GradientStrategy", "ReciprocityStrategy", "Request", "STRATEGIES", "Status",
           "Strategy", "three_point_gradient"]
