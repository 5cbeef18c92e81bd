"""Command-line arguments of the benchmark scripts, checked at the door.

A usage error is one ``error:`` line on stderr naming the option, the value and what is
allowed, and exit status 2, before any work (as the ``reciprocity`` console script does).
The ``type=`` checkers here (:func:`whole`, :func:`number`, :func:`among`, :func:`listed`)
refuse a bad value while the command line is parsed; :meth:`Parser.parse_resumable` adds
``--minutes`` and ``--out`` to a script whose runs append to a CSV and checks that folder
and that CSV (:meth:`Parser.output_folder`, :meth:`Parser.resumable_csv`) after it.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import stat
from collections.abc import Callable, Iterable
from pathlib import Path


class Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr and exit status 2."""

    @classmethod
    def of(cls, script: str, doc: str) -> "Parser":
        """The parser of the script at path `script` (its ``__file__``), described by the
        first line of its docstring `doc`."""
        return cls(prog=Path(script).name, description=doc.splitlines()[0])

    def error(self, message: str):
        self.exit(2, f"error: {message} (see `{self.prog} --help`)\n")

    def parse_resumable(self, argv: list[str] | None, out: str, csv_name: str, columns: Iterable[str],
                        holds: str = "") -> argparse.Namespace:
        """Add ``--minutes`` and ``--out``, parse `argv` and check the outputs.

        Parameters
        ----------
        argv : list of str or None
            The command line (None: ``sys.argv``).
        out : str
            The default output folder.
        csv_name : str
            The CSV in it that runs append to (see :meth:`resumable_csv`).
        columns : iterable of str
            Its columns, in order.
        holds : str
            What else the folder holds, for the help (e.g. ``", fig5.png"``).

        Returns
        -------
        argparse.Namespace
            With ``out`` the folder (a Path) and ``csv`` the CSV's path.
        """
        self.add_argument("--minutes", type=number(0, low_open=True), default=None,
                          help="start no new run after this many minutes (a rerun resumes)")
        self.add_argument("--out", default=out,
                          help=f"folder for {csv_name} (appended to: a rerun resumes){holds}")
        args = self.parse_args(argv)
        args.out = self.output_folder(args.out)
        args.csv = self.resumable_csv(args.out / csv_name, columns)
        return args

    def output_folder(self, path: str | Path, label: str = "--out") -> Path:
        """`path` as a folder that can be made and written (nothing is created yet).

        Parameters
        ----------
        path : str or Path
            The output folder.
        label : str
            The option that gave it.

        Returns
        -------
        Path
        """
        from arenas.files import ArenaError, check_output
        try:
            return check_output(path, label, folder=True)
        except ArenaError as exc:
            self.error(str(exc))

    def output_file(self, path: Path, label: str = "--out") -> Path:
        """`path`, a file written whole at the end (replaced, never written through a link),
        checked not to be a folder.

        Parameters
        ----------
        path : Path
            The file, inside an output folder checked by :meth:`output_folder`.
        label : str
            The option that named its folder.

        Returns
        -------
        Path
        """
        if path.is_dir():
            self.error(f"{label}: {str(path)!r} is a folder; remove it, or give another folder")
        return path

    def resumable_csv(self, path: Path, columns: Iterable[str], label: str = "--out") -> Path:
        """`path`, a CSV a run appends to: new, or a real file with these `columns` whose
        last row is whole (so that a rerun resumes it and appends nothing elsewhere).

        Parameters
        ----------
        path : Path
            The CSV, inside an output folder checked by :meth:`output_folder`.
        columns : iterable of str
            The columns the script writes, in order.
        label : str
            The option that named its folder.

        Returns
        -------
        Path
        """
        try:
            mode = path.lstat().st_mode
        except FileNotFoundError:
            return path
        if stat.S_ISLNK(mode) or not stat.S_ISREG(mode):
            what = "a symbolic link" if stat.S_ISLNK(mode) else "not a file"
            self.error(f"{label}: {str(path)!r} is {what}; the results are appended to a real file "
                       "(remove it, or give another folder)")
        if not os.access(path, os.R_OK | os.W_OK):
            self.error(f"{label}: {str(path)!r} cannot be read and appended to; give another folder")
        if path.stat().st_size == 0:                 # made, then cut before its header
            return path
        try:
            with path.open(newline="") as f:
                header = next(csv.reader(f), [])
            with path.open("rb") as f:
                f.seek(-1, 2)
                last = f.read(1)
        except (OSError, UnicodeDecodeError, csv.Error) as exc:
            self.error(f"{label}: {str(path)!r} cannot be read as a CSV ({exc}); give another folder")
        if header != list(columns):
            self.error(f"{label}: {str(path)!r} has the columns {header}, not this script's {list(columns)}; "
                       "give another folder to start afresh")
        if last != b"\n":
            self.error(f"{label}: {str(path)!r} ends in a cut-off row (an interrupted write); "
                       "delete its last line, then rerun to resume")
        return path


def whole(low: int = 1, high: int | None = None) -> Callable[[str], int]:
    """A ``type=`` checker: a whole number from `low` to `high` (None: no upper bound)."""
    def check(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < low or (high is not None and value > high):
            allowed = f"≥ {low}" if high is None else f"from {low} to {high}"
            raise argparse.ArgumentTypeError(f"{text!r}: give a whole number {allowed}")
        return value
    return check


def number(low: float = -math.inf, *, low_open: bool = False) -> Callable[[str], float]:
    """A ``type=`` checker: a finite number above `low` (or at least it, unless `low_open`)."""
    def check(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value) or value < low or (low_open and value == low):
            bound = "" if low == -math.inf else f" {'>' if low_open else '≥'} {low:g}"
            raise argparse.ArgumentTypeError(f"{text!r}: give a finite number{bound}")
        return value
    return check


def among(allowed: Iterable, cast: Callable[[str], object] = str) -> Callable[[str], object]:
    """A ``type=`` checker: one of `allowed`, read by `cast` (e.g. ``int``)."""
    allowed = tuple(allowed)

    def check(text: str):
        try:
            value = cast(text)
        except ValueError:
            value = None
        if value not in allowed:
            raise argparse.ArgumentTypeError(f"{text!r} is not one of: {', '.join(map(str, allowed))}")
        return value
    return check


def listed(check: Callable[[str], object]) -> Callable[[str], list]:
    """A ``type=`` checker: a comma-separated list, each item checked by `check` (one of
    this module's checkers), repeats dropped."""
    def check_all(text: str) -> list:
        out = []
        for item in text.split(","):
            try:
                out.append(check(item.strip()))
            except argparse.ArgumentTypeError as exc:
                where = f" (in {text!r})" if "," in text else ""
                raise argparse.ArgumentTypeError(f"{exc}{where}") from None
        return list(dict.fromkeys(out))
    return check_all
