"""Banks of value functions: precomputed on a lattice of targets, or solved on demand.

Landa et al. (section VI) precompute value functions for about 100 targets
12.7 cm apart on the 140 x 140 cm floor and steer towards any requested
target with the nearest precomputed one.

A bank lives in its own folder ``<cache>/<key>/`` of the cache directory
(:func:`default_cache_dir`): one compressed ``.npz`` per target and a
``bank.json`` describing the domain and the parameters.  The key hashes the
domain's geometry and every parameter that changes the values, so whoever
asks for the same bank -- the ``hjplanner bank`` command or a program --
finds the same files.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import multiprocessing
import os
import pickle
import re
import shutil
import stat
import time
import warnings
from collections import OrderedDict
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures import TimeoutError as FutureTimeout
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import numpy as np

from arenas.processes import die_with_parent

from ._grid import Grid, make_grid
from .errors import PlanningError
from .solver import SolverOptions, Workspace, prepare, prepared, solve_in, target_is_free, window
from .value_function import ValueFunction

__all__ = ["ValueFunctionBank", "OnDemandPlanner", "lattice_targets", "default_cache_dir", "cache_info",
           "clear_cache"]

CACHE_VERSION = 3
MANIFEST = "bank.json"
#: Files of the first cache layout (float64 values, one flat folder): unusable now, removed by clear_cache.
_LEGACY = re.compile(r"^[0-9a-f]{20}_\d{4}_.*\.npz$")


def default_cache_dir() -> Path:
    """Where banks are kept: ``$HJPLANNER_CACHE`` if set, else ``~/.cache/hjplanner``."""
    env = os.environ.get("HJPLANNER_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "hjplanner"


def _library_versions() -> dict:
    """The versions a value function's numbers depend on: this toolkit's and numpy's (an
    upgrade must not leave a plan depending on a warm cache)."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        toolkit = version("reciprocity-search")
    except PackageNotFoundError:          # run from a source tree that is not installed
        toolkit = "source"
    return {"toolkit": toolkit, "numpy": np.__version__}


def _digest(geometry: dict, params: dict) -> str:
    """Hash of the domain's polygons, the parameters and the libraries' versions (the
    bank's folder name)."""
    sha = hashlib.sha256()
    sha.update(json.dumps(dict(params, version=CACHE_VERSION, libraries=_library_versions()),
                          sort_keys=True).encode())
    for polygon in (geometry["boundary"], *geometry["obstacles"]):
        sha.update(np.ascontiguousarray(polygon, dtype="<f8").tobytes())
        sha.update(b"|")
    return sha.hexdigest()[:20]


def _lattice(grid: Grid, free: np.ndarray, spacing: float) -> np.ndarray:
    if not (np.isfinite(spacing) and spacing > 0):
        raise PlanningError(f"spacing must be a positive number, got {spacing!r}")
    axes = []
    for lo, hi in ((grid.x0, grid.x1), (grid.y0, grid.y1)):
        n = max(int(np.floor((hi - lo) / spacing)), 1)
        margin = 0.5 * ((hi - lo) - (n - 1) * spacing)
        axes.append(lo + margin + spacing * np.arange(n))
    gx, gy = np.meshgrid(*axes, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel()])
    keep = [target_is_free(grid, free, x, y) for x, y in points]
    return points[np.asarray(keep, dtype=bool)]


def lattice_targets(domain, spacing: float, *, h: float = 1.0, clearance: float = 0.0) -> np.ndarray:
    """Targets on a square lattice of ``spacing``, centred in the bounding box, in free space.

    Parameters
    ----------
    domain : arenas.Arena or ((float, float), (float, float))
        As in :func:`hjplanner.solve`.
    spacing : float
        Lattice spacing (length unit), > 0.
    h : float, optional
        Grid spacing deciding what is free.
    clearance : float, optional
        Required distance from every wall (length unit).

    Returns
    -------
    numpy.ndarray
        (n, 2) targets whose grid cell at spacing ``h`` has only free nodes.
    """
    grid, _, free = make_grid(domain, float(h), 8, float(clearance))
    return _lattice(grid, free, spacing)


_WORKSPACE: Workspace | None = None


