"""A CSV of benchmark rows written as episodes finish, that a second run resumes; the
strategy parameters a script takes as ``--set KEY=VALUE``."""

from __future__ import annotations

import csv
import time
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
    """A ``csv.DictWriter`` appending to `out` (header written when the file is new); flush
    the file after each row with ``writer.file.flush()``."""
    out.parent.mkdir(parents=True, exist_ok=True)
    new = not out.exists()
    with out.open("a", newline="") as f:
        w = csv.DictWriter(f, fields)
        w.file = f
        if new:
            w.writeheader()
        yield w


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
