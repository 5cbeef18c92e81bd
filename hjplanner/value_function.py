"""The value function φ(x, y, θ) as an object: evaluation, files, plots, paths."""

from __future__ import annotations

import json
from pathlib import Path as FsPath

import numpy as np
from numpy.typing import ArrayLike

from . import _sweep
from ._grid import Grid
from .dubins import local_exact
from .errors import PlanningError

__all__ = ["ValueFunction"]

FORMAT = "hjplanner.ValueFunction/1"


class ValueFunction:
    """φ on an (x, y, θ) grid, evaluated anywhere by interpolation.

    Usually made by :func:`hjplanner.solve` or :meth:`load`.

    Parameters
    ----------
    phi : numpy.ndarray
        Values, shape (ntheta, nx, ny); +inf where blocked or unreachable.
    grid : Grid
        Node coordinates.
    free : numpy.ndarray
        Free-space node mask, shape (nx, ny).
    meta : dict
        JSON-serialisable metadata (target, rho, h, ntheta, clearance, ...).
    geometry : dict, optional
        ``boundary`` and ``obstacles`` polygons of the domain, for plots.

    Examples
    --------
    >>> from hjplanner import solve
    >>> vf = solve(((-1, 1), (-1, 1)), (0, 0), rho=0.3, h=0.05, ntheta=32)
    >>> vf([-0.5, 0.5], [0.0, 0.0], [0.0, 0.0]).shape
    (2,)
    """

    def __init__(self, phi: np.ndarray, grid: Grid, free: np.ndarray, meta: dict, geometry: dict | None = None):
        self._phi = np.ascontiguousarray(phi, dtype=float)
        self.grid = grid
        self.free = np.asarray(free, dtype=bool)
        self.meta = dict(meta)
        self.geometry = geometry or {"boundary": None, "obstacles": []}

    # --- properties -------------------------------------------------------
    @property
    def values(self) -> np.ndarray:
        """Node values as an (nx, ny, ntheta) view (x index first)."""
        return self._phi.transpose(1, 2, 0)

    @property
    def target(self) -> np.ndarray:
        """Target position (2,)."""
        return np.asarray(self.meta["target"], dtype=float)

    @property
    def rho(self) -> float:
        """Minimum turning radius."""
        return float(self.meta["rho"])

    @property
    def reverse(self) -> bool:
        """Whether reverse driving was allowed (Reeds-Shepp)."""
        return bool(self.meta.get("reverse", False))

    # --- evaluation -------------------------------------------------------
    def __call__(self, x: ArrayLike, y: ArrayLike, theta: ArrayLike, *, cubic: bool = True) -> np.ndarray:
        """φ at poses, broadcasting ``x``, ``y`` (length unit) and ``theta`` (radians).

        Tricubic (Catmull-Rom) interpolation, periodic in θ, as in the paper;
        trilinear next to +inf nodes; +inf at unreachable states and outside
        the grid.  Within the solver's exact layer around a point target
        (``meta["local_radius"]``) the exact value is used where smaller.
        Never NaN for finite inputs.
        """
        x, y, theta = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), np.asarray(theta, float))
        shape = x.shape
        out = _sweep.interpolate(self._phi, self.grid.x0, self.grid.y0, self.grid.h,
                                 np.ascontiguousarray(x.ravel()), np.ascontiguousarray(y.ravel()),
                                 np.ascontiguousarray(theta.ravel()), bool(cubic))
        r0 = float(self.meta.get("local_radius", 0.0))
        if r0 > 0:
            # The solver's exact initial layer (see solve): where the optimal path
            # is shorter than r0, φ is known exactly and sharper than any
            # interpolant across the thin valley of φ around the target.
            xr, yr, tr = x.ravel(), y.ravel(), theta.ravel()
            near = np.hypot(xr - self.target[0], yr - self.target[1]) <= r0
            if near.any():
                exact = local_exact(xr[near], yr[near], tr[near], self.target, self.rho, r0, self.reverse)
                out[near] = np.minimum(out[near], exact)
        return out.reshape(shape)

    def dtheta(self, x: ArrayLike, y: ArrayLike, theta: ArrayLike, step: float | None = None) -> np.ndarray:
        """Centred difference approximation of φ_θ (length per radian), nan-free (+-inf or 0 when one-sided)."""
        step = self.grid.dtheta / 2 if step is None else float(step)
        plus = self(x, y, np.asarray(theta) + step)
        minus = self(x, y, np.asarray(theta) - step)
        with np.errstate(invalid="ignore"):
            d = (plus - minus) / (2 * step)
        return np.where(np.isnan(d), 0.0, d)

    # --- files ------------------------------------------------------------
    def save(self, path: str | FsPath) -> FsPath:
        """Write an ``.npz`` file (no pickles) with values, free mask, grid and metadata."""
        path = FsPath(path)
        meta = dict(self.meta, format=FORMAT,
                    grid=dict(x0=self.grid.x0, y0=self.grid.y0, h=self.grid.h, nx=self.grid.nx,
                              ny=self.grid.ny, ntheta=self.grid.ntheta))
        boundary = self.geometry.get("boundary")
        arrays = {"phi": self._phi, "free": self.free, "meta": np.array(json.dumps(meta)),
                  "boundary": np.zeros((0, 2)) if boundary is None else np.asarray(boundary, float),
                  "n_obstacles": np.array(len(self.geometry.get("obstacles", [])))}
        for n, obstacle in enumerate(self.geometry.get("obstacles", [])):
            arrays[f"obstacle_{n}"] = np.asarray(obstacle, float)
        with open(path, "wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path

    @classmethod
    def load(cls, path: str | FsPath) -> "ValueFunction":
        """Read a file written by :meth:`save`.

        Raises
        ------
        PlanningError
            If the file is missing or not a value-function file.
        """
        path = FsPath(path)
        try:
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                if meta.get("format") != FORMAT:
                    raise PlanningError(f"{path} is not an hjplanner value function (format {meta.get('format')!r})")
                g = meta.pop("grid")
                meta.pop("format")
                grid = Grid(float(g["x0"]), float(g["y0"]), float(g["h"]), int(g["nx"]), int(g["ny"]),
                            int(g["ntheta"]))
                boundary = data["boundary"]
                geometry = {"boundary": boundary if len(boundary) else None,
                            "obstacles": [data[f"obstacle_{n}"] for n in range(int(data["n_obstacles"]))]}
                phi, free = data["phi"], data["free"]
        except FileNotFoundError:
            raise PlanningError(f"value-function file {path} does not exist") from None
        except (OSError, KeyError, ValueError) as exc:
            if isinstance(exc, PlanningError):
                raise
            raise PlanningError(f"cannot read value function from {path}: {exc}") from None
        if phi.shape != (grid.ntheta, grid.nx, grid.ny):
            raise PlanningError(f"{path}: values of shape {phi.shape} do not match the grid")
        return cls(phi, grid, free, meta, geometry)

    # --- paths and plots --------------------------------------------------
    def path(self, start_pose: ArrayLike, ds: float | None = None, **kwargs):
        """Optimal path from ``start_pose`` (x, y, θ); see :func:`hjplanner.paths.optimal_path`."""
        from .paths import optimal_path
        return optimal_path(self, start_pose, ds=ds, **kwargs)

    def plot_slice(self, theta: float, ax=None, *, levels: int = 20, show_geometry: bool = True):
        """Filled contours of φ(·, ·, θ) at heading ``theta`` (radians); returns the Axes."""
        import matplotlib.pyplot as plt
        if ax is None:
            _, ax = plt.subplots(figsize=(5, 4.5))
        gx, gy = np.meshgrid(self.grid.x, self.grid.y, indexing="ij")
        values = self(gx, gy, np.full_like(gx, theta), cubic=False)
        masked = np.ma.masked_invalid(values)
        cs = ax.contourf(gx, gy, masked, levels=levels, cmap="viridis")
        ax.figure.colorbar(cs, ax=ax, label="φ (path length)")
        if show_geometry:
            for polygon in [self.geometry.get("boundary"), *self.geometry.get("obstacles", [])]:
                if polygon is not None and len(polygon):
                    closed = np.vstack([polygon, polygon[:1]])
                    ax.plot(closed[:, 0], closed[:, 1], "k-", lw=1)
        ax.plot(*self.target, "r*", ms=10)
        ax.set_aspect("equal")
        ax.set_title(f"φ(x, y, θ={np.degrees(theta):.0f}°)")
        return ax

    def __repr__(self) -> str:
        g = self.grid
        return (f"ValueFunction(domain={self.meta.get('domain')!r}, target={tuple(self.meta['target'])}, "
                f"rho={self.rho:g}, grid={g.nx}x{g.ny}x{g.ntheta}, h={g.h:g})")
