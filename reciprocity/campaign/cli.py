"""The ``campaign``, ``report`` and ``reproduce`` commands of the ``reciprocity`` CLI.

``reciprocity.cli.build_parser`` names them and calls :func:`declare` for the one chosen
(``run`` and ``--help`` never import this package); every handler returns the exit code
and raises :class:`reciprocity.errors.SearchError` on bad input (exit 2).
Numbers and addresses are checked when the command line is parsed, output folders and
the whole spec before any episode runs.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from arenas.files import check_output, real_folder

from ..errors import SearchError
from .cluster import TLSFiles, check_address, max_workers
from .spec import MAX_SEED, MAX_SEEDS

__all__ = ["declare"]


def _whole(text: str, lo: int, hi: int) -> int:
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"must be a whole number from {lo} to {hi}; got {text!r}")
    return value


def _rows(text: str) -> str:
    if not all(t.strip() for t in text.split(",")):
        raise argparse.ArgumentTypeError(f"must be row names separated by commas; got {text!r}")
    return text


def _workers(text: str) -> int:
    return _whole(text, 1, max_workers())


def _address(text: str) -> str:
    if text == "spec":
        return text
    try:
        return check_address(text)
    except SearchError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _where(p: argparse.ArgumentParser) -> None:
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=_workers, metavar="N",
                   help=f"local Dask worker processes, one thread each, 1 to {max_workers()} "
                   "(default: one per core)")
    g.add_argument("--scheduler", type=_address, metavar="ADDRESS",
                   help="address of a running Dask scheduler: tls://host:8786 with the --tls "
                   "files, or tcp://host:8786 on a trusted network only; 'spec' confirms the "
                   "scheduler the spec names (never used otherwise)")
    p.add_argument("--tls-ca-file", metavar="PEM", help="CA certificate of a tls:// scheduler")
    p.add_argument("--tls-cert", metavar="PEM", help="client certificate for a tls:// scheduler")
    p.add_argument("--tls-key", metavar="PEM", help="client private key for a tls:// scheduler")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _tls(args) -> TLSFiles | None:
    given = [args.tls_ca_file, args.tls_cert, args.tls_key]
    if not any(given):
        return None
    if not all(given):
        raise SearchError("give --tls-ca-file, --tls-cert and --tls-key together (PEM files of "
                          "the CA, the client certificate and its key)")
    return TLSFiles(*given)


def _progress(args) -> bool | None:
    return False if args.quiet else None


def _ran(result) -> str:
    return (f"{result.n_run} episodes run ({result.n_failed} failed), {result.n_skipped} already "
            f"in {result.directory}/, {result.wall_time_s:.1f} s; {_cache_line(result.cache_stats)}")


def _cache_line(stats: dict) -> str:
    if not stats:
        return "no workers started"
    hits = sum(h for per in stats.values() for h, _ in per.values())
    misses = sum(m for per in stats.values() for _, m in per.values())
    n = len(stats)
    return f"set-up caches on {n} worker{'' if n == 1 else 's'}: {hits} hits, {misses} misses"


def cmd_campaign(args) -> int:
    """``reciprocity campaign SPEC.yaml --out DIR``: run or resume a campaign."""
    from .execute import run_campaign
    from .report import build_report
    from .spec import load_spec
    check_output(args.out, "--out", folder=True, error=SearchError)
    spec = load_spec(args.spec, seed=args.seed)
    result = run_campaign(spec, args.out, workers=args.workers, scheduler=args.scheduler,
                          tls=_tls(args), progress=_progress(args))
    print(_ran(result))
    print(build_report(args.out).markdown(), end="")
    print(f"figures: reciprocity report {args.out}")
    return 0


def cmd_report(args) -> int:
    """``reciprocity report DIR [--out DIR]``: tables (stdout, Markdown, CSV) and figures."""
    from .report import build_report, write_report
    from .store import read_meta
    read_meta(args.dir)
    if args.out:
        out = check_output(args.out, "--out", folder=True, error=SearchError)
    else:   # inside the campaign folder: a real folder, never a link out of it
        out = real_folder(args.dir, "report", label=f"campaign folder {args.dir!r}", error=SearchError)
    report = build_report(args.dir)
    write_report(report, args.dir, out)
    print(report.markdown(), end="")
    print(f"report.md, CSV tables and figures are in {out}/")
    return 0


def cmd_reproduce(args) -> int:
    """``reciprocity reproduce TABLE`` / ``--list``: a paper table beside ours."""
    from .reproduce import TABLES, _table, comparison_markdown, reproduce
    if args.list:
        width = max(map(len, TABLES), default=0)
        for name, t in TABLES.items():
            extra = f" (--protocol {', '.join(t.protocols)})" if t.protocols else ""
            print(f"{name:<{width}}  {t.reference}: {t.title}{extra}")
        return 0
    if args.table is None:
        raise SearchError("name a table (reciprocity reproduce --list shows them)")
    _table(args.table).protocol(args.protocol).rows(args.rows)     # all checked before any output
    suffix = "" if args.protocol in (None, "default") else f"-{args.protocol}"
    if args.rows:      # a part of the table is a campaign of its own, in a folder of its own
        suffix += "-rows-" + re.sub(r"[^A-Za-z0-9_.-]+", "_", args.rows).strip("_")[:60]
    out = check_output(args.out or f"reproduce_{args.table}{suffix}", "--out", folder=True, error=SearchError)
    table, result, rows, files = reproduce(args.table, out, runs=args.runs, workers=args.workers,
                                           scheduler=args.scheduler, tls=_tls(args),
                                           progress=_progress(args), protocol=args.protocol, rows=args.rows)
    print(_ran(result))
    text = comparison_markdown(table, rows)
    (Path(out) / "comparison.md").write_text(text)
    print(text, end="")
    if files:
        print(f"figures: {', '.join(str(f) for f in files)}")
    if table.protocols or args.protocol not in (None, "default"):
        _print_protocols(args.table, Path(out), args.protocol, args.rows)
    return 0


def _print_protocols(name: str, out: Path, protocol: str | None, rows: str | None) -> None:
    """After a table's run, every protocol of it whose results lie beside `out` (in the
    default folders ``reproduce_TABLE`` and ``reproduce_TABLE-PROTOCOL`` of the same parent
    folder), side by side with verdicts, when there are at least two."""
    from .reproduce import _table, compare, protocols_markdown
    base = _table(name)
    columns = []
    for p in ("default", *base.protocols):
        folder = out if p == (protocol or "default") else \
            out.parent / (f"reproduce_{name}" + ("" if p == "default" else f"-{p}"))
        if not (folder / "campaign.json").exists():
            continue
        table = base.protocol(p).rows(rows)
        got = compare(table, folder)
        if any(r["runs"] for r in got):
            columns.append((p, got))
    if len(columns) > 1:
        text = protocols_markdown(base.rows(rows), columns)
        (out / "protocols.md").write_text(text)
        print("\n" + text, end="")


def declare(name: str, p: argparse.ArgumentParser) -> None:
    """Declare the arguments of command `name` on its parser.

    ``reciprocity.cli.build_parser`` adds the three commands by name and calls this only
    when one of them is chosen (or its help is asked for), so that ``run`` and ``--help``
    never import the campaign layer.

    Parameters
    ----------
    name : str
        ``"campaign"``, ``"report"`` or ``"reproduce"``.
    p : argparse.ArgumentParser
        The command's sub-parser.
    """
    {"campaign": _campaign, "report": _report, "reproduce": _reproduce}[name](p)


def _campaign(c: argparse.ArgumentParser) -> None:
    c.add_argument("spec", metavar="SPEC.yaml", help="campaign spec (see reciprocity.campaign.spec)")
    c.add_argument("--out", required=True, metavar="DIR", help="results folder")
    c.add_argument("--seed", type=lambda t: _whole(t, 0, MAX_SEED), metavar="N",
                   help="campaign seed (overrides the spec's)")
    _where(c)
    c.set_defaults(func=cmd_campaign)


def _report(r: argparse.ArgumentParser) -> None:
    r.add_argument("dir", metavar="DIR", help="campaign results folder")
    r.add_argument("--out", metavar="DIR", help="output folder (default DIR/report)")
    r.set_defaults(func=cmd_report)


def _reproduce(p: argparse.ArgumentParser) -> None:
    p.add_argument("table", nargs="?", metavar="TABLE", help="table name (see --list)")
    p.add_argument("--list", action="store_true", help="list the reproducible tables")
    p.add_argument("--runs", type=lambda t: _whole(t, 1, MAX_SEEDS), metavar="N",
                   help=f"runs per strategy, 1 to {MAX_SEEDS} (default: the table's)")
    p.add_argument("--out", metavar="DIR", help="results folder (default reproduce_TABLE, or "
                   "reproduce_TABLE-PROTOCOL)")
    p.add_argument("--rows", type=_rows, metavar="ROW[,ROW...]",
                   help="run only these rows of the table, each named by its row label, strategy "
                   "variant or scenario (song-100: the 100² rows of song2019-table1); the same "
                   "episodes as the whole table's")
    p.add_argument("--protocol", metavar="NAME", help="run the table under another protocol the table "
                   "offers (e.g. 'paper': the paper's own set-up; --list names them)")
    _where(p)
    p.set_defaults(func=cmd_reproduce)
