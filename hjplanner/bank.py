"""Banks of value functions: precomputed on a lattice of targets, or solved on demand.

Landa et al. (section VI) precompute value functions for about 100 targets
12.7 cm apart on the 140 x 140 cm floor and steer towards any requested
target with the nearest precomputed one.
"""

from __future__ import annotations

import hashlib
import json
import multiprocessing
import os
from collections import OrderedDict
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._grid import check_polygon, make_grid
from .errors import PlanningError
from .solver import SolverOptions, _target_is_free, solve
from .value_function import ValueFunction

__all__ = ["ValueFunctionBank", "OnDemandPlanner", "lattice_targets"]

CACHE_VERSION = 1


@dataclass(frozen=True)
class _Geometry:
    """Picklable stand-in for an arena: only what :func:`solve` reads."""

    boundary: np.ndarray
    obstacles: tuple
    name: str


def _geometry_of(domain) -> _Geometry | tuple:
    if hasattr(domain, "boundary"):
        return _Geometry(check_polygon(domain.boundary, "arena boundary"),
                         tuple(check_polygon(o, "arena obstacle") for o in getattr(domain, "obstacles", [])),
                         str(getattr(domain, "name", "arena")))
    try:
        (x0, x1), (y0, y1) = np.asarray(domain, dtype=float)
    except (TypeError, ValueError):
        raise PlanningError(
            f"domain must be an Arena or rectangle bounds ((x0, x1), (y0, y1)), got {domain!r}") from None
    return ((float(x0), float(x1)), (float(y0), float(y1)))


def _digest(geometry, params: dict) -> str:
    """Hash of the domain geometry and the solver parameters (the cache key)."""
    sha = hashlib.sha256()
    sha.update(json.dumps(dict(params, version=CACHE_VERSION), sort_keys=True).encode())
    if isinstance(geometry, _Geometry):
        for polygon in (geometry.boundary, *geometry.obstacles):
            sha.update(np.ascontiguousarray(polygon, dtype="<f8").tobytes())
            sha.update(b"|")
    else:
        sha.update(repr(geometry).encode())
    return sha.hexdigest()[:20]


def lattice_targets(domain, spacing: float, *, h: float = 1.0, clearance: float = 0.0) -> np.ndarray:
    """Targets on a square lattice of ``spacing``, centred in the bounding box, in free space.

    Returns an (n, 2) array.  Free means that the grid cell holding the
    target is free at spacing ``h`` after inflating obstacles by ``clearance``.
    """
    if not (np.isfinite(spacing) and spacing > 0):
        raise PlanningError(f"spacing must be positive, got {spacing!r}")
    grid, free, _, _ = make_grid(domain, h, 8, clearance)
    axes = []
    for lo, hi in ((grid.x0, grid.x1), (grid.y0, grid.y1)):
        n = max(int(np.floor((hi - lo) / spacing)), 1)
        margin = 0.5 * ((hi - lo) - (n - 1) * spacing)
        axes.append(lo + margin + spacing * np.arange(n))
    gx, gy = np.meshgrid(*axes, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel()])
    keep = [_target_is_free(grid, free, x, y) for x, y in points]
    return points[np.asarray(keep, dtype=bool)]


def _solve_to_file(geometry, target, params: dict, path: str) -> str:
    """Worker: solve one target and save it (runs in a child process)."""
    options = SolverOptions(**params.pop("options"))
    vf = solve(geometry, tuple(target), **params, options=options)
    tmp = f"{path}.{os.getpid()}.tmp"
    vf.save(tmp)
    os.replace(tmp, path)
    return path


