"""Running a campaign on Dask: a local cluster by default, any scheduler by address.

The driver keeps a bounded window of episodes in flight (a sliding window over
``as_completed``), so its memory does not grow with the campaign; finished rows are
buffered and written as one Parquet batch every `flush_rows` rows or `flush_seconds`
seconds. Episodes travel in chunks of up to :data:`MAX_CHUNK` (one Dask task each),
smaller as the campaign nears its end so that no worker waits on another's last chunk. Episodes already in the folder are skipped, so re-running the same command
resumes a campaign, even one whose driver was killed.
"""

from __future__ import annotations

import itertools
import sys
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import SearchError
from .cluster import CONNECT_TIMEOUT_S, TLSFiles, check_cluster, dask_client
from .spec import CampaignSpec
from .store import ResultStore
from .worker import _one_line, cache_stats, failure_row, run_tasks

__all__ = ["CampaignResult", "run_campaign", "confirmed_scheduler", "MAX_CHUNK", "chunk_size"]

#: Seconds between two looks at the finished episodes while none is ready.
POLL_S = 0.2
#: Seconds a campaign waits with no worker in the cluster before it ends with a message.
NO_WORKER_TIMEOUT_S = 60.0


#: Most episodes in one Dask task: every task costs the driver CPU on the cores the
#: workers share, which short episodes feel (benchmarks/LIMITS.md, "Campaigns").
MAX_CHUNK = 8


