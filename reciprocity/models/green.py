"""Green's functions as a strategy's model: FEM solvers shared across a strategy's episodes.

The truth (:mod:`reciprocity.worlds.poisson`) builds its own solver on its own mesh; it
never receives one of these, so a strategy is never scored against its own numbers.
"""

from __future__ import annotations


from arenas import Arena
from arenas.memo import sized_cache

from ..fem import GreenSolver
from ..spaces import mesh_space

__all__ = ["cached_solver"]


#: Bytes of strategy solvers (mesh, basis, factorization) kept per process: a worker running many
#: arenas keeps the most recent within it (issue 33). Counted by :func:`arenas.memo.nbytes_of`
#: (arrays and factorizations), about 3/4 of what a solver holds resident. The caches of
#: the truth's solvers, of search spaces and of lattice Green's functions have their own; with
#: all four full a worker held 1.05 GB resident on generated arenas at the earlier budgets.
SOLVER_CACHE_BYTES = 250 * 2**20


@sized_cache(SOLVER_CACHE_BYTES, maxsize=8)
def cached_solver(arena: Arena, h: float, order: int = 1) -> GreenSolver:
    """A :class:`~reciprocity.fem.GreenSolver` shared across a strategy's episodes on the same
    arena geometry (pass ``arena.without_scenario()``): meshed and factorized once per process.

    Parameters
    ----------
    arena : Arena
        The geometry the strategy believes, cm.
    h : float
        Mesh size, cm.
    order : int
        Element order (1 solves on the search space's own mesh).
    """
    mesh = mesh_space(arena, float(h)) if order == 1 else None
    return GreenSolver(arena, h=h, order=order, mesh=mesh)
