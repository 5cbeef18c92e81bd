"""Rules for value-function banks: a damaged cache never changes a plan, and a bank that is
killed, starved of disk or given a folder it cannot write leaves nothing behind.

Each test names the defect class it closes (issue 34, items 2, 4, 8-11)."""

import os
import signal
import subprocess
import sys

import numpy as np
import pytest

from arenas.cache_files import CacheWarning, QUARANTINE
from hjplanner import PlanningError, ValueFunctionBank
from hjplanner.bank import cache_info, clear_cache
from process_tree import descendants, kill_9_when

DOMAIN = ((0.0, 1.0), (0.0, 1.0))
PARAMS = dict(rho=0.2, h=0.05, ntheta=16)


def _bank(folder) -> ValueFunctionBank:
    return ValueFunctionBank(DOMAIN, 0.5, cache_dir=folder, **PARAMS)


@pytest.fixture
def built(tmp_path):
    bank = _bank(tmp_path)
    bank.build(workers=1, progress=False)
    reference = {i: bank.load(i).values.copy() for i in range(len(bank))}
    return tmp_path, reference


def _truncate(path, files):
    path.write_bytes(path.read_bytes()[:100])


def _swap(path, files):                       # another target's (valid) file in its place
    other = files[(files.index(path) + 1) % len(files)]
    path.write_bytes(_SAVED[other])


def _edit(path, files):                       # one byte of the compressed values changed
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


def _fifo(path, files):
    path.unlink()
    os.mkfifo(path)


def _link(path, files):
    target = path.with_name("elsewhere.npz")
    target.write_bytes(_SAVED[path])
    path.unlink()
    path.symlink_to(target)


def _chown(path, files):
    os.chown(path, 12345, 12345)


_SAVED: dict = {}
DAMAGE = {"empty": lambda p, f: p.write_bytes(b""), "truncated": _truncate, "swapped targets": _swap,
          "a byte changed": _edit, "a FIFO": _fifo, "a symbolic link": _link, "another user's file": _chown}


@pytest.mark.parametrize("damage", list(DAMAGE))
def test_a_damaged_bank_file_is_quarantined_and_solved_again(built, damage):
    """Defect 4: a truncated bank was reported as cached and planned nothing; swapped files
    planned for the wrong target."""
    if damage == "another user's file" and os.geteuid() != 0:
        pytest.xfail("only root can give a file to another user")
    folder, reference = built
    bank = _bank(folder)
    files = [bank.path_of(i) for i in range(len(bank))]
    _SAVED.clear()
    _SAVED.update({f: f.read_bytes() for f in files})
    for f in files:
        DAMAGE[damage](f, files)
    fresh = _bank(folder)
    with pytest.warns(CacheWarning):
        assert fresh.missing() == list(range(len(fresh)))       # nothing bad counts as cached
    fresh.build(workers=1, progress=False)
    for i in range(len(fresh)):
        assert np.array_equal(fresh.load(i).values, reference[i])
        assert files[i].is_file() and not files[i].is_symlink()
    assert len(list((bank.directory / QUARANTINE).iterdir())) == len(files)


def test_the_bank_command_counts_only_good_files(built, capsys):
    from hjplanner.cli import main
    folder, _ = built
    bank = _bank(folder)
    bank.path_of(0).write_bytes(b"")
    argv = ["bank", "--bounds", "0,1,0,1", "--spacing", "0.5", "--rho", "0.2", "--h", "0.05",
            "--ntheta", "16", "--cache", str(folder), "--workers", "1", "--quiet"]
    assert main(argv) == 0
    out = capsys.readouterr()
    assert "1 solved" in out.out and "3 from cache" in out.out
    assert out.err.startswith("warning: cache entry") and out.err.count("\n") == 1


#: A safety net against a hung command, never the assertion (minutes, far above any run here).
HANG_S = 600


def _cli(*args, env=None, preexec=None, **kw):
    return subprocess.run([sys.executable, "-m", "hjplanner", *args], capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, preexec_fn=preexec, timeout=HANG_S, **kw)


BANK_ARGS = ["bank", "--bounds", "0,1,0,1", "--spacing", "0.25", "--rho", "0.2", "--h", "0.02",
             "--ntheta", "32", "--quiet"]


