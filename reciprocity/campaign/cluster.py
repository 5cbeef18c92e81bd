"""Where a campaign's episodes run: a local Dask cluster, or a scheduler by address.

A Dask scheduler runs whatever code its clients send, so a scheduler given by address
must be one only you can reach: a plain ``tcp://`` scheduler belongs on a trusted
network only (a laptop, a private cluster network). Anywhere else use ``tls://``: the
scheduler and its workers are started with certificates signed by your own CA
(``dask scheduler --tls-ca-file ca.pem --tls-cert sched.pem --tls-key sched.key``,
the same for ``dask worker``), and the campaign connects with a client certificate of
that CA (:class:`TLSFiles`; ``--tls-ca-file``, ``--tls-cert``, ``--tls-key``, or the
spec's ``scheduler: {address: tls://..., tls: {ca_file, cert, key}}``). Every
connection is then encrypted and both ends must show a certificate of the CA.

Every setting is checked before any work: the worker count against :func:`max_workers`,
the address against the forms Dask accepts, the TLS files by loading them.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import ssl
import warnings
from collections.abc import Iterator
from dataclasses import dataclass

from arenas.files import read_text

from ..errors import SearchError

__all__ = ["UnencryptedSchedulerWarning", "TLSFiles", "dask_client", "check_cluster", "check_workers", "check_address", "max_workers",
           "MAX_WORKERS", "WORKERS_PER_CORE", "CONNECT_TIMEOUT_S"]

#: Seconds to wait for a Dask scheduler given by address before giving up.
CONNECT_TIMEOUT_S = 10.0
#: Most local worker processes, whatever the machine.
MAX_WORKERS = 64
#: Most local worker processes per CPU core (more only queue for the cores and memory).
WORKERS_PER_CORE = 4

_HOST = r"(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9][A-Za-z0-9.-]{0,252})"
_NETWORK = re.compile(rf"^(?:(?:tcp|tls)://)?{_HOST}:(\d{{1,5}})$")
_INPROC = re.compile(r"^inproc://[^\s/]+(?:/[^\s]*)?$")


class UnencryptedSchedulerWarning(UserWarning):
    """A campaign connects to a plain ``tcp://`` Dask scheduler."""


def _ssl_cause(exc: BaseException) -> str | None:
    """The SSL error in the chain of `exc` (Dask wraps it in a timeout or OSError), or None."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, ssl.SSLError):
            return " ".join(str(exc).split())
        exc = exc.__cause__ or exc.__context__
    return None


def max_workers() -> int:
    """The largest ``--workers`` on this machine: :data:`WORKERS_PER_CORE` per core
    available to this process, at most :data:`MAX_WORKERS`."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:          # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(MAX_WORKERS, WORKERS_PER_CORE * cores))


def check_workers(n) -> int:
    """`n` if it is a valid local worker count, else SearchError naming the range."""
    top = max_workers()
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= top:
        raise SearchError(f"--workers must be a whole number from 1 to {top} ({WORKERS_PER_CORE} "
                          f"per core on this machine, at most {MAX_WORKERS}); got {n!r}")
    return n


def check_address(address) -> str:
    """`address` if Dask can connect to it, else SearchError naming the forms.

    Accepted: ``tcp://HOST:PORT``, ``tls://HOST:PORT``, ``HOST:PORT`` (TCP) and
    ``inproc://...`` (a scheduler in this process), with a port from 1 to 65535.
    """
    text = address if isinstance(address, str) else ""
    m = _NETWORK.match(text)
    if not (m and 1 <= int(m.group(1)) <= 65535) and not _INPROC.match(text):
        raise SearchError("the scheduler address must be tcp://HOST:PORT, tls://HOST:PORT, "
                          f"inproc://... or HOST:PORT (port 1 to 65535); got {address!r}")
    return address


@dataclass(frozen=True)
class TLSFiles:
    """The client's TLS settings for a ``tls://`` scheduler (PEM files).

    Attributes
    ----------
    ca_file : str
        Certificate of the CA that signed the scheduler's and workers' certificates.
    cert : str
        The client's certificate, signed by that CA.
    key : str
        The client's private key.
    """

    ca_file: str
    cert: str
    key: str

    def security(self):
        """Dask's security settings: TLS required, these files, checked by loading them.

        Returns
        -------
        distributed.security.Security

        Raises
        ------
        SearchError
            A file missing, unreadable, or not a PEM certificate or key that fit together.
        """
        from distributed.security import Security
        for label, path in (("--tls-ca-file", self.ca_file), ("--tls-cert", self.cert),
                            ("--tls-key", self.key)):
            read_text(path, f"{label} {path!r}", error=SearchError)
        sec = Security(tls_ca_file=self.ca_file, tls_client_cert=self.cert,
                       tls_client_key=self.key, require_encryption=True)
        try:
            sec.get_connection_args("client")      # loads the CA, certificate and key
        except (ssl.SSLError, ValueError) as exc:
            raise SearchError(f"the TLS files (--tls-ca-file {self.ca_file!r}, --tls-cert "
                              f"{self.cert!r}, --tls-key {self.key!r}) do not load: "
                              f"{' '.join(str(exc).split())}") from None
        return sec


