"""Rules for campaign folders and drivers: a shared spec cannot choose where code runs,
nothing is written or deleted through a link, a damaged results file is quarantined and
re-run, and finished rows reach the disk on a timer even when every worker is gone.

Each test names the defect class of issue 34 it closes (items 1, 3, 6, 7, 12)."""

import subprocess
import sys
import threading
import time

import duckdb
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from reciprocity.campaign import ResultStore, load_spec, parse_spec, run_campaign
from reciprocity.campaign.cluster import UnencryptedSchedulerWarning, dask_client
from reciprocity.campaign.store import DamagedResultsWarning, episodes_sql, result_files
from reciprocity.errors import SearchError

SPEC = parse_spec({"strategies": {"reciprocity": {"h": 4.0}}, "scenarios": ["empty"], "seeds": 3})
FAST = """\
name: fast
seed: 11
seeds: {seeds}
strategies: {{random-walk: {{n_steps: 4}}}}
scenarios: [ristic-lattice]
"""


def _row(i):
    return {"campaign": "c", "episode_id": f"empty/reciprocity/{i}", "scenario": "empty",
            "variant": "reciprocity", "seed_index": i, "strategy": "reciprocity", "arena": "empty",
            "seed": 11, "source": np.array([1.0, 2.0]), "error": 0.5, "n_samples": 4, "success": True}


#: A safety net against a hung command, never the assertion (minutes, far above any run here).
HANG_S = 600
#: What the campaign is told (the behaviour under test, not a deadline): write finished rows
#: after this long, end after this long with no worker; and how long to try a dead address.
FLUSH_S, NO_WORKER_S, CONNECT_S = 0.5, 3.0, 0.5


def _cli(*args, **kw):
    return subprocess.run([sys.executable, "-m", "reciprocity.cli", *args], capture_output=True, text=True,
                          timeout=HANG_S, **kw)


@pytest.fixture
def folder(tmp_path):
    """A campaign folder with three rows, one file each."""
    out = tmp_path / "campaign"
    with ResultStore.open(out, SPEC) as store:
        for i in range(3):
            store.write([_row(i)])
    return out


@pytest.mark.slow
def test_a_scheduler_named_in_a_spec_is_used_only_when_confirmed(tmp_path):
    """Defect 1: a shared spec naming scheduler: tcp://... ran code as its user, unasked."""
    spec = tmp_path / "spec.yaml"
    spec.write_text(FAST.format(seeds=1) + "scheduler: tcp://127.0.0.1:9\n")
    r = _cli("campaign", str(spec), "--out", str(tmp_path / "out"), "--quiet")
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert "confirm it with --scheduler spec" in r.stderr
    assert not (tmp_path / "out").exists()
    r = _cli("campaign", str(spec), "--out", str(tmp_path / "out"), "--scheduler", "spec", "--quiet")
    assert r.returncode == 2                                      # confirmed: then it is tried (and warned about)
    assert r.stderr.splitlines()[0].startswith("warning: scheduler 'tcp://127.0.0.1:9' is plain TCP")
    assert r.stderr.splitlines()[1].startswith("error: no Dask scheduler answers")


def test_plain_tcp_always_warns():
    with pytest.warns(UnencryptedSchedulerWarning), pytest.raises(SearchError):
        with dask_client(scheduler="tcp://127.0.0.1:9", timeout=CONNECT_S):
            pass


def test_a_linked_report_folder_is_refused(folder, tmp_path):
    """Defect 3: a symlinked report/ made 'report' overwrite files outside the campaign."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "report.md").write_text("someone's notes")
    (folder / "report").symlink_to(outside, target_is_directory=True)
    r = _cli("report", str(folder))
    assert r.returncode == 2 and "is a symbolic link" in r.stderr and r.stderr.count("\n") == 1
    assert [p.name for p in outside.iterdir()] == ["report.md"]
    assert (outside / "report.md").read_text() == "someone's notes"


def test_report_files_replace_links_instead_of_writing_through_them(folder, tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (folder / "report").mkdir()
    (folder / "report" / "report.md").symlink_to(victim)
    r = _cli("report", str(folder))
    assert r.returncode == 0, r.stderr
    assert victim.read_text() == "precious"
    assert not (folder / "report" / "report.md").is_symlink()


def test_a_linked_partition_is_refused_and_what_it_shows_is_untouched(folder, tmp_path):
    """Defect 3: a symlinked partition counted rows from elsewhere, and the .*.tmp clean-up
    deleted a matching file in the link's target."""
    outside = tmp_path / "elsewhere"
    part = folder / "scenario=empty" / "strategy=reciprocity"
    part.rename(outside)
    part.symlink_to(outside, target_is_directory=True)
    (outside / ".part-00000000deadbeef.parquet.0badc0de.tmp").write_bytes(b"not ours to delete")
    before = sorted(p.name for p in outside.iterdir())
    with pytest.raises(SearchError, match="symbolic link"):
        result_files(folder)
    with pytest.raises(SearchError, match="symbolic link"):
        ResultStore.open(folder, SPEC)
    r = _cli("report", str(folder))
    assert r.returncode == 2 and "symbolic link" in r.stderr
    assert sorted(p.name for p in outside.iterdir()) == before