def _set_workspace(args: tuple) -> None:
    """Process-pool initializer: each worker prepares the workspace itself from the domain
    and parameters its owner passed (nothing is read from a file, nothing unpickled from
    disk), and dies with its owner."""
    global _WORKSPACE
    owner, domain, rho, h, ntheta, clearance, reverse, options = args
    die_with_parent(owner)
    _WORKSPACE = prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options)


#: Seconds a worker process may take to start (import numba, prepare the workspace) before
#: the bank is built in the calling process instead.
STARTUP_TIMEOUT = 120.0
#: Largest start-up message (bytes) sent to a worker: a larger domain is built in this
#: process, so that no write to a worker's pipe can block on a worker that never reads it.
MAX_STARTUP_BYTES = 48_000


def _start_pool(workers: int, initargs: tuple) -> ProcessPoolExecutor | None:
    """A pool of ``workers`` spawned processes, each preparing the workspace from
    ``initargs``, once one of them has answered; None (with a warning) if a worker died
    or did not answer within :data:`STARTUP_TIMEOUT`.

    A spawned worker first runs the caller's main module again.  A script that builds a bank
    outside ``if __name__ == "__main__":`` makes that worker fail; the bank is then built in
    this process.  The start-up message is at most :data:`MAX_STARTUP_BYTES`, less than a
    pipe's buffer, so this process never blocks on a worker that died before reading it.
    """
    if len(pickle.dumps(initargs, protocol=pickle.HIGHEST_PROTOCOL)) > MAX_STARTUP_BYTES:
        return None
    # spawn: no inherited threads or locks from the parent, the same on every OS.
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_set_workspace, initargs=((os.getpid(), *initargs),))
    ready = pool.submit(os.getpid)
    deadline = time.monotonic() + STARTUP_TIMEOUT
    while True:
        try:
            ready.result(timeout=0.25)
            return pool
        except FutureTimeout:
            if not any(p.exitcode is not None for p in _pool_processes(pool)) and time.monotonic() < deadline:
                continue
        except BrokenProcessPool:
            pass
        _stop_pool(pool)
        warnings.warn("hjplanner: the bank's worker processes could not start (a script that builds a bank "
                      "must do so under `if __name__ == '__main__':`); building it in this process",
                      RuntimeWarning, stacklevel=3)
        return None


def _pool_processes(pool: ProcessPoolExecutor) -> list:
    """The pool's worker processes (the executor keeps them in ``_processes``; none if that changes)."""
    return list((getattr(pool, "_processes", None) or {}).values())


def _stop_pool(pool: ProcessPoolExecutor) -> None:
    """Stop `pool` now: queued work cancelled, workers terminated and reaped."""
    processes = _pool_processes(pool)
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(5.0)


#: Temporary files of a bank folder (``.NNNN.npz.<pid>.tmp``, ``.probe.<pid>.tmp``,
#: ``.bank.json.<pid>.tmp``), removed when their writer is gone.
_TMP = re.compile(r"^\.(?:\d{4}\.npz|probe|bank\.json)\.(\d+)\.tmp$")


def _solve_to_file(target, path: str, ws: Workspace | None = None) -> str:
    """Solve one target and save it atomically (in a worker process, or here with ``ws``);
    the temporary file is removed on every exit path (a full disk, an interrupt)."""
    vf = solve_in(ws or _WORKSPACE, tuple(target))
    final = Path(path)
    tmp = final.with_name(f".{final.name}.{os.getpid()}.tmp")
    try:
        if not _save_unnamed(vf, final.parent, tmp):
            vf.save(tmp)
        os.replace(tmp, final)
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()
    return path


def _save_unnamed(vf: ValueFunction, folder: Path, name: Path) -> bool:
    """Write `vf` into an unnamed file of `folder` (Linux ``O_TMPFILE``) and give it the name
    `name` once complete: a process killed while writing leaves nothing behind. False
    (nothing written) where the system or the file system cannot do so."""
    if not _unnamed_files(folder):
        return False
    fd = os.open(folder, os.O_TMPFILE | os.O_WRONLY, 0o600)
    with os.fdopen(fd, "wb") as fh:
        vf.save(fh)
        fh.flush()
        os.link(f"/proc/self/fd/{fd}", name)
    return True


