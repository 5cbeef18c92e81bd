"""The Poisson arena world: the FEM signal of a point source behind walls, read with noise.

The truth is ``-Δu = c δ(x - S)`` on the free region, solved with its own discretisation
(quadratic elements on its own graded mesh, whatever mesh a strategy chooses: no inverse
crime), read at the observer's true position with Gaussian noise
(point observer), or painted on the testbed floor and read through the calibrated
reflectance sensor (car). Mismatch options make the truth differ from what a strategy
is told, on purpose.
"""

from __future__ import annotations

import weakref
from dataclasses import asdict, dataclass, replace
from functools import lru_cache

import numpy as np
from shapely.geometry import Polygon

from arenas import Arena, ArenaError
from arenas.memo import sized_cache

from ..errors import SearchError
from ..outcome import MAX_SOURCES
from ..fem.green import Field, GreenSolver
from .base import Reading, World, source_set

__all__ = ["PoissonWorld", "Mismatch", "TRUTH_H", "TRUTH_ORDER", "truth_solver", "shifted_walls",
           "superposed_field", "MAX_SOURCES"]

#: Mesh size of the truth (cm), whatever a strategy's ``h``: the truth has its own
#: discretisation, so the data never come from the very model that inverts them (no
#: "inverse crime"). Its error is in ``benchmarks/truth_discretisation.md``.
TRUTH_H = 1.4
#: Element order of the truth: quadratic, where every strategy's model is linear.
TRUTH_ORDER = 2
#: Grading of the truth's mesh toward re-entrant corners (what P2 needs to keep its order).
TRUTH_GRADING = 0.75


#: Bytes of truth solvers kept per process, as :func:`arenas.memo.nbytes_of` counts them (a
#: factorized P2 solver of a 140 cm office arena counts 116 MB and holds 153 MB resident).
TRUTH_CACHE_BYTES = 300 * 2**20


@sized_cache(TRUTH_CACHE_BYTES, maxsize=8)
def truth_solver(arena: Arena, h: float) -> GreenSolver:
    """The truth's own solver of `arena` (its true walls) at mesh size `h` (cm): P2 elements
    on its own graded mesh, kept for the truth alone (it factorizes on its first solve, and
    its true signal comes from the disk cache of Green's functions when there), so no
    strategy ever holds it (a strategy's solvers come from :func:`reciprocity.models.green.cached_solver`)."""
    return GreenSolver(arena, h=h, order=TRUTH_ORDER, grading=TRUTH_GRADING)


#: Largest factor of a mismatch (``strength_factor``, ``noise_factor``, ``paint_gamma``):
#: beyond it a true strength or noise overflows what a reading can hold.
MAX_FACTOR = 1e6


@dataclass(frozen=True)
class Mismatch:
    """How the true world differs from what the strategy is told.

    Attributes
    ----------
    strength_factor : float
        True strength = nominal strength × this.
    wall_shift : float
        Every obstacle of the true world is grown by this much (cm; negative shrinks it),
        clipped to the arena: the walls the strategy assumes are off by this.
    noise_factor : float
        True noise standard deviation = nominal × this.
    paint_gamma : float
        Car floor only: the printed signal is ``u_max (u / u_max)^gamma`` while the
        sensor's calibration assumes ``gamma = 1`` (a printer's tone curve).
    """

    strength_factor: float = 1.0
    wall_shift: float = 0.0
    noise_factor: float = 1.0
    paint_gamma: float = 1.0

    def __post_init__(self):
        for key in ("strength_factor", "noise_factor", "paint_gamma"):
            val = getattr(self, key)
            if isinstance(val, bool) or not isinstance(val, (int, float)) or not np.isfinite(val) or val <= 0 \
                    or val > MAX_FACTOR:
                raise SearchError(f"mismatch {key} must be a positive number up to {MAX_FACTOR:g}; got {val!r}")
        if isinstance(self.wall_shift, bool) or not isinstance(self.wall_shift, (int, float)) \
                or not np.isfinite(self.wall_shift) or abs(self.wall_shift) > 5:
            raise SearchError(f"mismatch wall_shift must be a number of cm in [-5, 5]; got {self.wall_shift!r}")

    @classmethod
    def from_dict(cls, data: dict | None) -> "Mismatch":
        data = dict(data or {})
        unknown = set(data) - set(cls.__dataclass_fields__)
        if unknown:
            raise SearchError(f"unknown mismatch option(s) {', '.join(sorted(unknown))}; choose from "
                              f"{', '.join(cls.__dataclass_fields__)}")
        return cls(**data)

    @property
    def none(self) -> bool:
        return self == Mismatch()