def _truncate(path):
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _mistype(path):
    table = pq.read_table(path)
    i = table.schema.get_field_index("episode_id")
    pq.write_table(table.set_column(i, "episode_id", pa.array([7] * len(table))), path)


DAMAGE = {"empty": lambda p: p.write_bytes(b""), "truncated": _truncate,
          "not Parquet": lambda p: p.write_text("id,error\n1,2\n"), "mistyped column": _mistype}


@pytest.mark.parametrize("damage", list(DAMAGE))
def test_a_damaged_results_file_is_named_quarantined_and_left_to_rerun(folder, damage):
    """Defect 6: a truncated, empty or mistyped part gave a raw DuckDB traceback from report
    and resume, until someone found the file by hand."""
    bad = result_files(folder)[1]
    DAMAGE[damage](bad)
    with pytest.warns(DamagedResultsWarning, match=bad.name):
        with ResultStore.open(folder, SPEC) as store:
            done = store.finished_ids()
    assert len(done) == 2                                          # its episode is to be run again
    assert not bad.exists()
    assert (folder / "quarantine" / "scenario=empty" / "strategy=reciprocity" / bad.name).exists()
    r = _cli("report", str(folder))
    assert r.returncode == 0 and "warning" not in r.stderr         # the folder is sound again


@pytest.mark.slow
def test_resume_reruns_the_episodes_of_a_damaged_file(tmp_path):
    spec = tmp_path / "fast.yaml"
    spec.write_text(FAST.format(seeds=6))
    out = tmp_path / "out"
    first = run_campaign(load_spec(spec), out, workers=1, progress=False)
    assert first.n_run == 6
    files = result_files(out)
    con = duckdb.connect()
    lost = con.execute(f"SELECT count(*) FROM read_parquet('{files[0]}')").fetchone()[0]
    files[0].write_bytes(b"")
    with pytest.warns(DamagedResultsWarning):
        again = run_campaign(load_spec(spec), out, workers=1, progress=False)
    assert again.n_run == lost and again.n_skipped == 6 - lost
    ids = [r[0] for r in con.execute(f"SELECT episode_id FROM {episodes_sql(out)}").fetchall()]
    assert len(ids) == len(set(ids)) == 6


@pytest.mark.slow
def test_losing_every_worker_ends_the_campaign_and_keeps_what_finished(tmp_path):
    """Defect 7: with every worker of an external scheduler dead the campaign waited with no
    message, and finished rows waited for another result before reaching the disk."""
    import warnings

    from distributed import LocalCluster
    spec = tmp_path / "fast.yaml"
    spec.write_text(FAST.format(seeds=400))
    out = tmp_path / "out"
    outcome = {}
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        def drive():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UnencryptedSchedulerWarning)
                    run_campaign(load_spec(spec), out, scheduler=cluster.scheduler_address, progress=False,
                                 flush_rows=10**6, flush_seconds=FLUSH_S, worker_timeout=NO_WORKER_S)
            except SearchError as exc:
                outcome["error"] = str(exc)
        thread = threading.Thread(target=drive)
        thread.start()
        # rows are written by the timer alone (flush_rows is never reached)
        while thread.is_alive() and not ((out / "campaign.json").exists() and result_files(out)):
            time.sleep(0.05)
        assert result_files(out), "no row reached the disk on the timer"
        cluster.scale(0)
        thread.join()
    assert "no worker for 3 s" in outcome.get("error", ""), outcome
    n = duckdb.connect().execute(f"SELECT count(*) FROM {episodes_sql(out)}").fetchone()[0]
    assert 0 < n < 800


@pytest.mark.slow
def test_kill_9_on_a_campaign_driver_leaves_no_worker_behind(tmp_path):
    """Process hygiene: the local cluster's workers die with the driver."""
    from process_tree import kill_9_when
    spec = tmp_path / "fast.yaml"
    spec.write_text(FAST.format(seeds=400))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "reciprocity.cli", "campaign", str(spec), "--out", str(out),
                             "--workers", "2", "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:                                            # once the workers have finished episodes
        workers, alive = kill_9_when(proc, lambda: (out / "campaign.json").exists() and bool(result_files(out)))
    finally:
        if proc.poll() is None:
            proc.kill()
    assert len(workers) >= 2 and not alive, f"orphans: {alive}"