_UNNAMED: dict[int, bool] = {}


def _unnamed_files(folder: Path) -> bool:
    """Whether unnamed files can be made in `folder` and linked into it (asked once per device)."""
    flag = getattr(os, "O_TMPFILE", None)
    try:
        dev = os.stat(folder).st_dev
    except OSError:
        return False
    if flag is None:
        return False
    if dev not in _UNNAMED:
        probe = folder / f".probe.{os.getpid()}.tmp"
        try:
            fd = os.open(folder, flag | os.O_WRONLY, 0o600)
            try:
                os.link(f"/proc/self/fd/{fd}", probe)
                _UNNAMED[dev] = True
            finally:
                os.close(fd)
        except OSError:
            _UNNAMED[dev] = False
        with contextlib.suppress(OSError):
            probe.unlink()
    return _UNNAMED[dev]


def _remove_orphan_tmp(folder: Path) -> None:
    """Remove the temporary files of `folder` whose writing process is gone (killed)."""
    with contextlib.suppress(OSError):
        for entry in os.scandir(folder):
            m = _TMP.match(entry.name)
            if m and entry.is_file(follow_symlinks=False) and not _alive(int(m.group(1))):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def check_cache_dir(folder: Path, label: str = "the value-function cache") -> Path:
    """`folder` if a bank can be kept there, else PlanningError naming it; checked before
    any work, creating nothing: an existing `folder` must be a real folder (not a link) this
    process can write into, a missing one must have a writable folder as its nearest
    existing ancestor."""
    import tempfile
    folder = Path(folder)
    probe = folder
    while not os.path.lexists(probe) and probe != probe.parent:
        probe = probe.parent
    try:
        st = os.lstat(probe)
        if not stat.S_ISDIR(st.st_mode):
            where = "is" if probe == folder else f"cannot be made: {str(probe)!r} is"
            raise PlanningError(f"{label} {str(folder)!r} {where} not a folder (or is a symbolic link); "
                                "give a folder (HJPLANNER_CACHE, --cache or cache_dir=)")
        with tempfile.TemporaryFile(dir=probe):
            pass
    except OSError as exc:
        raise PlanningError(f"{label} {str(folder)!r} cannot be written ({exc.strerror or exc}); "
                            "give a writable folder (HJPLANNER_CACHE, --cache or cache_dir=)") from None
    return folder


#: Bank files checked in this process: path -> (inode, mtime, size) when checked.
_CHECKED: OrderedDict = OrderedDict()
#: Most entries of :data:`_CHECKED`.
_CHECKED_SIZE = 4096


def _stamp(st: os.stat_result) -> tuple:
    """What changes whenever a file is replaced, written, or given to another user."""
    return st.st_ino, st.st_mtime_ns, st.st_ctime_ns, st.st_size, st.st_uid


def _remember_checked(path: str, stamp: tuple) -> None:
    _CHECKED[path] = stamp
    _CHECKED.move_to_end(path)
    while len(_CHECKED) > _CHECKED_SIZE:
        _CHECKED.popitem(last=False)