def chunk_size(left: int, threads: int) -> int:
    """Episodes in the next task when `left` episodes remain for `threads` worker threads:
    up to :data:`MAX_CHUNK`, and at most a quarter of each thread's share, so that the
    last tasks are single episodes and every thread finishes at about the same time."""
    return max(1, min(MAX_CHUNK, left // (4 * max(threads, 1))))


@dataclass
class CampaignResult:
    """What one run of :func:`run_campaign` did.

    Attributes
    ----------
    directory : Path
        Results folder.
    n_episodes : int
        Episodes in the spec.
    n_skipped : int
        Episodes already in the folder before this run (not re-run).
    n_run : int
        Episodes run and stored by this run.
    n_failed : int
        Of those, episodes that raised (stored with their ``error_message``).
    wall_time_s : float
        Duration of this run, s (including the cluster's start).
    cache_stats : dict
        Worker address -> ``{"module.function": (hits, misses)}`` of the set-up caches
        at the end of the run (see :func:`reciprocity.campaign.worker.cache_stats`).
    """

    directory: Path
    n_episodes: int
    n_skipped: int
    n_run: int = 0
    n_failed: int = 0
    wall_time_s: float = 0.0
    cache_stats: dict = field(default_factory=dict)


def run_campaign(spec: CampaignSpec, directory, *, workers: int | None = None,
                 scheduler: str | None = None, tls: TLSFiles | None = None,
                 progress: bool | None = None, window: int | None = None, flush_rows: int = 64, flush_seconds: float = 5.0,
                 timeout: float = CONNECT_TIMEOUT_S, worker_timeout: float = NO_WORKER_TIMEOUT_S) -> CampaignResult:
    """Run (or resume) a campaign, storing every finished episode under `directory`.

    Parameters
    ----------
    spec : CampaignSpec
        The validated campaign.
    directory : path-like
        Results folder (see :class:`reciprocity.campaign.store.ResultStore`).
    workers : int, optional
        Local worker processes; default: one per CPU core (or the spec's scheduler).
    scheduler : str, optional
        Address of a Dask scheduler to use instead of a local cluster, or ``"spec"`` for
        the one the spec names. A spec's scheduler is never used unless confirmed so: its
        workers run code as you and send back results that this process unpickles, and a
        spec file may come from someone else (see the docs' threat model).
    tls : TLSFiles, optional
        Client certificate for a ``tls://`` scheduler; default: the spec's, with
        ``scheduler="spec"``.
    progress : bool, optional
        Show a progress bar (done, failed, ETA); default: when stderr is a terminal.
    window : int, optional
        Episodes in flight at once; default: 8 per worker thread (at least 16).
    flush_rows : int
        Write a batch once this many rows are buffered.
    flush_seconds : float
        ... or once the oldest buffered row is this old, s (what a killed driver loses
        at most, in episodes to re-run).
    timeout : float
        Seconds to wait for `scheduler`.
    worker_timeout : float
        Seconds the cluster may have no worker at all before the campaign ends with a
        SearchError (the finished episodes saved; re-running resumes).

    Returns
    -------
    CampaignResult

    Raises
    ------
    SearchError
        Bad folder, a different spec in it, bad `workers`, `scheduler` or `tls`, or no
        scheduler answering; all before any episode runs. A failing episode does not raise: it is stored with its
        ``error_message``.
    """
    from tqdm import tqdm
    t0 = time.perf_counter()
    scheduler, tls = confirmed_scheduler(spec, workers, scheduler, tls)
    check_cluster(workers, scheduler, tls)
    # connect first: a scheduler that does not answer must leave the folder untouched
    with dask_client(workers, scheduler, tls=tls, timeout=timeout) as client, \
            ResultStore.open(directory, spec) as store:
        done = store.finished_ids()
        n_todo = sum(1 for t in spec.tasks() if t.episode_id not in done)
        result = CampaignResult(Path(directory), spec.n_episodes, spec.n_episodes - n_todo)
        if n_todo == 0:
            result.wall_time_s = time.perf_counter() - t0
            return result
        pending = (t for t in spec.tasks() if t.episode_id not in done)
        threads = sum(client.nthreads().values()) or 1
        show = sys.stderr.isatty() if progress is None else progress
        with tqdm(total=spec.n_episodes, initial=result.n_skipped, unit="ep", desc=spec.name,
                  disable=not show, file=sys.stderr, dynamic_ncols=True) as bar:
            bar.set_postfix_str("failed 0")
            _drive(client, pending, n_todo, threads, store, result, bar, window or max(16, 8 * threads),
                   flush_rows, flush_seconds, worker_timeout)
        result.cache_stats = client.run(cache_stats)
    result.wall_time_s = time.perf_counter() - t0
    return result


def confirmed_scheduler(spec: CampaignSpec, workers: int | None, scheduler: str | None,
                        tls: TLSFiles | None) -> tuple[str | None, TLSFiles | None]:
    """The scheduler and TLS files to use: the spec's only when `scheduler` is ``"spec"``.

    Raises
    ------
    SearchError
        ``"spec"`` for a spec that names none, or a spec that names one while neither
        `workers` nor `scheduler` says what to do.
    """
    if scheduler == "spec":
        if spec.scheduler is None:
            raise SearchError("--scheduler spec: the spec names no scheduler; give an address or --workers N")
        return spec.scheduler, tls or spec.tls
    if spec.scheduler is not None and workers is None and scheduler is None:
        raise SearchError(f"the spec names the Dask scheduler {spec.scheduler!r}, which would run code as you "
                          "and send back results this process unpickles; confirm it with --scheduler spec "
                          f"(or --scheduler {spec.scheduler}), or run locally with --workers N")
    return scheduler, tls


class _WorkerWatch:
    """Ends a campaign whose cluster has had no worker for `timeout` seconds (an external
    scheduler whose workers all died: nothing would ever finish)."""

    #: Seconds between two questions to the scheduler.
    EVERY_S = 2.0

    def __init__(self, client, timeout: float):
        self.client, self.timeout = client, float(timeout)
        self.asked = self.since = None

    def check(self) -> None:
        now = time.monotonic()
        if self.asked is not None and now - self.asked < self.EVERY_S:
            return
        self.asked = now
        try:
            n = len(self.client.scheduler_info().get("workers", {}))
        except Exception:                  # the scheduler itself is gone: as good as no worker
            n = 0
        if n:
            self.since = None
            return
        self.since = self.since if self.since is not None else now
        if now - self.since >= self.timeout:
            raise SearchError(f"the Dask cluster has had no worker for {self.timeout:g} s, so no episode can "
                              "finish; the finished ones are saved: start workers (dask worker ADDRESS) and "
                              "run the same command again to resume")


def _drive(client, pending, n_todo: int, threads: int, store: ResultStore, result: CampaignResult, bar,
           window: int, flush_rows: int, flush_seconds: float, worker_timeout: float = NO_WORKER_TIMEOUT_S) -> None:
    """Keep `window` chunks of episodes in flight; store rows in batches as they finish."""
    from distributed import as_completed
    inflight = {}
    finished = as_completed()
    left = n_todo

    def submit_next() -> None:
        nonlocal left
        chunk = list(itertools.islice(pending, chunk_size(left, threads)))
        if chunk:
            left -= len(chunk)
            # one key prefix for every task: the scheduler keeps a task group per prefix
            # for its whole life, so per-task prefixes grew the driver ~7 KB a task
            fut = client.submit(run_tasks, chunk, key=f"episode-{uuid.uuid4().hex}", pure=False)
            inflight[fut.key] = chunk
            finished.add(fut)

    for _ in range(window):
        submit_next()
    buffer, oldest = [], time.monotonic()
    watch = _WorkerWatch(client, worker_timeout)
    try:
        while inflight:
            ready = finished.next_batch(block=False) if finished.has_ready() else []
            if not ready:
                time.sleep(POLL_S)
                watch.check()
            for fut in ready:
                chunk = inflight.pop(fut.key)
                try:
                    rows = fut.result()
                except Exception as exc:  # the worker died or the task was lost
                    rows = [failure_row(task, f"worker lost: {_one_line(exc)}") for task in chunk]
                fut.release()
                if not buffer:
                    oldest = time.monotonic()
                buffer.extend(rows)
                result.n_run += len(rows)
                result.n_failed += sum(row["error_message"] is not None for row in rows)
                bar.update(len(rows))
                bar.set_postfix_str(f"failed {result.n_failed}", refresh=False)
                submit_next()
            # on a timer, not only when a result arrives: a killed driver loses at most
            # flush_seconds of finished episodes, even while the workers are gone
            if buffer and (len(buffer) >= flush_rows or time.monotonic() - oldest >= flush_seconds):
                store.write(buffer)
                buffer.clear()
    finally:
        # rows of finished episodes are results even when the driver is interrupted
        if buffer:
            store.write(buffer)
