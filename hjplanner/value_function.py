"""The value function φ(x, y, θ) as an object: evaluation, files, plots, paths."""

from __future__ import annotations

import json
import zipfile
import zlib
from pathlib import Path as FsPath

import numpy as np
from numpy.typing import ArrayLike

from . import _sweep
from ._grid import Grid, lower_wall_distance
from ._search import local_exact_many
from .errors import PlanningError

__all__ = ["ValueFunction"]

FORMAT = "hjplanner.ValueFunction/2"
#: Finite values are stored as uint16 multiples of a quantum; the largest code is +inf.
QUANTUM_STEPS = 65534
#: Grid headings on either side of a pose that :meth:`ValueFunction.__call__` reaches by exact arcs.
ARC_STEPS = 2
#: The quantum is h / QUANTA_PER_CELL, or larger if φ would not fit in QUANTUM_STEPS quanta.
QUANTA_PER_CELL = 64


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
    distance : numpy.ndarray
        Signed wall distance at the nodes (length unit), shape (nx, ny): the
        domain's geometry as the planner sees it (see :mod:`hjplanner._grid`).
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

    def __init__(self, phi: np.ndarray, grid: Grid, free: np.ndarray, distance: np.ndarray, meta: dict,
                 geometry: dict | None = None):
        self._phi = np.ascontiguousarray(phi, dtype=float)
        self.grid = grid
        self.free = np.ascontiguousarray(free, dtype=bool)
        self.distance = np.ascontiguousarray(distance, dtype=float)
        self.meta = dict(meta)
        self.geometry = geometry or {"boundary": None, "obstacles": []}
        #: SHA-256 of the file it was loaded from, checked on load (None if not loaded, or from
        #: a file written before files carried one).
        self.content_sha256: str | None = None

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

    @property
    def clearance(self) -> float:
        """Distance paths keep from every wall (length unit)."""
        return float(self.meta.get("clearance", 0.0))

    def certified_clear(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Whether positions are certified in free space at least :attr:`clearance` from every wall."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        bound = lower_wall_distance(self.distance, self.grid.x0, self.grid.y0, self.grid.h,
                                    np.ascontiguousarray(x.ravel()), np.ascontiguousarray(y.ravel()))
        return (bound >= self.clearance).reshape(x.shape)

    # --- evaluation -------------------------------------------------------
    def __call__(self, x: ArrayLike, y: ArrayLike, theta: ArrayLike, *, cubic: bool = True,
                 lenient: bool = False, arcs: bool = True) -> np.ndarray:
        """φ at poses, broadcasting ``x``, ``y`` (length unit) and ``theta`` (radians).

        Tricubic (Catmull-Rom) interpolation, periodic in θ, as in the paper;
        trilinear over the free corners next to blocked or +inf nodes (with
        ``lenient``, over the finite ones); +inf at unreachable states, at
        positions not certified clear of the walls and outside the grid.
        With ``arcs``, lowered where an exact arc clear of the walls to one of
        the :data:`ARC_STEPS` nearest grid headings on either side gives a
        smaller upper bound (arc length plus φ read at that heading, see
        :func:`hjplanner._sweep.arc_readings`): interpolation in θ smears the
        jumps of φ over a whole angular step.
        Within the solver's exact layer around a point target
        (``meta["local_radius"]``) the exact value is used where smaller.
        Never NaN for finite inputs.
        """
        x, y, theta = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), np.asarray(theta, float))
        return self.at_certified(x.ravel(), y.ravel(), theta.ravel(), self.certified_clear(x, y).ravel(),
                                 cubic=cubic, lenient=lenient, arcs=arcs).reshape(x.shape)

    def at_certified(self, x: np.ndarray, y: np.ndarray, theta: np.ndarray, certified: np.ndarray, *,
                     cubic: bool = True, lenient: bool = False, arcs: bool = True) -> np.ndarray:
        """φ at poses (n,) whose clearance the caller has already decided.

        As :meth:`__call__`, with ``certified`` in place of
        :meth:`certified_clear`: +inf where it is False.  For callers that
        certify positions on the way (a path search whose arcs end on their
        last certified sample).

        Parameters
        ----------
        x, y : numpy.ndarray
            (n,) positions (length unit of the grid).
        theta : numpy.ndarray
            (n,) headings, radians.
        certified : numpy.ndarray
            (n,) bool: the position keeps the clearance from every wall.
        cubic, lenient, arcs : bool
            As in :meth:`__call__`.

        Returns
        -------
        numpy.ndarray
            (n,) φ, +inf where not certified, unreachable or outside the grid.
        """
        out = _sweep.interpolate(self._phi, self.free, np.ascontiguousarray(certified), self.grid.x0,
                                 self.grid.y0, self.grid.h, np.ascontiguousarray(x),
                                 np.ascontiguousarray(y), np.ascontiguousarray(theta), bool(cubic),
                                 bool(lenient))
        if arcs:
            out = _sweep.arc_readings(self._phi, self.free, self.distance, self.clearance, self.grid.x0,
                                      self.grid.y0, self.grid.h, self.rho, self.reverse, np.ascontiguousarray(x),
                                      np.ascontiguousarray(y), np.ascontiguousarray(theta), out, ARC_STEPS,
                                      bool(cubic), bool(lenient))
        r0 = float(self.meta.get("local_radius", 0.0))
        if r0 > 0:
            # The solver's exact initial layer (see solve): where the optimal path
            # is shorter than r0, φ is known exactly and sharper than any
            # interpolant across the thin valley of φ around the target.
            near = np.hypot(x - self.target[0], y - self.target[1]) <= r0
            if near.any():
                exact = local_exact_many(np.ascontiguousarray(x[near], dtype=float),
                                         np.ascontiguousarray(y[near], dtype=float),
                                         np.ascontiguousarray(theta[near], dtype=float), float(self.target[0]),
                                         float(self.target[1]), float(self.rho), r0, bool(self.reverse))
                out[near] = np.minimum(out[near], exact)
        return out

    def dtheta(self, x: ArrayLike, y: ArrayLike, theta: ArrayLike, step: float | None = None) -> np.ndarray:
        """Centred difference of the interpolated φ in θ (length per radian, no arc readings), nan-free
        (+-inf or 0 when one-sided)."""
        step = self.grid.dtheta / 2 if step is None else float(step)
        plus = self(x, y, np.asarray(theta) + step, arcs=False)
        minus = self(x, y, np.asarray(theta) - step, arcs=False)
        with np.errstate(invalid="ignore"):
            d = (plus - minus) / (2 * step)
        return np.where(np.isnan(d), 0.0, d)

    # --- files ------------------------------------------------------------
    def save(self, path) -> FsPath:
        """Write a compressed ``.npz`` file (no pickles): values, free mask, wall distances, grid, metadata.

        `path` is a file name, or a file object open for binary writing. The file
        carries a SHA-256 of its metadata and arrays, checked by :meth:`load`.

        Values are stored as uint16 multiples of ``q = max(h/64, max φ/65534)``
        (code 65535: +inf), so a loaded value differs from the saved one by
        at most ``q/2`` -- h/128 (0.012 cm at h = 1.5 cm) unless φ exceeds
        1000 h -- far below the discretisation error.  The codes are stored
        as differences between neighbouring headings, split into high and
        low bytes, which deflate to about a quarter of the float64 size.
        """
        finite = np.isfinite(self._phi)
        top = float(self._phi[finite].max()) if finite.any() else 0.0
        quantum = max(self.grid.h / QUANTA_PER_CELL, top / QUANTUM_STEPS)
        codes = np.full(self._phi.shape, QUANTUM_STEPS + 1, dtype=np.uint16)
        codes[finite] = np.rint(self._phi[finite] / quantum).astype(np.uint16)
        steps = np.diff(codes, axis=0, prepend=np.zeros((1, *codes.shape[1:]), np.uint16))  # wraps mod 2**16
        data = {"phi_high": (steps >> 8).astype(np.uint8), "phi_low": (steps & 255).astype(np.uint8),
                "free": self.free, "distance": self.distance.astype(np.float32)}
        meta = dict(self.meta, format=FORMAT, quantum=quantum,
                    grid=dict(x0=self.grid.x0, y0=self.grid.y0, h=self.grid.h, nx=self.grid.nx,
                              ny=self.grid.ny, ntheta=self.grid.ntheta))
        meta["content_sha256"] = _content_digest(meta, data)
        boundary = self.geometry.get("boundary")
        arrays = {**data, "meta": np.array(json.dumps(meta)),
                  "boundary": np.zeros((0, 2)) if boundary is None else np.asarray(boundary, float),
                  "n_obstacles": np.array(len(self.geometry.get("obstacles", [])))}
        for n, obstacle in enumerate(self.geometry.get("obstacles", [])):
            arrays[f"obstacle_{n}"] = np.asarray(obstacle, float)
        if hasattr(path, "write"):              # an open binary file
            np.savez_compressed(path, **arrays)
            return path
        path = FsPath(path)
        with open(path, "wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path

    @classmethod
    def load(cls, path: str | FsPath) -> "ValueFunction":
        """Read a file written by :meth:`save`.

        Raises
        ------
        PlanningError
            If the file is missing, not a value-function file or written by
            an older hjplanner (solve again or rebuild the bank).
        """
        path = FsPath(path)
        _check_archive(path)
        try:
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                stored_digest = meta.pop("content_sha256", None) if isinstance(meta, dict) else None
                if not isinstance(meta, dict) or meta.get("format") != FORMAT:
                    found = meta.get("format") if isinstance(meta, dict) else type(meta).__name__
                    raise PlanningError(f"{path} is not an hjplanner value function of format {FORMAT!r} "
                                        f"(found {found!r}); solve it again")
                g = meta.pop("grid")
                meta.pop("format")
                quantum = float(meta.pop("quantum"))
                grid = Grid(float(g["x0"]), float(g["y0"]), float(g["h"]), int(g["nx"]), int(g["ny"]),
                            int(g["ntheta"]))
                _check_grid_meta(grid, quantum, path)
                n_obstacles = int(data["n_obstacles"])
                if not 0 <= n_obstacles <= 10_000:
                    raise PlanningError(f"{path}: n_obstacles {n_obstacles} is not from 0 to 10000")
                boundary = data["boundary"]
                geometry = {"name": meta.get("domain"), "boundary": boundary if len(boundary) else None,
                            "obstacles": [data[f"obstacle_{n}"] for n in range(n_obstacles)]}
                shape = (grid.ntheta, grid.nx, grid.ny)
                arrays = {k: data[k] for k in ("phi_high", "phi_low", "free", "distance")}
        except FileNotFoundError:
            raise PlanningError(f"value-function file {path} does not exist") from None
        except PlanningError:
            raise
        except (OSError, KeyError, ValueError, TypeError, AttributeError, EOFError, zipfile.BadZipFile,
                zlib.error) as exc:
            raise PlanningError(f"cannot read value function from {path}: {type(exc).__name__}: {exc}") from None
        expected = {"phi_high": (shape, np.uint8), "phi_low": (shape, np.uint8),
                    "free": (shape[1:], np.bool_), "distance": (shape[1:], None)}
        for key, (want, dtype) in expected.items():
            a = arrays[key]
            if a.shape != want or (dtype is not None and a.dtype != dtype) or (
                    dtype is None and a.dtype.kind != "f"):
                raise PlanningError(f"{path}: array {key!r} of shape {a.shape} and type {a.dtype} does not match "
                                    f"the grid {want}; solve it again")
        if stored_digest is not None and stored_digest != _content_digest(dict(meta, format=FORMAT, quantum=quantum,
                                                                               grid=g), arrays):
            raise PlanningError(f"{path}: its content does not match its digest (a damaged or edited file); "
                                "solve it again")
        steps = (arrays["phi_high"].astype(np.uint16) << 8) | arrays["phi_low"]
        codes = np.cumsum(steps, axis=0, dtype=np.uint16)
        free, distance = arrays["free"], arrays["distance"]
        phi = np.where(codes > QUANTUM_STEPS, np.inf, codes * quantum)
        vf = cls(phi, grid, free, distance, meta, geometry)
        vf.content_sha256 = stored_digest
        return vf

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


#: Largest value-function file read, and largest uncompressed content, bytes.
MAX_FILE_BYTES = 2 * 2**30
MAX_CONTENT_BYTES = 4 * 2**30


def _content_digest(meta: dict, arrays: dict) -> str:
    """SHA-256 of the metadata (as JSON, without the digest) and the stored arrays: what
    :meth:`ValueFunction.load` checks, so a damaged or edited file is never used."""
    from arenas.cache_files import digest
    text = json.dumps({k: v for k, v in meta.items() if k != "content_sha256"}, sort_keys=True)
    return digest(text, arrays)


def _check_archive(path: FsPath) -> None:
    """Refuse anything but a regular zip file of bounded uncompressed size (no FIFO, device or
    zip bomb), before numpy reads it."""
    import stat
    try:
        st = path.stat()
    except FileNotFoundError:
        raise PlanningError(f"value-function file {path} does not exist") from None
    except OSError as exc:
        raise PlanningError(f"cannot read value function from {path}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        kind = "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file"
        raise PlanningError(f"value-function file {path} is {kind}; give an .npz written by 'hjplanner solve'")
    if st.st_size > MAX_FILE_BYTES:
        raise PlanningError(f"value-function file {path} has {st.st_size} bytes; at most {MAX_FILE_BYTES} are read")
    try:
        with zipfile.ZipFile(path) as z:
            total = sum(info.file_size for info in z.infolist())
            # an array's own header says how much numpy will allocate, whatever the zip claims
            claimed = sum(_array_bytes(z, info) for info in z.infolist() if info.filename.endswith(".npy"))
    except (zipfile.BadZipFile, OSError, EOFError, ValueError, zlib.error) as exc:
        raise PlanningError(f"{path} is not an .npz archive ({exc}); give a file written by 'hjplanner solve'") from None
    if max(total, claimed) > MAX_CONTENT_BYTES:
        raise PlanningError(f"{path} unpacks to {max(total, claimed)} bytes; at most {MAX_CONTENT_BYTES} are read")


def _array_bytes(z: zipfile.ZipFile, info: zipfile.ZipInfo) -> int:
    """Bytes of the array stored in member `info`, from its ``.npy`` header alone."""
    with z.open(info) as fh:
        fmt = np.lib.format
        version = fmt.read_magic(fh)
        read = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
        shape, _, dtype = read(fh)
    return int(np.prod(shape, dtype=object)) * dtype.itemsize


def _check_grid_meta(grid: Grid, quantum: float, path: FsPath) -> None:
    from .limits import MAX_NODES, MAX_NTHETA, MIN_NTHETA
    ok = (np.isfinite([grid.x0, grid.y0, grid.h, quantum]).all() and grid.h > 0 and quantum > 0
          and min(grid.nx, grid.ny) >= 2 and MIN_NTHETA <= grid.ntheta <= MAX_NTHETA
          and grid.nx * grid.ny * grid.ntheta <= MAX_NODES)
    if not ok:
        raise PlanningError(f"{path}: its grid {grid} (quantum {quantum}) is not a valid value-function grid; "
                            "solve it again")