class ValueFunctionBank:
    """Value functions for a lattice of targets, cached on disk.

    Parameters
    ----------
    domain : arenas.Arena or ((float, float), (float, float))
        As in :func:`hjplanner.solve`.
    spacing : float
        Lattice spacing of the targets (length unit; the paper: 12.7 cm).
    rho, h, ntheta, clearance, reverse, options
        Passed to :func:`hjplanner.solve`.  ``options.threads`` does not
        change the bank (each worker process sweeps with one thread).
    cache_dir : str or Path, optional
        Cache directory; default :func:`default_cache_dir`.  The bank's
        files are in its subfolder :attr:`directory`, named by a hash of the
        domain's geometry and of every other parameter, so a changed arena
        or parameter never reuses stale files.
    memory : int, optional
        How many loaded value functions to keep in memory (LRU).

    Examples
    --------
    >>> bank = ValueFunctionBank(((0, 1), (0, 1)), 0.5, rho=0.2, h=0.05, ntheta=16,
    ...                          cache_dir=tmp_path)  # doctest: +SKIP
    >>> bank.build(workers=2)  # doctest: +SKIP
    >>> vf = bank.nearest((0.3, 0.6))  # doctest: +SKIP
    """

    def __init__(self, domain, spacing: float, *, rho: float, h: float, ntheta: int, clearance: float = 0.0,
                 reverse: bool = False, options: SolverOptions | None = None, cache_dir: str | Path | None = None,
                 memory: int = 8):
        options = options or SolverOptions()
        self.cache_dir = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
        check_cache_dir(self.cache_dir)
        self.workspace = prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options)
        self.targets = _lattice(self.workspace.grid, self.workspace.free, spacing)
        if len(self.targets) == 0:
            raise PlanningError(f"no free target on a lattice of spacing {spacing:g}; reduce the spacing")
        numerics = {k: v for k, v in options.as_dict().items() if k != "threads"}
        self.params = dict(rho=float(rho), h=float(h), ntheta=int(ntheta), clearance=float(clearance),
                           reverse=bool(reverse), spacing=float(spacing), options=numerics)
        self.key = _digest(self.workspace.geometry, self.params)
        single = SolverOptions(**dict(options.as_dict(), threads=1))
        self._initargs = (domain, float(rho), float(h), int(ntheta), float(clearance), bool(reverse), single)
        self._memory = OrderedDict()
        self._memory_size = int(memory)

    @property
    def directory(self) -> Path:
        """Folder of this bank's files in the cache."""
        return self.cache_dir / self.key

    def path_of(self, index: int) -> Path:
        """Cache file of target ``index``."""
        return self.directory / f"{index:04d}.npz"

    def missing(self) -> list[int]:
        """Indices of targets without a good file in the cache (absent, or failing its
        check: see :meth:`load`; a bad file is moved aside with a CacheWarning). A file
        checked before in this process and unchanged since (inode, time, size) is not read
        again, so a campaign's episodes pay for the check once per worker."""
        return [i for i in range(len(self.targets)) if not self._unchanged(i) and self._read(i) is None]

    def _unchanged(self, index: int) -> bool:
        try:
            st = os.lstat(self.path_of(index))
        except OSError:
            return False
        return _CHECKED.get(str(self.path_of(index))) == _stamp(st)

    def load(self, index: int) -> ValueFunction:
        """The cached value function of target ``index``, checked; solved (and cached) when
        absent or bad.

        A file is used only when it is a regular file of this user (not a link, not a
        FIFO), reads as a value function whose content matches its digest, and was solved
        for this bank: its target, turning radius, clearance, grid and domain. Anything else
        is moved into the bank's ``quarantine/`` with a
        :class:`~arenas.cache_files.CacheWarning` and solved again.
        """
        vf = self._read(index)
        if vf is None:
            self._write_manifest()
            _remove_orphan_tmp(self.directory)
            path = self.path_of(index)
            _solve_to_file(self.targets[index], str(path), self.workspace)
            vf = ValueFunction.load(path)
        return vf

    def _read(self, index: int) -> ValueFunction | None:
        """The file of target ``index`` if present and good, else None (a bad one moved aside)."""
        from arenas.cache_files import open_owned, quarantine
        path = self.path_of(index)
        try:
            with open_owned(path) as fh:
                st = os.fstat(fh.fileno())
            stamp = _stamp(st)
            vf = ValueFunction.load(path)
            self._check_file(vf, index)
            _remember_checked(str(path), stamp)
        except FileNotFoundError:
            return None
        except Exception as exc:          # whatever is wrong with it, a cache never fails a plan
            quarantine(path, " ".join(str(exc).split()).replace(str(path), "the file")[:300])
            return None
        return vf

    def _check_file(self, vf: ValueFunction, index: int) -> None:
        """PlanningError unless `vf` is this bank's value function of target ``index``."""
        g, mine = vf.grid, self.workspace.grid
        meta = vf.meta
        same = (vf.content_sha256 is not None
                and np.array_equal(np.asarray(meta.get("target"), dtype=float), self.targets[index])
                and (g.x0, g.y0, g.h, g.nx, g.ny, g.ntheta) == (mine.x0, mine.y0, mine.h, mine.nx, mine.ny,
                                                                mine.ntheta)
                and meta.get("rho") == self.params["rho"] and meta.get("clearance") == self.params["clearance"]
                and bool(meta.get("reverse", False)) == self.params["reverse"]
                and np.array_equal(vf.free, self.workspace.free))
        if not same:
            raise PlanningError(f"not this bank's value function of target {index} "
                                f"({self.targets[index].tolist()}): another target, grid or domain")

    def _write_manifest(self) -> None:
        try:
            self.directory.mkdir(mode=0o700, parents=True, exist_ok=True)
            manifest = dict(version=CACHE_VERSION, domain=self.workspace.geometry["name"], params=self.params,
                            targets=self.targets.tolist())
            tmp = self.directory / f".{MANIFEST}.{os.getpid()}.tmp"
            try:
                tmp.write_text(json.dumps(manifest, indent=1))
                os.replace(tmp, self.directory / MANIFEST)
            finally:
                with contextlib.suppress(OSError):
                    tmp.unlink()
        except OSError as exc:
            raise PlanningError(f"cannot write the bank's files in {str(self.directory)!r}: "
                                f"{exc.strerror or exc}") from None

    def build(self, workers: int | None = None, progress: bool = True) -> float:
        """Solve every missing target, in parallel processes; returns the wall time (s).

        Each process sweeps with one thread and prepares the workspace (grid, free
        space, clear stencils) once; ``workers`` defaults to the number of CPUs. Progress
        is shown with a tqdm bar. The first file that cannot be written (a full disk)
        stops the build: the work queued is cancelled, the workers are stopped, no
        temporary file is left, and PlanningError names the cause.
        """
        from tqdm import tqdm

        t0 = time.perf_counter()
        self._write_manifest()
        _remove_orphan_tmp(self.directory)
        todo = self.missing()
        workers = max(1, min(workers or os.cpu_count() or 1, len(todo) or 1))
        bar = tqdm(total=len(todo), desc=f"value functions ({self.key[:8]})", disable=not progress, unit="vf")
        pool = None
        try:
            pool = _start_pool(workers, self._initargs) if workers > 1 else None
            if pool is None:
                for i in todo:
                    self._solve(i)
                    bar.update()
            else:
                jobs = [pool.submit(_solve_to_file, self.targets[i], str(self.path_of(i))) for i in todo]
                for future in as_completed(jobs):
                    self._result(future)
                    bar.update()
        finally:
            bar.close()
            if pool is not None:
                _stop_pool(pool)
        return time.perf_counter() - t0

    def _solve(self, index: int) -> None:
        try:
            _solve_to_file(self.targets[index], str(self.path_of(index)), self.workspace)
        except OSError as exc:
            raise PlanningError(f"cannot write value function {self.path_of(index)}: {exc.strerror or exc}; "
                                "the bank is incomplete (free some space and build it again)") from None

    @staticmethod
    def _result(future) -> None:
        try:
            future.result()
        except OSError as exc:
            raise PlanningError(f"cannot write value function {exc.filename or ''}: {exc.strerror or exc}; "
                                "the bank is incomplete (free some space and build it again)") from None

    def nearest_index(self, target) -> int:
        """Index of the lattice target nearest to ``target``."""
        t = np.asarray(target, dtype=float).reshape(-1)
        if t.shape != (2,) or not np.isfinite(t).all():
            raise PlanningError(f"target must be a finite point (x, y), got {target!r}")
        return int(np.argmin(np.hypot(*(self.targets - t).T)))

    def nearest(self, target) -> ValueFunction:
        """Value function of the lattice target nearest to ``target`` (from the cache when
        a good file is there, else solved now: see :meth:`load`)."""
        index = self.nearest_index(target)
        if index in self._memory:
            self._memory.move_to_end(index)
            return self._memory[index]
        vf = self.load(index)
        self._memory[index] = vf
        while len(self._memory) > self._memory_size:
            self._memory.popitem(last=False)
        return vf

    def __len__(self) -> int:
        return len(self.targets)


