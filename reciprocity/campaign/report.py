"""Campaign reports: tables and figures computed by DuckDB SQL over the Parquet results.

Per scenario × strategy variant: runs, success rate with its Wilson 95 % interval, mean
and median steps, measurements and samples, median and 90th percentile of the error,
mean path length and simulated time. Paired differences between the variants of a
scenario on the same seed indices (same seed, same world), mean with a Student-t 95 %
interval. Figures: success against effort (survival curves), the distributions of the
error and the effort, a scenario × variant heat map of the success rate.

*Runs* are the episodes that finished; episodes that raised are counted as *crashed*
and left out of every statistic.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import duckdb

from arenas.files import atomic_output

from ..errors import SearchError
from .store import connect

__all__ = ["Report", "build_report", "write_report", "open_report_db", "SUMMARY_SQL", "Z95"]

#: Two-sided 95 % standard normal quantile.
Z95 = 1.959963984540054

#: Metrics compared between variants on the same seeds: column -> label.
PAIRED_METRICS = {"success": "success", "steps": "steps", "n_measurements": "measurements",
                  "n_samples": "samples", "error": "error", "path_length": "path"}

_MACROS = f"""
CREATE MACRO wilson(k, n, sign) AS CASE WHEN n = 0 THEN NULL ELSE
    ((k / n + {Z95}^2 / (2 * n)) + sign * {Z95} * sqrt(k / n * (1 - k / n) / n + {Z95}^2 / (4 * n * n)))
    / (1 + {Z95}^2 / n) END;
CREATE VIEW runs AS SELECT * FROM episodes WHERE error_message IS NULL;
"""

#: One row per scenario × variant (see the module docstring).
SUMMARY_SQL = """
SELECT e.scenario, e.variant,
       count(*) FILTER (WHERE error_message IS NULL) AS runs,
       count(*) FILTER (WHERE error_message IS NOT NULL) AS crashed,
       count(*) FILTER (WHERE error_message IS NULL AND success) AS successes,
       successes / nullif(runs, 0) AS success_rate,
       wilson(successes, runs, -1) AS success_lo,
       wilson(successes, runs, 1) AS success_hi,
       avg(steps) FILTER (WHERE error_message IS NULL) AS steps_mean,
       median(steps) FILTER (WHERE error_message IS NULL) AS steps_median,
       avg(n_measurements) FILTER (WHERE error_message IS NULL) AS measurements_mean,
       median(n_measurements) FILTER (WHERE error_message IS NULL) AS measurements_median,
       avg(n_samples) FILTER (WHERE error_message IS NULL) AS samples_mean,
       median(n_samples) FILTER (WHERE error_message IS NULL) AS samples_median,
       median(error) FILTER (WHERE error_message IS NULL) AS error_median,
       quantile_cont(error, 0.9) FILTER (WHERE error_message IS NULL) AS error_p90,
       avg(path_length) FILTER (WHERE error_message IS NULL) AS path_mean,
       avg(sim_time_s) FILTER (WHERE error_message IS NULL) AS sim_time_mean,
       avg(wall_time_s) FILTER (WHERE error_message IS NULL) AS wall_time_mean
FROM episodes e GROUP BY e.scenario, e.variant ORDER BY e.scenario, e.variant
"""

_PAIRED_SQL = """
SELECT a.scenario, a.variant AS a, b.variant AS b, '{label}' AS metric,
       count(*) AS pairs,
       avg(b.{col}::DOUBLE - a.{col}::DOUBLE) AS mean_diff,
       mean_diff - t975(pairs - 1) * stddev_samp(b.{col}::DOUBLE - a.{col}::DOUBLE) / sqrt(pairs) AS lo,
       mean_diff + t975(pairs - 1) * stddev_samp(b.{col}::DOUBLE - a.{col}::DOUBLE) / sqrt(pairs) AS hi
FROM runs a JOIN runs b
  ON a.scenario = b.scenario AND a.seed_index = b.seed_index AND a.variant < b.variant
WHERE a.{col} IS NOT NULL AND b.{col} IS NOT NULL
GROUP BY a.scenario, a.variant, b.variant
"""

_REACHABLE_SQL = """
SELECT scenario, variant, source_reachable, count(*) AS runs,
       count(*) FILTER (WHERE success) AS successes, successes / count(*) AS success_rate,
       wilson(successes, count(*), -1) AS success_lo, wilson(successes, count(*), 1) AS success_hi
