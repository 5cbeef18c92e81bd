"""The wiring of each world kind (each ``world:`` of scenario files) to its world (the
truth) and its platforms; this package was ``reciprocity.kinds``. The only modules that
import both :mod:`reciprocity.worlds` and :mod:`reciprocity.platforms`; each registers its
kind in :data:`reciprocity.scenarios.WORLD_KINDS` when imported (the registry imports them
lazily by name, through the lazy exports below)."""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "filament": ["FILAMENT"], "flow": ["FLOW"], "lattice": ["LATTICE"], "plume": ["PLUME"], "poisson": ["POISSON"]})
