"""The results of a campaign on disk: Parquet files under one folder.

Layout of ``DIR``::

    campaign.json                         name, spec hash and normalized spec
    scenario=<label>/strategy=<name>/part-<id>.parquet   one file per written batch

Each row is one finished episode: the columns of :data:`CONTRACT_SCHEMA` (always present,
fixed types; null where an episode did not report a key) followed by any further summary
keys (scalars and lists of numbers as such, anything else as a JSON string). A batch is
written to a hidden temporary name and renamed with :func:`os.replace`, so a file is
either complete or absent, whenever the driver is killed. Query the files directly with
DuckDB::

    SELECT strategy, avg(success::int) FROM read_parquet('DIR/**/*.parquet',
        union_by_name=true, hive_partitioning=false) GROUP BY strategy
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import uuid
from collections.abc import Iterable
from pathlib import Path

import duckdb
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ..errors import SearchError
from .spec import CampaignSpec

__all__ = ["CONTRACT_SCHEMA", "ResultStore", "rows_to_table", "episodes_sql", "connect"]

_F64_LIST = pa.list_(pa.float64())

#: Columns every results file has, in this order: the campaign's own, then the episode
#: summary keys of the public contract. ``source_reachable`` (whether the true source is
#: reachable by the platform) stays null until the framework reports it.
CONTRACT_SCHEMA = pa.schema([
    ("campaign", pa.string()), ("episode_id", pa.string()), ("scenario", pa.string()),
    ("variant", pa.string()), ("seed_index", pa.int64()),
    ("strategy", pa.string()), ("arena", pa.string()), ("world", pa.string()),
    ("seed", pa.int64()), ("source", _F64_LIST), ("estimate", _F64_LIST),
    ("error", pa.float64()), ("n_measurements", pa.int64()), ("n_samples", pa.int64()),
    ("steps", pa.int64()), ("path_length", pa.float64()), ("converged", pa.bool_()),
    ("success", pa.bool_()), ("stop_reason", pa.string()), ("region_area", pa.float64()),
    ("sim_time_s", pa.float64()), ("wall_time_s", pa.float64()), ("n_agents", pa.int64()),
    ("messages", pa.int64()), ("source_reachable", pa.bool_()), ("error_message", pa.string()),
])

_META = "campaign.json"
_LOCK = ".lock"


def episodes_sql(directory) -> str:
    """The DuckDB table expression over all results files of `directory`.

    Parameters
    ----------
    directory : path-like
        A campaign folder.

    Returns
    -------
    str
        ``read_parquet('DIR/**/*.parquet', union_by_name=true, hive_partitioning=false)``
        (the partition values are also columns of the files).
    """
    glob = str(Path(directory) / "**" / "*.parquet").replace("'", "''")
    return f"read_parquet('{glob}', union_by_name=true, hive_partitioning=false)"


def connect(directory) -> duckdb.DuckDBPyConnection:
    """An in-memory DuckDB connection with a view ``episodes`` over `directory`'s results.

    Parameters
    ----------
    directory : path-like
        A campaign folder holding at least one results file.

    Returns
    -------
    duckdb.DuckDBPyConnection

    Raises
    ------
    SearchError
        No results files in `directory`.
    """
    d = Path(directory)
    if not d.is_dir() or not any(d.glob("**/*.parquet")):
        raise SearchError(f"no campaign results (*.parquet) under {str(d)!r}; run "
                          "'reciprocity campaign SPEC.yaml --out DIR' first")
    con = duckdb.connect()
    con.execute(f"CREATE VIEW episodes AS SELECT * FROM {episodes_sql(d)}")
    return con


def _python(v):
    """Plain Python value of a summary entry (numpy scalars and arrays unwrapped)."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, tuple):
        return list(v)
    return v


def _json(v) -> str:
    def default(x):
        if isinstance(x, (np.ndarray, np.generic)):
            return _python(x)
        return str(x)
    return json.dumps(v, default=default, sort_keys=True)


def _coerce(v, typ: pa.DataType):
    v = _python(v)
    if v is None:
        return None
    if typ == _F64_LIST:
        return [float(x) for x in v]
    if pa.types.is_boolean(typ):
        return bool(v)
    if pa.types.is_integer(typ):
        return int(round(v))
    if pa.types.is_floating(typ):
        return float(v)
    return v if isinstance(v, str) else _json(v)


def _is_number_list(v) -> bool:
    return isinstance(v, list) and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)


def _extra_type(values: list) -> pa.DataType:
    if all(isinstance(v, bool) for v in values):
        return pa.bool_()
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return pa.int64()
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return pa.float64()
    if all(isinstance(v, str) for v in values):
        return pa.string()
    if all(_is_number_list(v) for v in values):
        return _F64_LIST
    return pa.string()


