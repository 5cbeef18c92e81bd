"""Old module paths kept importable for one release after the package layout changed."""

from __future__ import annotations

import sys
import warnings
from importlib import import_module

__all__ = ["alias"]


def alias(old: str, new: str) -> None:
    """Make module `old` another name for module `new`, warning whoever imports it.

    Called at the top level of the module left at the old path: importing `old` then
    yields the very module `new` (every name, the private ones too, is the same object),
    after a :class:`DeprecationWarning` that names the new path.
    """
    warnings.warn(f"{old} is deprecated and will be removed in the next release; import {new} instead",
                  DeprecationWarning, stacklevel=3)
    sys.modules[old] = import_module(new)
