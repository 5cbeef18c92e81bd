"""Search strategies, selectable by name (:data:`STRATEGIES`)."""

from .base import MAX_REJECTIONS, SearchContext, Status, Strategy
from .gradient import GradientStrategy, three_point_gradient
from .random_walk import RandomWalkStrategy
from .reciprocal import ReciprocityStrategy

#: Strategy classes by the name used on the command line; each says the world kinds it
#: applies to (``cls.worlds``) and how many observers it directs (``cls.agents``).
STRATEGIES: dict[str, type[Strategy]] = {
    "reciprocity": ReciprocityStrategy,
    "gradient": GradientStrategy,
    "random-walk": RandomWalkStrategy,
}


def register(cls: type[Strategy]) -> type[Strategy]:
    """Add a strategy class to :data:`STRATEGIES` under ``cls.name`` (a class decorator)."""
    STRATEGIES[cls.name] = cls
    return cls


from . import rbpf  # noqa: E402,F401  (registers "rbpf", "rbpf-infotaxis")
from . import infotaxis  # noqa: E402,F401  (registers the plume strategies)
from . import hmm_search  # noqa: E402,F401  (registers "hmm", "surge-cast")


__all__ = ["GradientStrategy", "MAX_REJECTIONS", "RandomWalkStrategy", "ReciprocityStrategy",
           "STRATEGIES", "SearchContext", "Status", "Strategy", "register", "three_point_gradient"]
