"""reciprocity: reciprocity-based source discovery with finite-element Green's functions.

Adjoint solves (:class:`GreenSolver`), probability imaging (:class:`ImagingMap`), the
search strategies of Landa et al. (Algorithms 1 and 2), and the framework every
strategy plugs into: worlds (truth), models and beliefs (inference), search spaces,
intents, platforms, episodes and scenarios.
"""

# The names below are imported on first use (PEP 562, via lazy_loader as in
# scikit-image): the FEM solver, the arenas' camera and car, and the strategies'
# numba kernels cost a second and 250 MB, which `reciprocity --help` never needs.
import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "api": ["check", "execute", "run"],
    "beliefs": ["Belief", "Predictive"],
    "episode": ["SUMMARY_KEYS", "Episode", "StepRecord"],
    "errors": ["MeshError", "ReciprocityError", "SearchError", "UnreachableTarget"],
    "fem": ["Field", "GreenSolver", "disk_green", "free_space_green", "mesh_free_region", "reentrant_corners"],
    "beliefs.combiners": ["COMBINATIONS"],
    "beliefs.imaging": ["ImagingMap"],
    "beliefs.level_sets": ["superlevel_area"],
    "intents": ["Intent", "Measure", "Move", "SampleGradient", "Stay", "StepToward"],
    "observations": ["Message", "MessageLog", "Observation"],
    "outcome": ["Stop", "StopReason"],
    "platforms": ["Platform", "PointPlatform", "WalkerPlatform"],
    "scenarios": ["Scenario", "load_scenario", "scenario_names"],
    "spaces": ["GridSpace", "MeshSpace", "SearchSpace"],
    "strategies": ["STRATEGIES", "GradientStrategy", "RandomWalkStrategy", "ReciprocityStrategy",
                   "SearchContext", "Strategy", "three_point_gradient"],
    "worlds": ["Mismatch", "PoissonWorld", "World"],
})
