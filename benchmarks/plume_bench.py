"""What the plume benchmark scripts share: a per-seed result cache, the parsing of
``--strategy`` and ``--world`` arguments, and the mean with its 95 % interval.

The cache gives each configuration key one file ``<sha1(key)[:16]>.jsonl`` under the
output folder; every finished seed is appended as one line and flushed, so an
interrupted run loses at most the line being written (a cut-off last line is skipped on
resume) and re-running skips the seeds already there.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np


def parse_strategy(text: str):
    """``name``, ``name:{json params}`` or ``label=name:{json params}`` ->
    ``(label, name, params)``."""
    label, _, rest = text.partition("=") if "=" in text.split(":")[0] else (None, "", text)
    name, _, js = rest.partition(":")
    params = json.loads(js) if js else {}
    return (label or (name if not params else f"{name}{json.dumps(params, sort_keys=True)}")), name, params


def parse_world(items) -> dict:
    """``["key=json", ...]`` -> world overrides (a start heading is in radians)."""
    return {k: json.loads(v) for k, v in (w.split("=", 1) for w in items)}


def mean_ci(x):
    """Mean and the half-width of its normal 95 % interval (nan below two values)."""
    x = np.asarray(x, dtype=float)
    if len(x) < 2:
        return (float(x.mean()) if len(x) else float("nan")), float("nan")
    return float(x.mean()), float(1.96 * x.std(ddof=1) / np.sqrt(len(x)))


def cached_seeds(out: Path, key, seeds, run_one, make_job, pool, *, chunksize: int = 2) -> list[dict]:
    """Results of `run_one(make_job(seed))` for every seed, from `out` where present.

    Parameters
    ----------
    out : Path
        Cache folder.
    key : JSON-serialisable
        What identifies the configuration (scenario, overrides, strategy, parameters).
    seeds : sequence of int
    run_one : callable
        Picklable worker ``job -> dict`` whose result holds ``"seed"``.
    make_job : callable
        ``seed -> job``.
    pool : multiprocessing.Pool

    Returns
    -------
    list of dict
        One result per seed, in the order of `seeds`.
    """
    f = Path(out) / (hashlib.sha1(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16] + ".jsonl")
    done = {}
    if f.exists():
        for line in f.read_text().splitlines():
            try:
                r = json.loads(line)
            except json.JSONDecodeError:      # cut off by an interruption: run it again
                continue
            done[r["seed"]] = r
    todo = [make_job(s) for s in seeds if s not in done]
    if todo:
        with f.open("a") as fh:
            for r in pool.imap_unordered(run_one, todo, chunksize=chunksize):
                done[r["seed"]] = r
                fh.write(json.dumps(r) + "\n")
                fh.flush()
    return [done[s] for s in seeds]
