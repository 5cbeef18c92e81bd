"""Rule: a damaged, swapped, planted or foreign cache entry never changes a result.

Every damage class below is applied to every entry of the Green's-function and mesh
caches after a clean run; the next run must give the same summary (to the bit, bar the
wall time), warn once per entry with a :class:`~arenas.cache_files.CacheWarning`, move
the entry into ``quarantine/``, and leave a good entry in its place.
"""

import io
import json
import os
import zipfile

import numpy as np
import pytest

import reciprocity
from arenas.cache_files import CacheWarning, QUARANTINE, digest

from memory_caches import forget_in_memory_caches


def _summary() -> dict:
    forget_in_memory_caches()
    episode, _, _ = reciprocity.execute("empty", "reciprocity", seed=1)
    return {k: v for k, v in json.loads(episode.to_json(with_trace=False)).items()
            if k != "wall_time_s"}


def _npz(**arrays) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _forged(path, change) -> bytes:
    """The entry with its arrays changed by `change` and its digest made to match: only
    the arrays' own checks can catch it."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {n: data[n] for n in data.files if not n.startswith("__")}
        key = str(data["__key__"][()])
    arrays = change(arrays)
    return _npz(**arrays, __key__=np.array(key), __digest__=np.array(digest(key, arrays)))


def _plain(path, change) -> bytes:
    """The entry's arrays changed by `change`, written as a plain ``.npz`` (no key)."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {n: data[n] for n in data.files if not n.startswith("__")}
    return _npz(**change(arrays))


def _each(fn):
    return lambda arrays: {n: fn(a) for n, a in arrays.items()}


# name -> how the file at `path` is replaced (bytes to write, or an action)
DAMAGE = {
    "empty": lambda p: b"",
    "truncated": lambda p: p.read_bytes()[: p.stat().st_size // 2],
    "not a zip": lambda p: b"not an npz file at all",
    "zip of junk": lambda p: _zip_of_junk(),
    "zeros": lambda p: _plain(p, _each(np.zeros_like)),
    "integers": lambda p: _plain(p, _each(lambda a: a.astype(np.int64))),
    "strings": lambda p: _plain(p, _each(lambda a: a.astype(str))),
    "NaN (forged digest)": lambda p: _forged(p, _each(lambda a: np.full(a.shape, np.nan)
                                                     if a.dtype.kind == "f" else a)),
    "transposed (forged digest)": lambda p: _forged(p, _each(lambda a: np.ascontiguousarray(a.T))),
    "out-of-range indices (forged digest)": lambda p: _forged(p, _each(
        lambda a: a + 10**6 if a.dtype.kind in "iu" else a[::-1].copy())),
    "content edited, digest kept": lambda p: _edited(p),
    "swapped with another entry": "swap",
    "a FIFO": "fifo",
    "a symbolic link": "link",
    "a folder": "folder",
    "another user's file": "chown",
}


def _zip_of_junk() -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("dofs.npy", b"\x93NUMPY garbage")
    return buf.getvalue()


def _edited(path) -> bytes:
    with np.load(path, allow_pickle=False) as data:
        arrays = {n: data[n].copy() for n in data.files}
    for n, a in arrays.items():
        if not n.startswith("__") and a.dtype.kind == "f":
            a.flat[0] += 1.0                      # a shifted point, a changed value
    return _npz(**arrays)


def _arrays(path):
    if path.is_symlink() or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            return {n: data[n].copy() for n in data.files if not n.startswith("__")}
    except Exception:
        return None


def _same(a, b) -> bool:
    return (a is not None and b is not None and a.keys() == b.keys()
            and all(a[n].shape == b[n].shape and np.array_equal(a[n], b[n], equal_nan=a[n].dtype.kind == "f")
                    for n in a))


def _damage(path, how, others) -> None:
    if callable(how):
        data = how(path)
        path.unlink()
        path.write_bytes(data)
        return
    if how == "swap":                           # each entry gets the next one's bytes
        path.write_bytes(others[path])
    elif how == "fifo":
        path.unlink()
        os.mkfifo(path)
    elif how == "link":
        target = path.with_name("elsewhere.bin")
        target.write_bytes(path.read_bytes())
        path.unlink()
        path.symlink_to(target)
    elif how == "folder":
        path.unlink()
        path.mkdir()
    elif how == "chown":
        os.chown(path, 12345, 12345)


@pytest.fixture(scope="module")
def clean():
    """The summary of a run on a cold, private cache."""
    import tempfile
    old = os.environ.get("RECIPROCITY_CACHE")
    with tempfile.TemporaryDirectory() as d:
        os.environ["RECIPROCITY_CACHE"] = d
        try:
            yield _summary()
        finally:
            if old is None:
                os.environ.pop("RECIPROCITY_CACHE")
            else:
                os.environ["RECIPROCITY_CACHE"] = old


#: Two damages run in the README's suite (an edit under a kept digest, a link); the rest,
#: each an episode twice over (a cut file and a forged digest among them), in the slow tier
#: that .ci/run also runs.
EVERY_RUN = ("content edited, digest kept", "a symbolic link")


@pytest.mark.parametrize("damage", [d if d in EVERY_RUN else pytest.param(d, marks=pytest.mark.slow)
                                    for d in DAMAGE])
def test_a_damaged_cache_never_changes_the_result(cache, clean, damage):
    if damage == "another user's file" and os.geteuid() != 0:
        pytest.xfail("only root can give a file to another user")
    assert _summary() == clean                                   # the cache is warm now
    entries = sorted(cache.glob("*/*.npz"))
    assert len(entries) >= 3                                     # meshes and a Green's function
    if damage == "swapped with another entry":
        entries = [e for e in entries if e.parent.name == "meshes"]
        assert len(entries) >= 2
    before = {e: _arrays(e) for e in entries}
    swapped = {e: entries[(i + 1) % len(entries)].read_bytes() for i, e in enumerate(entries)}
    for path in entries:
        _damage(path, DAMAGE[damage], swapped)
    if damage.startswith("transposed"):          # a 1-D array transposed is itself
        entries = [e for e in entries if not _same(before[e], _arrays(e))]
    # an intact discretisation estimate on disk spares the run its coarse mesh: taken
    # out, so that the run reads every damaged mesh
    for kept in set(cache.glob("discretisation/*.npz")) - set(entries):
        kept.unlink()
    assert entries
    with pytest.warns(CacheWarning) as caught:
        again = _summary()
    assert again == clean
    damaged = {str(e) for e in entries}
    warned = {str(w.message).split(" failed its check")[0].removeprefix("cache entry ") for w in caught
              if issubclass(w.category, CacheWarning)}
    assert damaged <= warned, [str(w.message)[:150] for w in caught]
    for path in entries:                                         # moved aside, a good entry in place
        assert path.is_file() and not path.is_symlink()
        assert any(path.parent.joinpath(QUARANTINE).glob(path.name + ".*"))
    forget_in_memory_caches()
    with warnings_as_errors():
        assert _summary() == clean                               # and it is trusted again


class warnings_as_errors:
    """No CacheWarning may be raised inside."""

    def __enter__(self):
        import warnings
        self._ctx = warnings.catch_warnings()
        self._ctx.__enter__()
        warnings.simplefilter("error", CacheWarning)

    def __exit__(self, *exc):
        self._ctx.__exit__(*exc)
