"""Per-seed result cache shared by the plume benchmark scripts (JSON lines, resumable).

Each (configuration) key gets one file ``<sha1(key)[:16]>.jsonl`` under the output
folder; every finished seed is appended as one line and flushed, so an interrupted run
loses nothing and re-running skips the seeds already there.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path


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
            r = json.loads(line)
            done[r["seed"]] = r
    todo = [make_job(s) for s in seeds if s not in done]
    if todo:
        with f.open("a") as fh:
            for r in pool.imap_unordered(run_one, todo, chunksize=chunksize):
                done[r["seed"]] = r
                fh.write(json.dumps(r) + "\n")
                fh.flush()
    return [done[s] for s in seeds]
