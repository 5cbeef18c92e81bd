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

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..errors import SearchError
from .cluster import TLSFiles
from .execute import CampaignResult, run_campaign
from .report import open_report_db
from .spec import MAX_SEEDS, CampaignSpec, parse_spec

__all__ = ["PaperValue", "PaperTable", "TABLES", "AMONG", "register", "reproduce", "compare",
           "comparison_markdown"]

#: Which runs a value averages: all finished runs (None) or the successful ones.
AMONG = (None, "success")


@dataclass(frozen=True)
class PaperValue:
    """One number of a published table (or one of ours the paper has no number for).

    Attributes
    ----------
    variant : str
        Strategy variant label in the campaign (``"reciprocity"``, ``"rbpf[n=500]"``).
    metric : str
        Result column: ``n_measurements``, ``n_samples``, ``steps``, ``error``,
        ``path_length``, ``sim_time_s``, ``success``, ``messages``,
        ``distance_at_stop``, ... A boolean column is a rate (Wilson interval).
    value : float or None
        The paper's value, in the column's unit (a rate as a fraction); None when the
        paper prints no number for it (printed as "–").
    scenario : str, optional
        Scenario label, when the campaign has several.
    among : {None, "success"}
        Average over all finished runs (None) or over the successful runs only.
    pm : float, optional
        The ± the paper prints beside `value` (its own convention; see the table's note).
    row : str, optional
        Row label in the printed table (default: ``variant (scenario)``).

    Raises
    ------
    SearchError
        `among` not in :data:`AMONG`.
    """

    variant: str
    metric: str
    value: float | None
    scenario: str | None = None
    among: str | None = None
    pm: float | None = None
    row: str | None = None

    def __post_init__(self):
        if self.among not in AMONG:
            raise SearchError(f"PaperValue among must be None (all runs) or 'success'; "
                              f"got {self.among!r}")

    @property
    def label(self) -> str:
        """The row label."""
        if self.row is not None:
            return self.row
        return self.variant if self.scenario is None else f"{self.variant} ({self.scenario})"


@dataclass(frozen=True)
class PaperTable:
    """A published table as a campaign.

    Attributes
    ----------
    name : str
        Registry key (``reciprocity reproduce NAME``).
    title : str
        One line: what the table shows.
    reference : str
        Paper and table.
    build_spec : callable
        ``build_spec(runs) -> dict``: the campaign spec mapping (see
        :mod:`reciprocity.campaign.spec`) with `runs` seeds.
    paper : tuple of PaperValue
        The paper's numbers (and ours it has none for), in print order.
    default_runs : int
        Seeds when ``--runs`` is not given.
    note : str
        Caveats printed under the comparison (settings that differ from the paper's,
        what the paper's ± means, why numbers differ).
    after : callable, optional
        ``after(directory, spec) -> list of Path``: called once the campaign is complete
        (e.g. the paper's figures, example tracks); writes under `directory` and returns
        the files written.
    """

    name: str
    title: str
    reference: str
    build_spec: Callable[[int], dict]
    paper: tuple[PaperValue, ...]
    default_runs: int = 20
    note: str = ""
    after: Callable[[Path, CampaignSpec], list[Path]] | None = None

    def spec(self, runs: int | None = None) -> CampaignSpec:
        """The validated campaign with `runs` seeds (default :attr:`default_runs`)."""
        return parse_spec({"name": self.name, **self.build_spec(runs or self.default_runs)})


#: Registered tables by name.
TABLES: dict[str, PaperTable] = {}


def register(table: PaperTable) -> PaperTable:
    """Add `table` to :data:`TABLES`; returns it.

    Raises
    ------
    SearchError
        A table of that name is already registered.
    """
    if table.name in TABLES:
        raise SearchError(f"a reproducible table named {table.name!r} is already registered")
    TABLES[table.name] = table
    return table


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
        (95 % interval; None with fewer than two runs for a mean).
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
        out.append(dict(label=pv.label, variant=pv.variant, scenario=pv.scenario,
                        metric=pv.metric, among=pv.among, rate=rate, paper=pv.value, pm=pv.pm,
                        runs=n, of=of, ours=mean, lo=lo, hi=hi))
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


def reproduce(name: str, directory, *, runs: int | None = None, workers: int | None = None,
              scheduler: str | None = None, tls: TLSFiles | None = None,
              progress: bool | None = None
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

    Returns
    -------
    (PaperTable, CampaignResult, list of dict, list of Path)
        The table, what the run did, :func:`compare`'s rows, and the files the table's
        :attr:`PaperTable.after` wrote (empty without one).
    """
    table = _table(name)
    if runs is not None and (isinstance(runs, bool) or not isinstance(runs, int)
                             or not 1 <= runs <= MAX_SEEDS):
        raise SearchError(f"--runs must be a whole number from 1 to {MAX_SEEDS}; got {runs!r}")
    spec = table.spec(runs)
    result = run_campaign(spec, directory, workers=workers, scheduler=scheduler, tls=tls,
                          progress=progress)
    rows = compare(table, directory)
    files = list(table.after(Path(directory), spec)) if table.after is not None else []
    return table, result, rows, files


from . import tables  # noqa: E402,F401  (registers the papers' tables; they import this module)
