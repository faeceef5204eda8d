"""One way to get a Dask client for the sweeps (compare, scene sweeps)."""

from __future__ import annotations

from contextlib import contextmanager

#: seconds to wait for an existing Dask scheduler to answer
CONNECT_SECONDS = 5.0


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
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0 \
            or not (workers or scheduler):
        from .errors import InvalidOptionError

        raise InvalidOptionError(f"--workers must be an integer >= 1 for a local Dask cluster "
                                 f"(or a --scheduler given); got {workers!r}")
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_SECONDS)
        except (OSError, TimeoutError) as exc:
            from .errors import InvalidOptionError

            raise InvalidOptionError(
                f"--scheduler {scheduler}: no Dask scheduler answered within {CONNECT_SECONDS:g} "
                f"s ({type(exc).__name__}); start one there (dask scheduler) or give its "
                "address, e.g. tcp://host:8786") from None
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