FROM runs WHERE source_reachable IS NOT NULL
GROUP BY ALL ORDER BY scenario, variant, source_reachable
"""


def _t975(df: int) -> float:
    from scipy.stats import t
    return float(t.ppf(0.975, df)) if df >= 1 else float("nan")


def _dicts(con: duckdb.DuckDBPyConnection, sql: str) -> list[dict]:
    cur = con.execute(sql)
    names = [d[0] for d in cur.description]
    return [dict(zip(names, row)) for row in cur.fetchall()]


def open_report_db(directory) -> duckdb.DuckDBPyConnection:
    """DuckDB connection over `directory`'s results with the report's views and macros.

    Views: ``episodes`` (every row), ``runs`` (finished episodes); macros:
    ``wilson(k, n, sign)`` (Wilson 95 % bound, sign -1 lower, +1 upper) and
    ``t975(df)`` (Student-t 97.5 % quantile).

    Parameters
    ----------
    directory : path-like
        Campaign folder.

    Returns
    -------
    duckdb.DuckDBPyConnection
    """
    con = connect(directory)
    con.create_function("t975", _t975, ["BIGINT"], "DOUBLE",
                        side_effects=False)
    con.execute(_MACROS)
    return con


@dataclass
class Report:
    """The tables of a campaign report (rows as dicts; numbers from DuckDB).

    Attributes
    ----------
    summary : list of dict
        One row per scenario × variant: the columns of :data:`SUMMARY_SQL`.
    paired : list of dict
        One row per (scenario, variant a, variant b, metric): ``pairs``, ``mean_diff``
        (b − a) and its 95 % interval ``lo``, ``hi``.
    reachability : list of dict
        Success by ``source_reachable`` (empty until episodes report it).
    effort : str
        The column the survival curves use: ``steps``, or ``n_samples`` when some
        episodes do not report steps.
    """

    summary: list[dict]
    paired: list[dict]
    reachability: list[dict]
    effort: str

    def markdown(self) -> str:
        """The tables as Markdown."""
        out = ["| scenario | strategy | runs | success [95 % CI] | steps mean / med | "
               "meas. mean / med | samples mean / med | error med / p90 | path mean | sim s mean |",
               "|---|---|---:|---|---:|---:|---:|---:|---:|---:|"]
        for r in self.summary:
            crashed = f" (+{r['crashed']} crashed)" if r["crashed"] else ""
            out.append(
                f"| {r['scenario']} | {r['variant']} | {r['runs']}{crashed} | "
                f"{_pct(r['success_rate'])} [{_pct(r['success_lo'])}, {_pct(r['success_hi'])}] | "
                f"{_num(r['steps_mean'])} / {_num(r['steps_median'])} | "
                f"{_num(r['measurements_mean'])} / {_num(r['measurements_median'])} | "
                f"{_num(r['samples_mean'])} / {_num(r['samples_median'])} | "
                f"{_num(r['error_median'], 2)} / {_num(r['error_p90'], 2)} | "
                f"{_num(r['path_mean'], 0)} | {_num(r['sim_time_mean'], 0)} |")
        if self.paired:
            out += ["", "Paired differences (b − a, same seeds and worlds), mean [95 % CI]:", "",
                    "| scenario | a | b | metric | pairs | b − a [95 % CI] |",
                    "|---|---|---|---|---:|---|"]
            for r in self.paired:
                scale = 100 if r["metric"] == "success" else 1
                unit = " pp" if r["metric"] == "success" else ""
                out.append(f"| {r['scenario']} | {r['a']} | {r['b']} | {r['metric']} | {r['pairs']} | "
                           f"{_num(_mul(r['mean_diff'], scale), 2)}{unit} "
                           f"[{_num(_mul(r['lo'], scale), 2)}, {_num(_mul(r['hi'], scale), 2)}] |")
        if self.reachability:
            out += ["", "Success by source reachability:", "",
                    "| scenario | strategy | source reachable | runs | success [95 % CI] |",
                    "|---|---|---|---:|---|"]
            for r in self.reachability:
                out.append(f"| {r['scenario']} | {r['variant']} | {r['source_reachable']} | {r['runs']} | "
                           f"{_pct(r['success_rate'])} [{_pct(r['success_lo'])}, {_pct(r['success_hi'])}] |")
        return "\n".join(out) + "\n"


def _mul(x, k):
    return None if x is None else x * k


def _num(x, digits: int = 1) -> str:
    return "–" if x is None or x != x else f"{x:.{digits}f}"


def _pct(x) -> str:
    return "–" if x is None else f"{100 * x:.0f} %"


def build_report(directory) -> Report:
    """Compute a campaign's report tables.

    Parameters
    ----------
    directory : path-like
        Campaign folder.

    Returns
    -------
    Report

    Raises
    ------
    SearchError
        No results in `directory`.
    """
    con = open_report_db(directory)
    summary = _dicts(con, SUMMARY_SQL)
    paired = _dicts(con, " UNION ALL ".join(_PAIRED_SQL.format(col=c, label=lab)
                                           for c, lab in PAIRED_METRICS.items())
                    + " ORDER BY scenario, a, b, metric")
    reach = _dicts(con, _REACHABLE_SQL)
    with_steps, total = con.execute("SELECT count(steps), count(*) FROM runs").fetchone()
    return Report(summary, paired, reach, "steps" if total and with_steps == total else "n_samples")


def write_report(report: Report, directory, out) -> list[Path]:
    """Write ``report.md``, the CSV tables and the figures into `out`.

    Parameters
    ----------
    report : Report
        From :func:`build_report` on `directory`.
    directory : path-like
        Campaign folder (the figures query it).
    out : path-like
        Output folder (created).

    Returns
    -------
    list of Path
        The files written.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "report.md"]
    with atomic_output(files[0], error=SearchError) as tmp:
        tmp.write_text(report.markdown())
    for name, rows in (("summary", report.summary), ("paired", report.paired),
                       ("reachability", report.reachability)):
        if rows:
            files.append(out / f"{name}.csv")
            with atomic_output(files[-1], error=SearchError) as tmp, tmp.open("w", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=list(rows[0]))
                w.writeheader()
                w.writerows(rows)
    con = open_report_db(directory)
    files += [_survival_figure(con, report.effort, out / "success_vs_effort.png"),
              _distribution_figure(con, report.effort, out / "distributions.png"),
              _heatmap_figure(report, out / "success_heatmap.png")]
    return files


