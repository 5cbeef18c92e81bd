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

import hashlib
import json
import multiprocessing
import os
import pickle
import re
import shutil
import tempfile
import time
import warnings
from collections import OrderedDict
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures import TimeoutError as FutureTimeout
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import numpy as np

from ._grid import Grid, make_grid
from .errors import PlanningError
from .solver import SolverOptions, Workspace, prepare, solve_in, target_is_free, window
from .value_function import ValueFunction

__all__ = ["ValueFunctionBank", "OnDemandPlanner", "lattice_targets", "default_cache_dir", "cache_info",
           "clear_cache"]

CACHE_VERSION = 2
MANIFEST = "bank.json"
#: Files of the first cache layout (float64 values, one flat folder): unusable now, removed by clear_cache.
_LEGACY = re.compile(r"^[0-9a-f]{20}_\d{4}_.*\.npz$")


def default_cache_dir() -> Path:
    """Where banks are kept: ``$HJPLANNER_CACHE`` if set, else ``~/.cache/hjplanner``."""
    env = os.environ.get("HJPLANNER_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "hjplanner"


def _digest(geometry: dict, params: dict) -> str:
    """Hash of the domain's polygons and the parameters (the bank's folder name)."""
    sha = hashlib.sha256()
    sha.update(json.dumps(dict(params, version=CACHE_VERSION), sort_keys=True).encode())
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


def _set_workspace(path: str) -> None:
    """Process-pool initializer: each worker reads the workspace once, from the file the
    pool's owner wrote (see :func:`_start_pool`)."""
    global _WORKSPACE
    with open(path, "rb") as fh:
        _WORKSPACE = pickle.load(fh)


#: Seconds a worker process may take to start (import numba, receive the workspace) before
#: the bank is built in the calling process instead.
STARTUP_TIMEOUT = 120.0


def _start_pool(workers: int, workspace_file: str) -> ProcessPoolExecutor | None:
    """A pool of ``workers`` spawned processes, each holding the workspace pickled in
    ``workspace_file``, once one of them has answered; None (with a warning) if a worker died
    or did not answer within :data:`STARTUP_TIMEOUT`.

    A spawned worker first runs the caller's main module again.  A script that builds a bank
    outside ``if __name__ == "__main__":`` makes that worker fail; the bank is then built in
    this process.  The workspace travels as a file name, not in the start-up message: a
    message larger than a pipe's buffer would block this process for ever on a worker that
    died before reading it.
    """
    # spawn: no inherited threads or locks from the parent, the same on every OS.
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_set_workspace, initargs=(workspace_file,))
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
        for process in _pool_processes(pool):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        warnings.warn("hjplanner: the bank's worker processes could not start (a script that builds a bank "
                      "must do so under `if __name__ == '__main__':`); building it in this process",
                      RuntimeWarning, stacklevel=3)
        return None


def _pool_processes(pool: ProcessPoolExecutor) -> list:
    """The pool's worker processes (the executor keeps them in ``_processes``; none if that changes)."""
    return list((getattr(pool, "_processes", None) or {}).values())


