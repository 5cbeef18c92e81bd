"""Published tables, re-run as campaigns and printed beside the paper's numbers.

:data:`TABLES` maps a table name (``reciprocity reproduce --list``) to a
:class:`PaperTable`: the campaign spec with the paper's set-up and the paper's numbers.
The tables live in :mod:`reciprocity.campaign.tables` (one module per paper) and are
registered when this module is imported. A paper's table is added with
:func:`register`::

    register(PaperTable(
        name="ristic2014-table1", title="...", reference="Ristic et al. (2014), Table 1",
        build_spec=lambda runs: {"strategies": ["rbpf"], "scenarios": ["ristic-lattice"],
                                 "seeds": runs},
        paper=(PaperValue("rbpf", "steps", 42.1, among="success"),
               PaperValue("rbpf", "success", 0.94)), default_runs=100))

Our numbers are means over the runs with a Student-t 95 % interval (Wilson for rates,
i.e. boolean columns), computed by DuckDB over the campaign's Parquet files. A value may
be averaged over the successful runs only (``among="success"``, the lattice and plume
papers' "mean search time"), and may have no published number (``value=None``: a paper
with figures only; printed as "–"). A table may write figures after its campaign
(:attr:`PaperTable.after`).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import SearchError
from .cluster import TLSFiles
from .execute import CampaignResult, run_campaign
from .report import open_report_db
from .paper_table import AMONG, TABLES, PaperTable, PaperValue, register
from .spec import MAX_SEEDS
from . import tables  # noqa: F401  (registers the papers' tables)

__all__ = ["PaperValue", "PaperTable", "TABLES", "AMONG", "register", "reproduce", "compare",
           "comparison_markdown", "protocols_markdown", "verdict"]

def _table(name: str) -> PaperTable:
    if name not in TABLES:
        raise SearchError(f"unknown table {name!r}; 'reciprocity reproduce --list' names them: "
                          f"{', '.join(TABLES)}")
    return TABLES[name]


def compare(table: PaperTable, directory) -> list[dict]:
    """Our numbers beside the paper's, from the campaign results in `directory`.

    Parameters
    ----------
    table : PaperTable
    directory : path-like
        The folder the table's campaign was run into.

    Returns
    -------
    list of dict
        Per paper value: ``label``, ``variant``, ``scenario``, ``metric``, ``among``,
        ``rate`` (a boolean column), ``paper``, ``pm``, ``runs`` (the runs averaged),
        ``of`` (all finished runs of the row), ``ours`` (mean, or rate), ``lo``, ``hi``
        (95 % interval; None with fewer than two runs for a mean), ``at_least`` (the share
        of those runs at or above the paper's value; None for a rate or without one).
    """
    con = open_report_db(directory)
    types = {name: typ for name, typ, *_ in con.execute("DESCRIBE runs").fetchall()}
    out = []
    for pv in table.paper:
        where = "variant = $v AND ($s IS NULL OR scenario = $s)"
        params = {"v": pv.variant, "s": pv.scenario}
        of = con.execute(f"SELECT count(*) FROM runs WHERE {where}", params).fetchone()[0]
        if pv.among == "success":
            where += " AND success"
        rate = types.get(pv.metric) == "BOOLEAN"
        if pv.metric not in types:          # no episode reported it
            n, mean, lo, hi = 0, None, None, None
        elif rate:
            col = f'"{pv.metric}"'
            k, n = f"count(*) FILTER (WHERE {col})", f"count({col})"
            sql = (f"SELECT {n}, avg({col}::INT), wilson({k}, {n}, -1), wilson({k}, {n}, 1) "
                   f"FROM runs WHERE {where}")
            n, mean, lo, hi = con.execute(sql, params).fetchone()
        else:
            col = f'"{pv.metric}"::DOUBLE'
            half = f"t975(count({col}) - 1) * stddev_samp({col}) / sqrt(count({col}))"
            sql = (f"SELECT count({col}), avg({col}), avg({col}) - {half}, avg({col}) + {half} "
                   f"FROM runs WHERE {where}")
            n, mean, lo, hi = con.execute(sql, params).fetchone()
        at_least = None
        if pv.metric in types and not rate and pv.value is not None and n:
            at_least = con.execute(f'SELECT avg(("{pv.metric}"::DOUBLE >= $p)::INT) FROM runs WHERE {where} '
                                   f'AND "{pv.metric}" IS NOT NULL', {**params, "p": pv.value}).fetchone()[0]
        out.append(dict(label=pv.label, variant=pv.variant, scenario=pv.scenario,
                        metric=pv.metric, among=pv.among, rate=rate, paper=pv.value, pm=pv.pm,
                        runs=n, of=of, ours=mean, lo=lo, hi=hi, at_least=at_least))
    return out


def _digits(x) -> int:
    """Decimals for a mean of magnitude `x`: 2 below 100, 1 below 10⁴, else 0."""
    return 2 if x is None or x != x or abs(x) < 100 else 1 if abs(x) < 1e4 else 0


def _num(x, digits: int = 2) -> str:
    return "–" if x is None or x != x else f"{x:.{digits}f}"


def _paper(x) -> str:
    return "–" if x is None else f"{x:g}"


def _pct(x) -> str:
    """A rate in per cent: whole numbers, one decimal where rounding would hide a bound
    (a Wilson bound of 99.6 % must not print as 100 %)."""
    if x is None or x != x:
        return "–"
    whole = f"{100 * x:.0f}"
    return f"{100 * x:.1f} %" if whole in ("0", "100") and 0 < x < 1 else f"{whole} %"


def comparison_markdown(table: PaperTable, rows: list[dict]) -> str:
    """The comparison as a Markdown table, with the table's title and note.

    Rates print as percentages; a value the paper has no number for prints "–"; a value
    averaged over the successful runs says so in the metric column and counts
    ``runs of all``.
    """
    lines = [f"{table.reference}: {table.title}", "",
             "| row | metric | paper | ours | 95 % CI | runs |",
             "|---|---|---:|---:|---|---:|"]
    for r in rows:
        d = _digits(r["ours"])                  # ours and its interval alike

        def f(x, rate=r["rate"], d=d):
            return _pct(x) if rate else _num(x, d)
        paper = _pct(r["paper"]) if r["rate"] else _paper(r["paper"])
        if r["pm"] is not None and r["paper"] is not None:
            paper += f" ± {_pct(r['pm']) if r['rate'] else _paper(r['pm'])}"
        metric = r["metric"] + (" (successful runs)" if r["among"] == "success" else "")
        runs = f"{r['runs']} of {r['of']}" if r["among"] == "success" else f"{r['runs']}"
        lines.append(f"| {r['label']} | {metric} | {paper} | {f(r['ours'])} | "
                     f"[{f(r['lo'])}, {f(r['hi'])}] | {runs} |")
    if table.note:
        lines += ["", table.note]
    return "\n".join(lines) + "\n"


def verdict(row: dict) -> str:
    """Where the paper's value falls among ours, in words.

    ``"in our 95 % CI"`` when it lies in our interval; else ``"above our CI"`` or
    ``"below our CI"``, with, for a mean, the share of our runs at or above the paper's
    value (a paper that reports one run is one draw, and this says how ordinary a draw it
    would be among ours); ``"–"`` without a paper value or without our interval.

    Parameters
    ----------
    row : dict
        One row of :func:`compare`.

    Returns
    -------
    str
    """
    paper, lo, hi = row["paper"], row["lo"], row["hi"]
    if paper is None or lo is None or hi is None or lo != lo or hi != hi:
        return "–"
    if lo <= paper <= hi:
        return "in our 95 % CI"
    side = "above" if paper > hi else "below"
    if row.get("at_least") is None:
        return f"{side} our CI"
    return f"{side} our CI; {_pct(row['at_least'])} of ours ≥ paper"


def protocols_markdown(table: PaperTable, columns: list[tuple[str, list[dict]]]) -> str:
    """Several protocols of one table side by side, each with its verdicts.

    Parameters
    ----------
    table : PaperTable
        The table (its title, reference and rows).
    columns : list of (str, list of dict)
        Per protocol: its name and its :func:`compare` rows (the same paper values, in the
        same order).

    Returns
    -------
    str
        A Markdown table: row, metric, paper, then per protocol our mean with its 95 %
        interval and the verdict (:func:`verdict`).
    """
    head = "| row | metric | paper | " + " | ".join(f"{name} | verdict" for name, _ in columns) + " |"
    lines = [f"{table.reference}: {table.title} (protocols side by side)", "", head,
             "|---|---|---:|" + "---|---|" * len(columns)]
    for i, pv in enumerate(table.paper):
        cells = []
        for _, rows in columns:
            r = rows[i]
            d = _digits(r["ours"])

            def f(x, rate=r["rate"], d=d):
                return _pct(x) if rate else _num(x, d)
            cells.append(f"{f(r['ours'])} [{f(r['lo'])}, {f(r['hi'])}] | {verdict(r)}")
        rate = columns[0][1][i]["rate"] if columns else False
        paper = _pct(pv.value) if rate else _paper(pv.value)
        lines.append(f"| {pv.label} | {pv.metric} | {paper} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def reproduce(name: str, directory, *, runs: int | None = None, workers: int | None = None,
              scheduler: str | None = None, tls: TLSFiles | None = None,
              progress: bool | None = None, protocol: str | None = None, rows=None
              ) -> tuple[PaperTable, CampaignResult, list[dict], list[Path]]:
    """Run (or resume) the campaign of table `name` and compare it with the paper.

    Parameters
    ----------
    name : str
        A key of :data:`TABLES`.
    directory : path-like
        Results folder.
    runs : int, optional
        Seeds (episodes per strategy), 1 to :data:`reciprocity.campaign.spec.MAX_SEEDS`;
        default: the table's.
    workers, scheduler, tls, progress
        As in :func:`reciprocity.campaign.run_campaign`.
    protocol : str, optional
        One of the table's :attr:`PaperTable.protocols` (default: its own set-up).
    rows : list of str, optional
        Run only these rows (:meth:`PaperTable.rows`: row labels, variants or scenarios);
        default: the whole table. A table's figures (:attr:`PaperTable.after`) are made
        for the whole table only.

    Returns
    -------
    (PaperTable, CampaignResult, list of dict, list of Path)
        The table, what the run did, :func:`compare`'s rows, and the files the table's
        :attr:`PaperTable.after` wrote (empty without one).
    """
    whole = _table(name).protocol(protocol)
    table = whole.rows(rows)
    if runs is not None and (isinstance(runs, bool) or not isinstance(runs, int)
                             or not 1 <= runs <= MAX_SEEDS):
        raise SearchError(f"--runs must be a whole number from 1 to {MAX_SEEDS}; got {runs!r}")
    spec = table.spec(runs)
    result = run_campaign(spec, directory, workers=workers, scheduler=scheduler, tls=tls,
                          progress=progress)
    rows = compare(table, directory)
    files = list(table.after(Path(directory), spec)) if table.after is not None and table is whole else []
    return table, result, rows, files


