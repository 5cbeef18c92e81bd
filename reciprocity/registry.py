"""Name registries that import a module only when one of its names is asked for.

The command line, campaigns and scripts look strategies and world kinds up by name. A
registry maps each built-in name to an attribute of one package, and that package exports
its attributes lazily, as every package here does (``lazy_loader.attach``, as in
scikit-image): one mechanism says where a name lives and imports it on first use. So
``reciprocity run --arena paper`` imports the reciprocity strategy and the Poisson world,
not the particle filters and plume models of the other papers (which pull in scipy.stats
and numba).
"""

from __future__ import annotations

from collections.abc import MutableMapping
from importlib import import_module

__all__ = ["LazyRegistry"]


class LazyRegistry(MutableMapping):
    """A mapping name -> object whose built-in entries are attributes of a package, looked
    up (and so imported, by the package's lazy exports) on first access.

    Parameters
    ----------
    package : str
        The package that exports the built-in entries (lazily, with ``lazy_loader.attach``).
    builtin : dict
        Name -> the attribute of `package` that holds the entry.

    Examples
    --------
    >>> reg = LazyRegistry("math", {"root": "sqrt"})
    >>> reg["root"](9.0), list(reg)
    (3.0, ['root'])
    """

    def __init__(self, package: str, builtin: dict[str, str]):
        self._package = package
        self._where = dict(builtin)
        self._loaded: dict = {}

    def __getitem__(self, name):
        if name not in self._loaded and name in self._where:
            value = getattr(import_module(self._package), self._where[name])
            # importing may have registered the name already (a class decorator): keep that
            self._loaded.setdefault(name, value)
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
