"""The numerical knobs of the solver: :class:`SolverOptions` (used by the solver, and by
paths to rebuild a value function's stencils)."""

from __future__ import annotations

from ._grid import Grid
from ._motion import controls
from .errors import PlanningError

__all__ = ["SolverOptions"]


class SolverOptions:
    """Numerical knobs of :func:`solve` (defaults measured on the reference setup).

    Parameters
    ----------
    turn_steps : tuple of int
        Turning steps, each an arc turning by that many angular steps ``Δθ``
        (arc length ``m ρ Δθ``), so that it lands on a grid heading.
    straight_cells : tuple of float
        Straight steps, as lengths in grid spacings ``h``.
    local_radius : float
        The exact initial layer of a point target covers the states whose
        optimal path is shorter than ``r0 = local_radius * sqrt(ρ h)``
        (at least the longest step plus 2 h): the region around the target
        where the valley of φ, of width about ``d²/ρ`` at distance ``d``, is
        thinner than the grid can resolve.  ``r0 → 0`` as ``h → 0``.
    exact_radius : float
        Lower bound on ``r0`` in length units (e.g. to hold the initial
        layer fixed while refining the grid in a convergence study).
    sweep_tol : float
        Stop sweeping when no value decreases by more than ``sweep_tol * h``.
    max_sweeps : int
        Upper bound on Gauss-Seidel sweeps.
    threads : int, optional
        Threads sweeping groups of layers concurrently; default 1.  With 2
        threads each sweep splits the headings into two groups that read
        each other's layers through snapshots taken at the start of the
        sweep, so the result does not depend on timing: the same inputs and
        thread count give the same bits (but not the same bits as 1
        thread: the Gauss-Seidel order differs, within the stopping
        tolerance), with a sweep or two more; 2 threads pay only on idle
        cores.  :class:`ValueFunctionBank` runs one thread per process.
    """

    def __init__(self, turn_steps: tuple[int, ...] = (1, 2, 3, 6), straight_cells: tuple[float, ...] = (3.0,),
                 local_radius: float = 2.0, exact_radius: float = 0.0, sweep_tol: float = 0.05,
                 max_sweeps: int = 500, threads: int | None = None):
        self.turn_steps = tuple(int(m) for m in turn_steps)
        self.straight_cells = tuple(float(c) for c in straight_cells)
        if not self.turn_steps or min(self.turn_steps) < 1 or not self.straight_cells or min(self.straight_cells) < 1:
            raise PlanningError("turn_steps must be integers >= 1 and straight_cells numbers >= 1")
        self.local_radius = float(local_radius)
        self.exact_radius = float(exact_radius)
        self.sweep_tol = float(sweep_tol)
        self.max_sweeps = int(max_sweeps)
        self.threads = None if threads is None else int(threads)

    def as_dict(self) -> dict:
        """JSON-serialisable form (stored in value-function metadata)."""
        return {key: list(v) if isinstance(v, tuple) else v for key, v in vars(self).items()}

    def controls(self, rho: float, grid: Grid, reverse: bool) -> list[tuple[int, int, float]]:
        """The (direction, steering, arc length) of each stencil; see :func:`hjplanner._motion.controls`."""
        return controls(rho, grid, self.turn_steps, self.straight_cells, reverse)
