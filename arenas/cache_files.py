"""Files kept in caches: trusted only once they are checked.

A cache folder may be damaged (a full disk, a killed writer, a copy gone wrong) or shared
with someone else (a group-writable ``$RECIPROCITY_CACHE`` or ``$HJPLANNER_CACHE``). The
rule is that a cache never makes a run fail or differ, so an entry is used only when

- it is a regular file, reached without following a symbolic link, and owned by the user
  running the process (a file another user put there is never read: he could have
  written anything into it, digest included);
- it is at most :data:`MAX_ENTRY_BYTES` and opens as an ``.npz`` without pickles;
- its stored digest equals the SHA-256 of its key (what it was computed from: arena,
  target, parameters, library versions) and of every array's name, dtype, shape and bytes;
- its arrays pass the caller's checks (shape, dtype, finiteness, meaning).

An entry that fails is moved aside into the folder's ``quarantine/`` (for a look later),
a :class:`CacheWarning` says so, and the caller computes the value again. Entries are
written under a unique temporary name (``O_EXCL``, mode 0600) and renamed into place, so
a reader never sees half a file and a planted symbolic link is replaced, never followed.

Used by :mod:`reciprocity.fem.disk_cache` and :mod:`hjplanner.bank`; nothing here is
unpickled, ever.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import stat
import tempfile
import time
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

__all__ = ["CacheWarning", "CacheEntryError", "MAX_ENTRY_BYTES", "QUARANTINE", "digest", "read_entry",
           "write_entry", "open_owned", "quarantine", "owned_folder"]

#: Largest cache entry read, bytes (a P2 Green's function of the finest accepted mesh is
#: a few tens of MB; value functions are compressed).
MAX_ENTRY_BYTES = 1 << 31
#: Sub-folder of a cache folder where entries that failed their check are moved.
QUARANTINE = "quarantine"
#: Names in an entry that hold its key and digest, not data.
_KEY, _DIGEST = "__key__", "__digest__"


class CacheWarning(UserWarning):
    """A cache entry failed its check: it was moved aside and is computed again."""


class CacheEntryError(Exception):
    """Why a cache entry cannot be trusted (raised by checks, caught by :func:`read_entry`)."""


def digest(key: str, arrays: Mapping[str, np.ndarray]) -> str:
    """SHA-256 (hex) of `key` and of each array's name, dtype, shape and bytes, by name.

    Parameters
    ----------
    key : str
        What the entry was computed from.
    arrays : mapping of str to numpy.ndarray
        The entry's data.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    sha = hashlib.sha256(key.encode())
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        sha.update(f"|{name}|{a.dtype.str}|{a.shape}|".encode())
        sha.update(a.tobytes())
    return sha.hexdigest()


def open_owned(path: Path, *, max_bytes: int = MAX_ENTRY_BYTES):
    """Open `path` for reading when it is a regular file owned by this user, not a link.

    Parameters
    ----------
    path : Path
        The file.
    max_bytes : int
        Size cap, bytes.

    Returns
    -------
    file object
        Opened in binary mode; the caller closes it.

    Raises
    ------
    FileNotFoundError
        Nothing at `path`.
    CacheEntryError
        A symbolic link, not a regular file (a FIFO is never waited on), another user's
        file, or too large.
    """
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise
    except OSError as exc:                       # ELOOP: a symbolic link
        raise CacheEntryError(f"cannot be opened as a plain file ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise CacheEntryError("not a regular file")
        if hasattr(os, "geteuid") and st.st_uid != os.geteuid():
            raise CacheEntryError(f"owned by user {st.st_uid}, not by this user ({os.geteuid()})")
        if st.st_size > max_bytes:
            raise CacheEntryError(f"{st.st_size} bytes, more than {max_bytes}")
        if hasattr(os, "O_NONBLOCK"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def owned_folder(folder: Path) -> bool:
    """Whether `folder` is a real folder (not a symbolic link) owned by this user."""
    try:
        st = os.lstat(folder)
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and (not hasattr(os, "geteuid") or st.st_uid == os.geteuid())


def quarantine(path: Path, reason: str, *, stacklevel: int = 3) -> Path | None:
    """Move the entry `path` into its folder's ``quarantine/`` and warn; returns where it went.

    The entry is removed if it cannot be moved; nothing raises.
    """
    dest = None
    with contextlib.suppress(OSError):
        target = path.parent / QUARANTINE
        target.mkdir(mode=0o700, exist_ok=True)
        if owned_folder(target):
            dest = target / f"{path.name}.{time.strftime('%Y%m%dT%H%M%S')}.{os.getpid()}"
            os.replace(path, dest)
    if dest is None:
        with contextlib.suppress(OSError):
            os.unlink(path)
    where = f"moved to {dest}" if dest is not None else "removed"
    warnings.warn(f"cache entry {path} failed its check ({reason}); {where}, and the value is computed "
                  "again", CacheWarning, stacklevel=stacklevel)
    return dest


def read_entry(path: Path, key: str, names: tuple[str, ...],
               check: Callable[[dict[str, np.ndarray]], None] | None = None) -> dict[str, np.ndarray] | None:
    """The arrays `names` of the cache entry `path`, checked; None when missing or bad.

    Parameters
    ----------
    path : Path
        The entry (an ``.npz`` written by :func:`write_entry`).
    key : str
        What the caller would compute the value from; must equal the entry's key.
    names : tuple of str
        The arrays the entry must hold (and no others).
    check : callable, optional
        ``check(arrays)`` raises :class:`CacheEntryError` (or ValueError) when the arrays
        do not fit the caller (shape, dtype, finiteness, meaning).

    Returns
    -------
    dict or None
        The arrays; None when there is no entry, or when it failed a check (it is then
        moved aside by :func:`quarantine`, with a :class:`CacheWarning`).
    """
    try:
        with open_owned(path) as fh, np.load(fh, allow_pickle=False) as data:
            stored = set(data.files)
            if stored != {*names, _KEY, _DIGEST}:
                raise CacheEntryError(f"holds {sorted(stored)}, not {sorted({*names, _KEY, _DIGEST})}")
            arrays = {n: np.array(data[n]) for n in names}
            entry_key, entry_digest = str(data[_KEY][()]), str(data[_DIGEST][()])
        if entry_key != key:
            raise CacheEntryError("its key is not the key of this computation")
        if entry_digest != digest(key, arrays):
            raise CacheEntryError("its content does not match its digest")
        if check is not None:
            try:
                check(arrays)
            except Exception as exc:
                raise CacheEntryError(" ".join(str(exc).split())[:200]) from None
    except FileNotFoundError:
        return None
    except CacheEntryError as exc:
        quarantine(path, str(exc))
        return None
    except Exception as exc:   # truncated, not a zip, strings, pickles refused, bad headers
        quarantine(path, f"unreadable: {type(exc).__name__}: {' '.join(str(exc).split())[:200]}")
        return None
    with contextlib.suppress(OSError):
        os.utime(path, follow_symlinks=False)     # recently used: pruned last
    return arrays


def write_entry(path: Path, key: str, **arrays: np.ndarray) -> bool:
    """Write `arrays` with `key` and their digest to `path`, atomically; True if written.

    The folder is created if missing (mode 0700) and must be a real folder owned by this
    user; the file is written under a unique temporary name and renamed into place. Any
    failure leaves the cache as it was and no temporary file behind.
    """
    tmp = None
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        if not owned_folder(path.parent):
            return False
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays, **{_KEY: np.array(key), _DIGEST: np.array(digest(key, arrays))})
        os.replace(tmp, path)
        tmp = None
        return True
    except OSError:
        return False
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
