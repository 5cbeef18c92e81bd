"""Name registries that import a module only when one of its names is asked for.

The command line, campaigns and scripts look strategies and world kinds up by name. The
registries know where each built-in one lives, so ``reciprocity run --arena paper``
imports the reciprocity strategy and the Poisson world, not the particle filters and
plume models of the other papers (which pull in scipy.stats and numba).
"""

from __future__ import annotations

from collections.abc import MutableMapping
from importlib import import_module

__all__ = ["LazyRegistry"]


class LazyRegistry(MutableMapping):
    """A mapping name -> object whose built-in entries are imported on first access.

    Parameters
    ----------
    builtin : dict
        Name -> ``"package.module"`` (importing it registers the name, e.g. with a
        decorator) or ``"package.module:attribute"``.

    Examples
    --------
    >>> reg = LazyRegistry({"sqrt": "math:sqrt"})
    >>> reg["sqrt"](9.0), list(reg)
    (3.0, ['sqrt'])
    """

    def __init__(self, builtin: dict[str, str]):
        self._where = dict(builtin)
        self._loaded: dict = {}

    def __getitem__(self, name):
        if name not in self._loaded and name in self._where:
            module, _, attr = self._where[name].partition(":")
            mod = import_module(module)
            if name not in self._loaded and attr:
                self._loaded[name] = getattr(mod, attr)
        return self._loaded[name]

    def __setitem__(self, name, value) -> None:
        self._loaded[name] = value

    def __delitem__(self, name) -> None:
        self._loaded.pop(name, None)
        self._where.pop(name, None)

    def __contains__(self, name) -> bool:
        return name in self._where or name in self._loaded

    def __iter__(self):
        yield from self._where
        yield from (n for n in self._loaded if n not in self._where)

    def __len__(self) -> int:
        return len(set(self._where) | set(self._loaded))
