"""Simulation speed of the car: simulated seconds per second of computing, episode by episode.

Runs the (source, start) pairs of ``search_car.yaml`` (the car benchmark: random pairs on
``paper``) with one strategy, in one process per tree and planner, one after the other
(never two at once), and prints per planner the overall speed (sum of simulated time over
sum of computing time, the ``sim_time_s`` and ``wall_time_s`` of the summaries), the median
and the slowest episode, the same by the process's CPU time (which other jobs on a busy machine
do not inflate; on an idle one it exceeds the wall time where two threads sweep), with the success count, so that a speed-up that changed the
searches would show. With ``--before REF`` the same runs are made on a ``git worktree`` of
REF first, and the table shows both.

    python benchmarks/bench_car_speed.py                          # 30 pairs, on-demand and bank
    python benchmarks/bench_car_speed.py --before 82cb658 --planners on-demand
    python benchmarks/bench_car_speed.py --pairs 10 --strategy gradient

The bank planner's value functions come from the disk cache (``~/.cache/hjplanner``, built
on first use: about 8 s on 2 cores for ``paper``); its episodes count only their loads.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SPEC = HERE / "search_car.yaml"


def run_pairs(strategy: str, planner: str, pairs: int) -> list[dict]:
    """The episodes of the first `pairs` seeds of ``search_car.yaml`` (in this process)."""
    import yaml

    from reciprocity import api
    from reciprocity.campaign.spec import entry_scenario, parse_spec, world_overrides
    from reciprocity.campaign.worker import scenario, world_draw

    data = yaml.safe_load(SPEC.read_text())
    data.update(strategies=[strategy], seeds=pairs)
    spec = parse_spec(data, base_dir=HERE)
    rows = []
    for task in spec.tasks():
        sc = entry_scenario(task.scenario, scenario(task.scenario.ref))
        world = world_overrides(task.scenario.world)
        world.update(world_draw(sc, task.seed))
        cpu = time.process_time()
        s = api.execute(sc, strategy, seed=task.seed, platform="car", world=world,
                        platform_options={"planner": planner})[0].summary
        rows.append({k: s[k] for k in ("sim_time_s", "wall_time_s", "success", "n_samples")})
        rows[-1]["cpu_time_s"] = time.process_time() - cpu
    import hjplanner
    rows[0]["tree"] = str(Path(hjplanner.__file__).parents[1])
    return rows


def child(tree: Path, strategy: str, planner: str, pairs: int) -> list[dict]:
    """:func:`run_pairs` in a fresh process with `tree` first on the path (run from a scratch
    folder: ``python -c`` puts its working folder before ``PYTHONPATH``)."""
    code = (f"import json, sys; sys.path.insert(0, {str(HERE)!r}); import bench_car_speed as b; "
            f"print(json.dumps(b.run_pairs({strategy!r}, {planner!r}, {pairs})))")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree)] + sys.path[1:]))
    with tempfile.TemporaryDirectory(prefix="bench_car_") as scratch:
        run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=scratch)
    if run.returncode:
        raise SystemExit(f"error: the runs on {tree} failed:\n{run.stderr[-3000:]}")
    rows = json.loads(run.stdout.strip().splitlines()[-1])
    if Path(rows[0]["tree"]).resolve() != tree.resolve():
        raise SystemExit(f"error: the runs meant for {tree} imported {rows[0]['tree']}")
    return rows


def row(label: str, planner: str, rows: list[dict]) -> str:
    """One table row: the speeds by wall clock, then by this process's CPU time (all threads),
    which a busy machine does not inflate. The first episode also builds the arena's truth
    (its solver and the floor's pixels) and, in a fresh worktree, compiles the planner's
    kernels: "slowest after the first" leaves it out."""
    sim = np.array([r["sim_time_s"] for r in rows])
    wall = np.array([r["wall_time_s"] for r in rows])
    cpu = np.array([r["cpu_time_s"] for r in rows])
    speed, by_cpu = sim / wall, sim / cpu
    ok = sum(bool(r["success"]) for r in rows)
    return (f"| {label} | {planner} | {len(rows)} | {sim.sum() / wall.sum():.1f}x | {np.median(speed):.1f}x | "
            f"{speed.min():.1f}x | {speed[1:].min() if len(rows) > 1 else speed.min():.1f}x | {sim.sum() / cpu.sum():.1f}x | {np.median(by_cpu):.1f}x | {by_cpu.min():.1f}x | "
            f"{by_cpu[1:].min() if len(rows) > 1 else by_cpu.min():.1f}x | {wall.sum():.1f} | {cpu.sum():.1f} | "
            f"{ok}/{len(rows)} | {np.median([r['n_samples'] for r in rows]):g} |")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", type=int, default=30, help="random (source, start) pairs (default 30)")
    ap.add_argument("--strategy", default="reciprocity", help="reciprocity (default) or gradient")
    ap.add_argument("--planners", default="on-demand,bank", help="comma-separated: on-demand, bank")
    ap.add_argument("--before", help="git ref to measure first, in a worktree")
    args = ap.parse_args(argv)
    planners = [p for p in args.planners.split(",") if p]
    if args.pairs < 1 or not set(planners) <= {"on-demand", "bank"} or not planners:
        print("error: --pairs must be >= 1 and --planners a list of on-demand, bank", file=sys.stderr)
        return 2
    lines = []
    if args.before:
        sys.path.insert(0, str(HERE))
        from reference_tree import reference_tree
        with reference_tree(args.before, "bench_car_") as (before, _):
            for planner in planners:
                lines.append(row(f"before ({args.before})", planner, child(before, args.strategy, planner, args.pairs)))
    for planner in planners:
        lines.append(row("after (working tree)", planner, child(ROOT, args.strategy, planner, args.pairs)))
    print(f"{args.strategy} on the car, the first {args.pairs} pairs of {SPEC.name}; one process at a time, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    print("| tree | planner | episodes | wall: overall | median episode | slowest episode | slowest after the first "
          "| CPU: overall | median episode | slowest episode | slowest after the first | wall s | CPU s | success "
          "| median samples |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