class ValueFunctionBank:
    """Value functions for a lattice of targets, cached on disk.

    Parameters
    ----------
    domain : Arena or ((float, float), (float, float))
        As in :func:`hjplanner.solve`.
    spacing : float
        Lattice spacing of the targets (length unit; the paper: 12.7 cm).
    rho, h, ntheta, clearance, reverse
        Passed to :func:`hjplanner.solve`.
    cache_dir : str or Path, optional
        Directory of the ``.npz`` files; default ``~/.cache/hjplanner``.  The
        file names hash the arena geometry and every solver parameter, so a
        changed arena or parameter never reuses stale files.
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
        self.geometry = _geometry_of(domain)
        self.targets = lattice_targets(self.geometry, spacing, h=h, clearance=clearance)
        if len(self.targets) == 0:
            raise PlanningError(f"no free target on a lattice of spacing {spacing:g}; reduce the spacing")
        self.options = options or SolverOptions()
        self.params = dict(rho=float(rho), h=float(h), ntheta=int(ntheta), clearance=float(clearance),
                           reverse=bool(reverse))
        self.key = _digest(self.geometry, dict(self.params, options=self.options.as_dict(), spacing=float(spacing)))
        self.cache_dir = Path(cache_dir) if cache_dir is not None else Path.home() / ".cache" / "hjplanner"
        self._memory = OrderedDict()
        self._memory_size = int(memory)

    def path_of(self, index: int) -> Path:
        """Cache file of target ``index``."""
        x, y = self.targets[index]
        return self.cache_dir / f"{self.key}_{index:04d}_{x:.4g}_{y:.4g}.npz"

    def missing(self) -> list[int]:
        """Indices of targets not yet in the cache."""
        return [i for i in range(len(self.targets)) if not self.path_of(i).exists()]

    def build(self, workers: int | None = None, progress: bool = True) -> float:
        """Solve every missing target, in parallel processes; returns the wall time (s).

        Each process sweeps with one thread, ``workers`` defaults to the
        number of CPUs.  Progress is shown with a tqdm bar.
        """
        import time

        from tqdm import tqdm

        t0 = time.perf_counter()
        self.cache_dir.mkdir(parents=True, exist_ok=True)
        todo = self.missing()
        workers = max(1, min(workers or os.cpu_count() or 1, len(todo) or 1))
        options = self.options.as_dict()
        if workers > 1:
            options["threads"] = 1
        jobs = [(self.geometry, tuple(self.targets[i]), dict(self.params, options=dict(options)), str(self.path_of(i)))
                for i in todo]
        bar = tqdm(total=len(jobs), desc=f"value functions ({self.key[:8]})", disable=not progress, unit="vf")
        try:
            if workers == 1:
                for job in jobs:
                    _solve_to_file(*job)
                    bar.update()
            else:
                # spawn: no inherited threads or locks from the parent, the same on every OS.
                context = multiprocessing.get_context("spawn")
                with ProcessPoolExecutor(workers, mp_context=context) as pool:
                    for future in as_completed([pool.submit(_solve_to_file, *job) for job in jobs]):
                        future.result()
                        bar.update()
        finally:
            bar.close()
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
            self.cache_dir.mkdir(parents=True, exist_ok=True)
            _solve_to_file(self.geometry, tuple(self.targets[index]),
                           dict(self.params, options=self.options.as_dict()), str(path))
        vf = ValueFunction.load(path)
        self._memory[index] = vf
        while len(self._memory) > self._memory_size:
            self._memory.popitem(last=False)
        return vf

    def __len__(self) -> int:
        return len(self.targets)


class OnDemandPlanner:
    """Solves for the exact requested target, keeping the last few in memory (LRU).

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
        self.domain = domain
        self.kwargs = dict(rho=rho, h=h, ntheta=ntheta, clearance=clearance, reverse=reverse, options=options)
        self.maxsize = int(maxsize)
        self.resolution = float(resolution) if resolution is not None else 0.1 * float(h)
        self._cache = OrderedDict()
        self.hits = 0
        self.misses = 0

    def get(self, target) -> ValueFunction:
        """Value function for ``target``, solved unless cached."""
        t = np.asarray(target, dtype=float).reshape(-1)
        if t.shape != (2,) or not np.isfinite(t).all():
            raise PlanningError(f"target must be a finite point (x, y), got {target!r}")
        key = tuple(np.round(t / self.resolution).astype(np.int64))
        if key in self._cache:
            self.hits += 1
            self._cache.move_to_end(key)
            return self._cache[key]
        self.misses += 1
        vf = solve(self.domain, tuple(t), **self.kwargs)
        self._cache[key] = vf
        while len(self._cache) > self.maxsize:
            self._cache.popitem(last=False)
        return vf
