"""Paired summary of the cross-run campaign of ``benchmarks/plume_beyond.yaml``.

    python benchmarks/plume_cross_report.py runs/plume_beyond

Per variant: success, readings, path walked, error, CPU/wall time; then the paired
differences of arena-infotaxis against each reciprocity variant on the same pairs
(mean ± 95 % normal interval of the per-pair difference).
"""

from __future__ import annotations

import sys

import numpy as np


def main(folder: str) -> None:
    from reciprocity.campaign import connect
    con = connect(folder)                      # the campaign's own partitions, never a recursive glob
    con.execute("CREATE VIEW r AS SELECT * FROM episodes")
    print("| variant | runs | success % | mean readings | median readings | mean path cm | median path cm "
          "| median error cm | p90 error cm | stops | mean wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for row in con.execute(
            "SELECT variant, count(*), 100*avg(success::INT), avg(n_measurements), median(n_measurements), "
            "avg(path_length), median(path_length), median(error), quantile_cont(error, 0.9), "
            "string_agg(DISTINCT stop, ', '), avg(wall_time_s) FROM r GROUP BY variant ORDER BY variant").fetchall():
        print("| {} | {} | {:.1f} | {:.1f} | {:.0f} | {:.0f} | {:.0f} | {:.2f} | {:.2f} | {} | {:.2f} |".format(*row))
    rows = con.execute("SELECT variant, seed_index, success::INT, n_measurements, path_length, error "
                       "FROM r ORDER BY variant, seed_index").fetchall()
    by = {}
    for v, i, s, m, p, e in rows:
        by.setdefault(v, {})[i] = (s, m, p, e)
    base = "arena-infotaxis"
    print(f"\n| {base} minus | pairs | Δ success (pp) | Δ readings | Δ path cm |")
    print("|---|---|---|---|---|")
    for v in sorted(by):
        if v == base:
            continue
        common = sorted(set(by[v]) & set(by[base]))
        d = np.array([[by[base][i][k] - by[v][i][k] for k in range(3)] for i in common], float)
        mean, half = d.mean(axis=0), 1.96 * d.std(axis=0, ddof=1) / np.sqrt(len(d))
        print(f"| {v} | {len(common)} | {100 * mean[0]:+.1f} ± {100 * half[0]:.1f} | {mean[1]:+.1f} ± {half[1]:.1f} "
              f"| {mean[2]:+.0f} ± {half[2]:.0f} |")
    fails = [(i, round(e, 1), m) for i, (s, m, p, e) in by[base].items() if not s]
    print(f"\n{base} failures (seed index, error cm, readings): {fails}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "runs/plume_beyond")