_BANK = re.compile(r"^[0-9a-f]{20}$")


def _entries(root: Path) -> list[os.DirEntry]:
    try:
        return sorted(os.scandir(root), key=lambda e: e.name)
    except (FileNotFoundError, NotADirectoryError):
        return []
    except OSError as exc:
        raise PlanningError(f"cannot read the cache folder {str(root)!r}: {exc.strerror or exc}") from None


def _manifest(folder: Path) -> dict | None:
    """The bank.json of `folder`, or None when missing, unreadable or not a bank's."""
    from arenas.cache_files import CacheEntryError, open_owned
    try:
        with open_owned(folder / MANIFEST, max_bytes=50_000_000) as fh:
            manifest = json.loads(fh.read().decode("utf-8"))
    except (OSError, CacheEntryError, ValueError):
        return None
    ok = isinstance(manifest, dict) and isinstance(manifest.get("params"), dict) \
        and isinstance(manifest.get("targets"), list)
    return manifest if ok else None


def folder_bytes(folder: Path) -> int:
    """Bytes of the files below `folder` (links are not followed)."""
    total = 0
    for dirpath, _, files in os.walk(folder):        # os.walk never follows links by default
        for f in files:
            with contextlib.suppress(OSError):
                total += os.lstat(os.path.join(dirpath, f)).st_size
    return total


