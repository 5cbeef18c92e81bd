"""The results of a campaign on disk: Parquet files under one folder.

Layout of ``DIR``::

    campaign.json                         name, spec hash and normalized spec
    scenario=<label>/strategy=<name>/part-<id>.parquet   one file per written batch

Each row is one finished episode: the columns of :data:`CONTRACT_SCHEMA` (always present,
fixed types; null where an episode did not report a key) followed by any further summary
keys (scalars and lists of numbers as such, anything else as a JSON string). A batch is
written to a hidden temporary name and renamed with :func:`os.replace`, so a file is
either complete or absent, whenever the driver is killed.

Readers (the report, resuming) read only the campaign's own files: ``campaign.json``
and the ``part-*.parquet`` files of the partitions it names (:func:`result_files`),
never a recursive search of a user's folder. Query them with :func:`connect`, or
directly with DuckDB::

    SELECT strategy, avg(success::int) FROM read_parquet(
        'DIR/scenario=*/strategy=*/part-*.parquet', union_by_name=true,
        hive_partitioning=false) GROUP BY strategy
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import re
import uuid
from collections.abc import Iterable
from pathlib import Path

import duckdb
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from arenas.files import read_text, real_folder

from ..errors import SearchError
from .spec import LABEL, CampaignSpec

__all__ = ["CONTRACT_SCHEMA", "DamagedResultsWarning", "ResultStore", "rows_to_table", "episodes_sql", "connect",
           "read_meta", "result_files", "MAX_META_BYTES"]

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
_PART = re.compile(r"^part-[0-9a-f]{16}\.parquet$")
#: Temporary files of :meth:`ResultStore._atomic_write`: the only files a clean-up removes.
_TMP = re.compile(r"^\.(?:part-[0-9a-f]{16}\.parquet|campaign\.json)\.[0-9a-f]{8}\.tmp$")
#: Largest ``campaign.json`` read, bytes (the normalized spec of the largest grids).
MAX_META_BYTES = 32_000_000


def read_meta(directory) -> dict:
    """The ``campaign.json`` of the campaign folder `directory`, checked.

    Parameters
    ----------
    directory : path-like
        A campaign folder.

    Returns
    -------
    dict
        ``name``, ``spec_hash``, ``seeds`` and ``spec`` (the normalized spec).

    Raises
    ------
    SearchError
        `directory` is not a folder, has no ``campaign.json``, or the file is not one
        that :class:`ResultStore` wrote.
    """
    d = Path(directory)
    if not d.is_dir():
        raise SearchError(f"campaign folder {str(d)!r} does not exist or is not a folder; give "
                          "the --out folder of 'reciprocity campaign'")
    if not (d / _META).is_file():
        raise SearchError(f"{str(d)!r} is not a campaign folder: it has no {_META}; give the "
                          "--out folder of 'reciprocity campaign'")
    meta = _load_meta(d)
    try:
        spec = meta["spec"]
        labels = [s["label"] for s in spec["scenarios"]]
        names = [v["strategy"] for v in spec["strategies"].values()]
    except (ValueError, KeyError, TypeError, AttributeError):
        raise SearchError(f"{_META} of {str(d)!r} is damaged: not the file a campaign wrote; "
                          "re-run the campaign into a new folder") from None
    bad = [x for x in labels + names if not isinstance(x, str) or not LABEL.match(x)]
    if bad:
        raise SearchError(f"{_META} of {str(d)!r} names partition {bad[0]!r}, not a label; "
                          "re-run the campaign into a new folder")
    return meta


def _refuse_foreign_folder(directory: Path) -> None:
    """A folder with things in it but no campaign.json is someone else's: never write there
    (only its top level is listed)."""
    if not (directory / _META).exists() and any(
            e.name != _LOCK for e in os.scandir(directory)):
        raise SearchError(f"{str(directory)!r} holds other files and no {_META}: not a "
                          "campaign folder; give a new or empty folder for --out")


def _load_meta(directory: Path) -> dict:
    text = read_text(directory / _META, f"{_META} of {str(directory)!r}", error=SearchError,
                     max_bytes=MAX_META_BYTES)
    try:
        meta = json.loads(text)
    except ValueError:
        meta = None
    if not isinstance(meta, dict):
        raise SearchError(f"{_META} of {str(directory)!r} is damaged: not the file a campaign "
                          "wrote; re-run the campaign into a new folder")
    return meta


def _partitions(directory: Path, spec: dict) -> list[Path]:
    """The partition folders a campaign with normalized spec `spec` writes."""
    strategies = dict.fromkeys(v["strategy"] for v in spec["strategies"].values())
    return [directory / f"scenario={s['label']}" / f"strategy={name}"
            for s in spec["scenarios"] for name in strategies]


def result_files(directory) -> list[Path]:
    """The results files of the campaign in `directory`, and nothing else.

    Only the ``part-*.parquet`` regular files of the partition folders that its
    ``campaign.json`` names are listed: no recursive search, no symbolic links.

    Parameters
    ----------
    directory : path-like
        A campaign folder.

    Returns
    -------
    list of Path
        Sorted; empty before the first batch is written.

    Raises
    ------
    SearchError
        Not a campaign folder (see :func:`read_meta`).
    """
    d = Path(directory)
    files = []
    for folder in _partitions(d, read_meta(d)["spec"]):
        _refuse_link(d, folder)
        try:
            entries = list(os.scandir(folder))
        except (FileNotFoundError, NotADirectoryError):
            continue
        except OSError as exc:
            raise SearchError(f"cannot read campaign results in {str(folder)!r}: "
                              f"{exc.strerror}") from None
        files += [Path(e.path) for e in entries
                  if _PART.match(e.name) and e.is_file(follow_symlinks=False) and _sound(d, Path(e.path))]
    return sorted(files)


class DamagedResultsWarning(UserWarning):
    """A results file of a campaign could not be read: it was quarantined, its episodes
    are run again on resume."""


def _sound(directory: Path, path: Path) -> bool:
    """Whether the results file `path` reads as a Parquet file with the contract's columns
    and types; a damaged one is moved into ``DIR/quarantine/`` with a warning naming it."""
    import warnings
    try:
        schema = pq.read_schema(path)
        wrong = [f.name for f in CONTRACT_SCHEMA if schema.field(f.name).type != f.type] \
            if set(CONTRACT_SCHEMA.names) <= set(schema.names) else ["(columns missing)"]
        if wrong:
            reason = f"columns of the wrong type: {', '.join(wrong)}"
        elif pq.read_metadata(path).num_rows < 1:
            reason = "no rows"
        else:
            return True
    except Exception as exc:                  # empty, truncated, not Parquet
        reason = f"unreadable ({type(exc).__name__}: {' '.join(str(exc).split())[:120]})"
    dest = None
    with contextlib.suppress(OSError, SearchError):
        folder = real_folder(directory, "quarantine", path.parent.parent.name, path.parent.name,
                             label=f"campaign folder {str(directory)!r}", error=SearchError)
        dest = folder / path.name
        os.replace(path, dest)
    warnings.warn(f"results file {str(path)!r} is damaged ({reason}); "
                  f"{'moved to ' + repr(str(dest)) if dest else 'left out'}; its episodes are run again when "
                  "the campaign resumes", DamagedResultsWarning, stacklevel=3)
    return False


def _refuse_link(directory: Path, folder: Path) -> None:
    """SearchError if `folder` (a partition of `directory`) or its parent is a symbolic link."""
    for path in (folder.parent, folder):
        if path.is_symlink():
            raise SearchError(f"{str(path)!r} in campaign folder {str(directory)!r} is a symbolic link; results "
                              "are read from and written to real folders inside the campaign folder only "
                              "(remove the link)")


def episodes_sql(directory) -> str:
    """The DuckDB table expression over the results files of the campaign in `directory`.

    Parameters
    ----------
    directory : path-like
        A campaign folder.

    Returns
    -------
    str
        ``read_parquet([...files...], union_by_name=true, hive_partitioning=false)``
        over :func:`result_files` (the partition values are also columns of the files).

    Raises
    ------
    SearchError
        Not a campaign folder, or no results in it yet.
    """
    files = result_files(directory)
    if not files:
        raise SearchError(f"no campaign results in {str(directory)!r} yet; run 'reciprocity "
                          "campaign SPEC.yaml --out DIR' first")
    listed = ", ".join("'" + str(f).replace("'", "''") + "'" for f in files)
    return f"read_parquet([{listed}], union_by_name=true, hive_partitioning=false)"


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
        Not a campaign folder, or no results in it yet.
    """
    con = duckdb.connect()
    con.execute(f"CREATE VIEW episodes AS SELECT * FROM {episodes_sql(directory)}")
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
            _refuse_foreign_folder(d)
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
            store._remove_partial_files(spec)
        except BaseException:
            store.close()
            raise
        return store

    def _check_spec(self, spec: CampaignSpec) -> None:
        meta = self.directory / _META
        if meta.exists():
            old = _load_meta(self.directory)
            if old.get("spec_hash") != spec.digest:
                raise SearchError(
                    f"{str(self.directory)!r} holds campaign {old.get('name')!r} made with a "
                    f"different spec (hash {str(old.get('spec_hash', '?'))[:12]} vs "
                    f"{spec.digest[:12]}); use another --out, or the spec (and --seed) that "
                    "made it")
            seeds = max(old.get("seeds", 0), spec.seeds)   # same hash: a file we wrote
        else:
            seeds = spec.seeds
        text = json.dumps(dict(name=spec.name, spec_hash=spec.digest, seeds=seeds,
                               spec=spec.source), indent=1)
        self._atomic_write(meta, text.encode())

    def _remove_partial_files(self, spec: CampaignSpec) -> None:
        # temporary files of a driver killed while writing (their episodes are re-run):
        # only files named as this class names them, in real folders of the campaign
        for folder in [self.directory, *_partitions(self.directory, spec.source)]:
            if folder != self.directory:
                _refuse_link(self.directory, folder)
            try:
                entries = list(os.scandir(folder))
            except (FileNotFoundError, NotADirectoryError):
                continue
            for e in entries:
                if _TMP.match(e.name) and e.is_file(follow_symlinks=False):
                    with contextlib.suppress(OSError):
                        os.unlink(e.path)

    def _atomic_write(self, path: Path, data: bytes) -> None:
        tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
        try:
            with open(tmp, "xb") as fh:
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
        if not result_files(self.directory):
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
            folder = real_folder(self.directory, f"scenario={scenario}", f"strategy={strategy}",
                                 label=f"campaign folder {str(self.directory)!r}", error=SearchError)
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
