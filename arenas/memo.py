"""Process-wide caches bounded in bytes as well as in entries.

A worker that runs many episodes on many distinct arenas (a campaign over generated arenas)
would otherwise hold the last solvers, meshes and factorizations of each cache up to its
entry count, whatever their size (issue 33: 2.48 GB after 224 arenas). :func:`sized_cache`
is :func:`functools.lru_cache` with a byte budget: after each new entry it measures every
entry kept (:func:`nbytes_of`: an entry may grow after it was stored, as a solver that
factorizes on its first solve does) and drops the least recently used until the rest fit.
The newest entry is always kept, whatever its size.

Dropping entries is not enough on its own: glibc keeps the freed memory of many medium-sized
arrays in its heap, and a worker that ran 12 arenas kept 983 MB resident with every cache
empty (109 MB once the heap was trimmed). A cache that is about to build a new entry, and
one that drops an entry, therefore hand the free memory back (:func:`release_memory`, a few
ms).
"""

from __future__ import annotations

import functools
import threading
from collections import OrderedDict
from typing import Any, Callable, NamedTuple

import numpy as np

__all__ = ["sized_cache", "nbytes_of", "CacheInfo", "release_memory"]

#: Depth to which :func:`nbytes_of` follows attributes and containers.
MAX_DEPTH = 6


class CacheInfo(NamedTuple):
    """As :func:`functools.lru_cache`'s, with the bytes held and the budget."""

    hits: int
    misses: int
    maxsize: int | None
    currsize: int
    nbytes: int
    max_bytes: int


def nbytes_of(obj: Any, _seen: set | None = None, _depth: int = 0) -> int:
    """Bytes held by the arrays reachable from `obj`: numpy arrays, scipy sparse matrices and
    SuperLU factorizations, found through attributes, slots, lists, tuples, sets and dicts
    (each object counted once, at most MAX_DEPTH levels deep).

    Parameters
    ----------
    obj : object
        What to measure.

    Returns
    -------
    int
        Bytes, a lower bound (interpreter objects other than arrays are not counted).
    """
    seen = set() if _seen is None else _seen
    if id(obj) in seen or _depth > MAX_DEPTH or obj is None or isinstance(obj, (str, bytes, int, float, bool)):
        return 0
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        base = obj.base if obj.base is not None else obj
        if id(base) in seen and base is not obj:
            return 0
        seen.add(id(base))
        return int(base.nbytes) if isinstance(base, np.ndarray) else int(obj.nbytes)
    kind = type(obj).__name__
    if kind == "SuperLU":        # scipy's factorization: L and U in CSC, two permutations
        return int((obj.L.nnz + obj.U.nnz) * 12 + 2 * obj.shape[0] * 4)
    if hasattr(obj, "data") and hasattr(obj, "nnz") and hasattr(obj, "indices"):   # scipy sparse
        return sum(nbytes_of(getattr(obj, a, None), seen, _depth + 1) for a in ("data", "indices", "indptr"))
    if isinstance(obj, dict):
        return sum(nbytes_of(v, seen, _depth + 1) for v in obj.values())
    if isinstance(obj, (list, tuple, set, frozenset)):
        return sum(nbytes_of(v, seen, _depth + 1) for v in obj)
    total = 0
    attrs = getattr(obj, "__dict__", None)
    if isinstance(attrs, dict):
        total += sum(nbytes_of(v, seen, _depth + 1) for v in attrs.values())
    for name in getattr(type(obj), "__slots__", ()):
        total += nbytes_of(getattr(obj, name, None), seen, _depth + 1)
    return total


_LIBC: list = []


def release_memory() -> None:
    """Return the heap's free memory to the system (glibc ``malloc_trim``); a no-op where
    the C library has none."""
    if not _LIBC:
        try:
            import ctypes
            libc = ctypes.CDLL("libc.so.6")
            _LIBC.append(libc.malloc_trim)
        except (OSError, AttributeError):
            _LIBC.append(None)
    if _LIBC[0] is not None:
        _LIBC[0](0)


def sized_cache(max_bytes: int, maxsize: int | None = None) -> Callable:
    """Decorator: memoise a function of hashable arguments, least recently used first out,
    within `max_bytes` (measured by :func:`nbytes_of`) and `maxsize` entries.

    The wrapper has ``cache_clear()`` and ``cache_info()`` (a :class:`CacheInfo`) as
    :func:`functools.lru_cache`'s has.

    Parameters
    ----------
    max_bytes : int
        Budget of the entries kept, bytes; the newest entry is kept even when it alone
        exceeds it.
    maxsize : int, optional
        Most entries kept; None: no count limit.
    """
    if int(max_bytes) <= 0 or (maxsize is not None and int(maxsize) < 1):
        raise ValueError(f"max_bytes must be > 0 and maxsize >= 1 or None; got {max_bytes!r}, {maxsize!r}")

    def decorate(fn: Callable) -> Callable:
        entries: OrderedDict = OrderedDict()
        lock = threading.RLock()
        stats = {"hits": 0, "misses": 0, "nbytes": 0}

        def _shrink() -> None:
            sizes = {k: nbytes_of(v) for k, v in entries.items()}
            total = sum(sizes.values())
            dropped = False
            while len(entries) > 1 and (total > max_bytes or (maxsize is not None and len(entries) > maxsize)):
                key, _ = entries.popitem(last=False)
                total -= sizes.pop(key)
                dropped = True
            stats["nbytes"] = total
            if dropped:
                release_memory()

        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            key = (args, tuple(sorted(kwargs.items())))
            with lock:
                if key in entries:
                    entries.move_to_end(key)
                    stats["hits"] += 1
                    return entries[key]
            if len(entries):
                # a new entry comes with a new arena: what the last one left behind is garbage
                # by now, and its memory goes back to the system before the new one is built
                release_memory()
            value = fn(*args, **kwargs)
            with lock:
                stats["misses"] += 1
                entries[key] = value
                entries.move_to_end(key)
                _shrink()
            return value

        def cache_clear() -> None:
            with lock:
                entries.clear()
                stats.update(hits=0, misses=0, nbytes=0)

        def cache_info() -> CacheInfo:
            with lock:
                return CacheInfo(stats["hits"], stats["misses"], maxsize, len(entries),
                                 stats["nbytes"], int(max_bytes))

        wrapper.cache_clear = cache_clear
        wrapper.cache_info = cache_info
        return wrapper

    return decorate
