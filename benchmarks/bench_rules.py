"""The reciprocity strategy's rules against the paper's Algorithm 1, on shared pairs.

Runs every variant of ``reciprocity_rules.yaml`` as its own campaign (same campaign
seed and ``random_source``, so every variant meets the same (source, start) pairs and
noise), one local Dask cluster for all, then prints one markdown table per table of
the file: success, measurements, errors and stop reasons. Resumable: re-running skips
finished episodes (delete a variant's folder after changing its code).

    python benchmarks/bench_rules.py [--out bench_rules] [--workers 2] [--runs 100]
    python benchmarks/bench_rules.py --table rules --only info --only info-unknown-c
    python benchmarks/bench_rules.py --timing       # step times per rule, paper, h = 1 cm
"""

from __future__ import annotations

import argparse
from pathlib import Path

import duckdb
import yaml

from reciprocity.campaign import dask_client, episodes_sql, parse_spec, run_campaign

HERE = Path(__file__).parent

#: One row per (scenario, variant): success with converged runs off by more than the
#: success radius counted apart, effort and error percentiles, stop reasons.
TABLE_SQL = """
SELECT scenario, variant, count(*) AS runs,
       100 * avg(success::INT) AS success_pct,
       count(*) FILTER (WHERE converged AND NOT success) AS converged_off,
       median(n_measurements) AS med_n, quantile_cont(n_measurements, 0.9) AS p90_n,
       median(error) AS med_err, quantile_cont(error, 0.9) AS p90_err, max(error) AS max_err,
       max(error) FILTER (WHERE converged) AS max_err_converged,
       string_agg(DISTINCT stop || ' ' || n_stop, ', ') AS stops
FROM (SELECT *, count(*) OVER (PARTITION BY scenario, variant, stop) AS n_stop FROM runs)
GROUP BY scenario, variant
"""


def run_table(name: str, table: dict, spec: dict, out: Path, workers: int, only: list[str]) -> str:
    """Run (or resume) the variants of `table`; return its markdown table."""
    labels = [v for v in table["variants"] if not only or v in only]
    with dask_client(workers) as client:
        for label in labels:
            data = dict(name=label, seed=spec["seed"], seeds=spec["seeds"], random_source=True,
                        platform=spec["platform"], scenarios=table["scenarios"],
                        strategies={"reciprocity": table["variants"][label] or {}})
            r = run_campaign(parse_spec(data, base_dir=HERE), out / label,
                             scheduler=client.scheduler.address)
            print(f"{name}/{label}: {r.n_run} run, {r.n_skipped} resumed, {r.wall_time_s:.0f} s")
    con = duckdb.connect()
    parts = " UNION ALL BY NAME ".join(
        f"SELECT *, '{label}' AS label FROM {episodes_sql(out / label)}" for label in labels)
    con.execute(f"CREATE VIEW runs AS SELECT * REPLACE (label AS variant) FROM ({parts})")
    rows = con.execute(TABLE_SQL).fetchall()
    order = {(s, v): (i, j) for i, s in enumerate(table["scenarios"]) for j, v in enumerate(labels)}
    rows.sort(key=lambda r: order[(r[0], r[1])])
    head = ("| scenario | variant | runs | success % | converged > 5 cm | median n | p90 n "
            "| median error cm | p90 error cm | max error cm | max error converged cm | stops |")
    lines = [head, "|" + " --- |" * 12]
    for r in rows:
        cells = [r[0], r[1], str(r[2]), f"{r[3]:.0f}", str(r[4]), f"{r[5]:g}", f"{r[6]:.1f}",
                 f"{r[7]:.2f}", f"{r[8]:.2f}", f"{r[9]:.1f}",
                 "-" if r[10] is None else f"{r[10]:.1f}", r[11]]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def step_times(arena_name: str = "paper", h: float = 1.0, repeat: int = 5) -> str:
    """Wall time of one strategy step (``observe``: imaging update, region area,
    estimate, stop test, next point) per rule, best of `repeat` searches, ms.

    The same seeded search is replayed `repeat` times per rule; "first" is the first
    replay of ``rule="info"`` (lattice columns solved on demand), the best of the rest
    has them cached, as every later search on the same solver in a process does.
    """
    import time

    import numpy as np

    import reciprocity as r
    from reciprocity.models.green import cached_solver
    arena = r.scenarios.load_scenario(arena_name).arena
    solver = cached_solver(arena.without_scenario(), h)
    ctx = dict(arena=arena.without_scenario(), strength=arena.strength, noise=12.0)
    truth = solver.field(arena.source, arena.strength)
    lines = ["| rule | steps | median step ms | max step ms | first search median ms |",
             "| --- | --- | --- | --- | --- |"]
    for rule in ("axis", "info"):
        runs = []
        for _ in range(repeat):
            s = r.ReciprocityStrategy(solver=solver, rule=rule)
            s.start(r.SearchContext("poisson", ctx, np.array([list(arena.start)]), np.random.default_rng(0)))
            noise = np.random.default_rng(1)
            times = []
            while not s.done:
                z = s.propose().point
                obs = r.Observation(z, float(truth([z])[0]) + 12.0 * noise.standard_normal())
                t = time.perf_counter()
                s.observe([obs], None)
                times.append(time.perf_counter() - t)
            runs.append(np.array(times) * 1e3)
        best = np.min(np.array(runs[1:]), axis=0)
        lines.append(f"| {rule} | {len(best)} | {np.median(best):.1f} | {best.max():.1f} | "
                     f"{np.median(runs[0]):.1f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spec", type=Path, default=HERE / "reciprocity_rules.yaml")
    ap.add_argument("--out", type=Path, default=Path("bench_rules"))
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--runs", type=int, help="pairs per scenario (default: the spec's)")
    ap.add_argument("--table", action="append", default=[], help="only these tables")
    ap.add_argument("--only", action="append", default=[], help="only these variants")
    ap.add_argument("--timing", action="store_true", help="only the step times at h = 1 cm")
    args = ap.parse_args(argv)
    if args.timing:
        print(step_times())
        return 0
    spec = yaml.safe_load(args.spec.read_text())
    if args.runs is not None:
        spec["seeds"] = args.runs
    for name, table in spec["tables"].items():
        if args.table and name not in args.table:
            continue
        print(f"\n### {name}\n\n" + run_table(name, table, spec, args.out / name, args.workers,
                                               args.only) + "\n", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
