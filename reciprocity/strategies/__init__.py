"""Search strategies, selectable by name (:data:`STRATEGIES`)."""

from ..registry import LazyRegistry
from .base import MAX_REJECTIONS, SearchContext, Status, Strategy

#: Strategy classes by the name used on the command line; each says the world kinds it
#: applies to (``cls.worlds``) and how many observers it directs (``cls.agents``). A
#: built-in strategy's module is imported when its name is first looked up.
STRATEGIES: LazyRegistry = LazyRegistry({
    "reciprocity": "reciprocity.strategies.reciprocal:ReciprocityStrategy",
    "gradient": "reciprocity.strategies.gradient:GradientStrategy",
    "random-walk": "reciprocity.strategies.random_walk:RandomWalkStrategy",
    "rbpf": "reciprocity.strategies.rbpf",
    "rbpf-infotaxis": "reciprocity.strategies.rbpf",
    "lattice-reciprocity": "reciprocity.strategies.lattice_reciprocity",
    "infotaxis": "reciprocity.strategies.infotaxis",
    "free-energy": "reciprocity.strategies.infotaxis",
    "mapless-infotaxis": "reciprocity.strategies.infotaxis",
    "entrotaxis": "reciprocity.strategies.infotaxis",
    "space-aware-infotaxis": "reciprocity.strategies.infotaxis",
    "voi": "reciprocity.strategies.infotaxis",
    "lookahead": "reciprocity.strategies.lookahead",
    "arena-infotaxis": "reciprocity.strategies.arena_infotaxis",
    "plume-reciprocity": "reciprocity.strategies.plume_imaging",
    "hmm": "reciprocity.strategies.hmm_search",
    "surge-cast": "reciprocity.strategies.hmm_search",
    "detection-infotaxis": "reciprocity.strategies.detection_infotaxis",
    "reciprocity-wind": "reciprocity.strategies.wind_reciprocity",
    "free-space-wind": "reciprocity.strategies.wind_reciprocity",
})


def register(cls: type[Strategy]) -> type[Strategy]:
    """Add a strategy class to :data:`STRATEGIES` under ``cls.name`` (a class decorator)."""
    STRATEGIES[cls.name] = cls
    return cls


def __getattr__(name: str):
    # the classes of the core strategies, imported on first use
    lazy = {"GradientStrategy": "gradient", "three_point_gradient": "gradient",
            "RandomWalkStrategy": "random-walk", "ReciprocityStrategy": "reciprocity"}
    if name in lazy:
        if name == "three_point_gradient":
            from .gradient import three_point_gradient
            return three_point_gradient
        return STRATEGIES[lazy[name]]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["GradientStrategy", "MAX_REJECTIONS", "RandomWalkStrategy", "ReciprocityStrategy",
           "STRATEGIES", "SearchContext", "Status", "Strategy", "register", "three_point_gradient"]
