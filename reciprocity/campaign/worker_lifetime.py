"""The lifetime of a local cluster's workers: they end with the campaign driver."""

from __future__ import annotations

from distributed.diagnostics.plugin import WorkerPlugin

__all__ = ["DieWithDriver"]


class DieWithDriver(WorkerPlugin):
    """A Dask worker plugin: each worker process of the local cluster ends with the driver
    that started it, even after ``kill -9`` of the driver (see
    :func:`arenas.processes.die_with_parent`). Not for a remote cluster, whose workers are
    not the driver's children."""

    def setup(self, worker) -> None:
        from arenas.processes import die_with_parent
        die_with_parent()
