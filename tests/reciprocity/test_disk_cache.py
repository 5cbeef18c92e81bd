"""The disk cache of meshes and Green's functions never makes a run fail or differ."""

import os
import time

import numpy as np
import pytest

import arenas
from reciprocity.fem import GreenSolver
from reciprocity.fem.disk_cache import STALE_TMP_S, read_arrays, write_arrays


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("RECIPROCITY_CACHE", str(tmp_path))
    return tmp_path


@pytest.mark.parametrize("damage", [b"", b"PK\x03\x04 truncated", b"not a zip at all"])
def test_a_damaged_file_is_removed_and_recomputed(cache, damage):
    solver = GreenSolver(arenas.load("empty"), h=8.0)
    fresh = solver.field((70.0, 70.0), cached=True).dofs
    files = list((cache / "greens").glob("*.npz"))
    assert len(files) == 1
    files[0].write_bytes(damage)
    again = GreenSolver(arenas.load("empty"), h=8.0).field((70.0, 70.0), cached=True).dofs
    assert np.array_equal(fresh, again)
    assert read_arrays(files[0], ("dofs",)) is not None         # written anew, readable


def test_a_damaged_mesh_is_remade(cache):
    GreenSolver(arenas.load("empty"), h=8.0)
    for f in (cache / "meshes").glob("*.npz"):
        f.write_bytes(b"")
    assert GreenSolver(arenas.load("empty"), h=8.0).n_unknowns > 0


def test_writes_are_atomic_and_pruned(tmp_path):
    path = tmp_path / "a.npz"
    stale = tmp_path / "old.x.tmp"
    stale.write_bytes(b"left by a writer that died")
    old = time.time() - 2 * STALE_TMP_S
    os.utime(stale, (old, old))
    for k in range(5):
        write_arrays(tmp_path / f"{k}.npz", keep=3, x=np.arange(k + 1))
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["2.npz", "3.npz", "4.npz"]                 # the stale temporary file is gone too
    assert read_arrays(path, ("x",)) is None                    # missing: None, nothing raised
    assert read_arrays(tmp_path / "4.npz", ("y",)) is None      # a missing array: recomputed
    assert not (tmp_path / "4.npz").exists()


def test_a_cache_that_cannot_be_written_is_passed_over(tmp_path, monkeypatch):
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache folder should be")
    monkeypatch.setenv("RECIPROCITY_CACHE", str(blocked))
    v = GreenSolver(arenas.load("empty"), h=8.0).field((70.0, 70.0), cached=True)
    assert np.isfinite(v.dofs).all()
