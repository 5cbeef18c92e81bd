"""Arrays kept on disk between processes: meshes and Green's functions.

A cache must never make a run fail or differ: a file that cannot be read (empty,
truncated, another format) is removed and the value computed again; a folder that cannot
be written is passed over; every file is written under a unique temporary name and
renamed into place, so concurrent writers (Dask workers with several threads, several
processes) never expose a half-written file.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

import numpy as np

# read_arrays and write_arrays serve this package's modules; the package exports cache_dir
__all__ = ["cache_dir"]

#: Temporary files older than this (s) are left-overs of a writer that died: pruned.
STALE_TMP_S = 3600.0


def cache_dir() -> Path | None:
    """Where meshes and fields are cached: ``$RECIPROCITY_CACHE`` (``off`` disables the
    cache), else ``~/.cache/reciprocity``."""
    env = os.environ.get("RECIPROCITY_CACHE")
    if env is not None and env.strip().lower() in ("off", "0", "none", ""):
        return None
    return Path(env).expanduser() if env else Path.home() / ".cache" / "reciprocity"


def read_arrays(path: Path, names: tuple[str, ...]) -> dict[str, np.ndarray] | None:
    """The arrays `names` of the ``.npz`` file `path`, or None when it is missing or
    unreadable (an unreadable file is removed). Reading marks the file as recently used
    where the folder allows it."""
    try:
        with np.load(path, allow_pickle=False) as data:
            out = {n: np.array(data[n]) for n in names}
    except FileNotFoundError:
        return None
    except Exception:            # empty, truncated, not a zip, a missing array: recompute
        try:
            path.unlink()
        except OSError:
            pass
        return None
    try:
        os.utime(path)           # recently used: pruned last
    except OSError:
        pass
    return out


def write_arrays(path: Path, *, keep: int | None = None, **arrays: np.ndarray) -> None:
    """Write `arrays` to `path` atomically (a unique temporary file renamed into place);
    with `keep`, prune the folder to its `keep` most recently used files. Any failure to
    write leaves the cache as it was."""
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=path.stem + ".", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
        tmp = None
        if keep is not None:
            _prune(path.parent, keep)
    except OSError:
        pass
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def _prune(folder: Path, keep: int) -> None:
    """Remove all but the `keep` most recently used ``.npz`` files of `folder`, and
    temporary files older than :data:`STALE_TMP_S`."""
    now = time.time()
    files = []
    for f in folder.iterdir():
        try:
            mtime = f.stat().st_mtime
        except OSError:
            continue
        if f.suffix == ".tmp":
            if now - mtime > STALE_TMP_S:
                f.unlink(missing_ok=True)
        elif f.suffix == ".npz":
            files.append((mtime, f))
    files.sort()
    for _, old in files[:max(0, len(files) - keep)]:
        old.unlink(missing_ok=True)
