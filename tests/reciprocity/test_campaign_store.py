"""Campaign results on disk: schema, atomic batches, resume set, spec hash, lock."""

import json

import duckdb
import numpy as np
import pytest

from reciprocity.campaign import CONTRACT_SCHEMA, ResultStore, parse_spec
from reciprocity.campaign.store import episodes_sql, rows_to_table
from reciprocity.campaign.worker import run_task
from reciprocity.errors import SearchError

SPEC = parse_spec({"strategies": {"reciprocity": {"h": 4.0}}, "scenarios": ["empty"], "seeds": 2})


def _row(i, **extra):
    return {"campaign": "c", "episode_id": f"empty/reciprocity/{i}", "scenario": "empty",
            "variant": "reciprocity", "seed_index": i, "strategy": "reciprocity", "arena": "empty",
            "seed": 11, "source": np.array([1.0, 2.0]), "error": np.float64(0.5),
            "n_samples": np.int64(4), "success": np.bool_(True), **extra}


def test_rows_keep_contract_columns_and_types_and_encode_nested_values():
    t = rows_to_table([_row(0, params={"h": 4.0}, n_rejected=1, note=None),
                       _row(1, params={"h": 2.0}, n_rejected=2.5, note=None)])
    assert t.schema.names[:len(CONTRACT_SCHEMA)] == CONTRACT_SCHEMA.names
    assert t.column("steps").null_count == 2  # not reported: null
    assert t.column("source").to_pylist() == [[1.0, 2.0]] * 2
    assert json.loads(t.column("params")[0].as_py()) == {"h": 4.0}
    assert t.column("n_rejected").to_pylist() == [1.0, 2.5]
    assert "note" not in t.schema.names


def test_batches_are_partitioned_and_read_back_for_resume(tmp_path):
    with ResultStore.open(tmp_path, SPEC) as store:
        assert store.finished_ids() == set()
        files = store.write([_row(0), _row(1)])
        assert store.finished_ids() == {"empty/reciprocity/0", "empty/reciprocity/1"}
    assert [f.relative_to(tmp_path).parts[:2] for f in files] == [("scenario=empty", "strategy=reciprocity")]
    assert not list(tmp_path.glob("**/*.tmp"))
    n = duckdb.connect().execute(f"SELECT count(*) FROM {episodes_sql(tmp_path)}").fetchone()[0]
    assert n == 2


def test_a_different_spec_or_a_second_driver_is_refused(tmp_path):
    with ResultStore.open(tmp_path, SPEC):
        with pytest.raises(SearchError, match="another campaign driver"):
            ResultStore.open(tmp_path, SPEC)
    other = parse_spec({"strategies": ["gradient"], "scenarios": ["empty"], "seeds": 2})
    with pytest.raises(SearchError, match="different spec"):
        ResultStore.open(tmp_path, other)
    grown = parse_spec({"strategies": {"reciprocity": {"h": 4.0}}, "scenarios": ["empty"], "seeds": 9})
    ResultStore.open(tmp_path, grown).close()  # more seeds of the same campaign are welcome


def test_leftover_temporary_files_are_removed(tmp_path):
    ResultStore.open(tmp_path, SPEC).close()
    part = tmp_path / "scenario=empty" / "strategy=reciprocity"
    part.mkdir(parents=True)
    (part / ".part-00000000deadbeef.parquet.0badc0de.tmp").write_bytes(b"partial")
    (part / ".notes.tmp").write_bytes(b"not a file the store wrote: kept")
    ResultStore.open(tmp_path, SPEC).close()
    assert [p.name for p in tmp_path.glob("**/*.tmp")] == [".notes.tmp"]


def test_unwritable_folder_is_a_clear_error(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(SearchError, match="cannot write campaign results"):
        ResultStore.open(tmp_path / "file" / "out", SPEC)


def test_a_failing_episode_becomes_a_row(monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("solver\nexploded")
    monkeypatch.setattr("reciprocity.api.execute", boom)
    row = run_task(next(SPEC.tasks()))
    assert row["error_message"].startswith("RuntimeError: solver exploded")
    assert row["episode_id"] == "empty/reciprocity/0" and row["strategy"] == "reciprocity"
    assert rows_to_table([row]).column("success").null_count == 1
