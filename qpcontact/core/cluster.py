"""One way to get a Dask client for the sweeps (compare, scene sweeps)."""

from __future__ import annotations

from contextlib import contextmanager


@contextmanager
def dask_client(workers: int, scheduler: str | None):
    """A client of the cluster at ``scheduler``, or of a local cluster of
    ``workers`` single-threaded processes (closed on exit)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        from .errors import BackendUnavailableError

        raise BackendUnavailableError(
            "--workers/--scheduler need Dask: pip install 'qpcontact[dask]'") from None
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
