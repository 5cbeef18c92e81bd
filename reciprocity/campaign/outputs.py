"""Output folders checked before any work, so that no result is lost to a bad path."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from ..errors import SearchError

__all__ = ["check_output_dir"]


def check_output_dir(path, option: str) -> Path:
    """Check that the folder `path` exists or can be created, and can be written.

    Nothing is created: the folder itself (when it exists) or its nearest existing
    ancestor must be a folder in which a file can be written; a probe file is created
    there and removed at once (permissions alone do not tell, e.g. under ``/proc`` or
    on a read-only file system).

    Parameters
    ----------
    path : path-like
        The output folder.
    option : str
        How messages name it (``"--out"``).

    Returns
    -------
    Path
        `path`.

    Raises
    ------
    SearchError
        `path` (or a parent of it) is a file, or the folder cannot be written.
    """
    p = Path(path)
    target = p.absolute()
    existing = next((a for a in (target, *target.parents) if a.exists()), None)
    if existing is None or not existing.is_dir():
        what = "is a file" if existing == target else f"cannot be created: {str(existing)!r} is a file"
        raise SearchError(f"{option} {str(p)!r} {what}; give a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=".write-test-", dir=existing)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        where = "" if existing == target else f" (in {str(existing)!r})"
        raise SearchError(f"{option} {str(p)!r} cannot be written{where}: "
                          f"{exc.strerror or exc}; choose another folder") from None
    return p
