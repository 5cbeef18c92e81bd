"""Monte Carlo search statistics: reciprocity (Algorithm 1) against gradient ascent (Algorithm 2).

Each run draws a source (at least 8 cm from any wall: closer to a Dirichlet wall the
signal is buried in the noise everywhere) and a start (5 cm clearance, random heading)
uniformly in the free region, and runs every strategy from the same start with the
same noise seed. Every finished episode is appended to a JSON-lines file at once, so an
interrupted benchmark resumes where it stopped.

    python benchmarks/bench_search.py --arena paper --runs 100 --out bench_search.jsonl
    python benchmarks/bench_search.py --platform car --runs 30 --out bench_car.jsonl

On the car (``--platform car``, options with ``--car KEY=VALUE``) the table adds the
simulated time, the collisions and the simulation speed: simulated seconds per second of
computing, over whole episodes (planning, imaging, physics, camera and sensor).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import yaml
from tqdm import tqdm

import arenas
from reciprocity.runner import search


def pairs(arena, runs: int, seed: int):
    rng = np.random.default_rng(seed)
    for i in range(runs):
        src = arena.random_free_points(1, rng, clearance=8.0)[0]
        start = arena.random_free_points(1, rng, clearance=5.0)[0]
        yield i, src, np.append(start, rng.uniform(0, 2 * np.pi))


def table(rows: list[dict]) -> str:
    car = all("sim_time_s" in r for r in rows)
    out = [f"{'strategy':<12} {'runs':>4} {'success':>8} {'meas. med/p90':>14} {'samples med/p90':>16} "
           f"{'error med/p90/max cm':>21} {'path med cm':>11} {'s/run':>6}"
           + (f" {'sim s med':>9} {'collisions':>10} {'sim speed':>9}" if car else "")]
    by = {}
    for r in rows:
        by.setdefault(r["strategy"], []).append(r)
    for name, rs in by.items():
        m = np.array([r["n_measurements"] for r in rs])
        s = np.array([r["n_samples"] for r in rs])
        e = np.array([r["error"] for r in rs])
        p = np.array([r["path_length"] for r in rs])
        t = np.array([r["wall_time_s"] for r in rs])
        out.append(f"{name:<12} {len(rs):>4} {np.mean([r['success'] for r in rs]):>7.0%} "
                   f"{np.median(m):>6.1f} / {np.percentile(m, 90):>5.1f} "
                   f"{np.median(s):>7.1f} / {np.percentile(s, 90):>6.1f} "
                   f"{np.median(e):>6.2f} / {np.percentile(e, 90):>5.2f} / {e.max():>5.2f} "
                   f"{np.median(p):>11.0f} {t.mean():>6.2f}"
                   + (f" {np.median([r['sim_time_s'] for r in rs]):>9.0f} "
                      f"{sum(r['collisions'] for r in rs):>10d} "
                      f"{sum(r['sim_time_s'] for r in rs) / t.sum():>8.0f}x" if car else ""))
    if {"reciprocity", "gradient"} <= set(by):
        ratio = np.median([r["n_samples"] for r in by["gradient"]]) / np.median(
            [r["n_samples"] for r in by["reciprocity"]])
        out.append(f"median samples, gradient / reciprocity: {ratio:.2f}x")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arena", default="paper")
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--first", type=int, default=0,
                    help="start at this run (to split a benchmark over processes; merge the files)")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--noise", type=float, default=12.0)
    ap.add_argument("--h", type=float, default=1.0)
    ap.add_argument("--strategies", default="reciprocity,gradient")
    ap.add_argument("--platform", choices=("point", "car"), default="point")
    ap.add_argument("--car", action="append", default=[], metavar="KEY=VALUE",
                    help="car option (see reciprocity.runner.CAR_KEYS), e.g. planner=bank")
    ap.add_argument("--out", default="bench_search.jsonl")
    args = ap.parse_args(argv)
    arena = arenas.load(args.arena)
    out = Path(args.out)
    done = {}
    if out.exists():
        for line in out.read_text().splitlines():
            r = json.loads(line)
            done[(r["run"], r["strategy"])] = r
    names = args.strategies.split(",")
    car = {k: yaml.safe_load(v) for k, v in (item.split("=", 1) for item in args.car)} or None
    with out.open("a") as fh:
        for i, src, start in tqdm(list(pairs(arena, args.runs, args.seed)), desc="runs", file=sys.stderr):
            for name in names:
                if i < args.first or (i, name) in done:
                    continue
                ep, _, _ = search(arena, name, source=src, start=start, seed=args.seed + i,
                                  noise=args.noise, h=args.h, platform=args.platform, car=car)
                row = dict(ep.summary, run=i)
                fh.write(json.dumps(row) + "\n")
                fh.flush()
                done[(i, name)] = row
    print(f"arena {args.arena!r}, {args.runs} random (source, start) pairs, noise sigma = {args.noise:g}, "
          f"mesh h = {args.h} cm, {args.platform} observer {args.car or ''}")
    print(table([r for r in done.values() if args.first <= r["run"] < args.runs]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
