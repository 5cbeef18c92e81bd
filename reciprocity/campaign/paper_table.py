"""A published table as a campaign: :class:`PaperTable`, its :class:`PaperValue` numbers and
the registry :data:`TABLES` (filled by :mod:`reciprocity.campaign.tables`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..errors import SearchError
from .spec import CampaignSpec, parse_spec

__all__ = ["AMONG", "PaperValue", "PaperTable", "TABLES", "register"]

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
    protocols : mapping, optional
        Other ways to run the same table (``reproduce TABLE --protocol NAME``): name ->
        ``(build_spec, note)``, e.g. ``"paper"``, the paper's own protocol where the
        default differs from it.
    """

    name: str
    title: str
    reference: str
    build_spec: Callable[[int], dict]
    paper: tuple[PaperValue, ...]
    default_runs: int = 20
    note: str = ""
    after: Callable[[Path, CampaignSpec], list[Path]] | None = None
    protocols: dict = field(default_factory=dict)

    def protocol(self, name: str | None) -> "PaperTable":
        """This table run under protocol `name` (None or ``"default"``: itself). Its
        campaign is named ``TABLE-NAME``, so its results never mix with the default's."""
        if name in (None, "default"):
            return self
        if name not in self.protocols:
            allowed = ", ".join(["default", *self.protocols])
            raise SearchError(f"--protocol must be one of {allowed} for table {self.name!r}; got {name!r}")
        build, note = self.protocols[name]
        return replace(self, name=f"{self.name}-{name}", build_spec=build, note=note, protocols={})

    def spec(self, runs: int | None = None) -> CampaignSpec:
        """The validated campaign with `runs` seeds (default :attr:`default_runs`)."""
        return parse_spec({"name": self.name, **self.build_spec(runs or self.default_runs)})

    def rows(self, wanted) -> "PaperTable":
        """This table cut to the rows `wanted` (None: itself): a list, or a text of items
        separated by commas (a row label with a comma in it, as ``(0, 7)``, may stand alone),
        each naming a row by its label, its strategy variant or its scenario; every row an
        item names is kept. Its
        campaign runs only the (scenario, variant) pairs of those rows, with the same
        episodes (ids and seeds) as the whole table's.

        Raises
        ------
        SearchError
            An item that names no row.
        """
        if not wanted:
            return self
        if isinstance(wanted, str):
            names = {v.label for v in self.paper} | {v.variant for v in self.paper} | {v.scenario for v in self.paper}
            wanted = [wanted] if wanted in names else [w.strip() for w in wanted.split(",")]
        keep = []
        for item in wanted:
            hits = [v for v in self.paper if item in (v.label, v.variant, v.scenario)]
            if not hits:
                names = sorted({v.label for v in self.paper} | {v.variant for v in self.paper}
                               | {v.scenario for v in self.paper if v.scenario})
                raise SearchError(f"--rows {item!r} names no row of table {self.name!r}; rows, variants and "
                                  f"scenarios are: {', '.join(names)}")
            keep += [v for v in hits if v not in keep]
        build = self.build_spec

        def build_rows(runs: int) -> dict:
            spec = build(runs)
            labels = [entry.label for entry in parse_spec({"name": self.name, **spec}).scenarios]
            pairs = sorted({(v.scenario or label, v.variant) for v in keep
                            for label in ([v.scenario] if v.scenario else labels)})
            return {**spec, "pairs": [list(p) for p in pairs]}

        return replace(self, build_spec=build_rows, paper=tuple(keep))


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