def shifted_walls(arena: Arena, shift: float) -> Arena:
    """`arena` with every obstacle grown by `shift` cm (negative: shrunk), mitred
    corners, clipped to the boundary. The source and start are kept."""
    if shift == 0:
        return arena
    outer = Polygon(arena.boundary)
    obstacles = []
    for o in arena.obstacles:
        grown = Polygon(o).buffer(shift, join_style="mitre", mitre_limit=3.0).intersection(outer)
        if grown.is_empty:
            continue
        if grown.geom_type != "Polygon":
            grown = max(grown.geoms, key=lambda g: g.area)
        obstacles.append(np.asarray(grown.exterior.coords)[:-1])
    try:
        out = Arena.from_polygons(arena.boundary, obstacles, name=arena.name, strength=arena.strength)
        return out.with_scenario(source=arena.source, start=arena.start)
    except ArenaError as exc:
        raise SearchError(f"wall_shift of {shift:g} cm makes arena {arena.name!r} invalid: {exc}") from None


def superposed_field(solver: GreenSolver, sources: np.ndarray, strengths: np.ndarray) -> Field:
    """``u = Σ_j c_j G(·, S_j)`` on `solver`: the signal of several point sources (the
    equation is linear), each Green's function from the disk cache when there."""
    dofs = sum(solver.field(s, c, cached=True).dofs for s, c in zip(sources, strengths))
    return Field(solver, dofs, "u")


@lru_cache(maxsize=4)
def _floor(arena: Arena, sources: tuple, strengths: tuple, h: float, px_per_mm: float, gamma: float):
    from arenas import render_floor
    from arenas.floor import free_pixels
    field = superposed_field(truth_solver(arena, h), np.array(sources), np.array(strengths))
    centres = free_pixels(arena, 10.0 * px_per_mm)[1]
    floor = render_floor(arena, _FloorField(field, centres), px_per_mm=px_per_mm)
    if gamma == 1.0:
        return floor
    u_max = floor.mapping.u_max
    printed = Field(field.solver, u_max * np.clip(field.dofs / u_max, 0, None) ** gamma, "u printed")
    return render_floor(arena, _FloorField(printed, centres), px_per_mm=px_per_mm, mapping=floor.mapping)


#: Where the probe matrices of the floor's pixel centres are: ``(solver, centres, {(first
#: row, rows): (matrix, inside)})``, all held weakly. The matrices are those the solver's
#: own cache (:meth:`GreenSolver.probe_matrix`, by content) holds; this finds them by the
#: identity of the centres instead of by hashing them (27 MB for a 140 cm arena at 1 px/mm)
#: for every floor painted on them, and keeps nothing alive the solver has let go.
_floor_probes: list = [None, None, {}]


class _FloorField:
    """`field` as :func:`arenas.render_floor` evaluates it on the free pixel centres
    `centres` (:func:`arenas.floor.free_pixels`: read-only, made in this process), a
    chunk at a time: bit for bit ``field(part)``, with the probe matrix of a chunk found by
    where it lies in `centres` (a read-only view of the read-only array, which this
    process made and nothing can change) when the solver still holds it. Any other
    points go to ``field`` itself."""

    def __init__(self, field: Field, centres: np.ndarray):
        self.field, self.centres = field, centres
        solver, held, probes = _floor_probes
        if held is None or held() is not centres or solver() is not field.solver:
            _floor_probes[:] = weakref.ref(field.solver), weakref.ref(centres), {}
        self._probes = _floor_probes[2]

    def __call__(self, points) -> np.ndarray:
        rows = self._rows(points)
        if rows is None:
            return self.field(points)
        refs = self._probes.get(rows)
        m, inside = (None, None) if refs is None else (refs[0](), refs[1]())
        if m is None or inside is None:
            m, inside = self.field.solver.probe_matrix(points)
            self._probes[rows] = weakref.ref(m), weakref.ref(inside)
        out = m @ self.field.dofs
        out[~inside] = np.nan
        return out

    def _rows(self, points) -> tuple[int, int] | None:
        """``(first row, rows)`` of `points` in the centres when they are a read-only slice
        of rows of the read-only centres, else None."""
        c = self.centres
        if (not isinstance(points, np.ndarray) or points.base is not c or c.flags.writeable
                or points.flags.writeable or points.dtype != c.dtype or points.strides != c.strides):
            return None
        first, rest = divmod(points.ctypes.data - c.ctypes.data, c.strides[0])
        return (int(first), len(points)) if rest == 0 and 0 <= first <= len(c) - len(points) else None


