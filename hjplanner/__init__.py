"""Hamilton-Jacobi planner for the simple car (Landa et al., section IV).

Value functions φ(x, y, θ) of the shortest-path problem of a car with
minimum turning radius ρ, optimal paths read off them, feedback steering and
banks of precomputed value functions.
"""

# The names below are imported on first use (PEP 562, via lazy_loader as in
# scikit-image): the solver compiles numba kernels and the bank starts process
# pools, and `hjplanner --help` or an error message needs neither.
import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "bank": ["OnDemandPlanner", "ValueFunctionBank", "cache_info", "clear_cache", "default_cache_dir",
             "lattice_targets"],
    "dubins": ["half_plane_distance", "point_distance", "reeds_shepp_line_distance"],
    "errors": ["HJPlannerError", "PlanningError"],
    "feedback": ["steering"],
    "paths": ["PlannedPath", "merge_short_segments", "optimal_path"],
    "reach": ["FreeComponents", "ReachableRegion"],
    "solver": ["SolverOptions", "solve"],
    "value_function": ["ValueFunction"],
})
