"""Published tables, re-run as campaigns and printed beside the paper's numbers.

:data:`TABLES` maps a table name (``reciprocity reproduce --list``) to a
:class:`PaperTable`: the campaign spec with the paper's set-up and the paper's numbers.
Model engineers add theirs with :func:`register`::

    register(PaperTable(
        name="ristic2014-table1", title="...", reference="Ristic et al. (2014), Table 1",
        build_spec=lambda runs: {"strategies": ["rbpf"], "scenarios": ["ristic-lattice"],
                                 "seeds": runs},
        paper=(PaperValue("rbpf", "steps", 123.0),), default_runs=100))

Our numbers are means over the runs with a Student-t 95 % interval (Wilson for rates),
computed by DuckDB over the campaign's Parquet files.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..errors import SearchError
from .execute import CampaignResult, run_campaign
from .report import open_report_db
from .spec import CampaignSpec, parse_spec

__all__ = ["PaperValue", "PaperTable", "TABLES", "register", "reproduce", "compare",
           "comparison_markdown"]


@dataclass(frozen=True)
class PaperValue:
    """One number of a published table.

    Attributes
    ----------
    variant : str
        Strategy variant label in the campaign (``"reciprocity"``, ``"rbpf[n=500]"``).
    metric : str
        Result column: ``n_measurements``, ``n_samples``, ``steps``, ``error``,
        ``path_length``, ``sim_time_s``, ``success``, ...
    value : float
        The paper's value, in the column's unit (a rate as a fraction).
    scenario : str, optional
        Scenario label, when the campaign has several.
    """

    variant: str
    metric: str
    value: float
    scenario: str | None = None


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
        The paper's numbers.
    default_runs : int
        Seeds when ``--runs`` is not given.
    note : str
        Caveats printed under the comparison (e.g. a single run in the paper).
    """

    name: str
    title: str
    reference: str
    build_spec: Callable[[int], dict]
    paper: tuple[PaperValue, ...]
    default_runs: int = 20
    note: str = ""

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
        Per paper value: ``variant``, ``scenario``, ``metric``, ``paper``, ``runs``,
        ``ours`` (mean, or rate), ``lo``, ``hi`` (95 % interval).
    """
    con = open_report_db(directory)
    out = []
    for pv in table.paper:
        where = "variant = $v AND ($s IS NULL OR scenario = $s)"
        if pv.metric == "success":
            sql = (f"SELECT count(*), avg(success::INT), wilson(count(*) FILTER (WHERE success), "
                   f"count(*), -1), wilson(count(*) FILTER (WHERE success), count(*), 1) "
                   f"FROM runs WHERE {where}")
        else:
            col = f'"{pv.metric}"::DOUBLE'
            half = f"t975(count({col}) - 1) * stddev_samp({col}) / sqrt(count({col}))"
            sql = (f"SELECT count({col}), avg({col}), avg({col}) - {half}, avg({col}) + {half} "
                   f"FROM runs WHERE {where}")
        n, mean, lo, hi = con.execute(sql, {"v": pv.variant, "s": pv.scenario}).fetchone()
        out.append(dict(variant=pv.variant, scenario=pv.scenario, metric=pv.metric,
                        paper=pv.value, runs=n, ours=mean, lo=lo, hi=hi))
    return out


def comparison_markdown(table: PaperTable, rows: list[dict]) -> str:
    """The comparison as a Markdown table, with the table's title and note."""
    def f(x):
        return "–" if x is None or x != x else f"{x:.2f}"
    lines = [f"{table.reference}: {table.title}", "",
             "| strategy | metric | paper | ours (mean) | 95 % CI | runs |",
             "|---|---|---:|---:|---|---:|"]
    for r in rows:
        what = r["variant"] if r["scenario"] is None else f"{r['variant']} ({r['scenario']})"
        lines.append(f"| {what} | {r['metric']} | {f(r['paper'])} | {f(r['ours'])} | "
                     f"[{f(r['lo'])}, {f(r['hi'])}] | {r['runs']} |")
    if table.note:
        lines += ["", table.note]
    return "\n".join(lines) + "\n"


def reproduce(name: str, directory, *, runs: int | None = None, workers: int | None = None,
              scheduler: str | None = None, progress: bool | None = None
              ) -> tuple[PaperTable, CampaignResult, list[dict]]:
    """Run (or resume) the campaign of table `name` and compare it with the paper.

    Parameters
    ----------
    name : str
        A key of :data:`TABLES`.
    directory : path-like
        Results folder.
    runs : int, optional
        Seeds (episodes per strategy); default: the table's.
    workers, scheduler, progress
        As in :func:`reciprocity.campaign.run_campaign`.

    Returns
    -------
    (PaperTable, CampaignResult, list of dict)
        The table, what the run did, and :func:`compare`'s rows.
    """
    table = _table(name)
    if runs is not None and runs < 1:
        raise SearchError(f"--runs must be at least 1; got {runs}")
    result = run_campaign(table.spec(runs), directory, workers=workers, scheduler=scheduler,
                          progress=progress)
    return table, result, compare(table, directory)


register(PaperTable(
    name="landa2020-testbed",
    title="reciprocity search vs gradient ascent on the car testbed, from the paper arena's "
          "start to its source",
    reference="Landa et al. (2020), testbed experiment (Sec. 5)",
    build_spec=lambda runs: {"strategies": ["reciprocity", "gradient"], "scenarios": ["paper"],
                             "platform": "car", "seeds": runs},
    paper=(PaperValue("reciprocity", "n_measurements", 7.0),
           PaperValue("reciprocity", "error", 4.35),
           PaperValue("gradient", "n_samples", 18.0),
           PaperValue("gradient", "error", 5.0)),
    default_runs=20,
    note="The paper reports a single run of each strategy (no interval); our runs differ in "
         "the sensor noise and the car's actuation only (same arena, source and start).",
))
