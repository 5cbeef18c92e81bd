"""A floor's probe on the truth's quadratic mesh: the compiled inverse map and basis values
against scikit-fem's NumPy code, in the same run.

    python benchmarks/bench_inverse_map.py                 # ring-1, disk, paper at the truth's h, 10 px/cm
    python benchmarks/bench_inverse_map.py --h 4 --px-per-cm 2

For each arena: the truth's solver (P2, `--h` cm), the free pixel centres of its floor, each
in the cell a probe matrix gives it, taken in the floor's chunks of 200 000 points. Per
chunk, the reference coordinates (scikit-fem's ``mapping.invF``, or the NumPy fallback where
it raises) and the basis values (``gbasis``), then the same from
:func:`reciprocity.fem.inverse_map.inverse_map` and ``basis_values``. Prints one Markdown
row per arena (points, chunks that fell back, both times and their ratio), and fails if the
two give different bits.
"""

from __future__ import annotations

import argparse
import sys
import time

CHUNK = 200_000


def _numpy(solver, x, cells):
    """scikit-fem's answers, and whether its Newton gave up."""
    import numpy as np

    from reciprocity.fem.inverse_map import _projected
    mapping = solver.basis.mapping
    try:
        X, fell_back = mapping.invF(x, tind=cells), False
    except Exception:                                    # noqa: BLE001 - scikit-fem's bare Exception
        X, fell_back = _projected(mapping, x, cells), True
    phis = np.array([solver.basis.elem.gbasis(mapping, X, k, tind=cells)[0]
                     for k in range(solver.basis.Nbfun)])
    return X, phis, fell_back


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h", type=float, default=None, help="mesh size, cm (default: the truth's)")
    ap.add_argument("--px-per-cm", type=float, default=10.0, help="floor resolution")
    args = ap.parse_args(argv)
    for key, value in (("--h", args.h), ("--px-per-cm", args.px_per_cm)):
        if value is not None and not value > 0:
            print(f"error: {key} {value!r}: must be a length > 0", file=sys.stderr)
            return 2
    import numpy as np

    import arenas
    from arenas.floor import free_pixels
    from reciprocity.fem.inverse_map import basis_values, inverse_map
    from reciprocity.worlds.poisson import TRUTH_H, truth_solver

    h = TRUTH_H if args.h is None else args.h
    print(f"| arena (P2, h = {h:g} cm) | points | chunks falling back | scikit-fem | compiled | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for arena in (arenas.generate("ring", 1), arenas.load("disk"), arenas.load("paper")):
        solver = truth_solver(arena, h)
        pts = free_pixels(arena, args.px_per_cm)[1]
        cells, inside = solver._probe_cells(pts)
        pts, cells = pts[inside], cells[inside]
        inverse_map(solver.basis.mapping, pts[:4096].T[:, :, None], cells[:4096])   # load the kernels
        slow = fast = 0.0
        falls = 0
        for lo in range(0, len(pts), CHUNK):
            x, c = pts[lo:lo + CHUNK].T[:, :, None], cells[lo:lo + CHUNK]
            t = time.perf_counter()
            X, phis, fell_back = _numpy(solver, x, c)
            slow += time.perf_counter() - t
            t = time.perf_counter()
            got = inverse_map(solver.basis.mapping, x, c)
            values = basis_values(solver.basis, got, c)
            fast += time.perf_counter() - t
            falls += fell_back
            if not (np.array_equal(got, X) and np.array_equal(values, phis)):
                print(f"error: the two paths differ on {arena.name}, chunk at point {lo}", file=sys.stderr)
                return 1
        chunks = -(-len(pts) // CHUNK)
        print(f"| {arena.name} | {len(pts)} | {falls} of {chunks} | {slow:.2f} s | {fast:.3f} s "
              f"| {slow / fast:.0f}x |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