def _solve_to_file(target, path: str, ws: Workspace | None = None) -> str:
    """Solve one target and save it atomically (in a worker process, or here with ``ws``)."""
    vf = solve_in(ws or _WORKSPACE, tuple(target))
    tmp = f"{path}.{os.getpid()}.tmp"
    vf.save(tmp)
    os.replace(tmp, path)
    return path


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
        self.workspace = prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options)
        self.targets = _lattice(self.workspace.grid, self.workspace.free, spacing)
        if len(self.targets) == 0:
            raise PlanningError(f"no free target on a lattice of spacing {spacing:g}; reduce the spacing")
        numerics = {k: v for k, v in options.as_dict().items() if k != "threads"}
        self.params = dict(rho=float(rho), h=float(h), ntheta=int(ntheta), clearance=float(clearance),
                           reverse=bool(reverse), spacing=float(spacing), options=numerics)
        self.key = _digest(self.workspace.geometry, self.params)
        self.cache_dir = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
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
        """Indices of targets not yet in the cache."""
        return [i for i in range(len(self.targets)) if not self.path_of(i).exists()]

    def _write_manifest(self) -> None:
        self.directory.mkdir(parents=True, exist_ok=True)
        manifest = dict(version=CACHE_VERSION, domain=self.workspace.geometry["name"], params=self.params,
                        targets=self.targets.tolist())
        (self.directory / MANIFEST).write_text(json.dumps(manifest, indent=1))

    def build(self, workers: int | None = None, progress: bool = True) -> float:
        """Solve every missing target, in parallel processes; returns the wall time (s).

        Each process sweeps with one thread and receives the prepared
        workspace (grid, free space, clear stencils) once; ``workers``
        defaults to the number of CPUs.  Progress is shown with a tqdm bar.
        """
        from tqdm import tqdm

        t0 = time.perf_counter()
        self._write_manifest()
        todo = self.missing()
        workers = max(1, min(workers or os.cpu_count() or 1, len(todo) or 1))
        ws = self.workspace
        if workers > 1:
            ws = Workspace(**{**vars(ws), "options": SolverOptions(**dict(ws.options.as_dict(), threads=1))})
        bar = tqdm(total=len(todo), desc=f"value functions ({self.key[:8]})", disable=not progress, unit="vf")
        scratch = None
        try:
            pool = None
            if workers > 1:
                self.directory.mkdir(parents=True, exist_ok=True)
                with tempfile.NamedTemporaryFile("wb", dir=self.directory, suffix=".workspace", delete=False) as fh:
                    pickle.dump(ws, fh, protocol=pickle.HIGHEST_PROTOCOL)
                scratch = Path(fh.name)
                pool = _start_pool(workers, str(scratch))
            if pool is None:
                for i in todo:
                    _solve_to_file(self.targets[i], str(self.path_of(i)), self.workspace)
                    bar.update()
            else:
                with pool:
                    jobs = [pool.submit(_solve_to_file, self.targets[i], str(self.path_of(i))) for i in todo]
                    for future in as_completed(jobs):
                        future.result()
                        bar.update()
        finally:
            bar.close()
            if scratch is not None:
                scratch.unlink(missing_ok=True)
        return time.perf_counter() - t0

    def nearest_index(self, target) -> int:
        """Index of the lattice target nearest to ``target``."""
        t = np.asarray(target, dtype=float).reshape(-1)
        if t.shape != (2,) or not np.isfinite(t).all():
            raise PlanningError(f"target must be a finite point (x, y), got {target!r}")
        return int(np.argmin(np.hypot(*(self.targets - t).T)))

    def nearest(self, target) -> ValueFunction:
        """Value function of the lattice target nearest to ``target`` (solved now if not cached)."""
        index = self.nearest_index(target)
        if index in self._memory:
            self._memory.move_to_end(index)
            return self._memory[index]
        path = self.path_of(index)
        if not path.exists():
            self._write_manifest()
            _solve_to_file(self.targets[index], str(path), self.workspace)
        vf = ValueFunction.load(path)
        self._memory[index] = vf
        while len(self._memory) > self._memory_size:
            self._memory.popitem(last=False)
        return vf

    def __len__(self) -> int:
        return len(self.targets)


def cache_info(cache_dir: str | Path | None = None) -> list[dict]:
    """The banks in a cache directory (default :func:`default_cache_dir`).

    Returns
    -------
    list of dict
        One entry per bank folder: ``key``, ``domain``, ``params``,
        ``files`` (value functions present), ``targets`` and ``bytes``; and,
        if any, one entry with key ``"legacy"`` for files of the first cache
        layout, which are no longer read.
    """
    root = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
    out = []
    if not root.is_dir():
        return out
    for folder in sorted(p for p in root.iterdir() if (p / MANIFEST).is_file()):
        manifest = json.loads((folder / MANIFEST).read_text())
        files = list(folder.glob("*.npz"))
        out.append(dict(key=folder.name, domain=manifest.get("domain"), params=manifest.get("params"),
                        files=len(files), targets=len(manifest.get("targets", [])),
                        bytes=sum(f.stat().st_size for f in folder.iterdir() if f.is_file())))
    legacy = [p for p in root.iterdir() if p.is_file() and _LEGACY.match(p.name)]
    if legacy:
        out.append(dict(key="legacy", domain=None, params=None, files=len(legacy), targets=None,
                        bytes=sum(p.stat().st_size for p in legacy)))
    return out


def clear_cache(cache_dir: str | Path | None = None) -> int:
    """Delete the banks (and legacy files) of a cache directory; returns the bytes freed.

    Only hjplanner's own files are removed: bank folders holding a
    ``bank.json`` and files of the first cache layout.
    """
    root = Path(cache_dir).expanduser() if cache_dir is not None else default_cache_dir()
    freed = sum(entry["bytes"] for entry in cache_info(root))
    if root.is_dir():
        for folder in [p for p in root.iterdir() if (p / MANIFEST).is_file()]:
            shutil.rmtree(folder)
        for legacy in [p for p in root.iterdir() if p.is_file() and _LEGACY.match(p.name)]:
            legacy.unlink()
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
        self.workspace = prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options)
        self.maxsize = int(maxsize)
        self.resolution = float(resolution) if resolution is not None else 0.1 * float(h)
        self._cache = OrderedDict()
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