def cache_info(cache_dir: str | Path | None = None) -> list[dict]:
    """The banks in a cache directory (default :func:`default_cache_dir`).

    Returns
    -------
    list of dict
        One entry per bank folder: ``key``, ``domain``, ``params``, ``files`` (value
        functions present), ``targets``, ``bytes`` and ``damaged`` (its ``bank.json`` is
        missing or unreadable: cleared like the others); and, if any, one entry with key
        ``"legacy"`` for files of the first cache layout, which are no longer read.
        Symbolic links are never followed.
    """
    root = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
    out = []
    legacy = []
    for e in _entries(root):
        if e.is_dir(follow_symlinks=False) and (_BANK.match(e.name) or (Path(e.path) / MANIFEST).exists()):
            folder = Path(e.path)
            manifest = _manifest(folder)
            files = [f for f in os.scandir(folder) if f.name.endswith(".npz") and f.is_file(follow_symlinks=False)]
            out.append(dict(key=e.name, domain=manifest.get("domain") if manifest else None,
                            params=manifest["params"] if manifest else None, files=len(files),
                            targets=len(manifest["targets"]) if manifest else None, bytes=folder_bytes(folder),
                            damaged=manifest is None))
        elif e.is_file(follow_symlinks=False) and _LEGACY.match(e.name):
            legacy.append(e)
    if legacy:
        out.append(dict(key="legacy", domain=None, params=None, files=len(legacy), targets=None,
                        bytes=sum(e.stat(follow_symlinks=False).st_size for e in legacy), damaged=False))
    return out


def clear_cache(cache_dir: str | Path | None = None) -> int:
    """Delete the banks (and legacy files) of a cache directory; returns the bytes freed.

    Only hjplanner's own entries are removed: bank folders (named by their key, or
    holding a ``bank.json``, damaged or not) and files of the first cache layout. A
    symbolic link named like a bank is removed itself; what it points to is never touched.
    """
    root = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
    freed = 0
    for e in _entries(root):
        path = Path(e.path)
        try:
            if e.is_symlink() and (_BANK.match(e.name) or _LEGACY.match(e.name)):
                path.unlink()
            elif e.is_dir(follow_symlinks=False) and (_BANK.match(e.name) or (path / MANIFEST).exists()):
                freed += folder_bytes(path)
                shutil.rmtree(path)
            elif e.is_file(follow_symlinks=False) and _LEGACY.match(e.name):
                freed += e.stat(follow_symlinks=False).st_size
                path.unlink()
        except OSError as exc:
            raise PlanningError(f"cannot remove {str(path)!r} from the cache: {exc.strerror or exc}") from None
    return freed


