"""Validation of user-given values: one-line errors that name the key, the value and
what is allowed.

Every numeric key of a scenario, a platform option or a strategy parameter has bounds,
checked when it is parsed, before any meshing, solving or allocation: no input can make
the program allocate beyond a few GB or run for hours. The helpers here raise
:class:`~reciprocity.errors.SearchError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

import numpy as np

from .errors import SearchError

__all__ = ["Bound", "number", "whole", "positive", "point", "check_bounds", "starts_in_box", "MAX_COORD",
           "MAX_CELLS"]

#: Largest absolute coordinate of any world, in its length unit (cm for arenas).
MAX_COORD = 1e5
#: Most cells or nodes of any grid a world or a strategy builds (a float64 array of this
#: size is 32 MB; dense models keep a few such arrays).
MAX_CELLS = 4_000_000
#: Most observers of one episode (scenario files, campaign specs, the command line).
MAX_AGENTS = 64


def _fmt(x: float) -> str:
    return f"{x:g}" if isinstance(x, float) else str(x)


def number(value, key: str, lo: float = -math.inf, hi: float = math.inf, *, where: str = "",
           lo_open: bool = False, hi_open: bool = False, unit: str = "") -> float:
    """`value` as a finite float within ``[lo, hi]`` (``(lo`` / ``hi)`` when open).

    Parameters
    ----------
    value : object
        What the user gave.
    key : str
        Its name, as the user wrote it.
    lo, hi : float
        Bounds.
    where : str
        Context for the message (e.g. ``"scenario 'x': "``).
    lo_open, hi_open : bool
        Whether the bounds themselves are excluded.
    unit : str
        Unit named in the message.

    Raises
    ------
    SearchError
        Not a number (a bool, a string, a list...), not finite, or out of bounds.
    """
    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value))
    if ok:
        v = float(value)
        ok = (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        raise SearchError(f"{where}{key} must be a number in {'(' if lo_open else '['}{_fmt(lo)}, "
                          f"{_fmt(hi)}{')' if hi_open else ']'}{' ' + unit if unit else ''}; got {value!r}")
    return float(value)


def whole(value, key: str, lo: int, hi: int, *, where: str = "") -> int:
    """`value` as an int in ``[lo, hi]`` (a float with no fraction is accepted)."""
    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)) \
        and float(value) == int(value) and lo <= int(value) <= hi
    if not ok:
        raise SearchError(f"{where}{key} must be a whole number from {lo} to {hi}; got {value!r}")
    return int(value)


def positive(value, key: str, *, integer: bool = False, below_one: bool = False, none: bool = False):
    """`value` as a positive finite number (an int if `integer`; below 1 if `below_one`;
    None passes if `none`), else SearchError naming `key` and the value."""
    if value is None and none:
        return None
    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)) \
        and float(value) > 0 and (not integer or float(value).is_integer()) and (not below_one or value < 1)
    if not ok:
        kind = "positive whole number" if integer else "positive number"
        tail = " below 1" if below_one else " or null" if none else ""
        raise SearchError(f"{key} must be a {kind}{tail}; got {value!r}")
    return int(value) if integer else float(value)


def point(value, key: str, *, where: str = "", size: int = 2, bound: float = MAX_COORD) -> np.ndarray:
    """`value` as a finite point of `size` numbers, each within ``±bound``."""
    items = value if isinstance(value, (list, tuple, np.ndarray)) else None
    ok = items is not None and len(items) == size and all(
        isinstance(v, Real) and not isinstance(v, bool) and math.isfinite(float(v)) and abs(float(v)) <= bound
        for v in items)
    if not ok:
        names = ", ".join("xyz"[:size]) if size <= 3 else f"{size} numbers"
        raise SearchError(f"{where}{key} must be [{names}], numbers within ±{bound:g}; got {value!r}")
    return np.asarray(items, dtype=float)


@dataclass(frozen=True)
class Bound:
    """The allowed values of one parameter.

    Attributes
    ----------
    lo, hi : float
        Closed range of a numeric value.
    integer : bool
        A whole number.
    words : tuple of str
        Words accepted instead of a number (e.g. ``"arena"``).
    none : bool
        Whether None (YAML ``null``) is accepted.
    python : bool
        The value is a Python object (a solver, a space), set from Python only.
    unit : str
        Unit, for the message.
    lo_open, hi_open : bool
        Whether `lo` / `hi` themselves are excluded.
    """

    lo: float = -math.inf
    hi: float = math.inf
    integer: bool = False
    words: tuple = ()
    none: bool = False
    python: bool = False
    unit: str = ""
    lo_open: bool = False
    hi_open: bool = False

    def check(self, value, key: str, where: str = ""):
        """`value` if allowed; else SearchError naming `key`, the value and the range."""
        if value is None and (self.none or self.python):
            return value
        if self.python:
            if isinstance(value, (str, Real, list, dict)):
                raise SearchError(f"{where}{key} is a Python object (set it from Python, not from a file "
                                  f"or the command line); got {value!r}")
            return value
        if isinstance(value, str):
            if value in self.words:
                return value
            allowed = f"one of {', '.join(map(repr, self.words))} or " if self.words else ""
            kind = "a whole number" if self.integer else "a number"
            raise SearchError(f"{where}{key} must be {allowed}{kind} in {'(' if self.lo_open else '['}"
                              f"{_fmt(self.lo)}, {_fmt(self.hi)}{')' if self.hi_open else ']'}"
                              f"{' ' + self.unit if self.unit else ''}{' (or null for none)' if self.none else ''}"
                              f"; got {value!r}")
        if self.integer:
            return whole(value, key, int(self.lo), int(self.hi), where=where)
        return number(value, key, self.lo, self.hi, where=where, unit=self.unit,
                      lo_open=self.lo_open, hi_open=self.hi_open)


def check_bounds(params: dict, bounds: dict, where: str = "") -> None:
    """Check each of `params` that `bounds` (name -> :class:`Bound`) names."""
    for key, value in params.items():
        b = bounds.get(key)
        if b is not None:
            b.check(value, key, where)


def starts_in_box(starts: np.ndarray, box, name: str) -> None:
    """Refuse start poses (n, 3) outside the rectangle ``box = (x0, x1, y0, y1)``, called `name`."""
    x0, x1, y0, y1 = box
    for s in starts:
        if not (x0 <= s[0] <= x1 and y0 <= s[1] <= y1):
            raise SearchError(f"start ({s[0]:g}, {s[1]:g}) lies outside the {name} "
                              f"[{x0:g}, {x1:g}] × [{y0:g}, {y1:g}]; choose a point inside it")