class PoissonWorld(World):
    """Truth of the Poisson arena: the FEM field of the true source, read with noise.

    Parameters
    ----------
    arena : Arena
        The nominal arena with its true source and nominal strength (cm).
    noise : float
        Nominal noise standard deviation of one reading (signal units).
    h : float
        Mesh size of the truth's quadratic elements, cm (its own, whatever a strategy's).
    mismatch : Mismatch, optional
        How the truth departs from what the strategy is told.
    success_radius : float
        A converged estimate within this distance (cm) succeeds.
    sources : array_like, shape (K, 2), optional
        Several true sources (cm), replacing the arena's one; the signal is the
        superposition of their fields.
    strengths : array_like, shape (K,), optional
        Their true strengths (default: each the arena's nominal strength), before the
        mismatch's ``strength_factor``. The strategy is told the nominal strength only.
    max_sources : int, optional
        The task's public bound on the number of sources (default 1 with the arena's
        source, MAX_SOURCES with `sources`): part of what a strategy is told, never
        the number of sources itself.
    believed : Arena, optional
        The walls the strategy is told instead of the true ones (``map: unknown``: the
        boundary alone; ``map: {known: FILE}``: a partial map); None tells the true walls.
    lidar : dict, optional
        The platform's range sensor ``{beams, range, noise}`` (cm), told to the strategy
        as it is (the platforms read it on :attr:`true_arena`).
    source_clearance : float
        The task's public statement that every source lies at least this far (cm) from
        the walls, told to the strategy (0: anywhere).
    """

    kind = "poisson"

    def __init__(self, arena: Arena, *, noise: float = 12.0, h: float = TRUTH_H,
                 mismatch: Mismatch | None = None, success_radius: float = 5.0,
                 sources=None, strengths=None, max_sources: int | None = None,
                 believed: Arena | None = None, lidar: dict | None = None,
                 source_clearance: float = 0.0):
        if arena.source is None and sources is None:
            raise SearchError(f"arena {arena.name!r} has no true source: give source: [x, y]")
        if not np.isfinite(noise) or noise < 0:
            raise SearchError(f"noise must be a non-negative number; got {noise!r}")
        self.arena = arena
        self.mismatch = mismatch or Mismatch()
        self.true_arena = shifted_walls(arena, self.mismatch.wall_shift)
        points, given, self.max_sources = source_set("poisson", arena.source, sources, strengths,
                                                     float(arena.strength), max_sources)
        if not np.all(self.true_arena.contains(points)):
            raise SearchError("a source lies inside a shifted wall: reduce wall_shift")
        #: true strengths (the nominal strength is the task's, ``arena.strength``)
        self.sources, self.strengths = points, given * self.mismatch.strength_factor
        self.source = points[0]
        self.strength = float(self.strengths[0])
        self.noise = float(noise)
        self.true_noise = self.noise * self.mismatch.noise_factor
        self.h = float(h)
        self.success_radius = float(success_radius)
        self._field: Field | None = None
        self.believed = believed
        self.lidar = None if lidar is None else dict(lidar)
        self.source_clearance = float(source_clearance)

    @property
    def field(self) -> Field:
        """The true signal ``u`` (a field evaluable at any points, cm)."""
        if self._field is None:
            # the same signal in every process that asks: kept on disk, so that a warm
            # start neither assembles nor factorizes the truth's quadratic elements
            solver = truth_solver(self.true_arena.without_scenario(), self.h)
            self._field = superposed_field(solver, self.sources, self.strengths)
        return self._field

    def read(self, position, *, time: float = 0.0, dwell: float = 0.0,
             rng: np.random.Generator, observer: int = 0) -> Reading:
        value = float(self.field(np.asarray(position, dtype=float)[None, :2])[0])
        if not np.isfinite(value):
            raise SearchError(f"position ({position[0]:.4g}, {position[1]:.4g}) is not in the free region")
        return Reading(value + self.true_noise * float(rng.standard_normal()))

    def contains(self, points) -> np.ndarray:
        return self.true_arena.contains(np.atleast_2d(np.asarray(points, dtype=float)))

    def figure_record(self) -> dict:
        """``field``: the true signal; ``true_arena``: the true walls."""
        return dict(field=self.field, true_arena=self.true_arena)

    def floor(self, px_per_mm: float = 1.0):
        """The testbed floor painted from the true field (the car's truth): the signal as
        printed (with the `paint_gamma` mismatch) and the grey mapping the calibration
        assumes (the nominal print). Cached per process."""
        return _floor(self.true_arena.without_scenario(), tuple(map(tuple, self.sources.tolist())),
                      tuple(self.strengths.tolist()), self.h, float(px_per_mm), self.mismatch.paint_gamma)

    def nominal(self) -> dict:
        out = self._nominal_sources(dict(arena=replace(self.arena, source=None),
                                         strength=float(self.arena.strength), noise=self.noise))
        if self.believed is not None:   # the walls are not all known: only what the map tells
            out.update(arena=self.believed, map="unknown")
        if self.lidar is not None:
            out["lidar"] = dict(self.lidar)
        return out

    def describe(self) -> dict:
        out = dict(noise=self.noise, truth_h=self.h, mismatch=asdict(self.mismatch))
        if self.believed is not None:
            out["map"] = "unknown" if not self.believed.obstacles else "partial"
        if self.lidar is not None:
            out["lidar"] = dict(self.lidar)
        return self._described_sources(out)