def rows_to_table(rows: list[dict]) -> pa.Table:
    """An Arrow table of result rows with the contract columns first.

    Parameters
    ----------
    rows : list of dict
        Rows from :func:`reciprocity.campaign.worker.run_task`.

    Returns
    -------
    pyarrow.Table
        :data:`CONTRACT_SCHEMA` (null where a row lacks a key), then the other keys in
        sorted order: booleans, integers, floats, strings and lists of numbers keep
        their type; nested or mixed values become JSON strings; keys that are None in
        every row are left out (they read back as null).
    """
    columns, fields = [], []
    for f in CONTRACT_SCHEMA:
        columns.append(pa.array([_coerce(r.get(f.name), f.type) for r in rows], type=f.type))
        fields.append(f)
    extras = sorted({k for r in rows for k in r} - set(CONTRACT_SCHEMA.names))
    for key in extras:
        raw = [_python(r.get(key)) for r in rows]
        present = [v for v in raw if v is not None]
        if not present:
            continue
        typ = _extra_type(present)
        columns.append(pa.array([_coerce(v, typ) for v in raw], type=typ))
        fields.append(pa.field(key, typ))
    return pa.Table.from_arrays(columns, schema=pa.schema(fields))


class ResultStore:
    """A campaign folder opened for writing (one driver at a time).

    Use :meth:`open`; close it (or use it as a context manager) to release the lock.

    Parameters
    ----------
    directory : Path
        The campaign folder.
    lock : file object
        The open, ``flock``-ed lock file.
    """

    def __init__(self, directory: Path, lock):
        self.directory = directory
        self._lock = lock

    @classmethod
    def open(cls, directory, spec: CampaignSpec) -> ResultStore:
        """Create or reopen the folder of `spec`'s campaign.

        Parameters
        ----------
        directory : path-like
            Results folder (created if missing).
        spec : CampaignSpec
            The campaign; its hash is stored on first use and must match afterwards.

        Returns
        -------
        ResultStore

        Raises
        ------
        SearchError
            The folder cannot be created or written, holds results of a different spec,
            or another driver is writing to it.
        """
        d = Path(directory)
        try:
            d.mkdir(parents=True, exist_ok=True)
            lock = open(d / _LOCK, "a")
        except OSError as exc:
            raise SearchError(f"cannot write campaign results to {str(d)!r}: "
                              f"{exc.strerror}; choose another --out") from None
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            lock.close()
            raise SearchError(f"another campaign driver is writing to {str(d)!r}; wait for it "
                              "to finish or choose another --out") from None
        store = cls(d, lock)
        try:
            store._check_spec(spec)
            store._remove_partial_files()
        except BaseException:
            store.close()
            raise
        return store

    def _check_spec(self, spec: CampaignSpec) -> None:
        meta = self.directory / _META
        if meta.exists():
            old = json.loads(meta.read_text())
            if old.get("spec_hash") != spec.digest:
                raise SearchError(
                    f"{str(self.directory)!r} holds campaign {old.get('name')!r} made with a "
                    f"different spec (hash {old.get('spec_hash', '?')[:12]} vs "
                    f"{spec.digest[:12]}); use another --out, or the spec (and --seed) that "
                    "made it")
            seeds = max(int(old.get("seeds", 0)), spec.seeds)
        elif any(self.directory.glob("**/*.parquet")):
            raise SearchError(f"{str(self.directory)!r} holds Parquet files but no {_META}: not "
                              "a campaign folder; choose another --out")
        else:
            seeds = spec.seeds
        text = json.dumps(dict(name=spec.name, spec_hash=spec.digest, seeds=seeds,
                               spec=spec.source), indent=1)
        self._atomic_write(meta, text.encode())

    def _remove_partial_files(self) -> None:
        # temporary files of a driver killed while writing; their episodes are re-run
        for tmp in self.directory.glob("**/.*.tmp"):
            tmp.unlink()

    def _atomic_write(self, path: Path, data: bytes) -> None:
        tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
        try:
            with open(tmp, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except OSError as exc:
            with contextlib.suppress(OSError):
                tmp.unlink()
            raise SearchError(f"cannot write {str(path)!r}: {exc.strerror}") from None

    def finished_ids(self) -> set[str]:
        """Episode ids already stored (finished or failed), read back from the files.

        Returns
        -------
        set of str
        """
        if not any(self.directory.glob("**/*.parquet")):
            return set()
        con = duckdb.connect()
        rows = con.execute(f"SELECT DISTINCT episode_id FROM {episodes_sql(self.directory)}")
        return {r[0] for r in rows.fetchall()}

    def write(self, rows: Iterable[dict]) -> list[Path]:
        """Store a batch of rows: one new file per (scenario, strategy) partition.

        Parameters
        ----------
        rows : iterable of dict
            Result rows.

        Returns
        -------
        list of Path
            The files written.
        """
        parts: dict[tuple[str, str], list[dict]] = {}
        for r in rows:
            parts.setdefault((r["scenario"], r["strategy"]), []).append(r)
        written = []
        for (scenario, strategy), part in parts.items():
            folder = self.directory / f"scenario={scenario}" / f"strategy={strategy}"
            folder.mkdir(parents=True, exist_ok=True)
            name = f"part-{uuid.uuid4().hex[:16]}.parquet"
            sink = pa.BufferOutputStream()
            pq.write_table(rows_to_table(part), sink, compression="zstd")
            self._atomic_write(folder / name, sink.getvalue().to_pybytes())
            written.append(folder / name)
        return written

    def close(self) -> None:
        """Release the folder's lock."""
        if not self._lock.closed:
            fcntl.flock(self._lock, fcntl.LOCK_UN)
            self._lock.close()

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
