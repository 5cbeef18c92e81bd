"""Several sources, their number unknown: the table of issue 23 (K = 1, 2, 3 on paper and maze).

A thin driver over the campaign ``several_sources.yaml`` (or another spec with scenarios
that have ``sources``): it runs or resumes the campaign, then prints per scenario the
share of runs with K right and with every source within the success radius (Wilson 95 %
intervals), the errors of the sources matched by optimal assignment, the readings and the
path. The classic single-source scenarios (the task says one source) are the baseline.

    python benchmarks/several_sources.py                          # 50 seeds, point observer
    python benchmarks/several_sources.py --runs 10 --platform car --out bench_sources_car
    python benchmarks/several_sources.py --report-only bench_sources
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import yaml

from reciprocity.campaign import parse_spec, run_campaign
from reciprocity.campaign.report import open_report_db
from reciprocity.errors import ReciprocityError

HERE = Path(__file__).parent

#: Per scenario: K right, success, errors (every matched source), readings, path, wall time.
TABLE_SQL = """
WITH r AS (SELECT *, coalesce(json_array_length(sources), 1) AS k,
                  coalesce(n_sources_right, true) AS k_right FROM runs)
SELECT scenario, any_value(k) AS k, count(*) AS runs,
       avg(k_right::INT) AS k_rate, wilson(sum(k_right::INT), count(*), -1) AS k_lo,
       wilson(sum(k_right::INT), count(*), 1) AS k_hi,
       avg(success::INT) AS s_rate, wilson(sum(success::INT), count(*), -1) AS s_lo,
       wilson(sum(success::INT), count(*), 1) AS s_hi,
       median(n_measurements) AS readings_med, avg(n_measurements) AS readings_mean,
       median(path_length) AS path_med, median(wall_time_s) AS wall_med,
       count(*) FILTER (WHERE source_reachable) AS reach_runs,
       sum(success::INT) FILTER (WHERE source_reachable) AS reach_wins, sum(collisions) AS contacts
FROM r GROUP BY scenario ORDER BY any_value(arena), k, scenario
"""

#: Per run: the errors of its true sources (a list; a JSON text where every entry was null).
ERRORS_SQL = "SELECT scenario, CAST(errors AS VARCHAR) AS errors, error FROM runs"
#: The same where no run had several sources.
ERROR_SQL = "SELECT scenario, NULL AS errors, error FROM runs"

def table(directory: Path) -> str:
    """The Markdown table of a finished (or partial) campaign in `directory`."""
    con = open_report_db(directory)
    columns = {c[0] for c in con.execute("DESCRIBE runs").fetchall()}
    sql = TABLE_SQL
    for column, used, absent in (("collisions", "sum(collisions)", "NULL"),          # the car's
                                 ("sources", "json_array_length(sources)", "NULL"),  # several sources'
                                 ("n_sources_right", "coalesce(n_sources_right, true)", "true")):
        if column not in columns:
            sql = sql.replace(used, absent)
    rows = con.execute(sql).fetchall()
    names = [d[0] for d in con.description]
    errors: dict[str, list] = {}
    for scenario, listed, error in con.execute(ERRORS_SQL if "errors" in columns else ERROR_SQL).fetchall():
        values = [error] if listed is None else json.loads(listed.replace("NULL", "null"))
        errors.setdefault(scenario, []).extend(values)
    out = ["| scenario | K | runs | K right [95 % CI] | success [95 % CI] | error med / p90 (cm) | "
           "sources missed | readings med (mean) | path med (cm) | wall s med | success, every source reachable |",
           "|---|---:|---:|---|---|---|---:|---|---:|---:|---|"]
    for row in rows:
        r = dict(zip(names, row))
        contacts = "" if r["contacts"] is None else f", {int(r['contacts'])} contacts"
        e = errors.get(r["scenario"], [])
        found = np.array([v for v in e if v is not None], dtype=float)
        r.update(err_med=np.median(found) if found.size else np.nan,
                 err_p90=np.quantile(found, 0.9) if found.size else np.nan,
                 missed=(len(e) - found.size) / len(e) if e else None)
        pct = lambda x: "–" if x is None else f"{100 * x:.0f} %"   # noqa: E731
        out.append(f"| {r['scenario']} | {r['k']} | {r['runs']} | {pct(r['k_rate'])} [{pct(r['k_lo'])}, "
                   f"{pct(r['k_hi'])}] | {pct(r['s_rate'])} [{pct(r['s_lo'])}, {pct(r['s_hi'])}] | "
                   f"{r['err_med']:.2f} / {r['err_p90']:.2f} | {pct(r['missed'])} | "
                   f"{r['readings_med']:.0f} ({r['readings_mean']:.1f}) | {r['path_med']:.0f} | "
                   f"{r['wall_med']:.1f} | {r['reach_wins'] or 0}/{r['reach_runs']}{contacts} |")
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spec", type=Path, default=HERE / "several_sources.yaml", help="campaign spec")
    ap.add_argument("--runs", type=int, help="seeds per scenario (default: the spec's)")
    ap.add_argument("--platform", choices=("point", "car"), help="platform (default: the spec's)")
    ap.add_argument("--out", type=Path, default=Path("bench_sources"), help="results folder")
    ap.add_argument("--workers", type=int, help="local Dask workers (default: one per core)")
    ap.add_argument("--report-only", type=Path, metavar="DIR", help="print the table of a finished campaign")
    args = ap.parse_args(argv)
    try:
        if args.report_only is None:
            data = yaml.safe_load(args.spec.read_text())
            if args.runs is not None:
                data["seeds"] = args.runs
            if args.platform is not None:
                data["platform"] = args.platform
            spec = parse_spec(data, base_dir=args.spec.parent)
            run_campaign(spec, args.out, workers=args.workers)
        print(table(args.report_only or args.out), end="")
    except ReciprocityError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