def _save(fig, path: Path) -> None:
    with atomic_output(path, error=SearchError) as tmp:
        fig.savefig(tmp, dpi=130, format="png")


def _figure(n_panels: int, width: float = 4.2, height: float = 3.4):
    from matplotlib.figure import Figure
    fig = Figure(figsize=(width * n_panels, height), layout="constrained")
    return fig, [fig.add_subplot(1, n_panels, i + 1) for i in range(n_panels)]


def _effort_label(effort: str) -> str:
    return "steps" if effort == "steps" else "samples (sensor readings)"


def _survival_figure(con, effort: str, path: Path) -> Path:
    rows = _dicts(con, f"""
        WITH n AS (SELECT scenario, variant, count(*) AS runs FROM runs GROUP BY ALL),
             s AS (SELECT scenario, variant, {effort} AS effort, count(*) AS k
                   FROM runs WHERE success AND {effort} IS NOT NULL GROUP BY ALL)
        SELECT s.scenario, s.variant, s.effort,
               sum(s.k) OVER (PARTITION BY s.scenario, s.variant ORDER BY s.effort) / n.runs AS frac
        FROM s JOIN n USING (scenario, variant) ORDER BY s.scenario, s.variant, s.effort""")
    scenarios = [r[0] for r in con.execute("SELECT DISTINCT scenario FROM runs ORDER BY 1").fetchall()]
    fig, axes = _figure(max(len(scenarios), 1))
    for ax, sc in zip(axes, scenarios):
        curves: dict[str, tuple[list, list]] = {}
        for r in rows:
            if r["scenario"] == sc:
                xs, ys = curves.setdefault(r["variant"], ([0], [0.0]))
                xs.append(r["effort"])
                ys.append(r["frac"])
        for variant, (xs, ys) in curves.items():
            ax.step(xs, ys, where="post", label=variant)
        ax.set(title=sc, xlabel=_effort_label(effort), ylabel="fraction of runs succeeded",
               ylim=(0, 1.02))
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
    _save(fig, path)
    return path


def _distribution_figure(con, effort: str, path: Path) -> Path:
    rows = _dicts(con, f"SELECT scenario || ' · ' || variant AS key, error, {effort} AS effort "
                       "FROM runs ORDER BY scenario, variant")
    keys = list(dict.fromkeys(r["key"] for r in rows))
    fig, (ax_e, ax_s) = _figure(2, width=max(4.2, 1.1 * len(keys) + 1.5))
    for ax, col, label in ((ax_e, "error", "error (cm or world unit)"),
                           (ax_s, "effort", _effort_label(effort))):
        data = [[r[col] for r in rows if r["key"] == k and r[col] is not None] for k in keys]
        ax.boxplot([d or [float("nan")] for d in data], showmeans=True)
        ax.set_xticks(range(1, len(keys) + 1), keys, rotation=30, ha="right", fontsize="small")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, axis="y")
    ax_e.set_yscale("symlog", linthresh=1.0)  # a few lost runs are off by the arena's size
    _save(fig, path)
    return path


def _heatmap_figure(report: Report, path: Path) -> Path:
    import numpy as np
    scenarios = list(dict.fromkeys(r["scenario"] for r in report.summary))
    variants = list(dict.fromkeys(r["variant"] for r in report.summary))
    grid = np.full((len(scenarios), len(variants)), np.nan)
    for r in report.summary:
        if r["success_rate"] is not None:
            grid[scenarios.index(r["scenario"]), variants.index(r["variant"])] = r["success_rate"]
    fig, (ax,) = _figure(1, width=1.2 * len(variants) + 2.5, height=0.6 * len(scenarios) + 1.8)
    im = ax.imshow(grid, vmin=0, vmax=1, cmap="viridis", aspect="auto")
    for (i, j), v in np.ndenumerate(grid):
        if v == v:
            ax.text(j, i, f"{100 * v:.0f} %", ha="center", va="center",
                    color="white" if v < 0.6 else "black", fontsize="small")
    ax.set_xticks(range(len(variants)), variants, rotation=30, ha="right")
    ax.set_yticks(range(len(scenarios)), scenarios)
    fig.colorbar(im, ax=ax, label="success rate")
    _save(fig, path)
    return path
