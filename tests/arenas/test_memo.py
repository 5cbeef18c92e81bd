"""Caches bounded in bytes (arenas.memo): what they keep, what they drop, what they measure."""

import os
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from arenas.memo import nbytes_of, sized_cache


def test_nbytes_counts_arrays_sparse_and_factorizations_once():
    a = np.zeros(1000)
    holder = type("Holder", (), {})()
    holder.a, holder.view, holder.same = a, a[10:], a          # a view and an alias: counted once
    holder.m = sp.identity(100, format="csr")
    assert nbytes_of(holder) == 8000 + holder.m.data.nbytes + holder.m.indices.nbytes + holder.m.indptr.nbytes
    from scipy.sparse.linalg import splu
    lu = splu(sp.identity(50, format="csc"))
    assert nbytes_of({"lu": lu}) == (lu.L.nnz + lu.U.nnz) * 12 + 2 * 50 * 4


def test_sized_cache_drops_the_least_recent_beyond_its_budget():
    calls = []

    @sized_cache(max_bytes=3 * 8000)
    def make(k):
        calls.append(k)
        return np.full(1000, float(k))

    for k in range(5):
        make(k)
    info = make.cache_info()
    assert info.currsize == 3 and info.nbytes == 24000 and info.max_bytes == 24000
    make(4), make(2)                       # kept: no new call
    assert calls == [0, 1, 2, 3, 4]
    make(0)                                # dropped: computed again, and 3 (least recent) goes
    make(3)
    assert calls == [0, 1, 2, 3, 4, 0, 3]
    make.cache_clear()
    assert make.cache_info().currsize == 0


def test_sized_cache_keeps_the_newest_entry_even_when_too_big_and_counts_growth():
    @sized_cache(max_bytes=100)
    def big(k):
        return {"x": np.zeros(1000)}

    first = big(1)
    assert big(1) is first and big.cache_info().currsize == 1
    grown = {}

    @sized_cache(max_bytes=20000, maxsize=10)
    def grows(k):
        grown[k] = {"x": np.zeros(1000)}
        return grown[k]

    grows(1), grows(2)
    assert grows.cache_info().currsize == 2
    grown[1]["y"] = np.zeros(2000)         # an entry that grew after it was stored (a solver factorizing)
    grows(3)
    assert grows.cache_info().currsize == 2 and grows.cache_info().nbytes <= 20000


@pytest.mark.parametrize("bad", [dict(max_bytes=0), dict(max_bytes=10, maxsize=0)])
def test_sized_cache_refuses_an_empty_budget(bad):
    with pytest.raises(ValueError):
        sized_cache(**bad)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's malloc_trim, read through /proc")
def test_release_memory_hands_freed_heap_back():
    from arenas.memo import release_memory

    def resident_mb():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20

    release_memory()
    # many medium arrays (below the mmap threshold, so on the heap), every other one freed:
    # the heap cannot shrink from its top, and holds the freed half
    blocks = [np.ones(10_000 + i % 7) for i in range(3_000)]
    del blocks[::2]
    before = resident_mb()
    release_memory()
    after = resident_mb()
    assert after < before - 50           # about 120 MB were freed; most of it goes back
    assert blocks[0].sum() == 10_001     # what is still held is untouched
