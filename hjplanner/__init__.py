"""Hamilton-Jacobi planner for the simple car (Landa et al., section IV).

Value functions φ(x, y, θ) of the shortest-path problem of a car with
minimum turning radius ρ, optimal paths read off them, feedback steering and
banks of precomputed value functions.
"""
from .bank import OnDemandPlanner, ValueFunctionBank, cache_info, clear_cache, default_cache_dir, lattice_targets
from .dubins import half_plane_distance, point_distance, reeds_shepp_line_distance
from .errors import HJPlannerError, PlanningError
from .feedback import steering
from .paths import PlannedPath, merge_short_segments, optimal_path
from .solver import SolverOptions, solve
from .value_function import ValueFunction

__all__ = [
    "solve", "SolverOptions", "ValueFunction",
    "optimal_path", "PlannedPath", "merge_short_segments", "steering",
    "ValueFunctionBank", "OnDemandPlanner", "lattice_targets", "default_cache_dir", "cache_info", "clear_cache",
    "point_distance", "half_plane_distance", "reeds_shepp_line_distance",
    "HJPlannerError", "PlanningError",
]
