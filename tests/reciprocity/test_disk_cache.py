"""The disk cache of meshes and Green's functions never makes a run fail or differ.

The damage classes (every way an entry can be wrong) are in ``tests/faults/``; this file
checks the cache's ordinary life: written atomically, read back, pruned, passed over."""

import os
import time

import numpy as np
import pytest

import arenas
from reciprocity.fem import GreenSolver
from reciprocity.fem.disk_cache import STALE_TMP_S, read_cached, write_cached


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("RECIPROCITY_CACHE", str(tmp_path))
    return tmp_path


def test_a_field_is_read_back_bit_for_bit(cache):
    fresh = GreenSolver(arenas.load("empty"), h=8.0).field((70.0, 70.0), cached=True).dofs
    assert len(list((cache / "greens").glob("*.npz"))) == 1
    again = GreenSolver(arenas.load("empty"), h=8.0).field((70.0, 70.0), cached=True).dofs
    assert np.array_equal(fresh, again)
    assert not (cache / "greens" / "quarantine").exists()


def test_writes_are_atomic_and_pruned(cache):
    folder = cache / "things"
    folder.mkdir(mode=0o700)
    stale = folder / ".0123456789abcdef0123456789abcdef.x.tmp"
    stale.write_bytes(b"left by a writer that died")
    old = time.time() - 2 * STALE_TMP_S
    os.utime(stale, (old, old))
    foreign = folder / "notes.npz"                              # not an entry of ours: kept
    foreign.write_bytes(b"a user's own file")
    for k in range(5):
        write_cached("things", f"key {k}", keep=3, x=np.arange(k + 1))
        time.sleep(0.01)
    entries = sorted(p.name for p in folder.iterdir() if p.name != "notes.npz")
    assert len(entries) == 3 and foreign.exists() and not stale.exists()
    assert read_cached("things", "key 0", ("x",)) is None      # pruned: None, nothing raised
    assert np.array_equal(read_cached("things", "key 4", ("x",))["x"], np.arange(5))


def test_a_cache_that_cannot_be_written_is_passed_over(tmp_path, monkeypatch):
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache folder should be")
    monkeypatch.setenv("RECIPROCITY_CACHE", str(blocked))
    v = GreenSolver(arenas.load("empty"), h=8.0).field((70.0, 70.0), cached=True)
    assert np.isfinite(v.dofs).all()


def test_the_cache_can_be_turned_off(monkeypatch):
    monkeypatch.setenv("RECIPROCITY_CACHE", "off")
    write_cached("things", "k", x=np.arange(3))
    assert read_cached("things", "k", ("x",)) is None