def check_cluster(workers: int | None = None, scheduler: str | None = None,
                  tls: TLSFiles | None = None):
    """Check where a campaign would run, cheaply and before any work.

    Parameters
    ----------
    workers, scheduler, tls
        As in :func:`dask_client`.

    Returns
    -------
    distributed.security.Security or None
        The security settings of a ``tls://`` scheduler, else None.

    Raises
    ------
    SearchError
        Both `workers` and `scheduler`, a worker count out of range, an address Dask
        cannot use, TLS files that do not fit the address or do not load.
    """
    if workers is not None and scheduler is not None:
        raise SearchError("give either --workers N (a local cluster) or --scheduler ADDRESS, not both")
    if workers is not None:
        check_workers(workers)
    if scheduler is None:
        if tls is not None:
            raise SearchError("TLS files apply to a tls:// scheduler; give --scheduler tls://HOST:PORT "
                              "or drop --tls-ca-file, --tls-cert and --tls-key")
        return None
    if check_address(scheduler).startswith("tls://"):
        if tls is None:
            raise SearchError(f"scheduler {scheduler!r} needs TLS files: --tls-ca-file, --tls-cert "
                              "and --tls-key (or tls: in the spec's scheduler)")
        return tls.security()
    if tls is not None:
        raise SearchError(f"TLS files given but scheduler {scheduler!r} is not tls://; connect to "
                          "tls://HOST:PORT (a plain tcp:// scheduler belongs on a trusted network only)")
    return None


#: Dask settings of the local cluster's workers (a remote cluster keeps its own). Dask's
#: nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which also freezes glibc's
#: mmap threshold at 128 KB: every array of more than 16k floats is then mapped and unmapped
#: anew, and episodes run markedly slower than in a plain process. Thresholds of 64 and
#: 32 MiB keep such arrays on the heap. The statistical profiler samples every task's stack
#: every 10 ms; nobody reads it here. Measured in benchmarks/LIMITS.md ("Campaigns").
#: Variables already set in the environment win over these.
LOCAL_WORKER_CONFIG = {
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": 64 * 2**20,
    "distributed.nanny.pre-spawn-environ.MALLOC_MMAP_THRESHOLD_": 32 * 2**20,
    "distributed.worker.profile.enabled": False,
}


@contextlib.contextmanager
def dask_client(workers: int | None = None, scheduler: str | None = None, *,
                tls: TLSFiles | None = None, timeout: float = CONNECT_TIMEOUT_S) -> Iterator:
    """A Dask client: on a new local cluster, or connected to `scheduler`.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (one thread each), 1 to :func:`max_workers`; default:
        one per CPU core.
    scheduler : str, optional
        Address of a running scheduler (``tls://host:8786``, or ``tcp://host:8786`` on a
        trusted network); its workers must have this package installed and read
        scenario files at the same paths.
    tls : TLSFiles, optional
        Client certificate for a ``tls://`` scheduler (required there, refused elsewhere).
    timeout : float
        Seconds to wait for `scheduler` to answer.

    Yields
    ------
    distributed.Client

    Raises
    ------
    SearchError
        Both or invalid `workers`/`scheduler`, TLS files that do not fit the address or
        do not load, or no scheduler answering in time.
    """
    import dask
    from distributed import Client, LocalCluster
    security = check_cluster(workers, scheduler, tls)
    if scheduler is not None:
        if not scheduler.startswith(("tls://", "inproc://")):
            warnings.warn(f"scheduler {scheduler!r} is plain TCP: unencrypted and unauthenticated, so anyone "
                          "who can reach it can run code as you and forge the results this process "
                          "unpickles; use it on a trusted network only, or tls:// with certificates",
                          UnencryptedSchedulerWarning, stacklevel=3)
        try:
            client = Client(scheduler, timeout=timeout, security=security)
        except (OSError, TimeoutError, ValueError) as exc:
            cause = _ssl_cause(exc)
            if cause is None and scheduler.startswith("tls://") and "CommClosed" in type(exc).__name__:
                cause = "the scheduler closed the connection during the handshake (it refused this certificate)"
            if cause is not None:
                raise SearchError(f"the TLS handshake with the Dask scheduler at {scheduler!r} failed: {cause}; "
                                  "check that --tls-ca-file signed the scheduler's certificate and that "
                                  "the scheduler accepts --tls-cert") from None
            raise SearchError(f"no Dask scheduler answers at {scheduler!r} within {timeout:g} s "
                              f"({type(exc).__name__}); start one with 'dask scheduler' "
                              "or run locally with --workers N") from None
        with client:
            yield client
        return
    n = check_workers(workers if workers is not None else min(os.cpu_count() or 1, max_workers()))
    # no dashboard; the scheduler's health/metrics HTTP server on a free port (its default,
    # 8787, warns "already in use" as soon as two campaigns or test workers run at once)
    with dask.config.set(LOCAL_WORKER_CONFIG), \
            LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                         scheduler_kwargs={"dashboard_address": ":0"},
                         silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        from .worker_lifetime import DieWithDriver
        client.register_plugin(DieWithDriver(), name="die-with-driver")
        yield client
