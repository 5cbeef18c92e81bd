"""Campaigns on local Dask clusters: kill -9 and resume, worker-count independence,
report numbers against direct SQL, set-up cache reuse."""

import math
import os
import signal
import subprocess
import sys
import time

import duckdb
import pytest

from reciprocity.campaign import build_report, episodes_sql, load_spec, run_campaign

SPEC = """\
name: tiny
seed: 3
seeds: 7
random_source: true
strategies:
  reciprocity: {h: 4.0}
  gradient: {h: 4.0}
scenarios: [empty]
"""

# a driver that writes every row at once and keeps only 2 episodes in flight, so that a
# kill lands between batches
DRIVER = """\
import sys
from reciprocity.campaign import load_spec, run_campaign
run_campaign(load_spec(sys.argv[1]), sys.argv[2], workers=2, progress=False, window=2,
             flush_rows=1, flush_seconds=0.0)
"""


def _rows(directory) -> list[tuple]:
    """All rows by episode id, without the wall time (the one nondeterministic column)."""
    cur = duckdb.connect().execute(
        f"SELECT * EXCLUDE (wall_time_s) FROM {episodes_sql(directory)} ORDER BY episode_id")
    names = [d[0] for d in cur.description]
    return [tuple(sorted(zip(names, r), key=lambda kv: kv[0])) for r in cur.fetchall()]


@pytest.fixture(scope="module")
def spec_file(tmp_path_factory):
    f = tmp_path_factory.mktemp("spec") / "tiny.yaml"
    f.write_text(SPEC)
    return f


@pytest.fixture(scope="module")
def reference(spec_file, tmp_path_factory):
    """The campaign run in one go on a single worker."""
    out = tmp_path_factory.mktemp("ref")
    return out, run_campaign(load_spec(spec_file), out, workers=1, progress=False)


def test_reference_run_stores_every_episode_and_reuses_setup(reference, spec_file):
    out, result = reference
    assert (result.n_run, result.n_failed, result.n_skipped) == (14, 0, 0)
    assert len(_rows(out)) == 14
    (stats,) = result.cache_stats.values()
    hits, misses = sum(h for h, _ in stats.values()), sum(m for _, m in stats.values())
    assert hits > misses  # meshes and factorizations are built once per worker, then reused
    again = run_campaign(load_spec(spec_file), out, workers=1, progress=False)
    assert (again.n_run, again.n_skipped, again.cache_stats) == (0, 14, {})  # nothing to do


@pytest.mark.slow
def test_killed_driver_resumes_without_losing_or_repeating(spec_file, reference, tmp_path):
    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-c", DRIVER, str(spec_file), str(out)],
                            start_new_session=True, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 600  # a safety net against a hang, not a speed check
        while len(list(out.glob("**/*.parquet"))) < 3:
            assert proc.poll() is None and time.monotonic() < deadline, "driver ended early"
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)  # kill -9 the driver mid-way
        proc.wait()
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # its orphaned worker processes
    partial = _rows(out)
    assert 3 <= len(partial) < 14
    result = run_campaign(load_spec(spec_file), out, workers=2, progress=False)
    assert result.n_skipped == len(partial) and result.n_run == 14 - len(partial)
    # same rows as one uninterrupted run on one worker: none lost, none repeated, and
    # independent of the worker count
    assert _rows(out) == _rows(reference[0])


def test_report_numbers_equal_direct_sql(reference):
    out, _ = reference
    report = build_report(out)
    direct = duckdb.connect().execute(f"""
        SELECT variant, count(*), avg(success::INT), median(error), quantile_cont(error, 0.9),
               avg(n_samples), median(n_measurements), avg(path_length)
        FROM {episodes_sql(out)} GROUP BY variant ORDER BY variant""").fetchall()
    got = [(r["variant"], r["runs"], r["success_rate"], r["error_median"], r["error_p90"],
            r["samples_mean"], r["measurements_median"], r["path_mean"]) for r in report.summary]
    assert len(got) == len(direct) == 2
    for g, d in zip(got, direct):
        assert g[:2] == d[:2]
        assert all(math.isclose(a, b) for a, b in zip(g[2:], d[2:]))
    (samples,) = [r for r in report.paired if r["metric"] == "samples"]
    d = duckdb.connect().execute(f"""
        SELECT avg(b.n_samples - a.n_samples), count(*) FROM {episodes_sql(out)} a
        JOIN {episodes_sql(out)} b USING (seed_index)
        WHERE a.variant = 'gradient' AND b.variant = 'reciprocity'""").fetchone()
    assert (samples["a"], samples["b"], samples["pairs"]) == ("gradient", "reciprocity", 7)
    assert math.isclose(samples["mean_diff"], d[0]) and samples["lo"] < d[0] < samples["hi"]
    # the pairs meet the same worlds
    worlds = duckdb.connect().execute(f"""
        SELECT count(DISTINCT (seed_index, seed, source, start)) FROM {episodes_sql(out)}""").fetchone()
    assert worlds == (7,)


def test_chunks_shrink_to_single_episodes_at_the_end():
    from reciprocity.campaign.execute import MAX_CHUNK, chunk_size
    for n, threads in ((1, 1), (7, 2), (200, 2), (10_000, 16)):
        left, sizes = n, []
        while left:
            sizes.append(chunk_size(left, threads))
            left -= sizes[-1]
        assert sum(sizes) == n and max(sizes) <= MAX_CHUNK
        assert sizes[-4 * threads:] == [1] * min(len(sizes), 4 * threads)   # the tail: one episode a task
        assert sizes == sorted(sizes, reverse=True)


def test_local_workers_keep_arrays_on_the_heap_and_do_not_profile():
    """Dask's default MALLOC_TRIM_THRESHOLD_ (64 KiB) made episodes 1.5x slower (see
    reciprocity.campaign.cluster.LOCAL_WORKER_CONFIG)."""
    from reciprocity.campaign import dask_client
    with dask_client(1) as client:
        env = list(client.run(lambda: (os.environ.get("MALLOC_TRIM_THRESHOLD_"),
                                       os.environ.get("MALLOC_MMAP_THRESHOLD_"))).values())[0]
        import dask
        profiling = list(client.run(lambda: dask.config.get("distributed.worker.profile.enabled")).values())[0]
    if "MALLOC_TRIM_THRESHOLD_" not in os.environ:           # a variable set by the user wins
        assert env == (str(64 * 2**20), str(32 * 2**20))
    assert profiling is False
