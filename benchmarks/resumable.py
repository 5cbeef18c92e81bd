"""A CSV of benchmark rows written as episodes finish, that a second run resumes
(:func:`resume` runs what it lacks and reads it back); the strategy parameters a script
takes as ``--set KEY=VALUE``."""

from __future__ import annotations

import csv
import io
import time
from collections.abc import Callable, Hashable
from contextlib import contextmanager
from pathlib import Path


def done_keys(out: Path, key) -> set:
    """``key(row)`` of every row already in `out` (empty if it does not exist)."""
    if not out.exists():
        return set()
    with out.open() as f:
        return {key(r) for r in csv.DictReader(f)}


@contextmanager
def appending(out: Path, fields: list[str]):
    """A ``csv.DictWriter`` appending to `out` (header written when the file is new or empty); flush
    the file after each row with ``writer.file.flush()``."""
    out.parent.mkdir(parents=True, exist_ok=True)
    new = not out.exists() or out.stat().st_size == 0
    with out.open("a", newline="") as f:
        w = csv.DictWriter(f, fields)
        w.file = f
        if new:
            w.writeheader()
            f.flush()
        yield w


def append_rows(writer, rows: list[dict]) -> None:
    """Append `rows` (one episode's, say) to the file of :func:`appending`'s `writer` in
    one write and flush it, so that an interruption between episodes leaves none of the
    next one's rows (one inside the write may cut the last row, which
    ``arguments.Parser.resumable_csv`` refuses)."""
    buf = io.StringIO(newline="")
    csv.DictWriter(buf, writer.fieldnames).writerows(rows)
    writer.file.write(buf.getvalue())
    writer.file.flush()


def read_rows(out: Path, types: dict) -> list[dict]:
    """The rows of `out`, each column read by ``types[column]`` (e.g. ``int``,
    :func:`truth`)."""
    with out.open(newline="") as f:
        return [{k: types[k](v) for k, v in r.items()} for r in csv.DictReader(f)]


def truth(text: str) -> bool:
    """A ``True``/``False`` cell of a CSV written by :func:`appending`."""
    return text == "True"


def resume(out: Path, types: dict[str, Callable[[str], object]], keys: list[Hashable],
           key: Callable[[dict], Hashable], rows_of: Callable[[Hashable], list[dict]],
           minutes: float | None = None, mapper: Callable = map) -> list[dict]:
    """Append to `out` the rows of every run of `keys` not yet there, in order, until
    `minutes` have passed; then the rows of `out` of all the runs of `keys`.

    Parameters
    ----------
    out : Path
        The CSV (see :func:`appending`).
    types : dict
        Its columns, in order, each with how a cell is read back (see :func:`read_rows`).
    keys : list
        What identifies a run (hashable), in the order to run them.
    key : callable
        ``key(row)``: the key of a row read back by `types`.
    rows_of : callable
        ``rows_of(k)``: the rows of the run `k`, appended in one write.
    minutes : float or None
        Start no new run after this many minutes (None: no limit); with a pool's `mapper`,
        take no more results (the runs under way are lost with the pool).
    mapper : callable
        ``mapper(rows_of, keys)`` yields the rows of each run in the order of `keys`:
        ``map``, or a pool's ``imap`` to run them in parallel (`rows_of` then picklable).

    Returns
    -------
    list of dict
        The rows of `out` whose key is among `keys`, read by `types`, in the file's order.
    """
    done = {key(r) for r in read_rows(out, types)} if out.exists() else set()
    todo = [k for k in keys if k not in done]
    expired = deadline(minutes)
    with appending(out, list(types)) as w:
        for i, rows in enumerate(mapper(rows_of, todo)):
            append_rows(w, rows)
            if expired() and i + 1 < len(todo):
                print(f"stopped after {minutes:g} min with {len(todo) - i - 1} runs left; rerun with the same "
                      "output to resume", flush=True)
                break
    asked = set(keys)
    return [r for r in read_rows(out, types) if key(r) in asked]


def deadline(minutes: float | None):
    """``expired()``: whether `minutes` have passed since this call (never, for None)."""
    end = None if minutes is None else time.monotonic() + 60 * minutes
    return lambda: end is not None and time.monotonic() > end


def strategy_sets(items: list[str]) -> dict:
    """``--set KEY=VALUE`` options as strategy parameters (each value read as YAML).

    Raises
    ------
    ValueError
        An item without ``=`` or without a key (the message names it).
    """
    import yaml
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise ValueError(f"--set {item!r}: give KEY=VALUE")
        out[key] = yaml.safe_load(value)
    return out
