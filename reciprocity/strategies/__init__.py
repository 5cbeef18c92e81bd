"""Search strategies, selectable by name (:data:`STRATEGIES`).

The strategy classes are exported lazily (lazy_loader, as the other packages): a
strategy's module is imported when its class or its name in :data:`STRATEGIES` is first
asked for.
"""

import lazy_loader as _lazy

from ..registry import LazyRegistry
from .base import MAX_REJECTIONS, SearchContext, Status, Strategy

#: Strategy classes by the name used on the command line; each says the world kinds it
#: applies to (``cls.worlds``) and how many observers it directs (``cls.agents``). A
#: built-in strategy's module is imported when its name is first looked up.
STRATEGIES: LazyRegistry = LazyRegistry(__name__, {
    "reciprocity": "ReciprocityStrategy",
    "gradient": "GradientStrategy",
    "random-walk": "RandomWalkStrategy",
    "rbpf": "RBPFStrategy",
    "rbpf-infotaxis": "RBPFInfotaxisStrategy",
    "lattice-reciprocity": "LatticeReciprocityStrategy",
    "infotaxis": "Infotaxis",
    "free-energy": "FreeEnergyInfotaxis",
    "mapless-infotaxis": "MaplessInfotaxis",
    "entrotaxis": "Entrotaxis",
    "space-aware-infotaxis": "SpaceAwareInfotaxis",
    "voi": "VoIInfotaxis",
    "lookahead": "Lookahead",
    "arena-infotaxis": "ArenaInfotaxis",
    "plume-reciprocity": "PlumeImaging",
    "hmm": "HMMSearch",
    "surge-cast": "SurgeCast",
    "detection-infotaxis": "DetectionInfotaxis",
    "reciprocity-wind": "WindReciprocity",
    "free-space-wind": "FreeSpaceWind",
    "team-reciprocity-wind": "TeamWindReciprocity",
    "infotaxis-wind": "WindInfotaxis",
    "free-space-infotaxis-wind": "FreeSpaceWindInfotaxis",
    "free-energy-wind": "WindFreeEnergy",
    "free-space-free-energy-wind": "FreeSpaceWindFreeEnergy",
    "surge-cast-wind": "SurgeCastWind",
    "gradient-wind": "GradientWind",
    "infotaxis-ii": "InfotaxisII",
    "infotaxis-iii": "InfotaxisIII",
})


def register(cls: type[Strategy]) -> type[Strategy]:
    """Add a strategy class to :data:`STRATEGIES` under ``cls.name`` (a class decorator)."""
    STRATEGIES[cls.name] = cls
    return cls


# Last: an eager import (lazy_loader's EAGER_IMPORT) imports the strategy modules, which
# need `register` above.
__getattr__, _, _ = _lazy.attach(__name__, submod_attrs={
    "arena_infotaxis": ["ArenaInfotaxis"],
    "detection_infotaxis": ["DetectionInfotaxis"],
    "gradient": ["GradientStrategy", "three_point_gradient"],
    "hmm": ["HMMSearch", "SurgeCast"],
    "infotaxis": ["Entrotaxis", "FreeEnergyInfotaxis", "Infotaxis", "MaplessInfotaxis", "SpaceAwareInfotaxis",
                  "VoIInfotaxis"],
    "lattice_reciprocity": ["LatticeReciprocityStrategy"],
    "lookahead": ["Lookahead"],
    "plume_reciprocity": ["PlumeImaging"],
    "random_walk": ["RandomWalkStrategy"],
    "rbpf": ["RBPFInfotaxisStrategy", "RBPFStrategy"],
    "reciprocity": ["ReciprocityStrategy"],
    "infotaxis_wind": ["FreeSpaceWindInfotaxis", "WindInfotaxis"],
    "free_energy_wind": ["FreeSpaceWindFreeEnergy", "WindFreeEnergy"],
    "reciprocity_wind": ["FreeSpaceWind", "TeamWindReciprocity", "WindReciprocity"],
    "surge_cast_wind": ["SurgeCastWind"],
    "gradient_wind": ["GradientWind", "log_rate_slope"],
    "reward_infotaxis": ["InfotaxisII", "InfotaxisIII"],
})

__all__ = ["GradientStrategy", "MAX_REJECTIONS", "RandomWalkStrategy", "ReciprocityStrategy",
           "STRATEGIES", "SearchContext", "Status", "Strategy", "register", "three_point_gradient"]
