"""Arrays kept on disk between processes: meshes, Green's functions and discretisation estimates.

A cache must never make a run fail or differ. Each entry carries its key (everything it
was computed from: the arena's geometry, the mesh, the elements, the point, the libraries'
versions) and a digest of its content, and is read through
:func:`arenas.cache_files.read_entry`: only a regular file of this user, whose key and
digest match and whose arrays pass the caller's checks, is used. Anything else (empty,
truncated, another format, swapped, edited, a FIFO, a link, another user's file) is moved
into ``quarantine/`` with a :class:`~arenas.cache_files.CacheWarning` and the value
computed again. A folder that cannot be written is passed over; every file is written
under a unique temporary name and renamed into place, so concurrent writers (Dask workers
with several threads, several processes) never expose a half-written file.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from arenas.cache_files import owned_folder, read_entry, write_entry

# read_cached and write_cached serve this package's modules; the package exports cache_dir
__all__ = ["cache_dir"]

#: Temporary files older than this (s) are left-overs of a writer that died: pruned.
STALE_TMP_S = 3600.0
#: Names of the entries this module writes (the first 32 hex digits of the key's SHA-256).
_ENTRY = re.compile(r"^[0-9a-f]{32}\.npz$")
_TMP = re.compile(r"^\.[0-9a-f]{32}\..+\.tmp$")


def cache_dir() -> Path | None:
    """Where meshes and fields are cached: ``$RECIPROCITY_CACHE`` (``off`` disables the
    cache), else ``~/.cache/reciprocity``."""
    env = os.environ.get("RECIPROCITY_CACHE")
    if env is not None and env.strip().lower() in ("off", "0", "none", ""):
        return None
    return Path(env).expanduser() if env else Path.home() / ".cache" / "reciprocity"


def entry_path(kind: str, key: str) -> Path | None:
    """File of the entry `key` in the sub-folder `kind`, or None when the cache is off."""
    folder = cache_dir()
    if folder is None:
        return None
    return folder / kind / f"{hashlib.sha256(key.encode()).hexdigest()[:32]}.npz"


def read_cached(kind: str, key: str, names: tuple[str, ...],
                check: Callable[[dict[str, np.ndarray]], None] | None = None) -> dict[str, np.ndarray] | None:
    """The arrays `names` of the entry `key` of `kind`, checked (see
    :func:`arenas.cache_files.read_entry`); None when absent, bad or the cache is off."""
    path = entry_path(kind, key)
    if path is None or not owned_folder(path.parent):
        return None
    return read_entry(path, key, names, check)


def write_cached(kind: str, key: str, *, keep: int | None = None, **arrays: np.ndarray) -> None:
    """Keep `arrays` as the entry `key` of `kind`; with `keep`, prune the folder to its
    `keep` most recently used entries. Any failure to write leaves the cache as it was."""
    path = entry_path(kind, key)
    if path is None:
        return
    if write_entry(path, key, **arrays) and keep is not None:
        _prune(path.parent, keep)


def _prune(folder: Path, keep: int) -> None:
    """Remove all but the `keep` most recently used entries of `folder`, and temporary
    files older than :data:`STALE_TMP_S`: only files named as this module names them, in
    a folder of this user (never through a link)."""
    if not owned_folder(folder):
        return
    now = time.time()
    entries = []
    for f in os.scandir(folder):
        if not f.is_file(follow_symlinks=False):
            continue
        with contextlib.suppress(OSError):
            mtime = f.stat(follow_symlinks=False).st_mtime
            if _TMP.match(f.name) and now - mtime > STALE_TMP_S:
                os.unlink(f.path)
            elif _ENTRY.match(f.name):
                entries.append((mtime, f.path))
    entries.sort()
    for _, old in entries[:max(0, len(entries) - keep)]:
        with contextlib.suppress(OSError):
            os.unlink(old)
