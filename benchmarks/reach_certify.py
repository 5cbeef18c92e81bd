"""Reachability by flood fill, certified against the HJ value (issue 35).

For each arena (``paper``, the built-in ``maze`` and draws of every generated family) and a
few starts in it, the car's planner (its defaults: h 1.5 cm, 48 headings, clearance 4 cm,
reversing) answers "which points can the car reach?" twice:

- **HJ**: the value function of the start, solved on the whole map, finite at the point
  for one of 8 headings (what the car's evaluator asked before);
- **flood**: :meth:`hjplanner.OnDemandPlanner.reachable_from`, the connected free nodes
  around the start, with no solve.

at random points of the free region (and the arena's source). Every disagreement is a row
of the CSV; the table counts them per family.

    python benchmarks/reach_certify.py --draws 10 --starts 3 --points 300 --out benchmarks/reach_certify/runs.csv
    python benchmarks/reach_certify.py --table benchmarks/reach_certify/runs.csv
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

FIELDS = ["arena", "draw", "start", "points", "hj", "flood", "flood_only", "hj_only", "hj_s", "flood_s",
          "worst_gap_cm"]
#: The car's planner, as :class:`reciprocity.platforms.car.DrivingOptions` sets it.
H, NTHETA, CLEARANCE = 1.5, 48, 4.0
HEADINGS = np.linspace(0.0, 2.0 * np.pi, 8, endpoint=False)


BUILTIN = ("paper", "builtin-maze")


def arenas_of(names: list[str], draws: int):
    """(name, draw, arena) of the built-in arenas named, then `draws` draws of each
    generated family named."""
    import arenas
    for name in names:
        if name in BUILTIN:
            yield name, 0, arenas.load(name.removeprefix("builtin-"))
    for i in range(draws):
        for name in names:
            if name not in BUILTIN:
                yield name, i, arenas.generate(name, i)


def certify(arena, starts: int, points: int, rng: np.random.Generator) -> list[dict]:
    """One row per start: the points each method calls reachable, and where they differ."""
    from arenas import CarSpec
    from hjplanner import OnDemandPlanner
    from hjplanner.reach import FreeComponents
    walls = arena.without_scenario()
    planner = OnDemandPlanner(walls, rho=CarSpec().rho, h=H, ntheta=NTHETA, clearance=CLEARANCE,
                              reverse=True, maxsize=1)
    begin = [arena.start[:2]] if arena.start is not None else []
    begin += list(arena.random_free_points(starts - len(begin), rng, clearance=CLEARANCE + H))
    pts = arena.random_free_points(points, rng)
    if arena.source is not None:
        pts = np.vstack([pts, np.asarray(arena.source, dtype=float)[None]])
    rows = []
    for k, start in enumerate(begin[:starts]):
        t = time.perf_counter()
        vf = planner.get(np.asarray(start, dtype=float))
        hj = np.zeros(len(pts), dtype=bool)
        for th in HEADINGS:
            hj |= np.isfinite(vf(pts[:, 0], pts[:, 1], np.full(len(pts), th), cubic=False))
        hj_s = time.perf_counter() - t
        t = time.perf_counter()                      # the labelling too, as a new planner pays it
        flood = FreeComponents(planner.workspace.grid, planner.workspace.free).region(start)(pts)
        flood_s = time.perf_counter() - t
        differ = hj != flood
        gap = float(walls.wall_distance(pts[differ]).min()) if differ.any() else float("nan")
        rows.append(dict(start=k, points=len(pts), hj=int(hj.sum()), flood=int(flood.sum()),
                         flood_only=int((flood & ~hj).sum()), hj_only=int((hj & ~flood).sum()),
                         hj_s=round(hj_s, 4), flood_s=round(flood_s, 4), worst_gap_cm=round(gap, 2)))
    return rows


def table(path: Path) -> str:
    """Per family: starts, points, agreement, and each kind of disagreement."""
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    fam: dict[str, list] = {}
    for r in rows:
        fam.setdefault(r["arena"], []).append(r)
    out = ["| arena | arenas × starts | points | reachable (HJ) | flood only | HJ only | agree | "
           "HJ s / flood s (median) |", "|---|---:|---:|---:|---:|---:|---:|---|"]
    total = {k: 0 for k in ("n", "p", "hj", "fo", "ho")}
    for name, rs in fam.items():
        p = sum(int(r["points"]) for r in rs)
        fo, ho = sum(int(r["flood_only"]) for r in rs), sum(int(r["hj_only"]) for r in rs)
        hj = sum(int(r["hj"]) for r in rs)
        out.append(f"| {name} | {len(rs)} | {p} | {hj} | {fo} | {ho} | {100 * (1 - (fo + ho) / p):.2f} % | "
                   f"{np.median([float(r['hj_s']) for r in rs]):.3f} / "
                   f"{np.median([float(r['flood_s']) for r in rs]):.4f} |")
        for k, v in zip(("n", "p", "hj", "fo", "ho"), (len(rs), p, hj, fo, ho)):
            total[k] += v
    out.append(f"| all | {total['n']} | {total['p']} | {total['hj']} | {total['fo']} | {total['ho']} | "
               f"{100 * (1 - (total['fo'] + total['ho']) / max(total['p'], 1)):.2f} % | |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arenas", default="all", help="comma-separated: paper, builtin-maze and generated "
                    "families (default all)")
    ap.add_argument("--draws", type=int, default=10, help="draws per generated family")
    ap.add_argument("--starts", type=int, default=3, help="starts per arena")
    ap.add_argument("--points", type=int, default=300, help="random free points per arena")
    ap.add_argument("--out", type=Path, default=Path("reach_certify.csv"))
    ap.add_argument("--table", type=Path, help="print the table of a finished CSV instead")
    args = ap.parse_args(argv)
    if args.table is not None:
        if not args.table.is_file():
            ap.exit(2, f"error: --table {str(args.table)!r} is not a file (give a CSV this script wrote)\n")
        print(table(args.table))
        return 0
    for key in ("draws", "starts", "points"):
        if getattr(args, key) < 1:
            ap.exit(2, f"error: --{key} {getattr(args, key)} must be a whole number >= 1\n")
    import arenas
    from arenas.files import check_output
    from resumable import appending, done_keys
    allowed = (*BUILTIN, *arenas.FAMILIES)
    names = list(allowed) if args.arenas == "all" else args.arenas.split(",")
    wrong = [n for n in names if n not in allowed]
    if wrong:
        ap.exit(2, f"error: --arenas {wrong[0]!r} is not an arena here; allowed: {', '.join(allowed)} or all\n")
    try:
        check_output(args.out, "--out")
    except Exception as exc:       # an unwritable or linked path: one line, exit 2
        ap.exit(2, f"error: {exc}\n")
    done = done_keys(args.out, lambda r: (r["arena"], int(r["draw"])))
    with appending(args.out, FIELDS) as w:
        for name, i, arena in arenas_of(names, args.draws):
            if (name, i) in done:
                continue
            rng = np.random.default_rng([i, 35])
            for row in certify(arena, args.starts, args.points, rng):
                w.writerow(dict(arena=name, draw=i, **row))
            w.file.flush()
    print(table(args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
