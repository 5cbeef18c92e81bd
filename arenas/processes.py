"""Helper processes that end with the process that started them.

A pool of workers (a value-function bank's, a local Dask cluster's) must not outlive its
owner: after ``kill -9`` of the owner, orphaned workers would keep their memory (about
160 MB each) and their CPU, and what they hold open. :func:`die_with_parent`, called in
each worker, makes the kernel end it when its parent ends (Linux ``PR_SET_PDEATHSIG``),
and starts a watch thread that ends it where the kernel cannot (other systems, or a
parent that died before the call).
"""

from __future__ import annotations

import contextlib
import os
import threading
import time

__all__ = ["die_with_parent", "WATCH_S"]

#: Seconds between two looks of the watch thread at the parent.
WATCH_S = 1.0


def die_with_parent(parent: int | None = None) -> None:
    """End this process (exit code 1) as soon as its parent process ends.

    Parameters
    ----------
    parent : int, optional
        The parent's process id, as the parent saw it (``os.getpid()`` there) when it
        started this process. Pass it: a parent killed while this process was still
        starting has already been replaced by another (``os.getppid()`` then names an
        adoptive process), and only the id known beforehand tells. Default: the parent
        now.
    """
    parent = os.getppid() if parent is None else int(parent)
    with contextlib.suppress(Exception):
        import ctypes
        import signal
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)      # PR_SET_PDEATHSIG

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCH_S)
        os._exit(1)

    if os.getppid() != parent:
        os._exit(1)
    threading.Thread(target=watch, daemon=True, name="die-with-parent").start()