class OnDemandPlanner:
    """Solves for the exact requested target, keeping the last few in memory (LRU).

    The target-independent part of the solve (grid, free space, clear
    stencils) is prepared once.

    Parameters
    ----------
    domain, rho, h, ntheta, clearance, reverse, options
        As in :func:`hjplanner.solve`.
    maxsize : int
        Number of value functions kept.
    resolution : float, optional
        Targets closer than this are the same cache entry; default ``h/10``.
    """

    def __init__(self, domain, *, rho: float, h: float, ntheta: int, clearance: float = 0.0,
                 reverse: bool = False, options: SolverOptions | None = None, maxsize: int = 4,
                 resolution: float | None = None):
        self.workspace = prepared(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options)
        self.maxsize = int(maxsize)
        self.resolution = float(resolution) if resolution is not None else 0.1 * float(h)
        self._cache = OrderedDict()
        self._components = None
        self.hits = 0
        self.misses = 0

    def get(self, target, near=None, margin: float | None = None) -> ValueFunction:
        """Value function for ``target``, solved unless cached.

        Parameters
        ----------
        target : (float, float)
            The target point.
        near : (float, float), optional
            A point the value function must serve (the car's position).  With
            ``margin``, the solve covers only the rectangle around ``target`` and
            ``near`` widened by ``margin`` on every side (see
            :func:`hjplanner.solver.window`): the paths found stay in it.  The whole
            grid is solved when that rectangle covers most of it.
        margin : float, optional
            Width added around the rectangle (length unit), > 0.

        Returns
        -------
        ValueFunction
            On the window's grid when one was used (``meta["window"]``: its
            ``[x0, x1, y0, y1]``).
        """
        t = np.asarray(target, dtype=float).reshape(-1)
        if t.shape != (2,) or not np.isfinite(t).all():
            raise PlanningError(f"target must be a finite point (x, y), got {target!r}")
        bounds = None if near is None or margin is None else self._window(t, near, margin)
        key = (tuple(np.round(t / self.resolution).astype(np.int64)), bounds)
        if key in self._cache:
            self.hits += 1
            self._cache.move_to_end(key)
            return self._cache[key]
        self.misses += 1
        ws = self.workspace if bounds is None else window(self.workspace, *bounds)
        vf = solve_in(ws, tuple(t))
        if bounds is not None:
            g = ws.grid
            vf.meta["window"] = [g.x0, g.x0 + (g.nx - 1) * g.h, g.y0, g.y0 + (g.ny - 1) * g.h]
        self._cache[key] = vf
        while len(self._cache) > self.maxsize:
            self._cache.popitem(last=False)
        return vf

    def reachable_from(self, start) -> "ReachableRegion":
        """The points a car at `start` (x, y) reaches on this planner's free nodes, by a
        flood fill, with no value function solved (:mod:`hjplanner.reach`; for the
        reversing car only). It may hold points behind gaps the solver's arcs cannot
        thread (``benchmarks/reach_certify.py`` counts them).

        Raises
        ------
        PlanningError
            When the planner's car cannot reverse, or no free node lies near `start`.
        """
        from .reach import FreeComponents
        if not self.workspace.reverse:
            raise PlanningError("reachable_from needs a car that reverses (reverse=True): a forward-only "
                                "car does not reach the whole of a connected free region")
        if self._components is None:
            self._components = FreeComponents(self.workspace.grid, self.workspace.free)
        return self._components.region(start)

    #: A window covering more than this share of the grid's nodes is not worth it: the whole grid is solved.
    WINDOW_SHARE = 0.8

    def _window(self, target: np.ndarray, near, margin: float) -> tuple[int, int, int, int] | None:
        """Node index bounds ``(i0, i1, j0, j1)`` of the window, or None for the whole grid."""
        p = np.asarray(near, dtype=float).reshape(-1)
        if p.shape != (2,) or not np.isfinite(p).all():
            raise PlanningError(f"near must be a finite point (x, y), got {near!r}")
        if not (isinstance(margin, (int, float)) and margin > 0 and np.isfinite(margin)):
            raise PlanningError(f"margin must be a positive length, got {margin!r}")
        g = self.workspace.grid
        lo = (np.minimum(target, p) - margin - (g.x0, g.y0)) / g.h
        hi = (np.maximum(target, p) + margin - (g.x0, g.y0)) / g.h
        i0, j0 = (max(0, int(np.floor(v))) for v in lo)
        i1, j1 = min(g.nx, int(np.ceil(hi[0])) + 1), min(g.ny, int(np.ceil(hi[1])) + 1)
        if i1 - i0 < 4 or j1 - j0 < 4 or (i1 - i0) * (j1 - j0) > self.WINDOW_SHARE * g.nx * g.ny:
            return None
        return i0, i1, j0, j1
