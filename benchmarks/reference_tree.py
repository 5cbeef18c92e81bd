"""A git ref checked out beside the working tree, for benchmarks that measure both in one run.

    with reference_tree("1f8c377", "bench_startup_") as (before, tmp):
        ...   # before: the ref's tree; tmp: a scratch folder removed with it
"""

from __future__ import annotations

import contextlib
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

#: The repository this file belongs to.
ROOT = Path(__file__).resolve().parents[1]


@contextlib.contextmanager
def reference_tree(ref: str, prefix: str = "bench_") -> Iterator[tuple[Path, Path]]:
    """A detached ``git worktree`` of `ref` in a temporary folder: yields ``(tree,
    scratch)`` and removes both afterwards, whatever happens in between."""
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        tree = Path(tmp) / "before"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "--quiet", str(tree), ref],
                       check=True)
        try:
            yield tree, Path(tmp)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=True)
            shutil.rmtree(tree, ignore_errors=True)
