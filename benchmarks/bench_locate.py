"""Point location on a floor's pixel centres: the compiled pass over binned triangles
against the nearest-centroid path it falls back to, in the same run.

    python benchmarks/bench_locate.py                 # paper, maze, pillars-1, rooms-2 at h = 1 cm, 8 px/cm
    python benchmarks/bench_locate.py --h 2 --px-per-cm 4

Prints one Markdown row per arena: triangles, points, both times (the best of three for
the compiled pass, after a first call that loads it) and their ratio, and fails if the two
give different triangles.
"""

from __future__ import annotations

import argparse
import sys
import time


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h", type=float, default=1.0, help="mesh size, cm")
    ap.add_argument("--px-per-cm", type=float, default=8.0, help="floor resolution")
    args = ap.parse_args(argv)
    if not (args.h > 0 and args.px_per_cm > 0):
        key, value = ("--h", args.h) if not args.h > 0 else ("--px-per-cm", args.px_per_cm)
        print(f"error: {key} {value!r}: must be a length > 0", file=sys.stderr)
        return 2
    import numpy as np

    import arenas
    from arenas.floor import free_pixels
    from reciprocity.fem.locate import TriangleLocator
    from reciprocity.fem.mesh import mesh_free_region

    print("| arena | triangles | points | nearest centroids | binned, compiled | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for arena in (arenas.load("paper"), arenas.load("maze"), arenas.generate("pillars", 1),
                  arenas.generate("rooms", 2)):
        mesh = mesh_free_region(arena, args.h)
        loc = TriangleLocator(mesh.p.T, mesh.t.T)
        pts = free_pixels(arena, args.px_per_cm)[1]
        loc.locate(pts[:10])
        fast = []
        for _ in range(3):
            t = time.perf_counter()
            got = loc.locate(pts)
            fast.append(time.perf_counter() - t)
        t = time.perf_counter()
        ref = loc._locate_nearest(pts, 8)
        slow = time.perf_counter() - t
        if not np.array_equal(got, ref):
            print(f"error: the two paths differ on {int(np.sum(got != ref))} points of {arena.name}",
                  file=sys.stderr)
            return 1
        print(f"| {arena.name} | {mesh.t.shape[1]} | {len(pts)} | {slow:.2f} s | {min(fast):.3f} s "
              f"| {slow / min(fast):.0f}x |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