@pytest.mark.slow
def test_a_full_disk_stops_the_bank_at_the_first_failed_write(tmp_path):
    """Defect 9: a full disk left a partial workspace or 96 temporary files, and every
    remaining target was solved before the error."""
    import resource

    def small_files():                 # every write past 4 kB fails, as on a full disk
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))

    for workers in ("1", "2"):
        folder = tmp_path / f"w{workers}"
        r = _cli(*BANK_ARGS, "--cache", str(folder), "--workers", workers, preexec=small_files)
        assert r.returncode == 2, r.stderr
        assert r.stderr.startswith("error: cannot write value function") and r.stderr.count("\n") == 1
        left = [p.name for p in folder.rglob("*") if p.is_file() and p.name != "bank.json"]
        assert left == [], left                                   # no temporary file, no partial file


def test_a_cache_folder_that_cannot_be_written_is_refused_before_any_work(tmp_path):
    """Defect 11: HJPLANNER_CACHE on a read-only folder gave an OSError traceback."""
    r = _cli(*BANK_ARGS, env={"HJPLANNER_CACHE": "/proc/hjplanner-cache"})
    assert r.returncode == 2 and r.stderr.startswith("error: the cache folder (HJPLANNER_CACHE) "
                                                     "'/proc/hjplanner-cache'"), r.stderr
    assert r.stderr.count("\n") == 1
    with pytest.raises(PlanningError, match="cannot be written"):
        ValueFunctionBank(DOMAIN, 0.5, cache_dir="/proc/hjplanner-cache", **PARAMS)


def test_the_car_refuses_a_cache_it_cannot_write(tmp_path):
    r = subprocess.run([sys.executable, "-m", "reciprocity.cli", "run", "--arena", "paper", "--strategy",
                        "reciprocity", "--platform", "car", "--car", "planner=bank", "--quiet"], capture_output=True, text=True, timeout=HANG_S,
                       env={**os.environ, "HJPLANNER_CACHE": "/proc/hjplanner-cache"})
    assert r.returncode == 2 and r.stderr.startswith("error: HJPLANNER_CACHE '/proc/hjplanner-cache'"), r.stderr
    assert r.stderr.count("\n") == 1


def test_clearing_survives_a_damaged_manifest_and_never_follows_a_link(built, tmp_path_factory):
    """Defect 10: a damaged bank.json gave a traceback; a linked entry cleared nothing."""
    folder, _ = built
    bank = _bank(folder)
    (bank.directory / "bank.json").write_text("{ not json")
    precious = tmp_path_factory.mktemp("precious")
    (precious / "0000.npz").write_bytes(b"someone else's")
    (precious / "bank.json").write_text("{}")
    (folder / ("f" * 20)).symlink_to(precious, target_is_directory=True)
    info = cache_info(folder)
    assert [e["damaged"] for e in info] == [True]
    assert clear_cache(folder) > 0
    assert list(folder.iterdir()) == []                          # the bank and the link are gone ...
    assert sorted(p.name for p in precious.iterdir()) == ["0000.npz", "bank.json"]   # ... not what it showed


@pytest.mark.slow
@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc to find the workers")
def test_kill_9_on_a_bank_leaves_no_worker_behind(tmp_path):
    """Defect 8: kill -9 on 'hjplanner bank' orphaned its pool workers (about 160 MB each),
    the resource tracker, and its workspace file."""
    proc = subprocess.Popen([sys.executable, "-m", "hjplanner", *BANK_ARGS[:-1], "--h", "0.01", "--ntheta", "64",
                             "--spacing", "0.1", "--cache", str(tmp_path), "--workers", "2", "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:                                          # once both workers have written a file
        workers, alive = kill_9_when(proc, lambda: len(descendants(proc.pid)) >= 3
                                     and len(list(tmp_path.rglob("0*.npz"))) >= 2)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert len(workers) >= 2 and not alive, f"orphans: {alive}"
    assert not list(tmp_path.rglob("*.workspace")) and not list(tmp_path.rglob("*.pkl"))
    bank_dir = next(p for p in tmp_path.iterdir() if p.is_dir())
    ValueFunctionBank(DOMAIN, 0.1, cache_dir=tmp_path, rho=0.2, h=0.01, ntheta=64).missing()
    from hjplanner.bank import _remove_orphan_tmp
    _remove_orphan_tmp(bank_dir)                   # what a killed writer left is removed on next use
    assert not list(bank_dir.glob(".*.tmp"))
