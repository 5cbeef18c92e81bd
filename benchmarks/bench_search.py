"""Monte Carlo search statistics: reciprocity (Algorithm 1) against gradient ascent (Algorithm 2).

A thin driver over campaigns: it runs (or resumes) the campaign of a spec file
(``search_point.yaml``: 100 random (source, start) pairs on the paper arena with the
point observer; ``search_car.yaml``: 30 pairs on the simulated car), then prints the
campaign report. Interrupt it at any time: re-running resumes where it stopped.

    python benchmarks/bench_search.py                        # point observer, 100 pairs
    python benchmarks/bench_search.py --platform car         # the car, 30 pairs
    python benchmarks/bench_search.py --spec my.yaml --runs 20 --workers 2

On the car the table adds the collisions and the simulation speed: simulated seconds per
second of computing, over whole episodes (planning, imaging, physics, camera and sensor).
Success split by whether the source is reachable by the platform appears once the
episodes report ``source_reachable``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from reciprocity.campaign import build_report, parse_spec, run_campaign
from reciprocity.campaign.report import open_report_db
from reciprocity.errors import ReciprocityError

HERE = Path(__file__).parent
SPECS = {"point": HERE / "search_point.yaml", "car": HERE / "search_car.yaml"}

#: Per variant: collisions and simulated seconds per second of computing (car runs).
CAR_SQL = """
SELECT variant, sum(collisions) AS collisions, sum(sim_time_s) / sum(wall_time_s) AS sim_speed
FROM runs GROUP BY variant ORDER BY variant
"""

#: Median samples of gradient ascent over those of the reciprocity search.
RATIO_SQL = """
SELECT median(n_samples) FILTER (WHERE strategy = 'gradient')
       / median(n_samples) FILTER (WHERE strategy = 'reciprocity') FROM runs
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--platform", choices=tuple(SPECS), default="point",
                    help="which spec file: search_point.yaml or search_car.yaml")
    ap.add_argument("--spec", type=Path, help="another campaign spec (overrides --platform)")
    ap.add_argument("--runs", type=int, help="seeds (random source/start pairs); default: the spec's")
    ap.add_argument("--out", type=Path, help="results folder (default bench_<spec name>)")
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="local Dask workers (default: one per core)")
    where.add_argument("--scheduler", help="address of a Dask scheduler")
    args = ap.parse_args(argv)
    path = args.spec or SPECS[args.platform]
    data = yaml.safe_load(path.read_text())
    if args.runs is not None:
        data["seeds"] = args.runs
    try:
        spec = parse_spec(data, base_dir=path.parent)
        out = args.out or Path(f"bench_{spec.name}")
        result = run_campaign(spec, out, workers=args.workers, scheduler=args.scheduler)
    except ReciprocityError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{spec.name}: {spec.seeds} random (source, start) pairs, {spec.platform} observer; "
          f"{result.n_run} episodes run now, {result.n_skipped} resumed from {out}/")
    print(build_report(out).markdown(), end="")
    con = open_report_db(out)
    ratio = con.execute(RATIO_SQL).fetchone()[0]
    if ratio is not None:
        print(f"median samples, gradient / reciprocity: {ratio:.2f}x")
    if spec.platform == "car":
        for variant, collisions, speed in con.execute(CAR_SQL).fetchall():
            print(f"{variant}: {collisions} collisions, simulation speed {speed:.0f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
