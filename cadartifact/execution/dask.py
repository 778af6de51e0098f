"""The Dask backend: a client of a scheduler, or of a local cluster it starts (``--scheduler ADDRESS|local``).

``distributed`` is imported only here, and only when a scheduler is asked for: the optional extra
``pip install "cadartifact[dask]"``. :func:`session` gives a connected client and closes it (and the local
cluster) afterwards; what runs on it is the caller's (the gate's batches: :mod:`cadartifact.gate.cluster`).
"""

from __future__ import annotations

import contextlib

from ..errors import CadArtifactError, MissingDependencyError, OptionError
from .executors import workers_can_start
from .settings import ClusterOptions

__all__ = ["EXTRA", "LOCAL_ALLOWED_FAILURES", "WORKER_ENVIRON", "connect", "require_distributed", "session"]

EXTRA = 'pip install "cadartifact[dask]"'

#: Environment of the local cluster's workers (see :func:`connect`; remote workers: set it where they start).
WORKER_ENVIRON = {"MALLOC_TRIM_THRESHOLD_": "134217728", "MALLOC_MMAP_THRESHOLD_": "134217728"}

#: Worker deaths a task is allowed on the local cluster before Dask gives up on it.
LOCAL_ALLOWED_FAILURES = 2


def require_distributed():
    """Import ``distributed`` or raise :class:`MissingDependencyError` naming the extra."""
    try:
        import distributed
    except ImportError as exc:
        raise MissingDependencyError(f"--scheduler needs dask.distributed, which could not be imported ({exc}); "
                                     f"install it with: {EXTRA}") from None
    return distributed


def connect(options: ClusterOptions):
    """A ``(client, cluster or None)`` pair; one-line errors for an unreachable scheduler."""
    import logging

    distributed = require_distributed()
    import dask

    # the cluster's own chatter (a worker restarted after a death...) would bury the gate's report
    for name in ("distributed", "distributed.nanny", "distributed.scheduler", "distributed.worker"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
    if options.address == "local":
        if not workers_can_start():  # spawned workers re-import __main__ by path: '<stdin>' cannot be
            raise CadArtifactError("--scheduler local: worker processes cannot be started from a program read "
                                   "from standard input; run it from a file, or give a scheduler address")
        # non-daemonic workers may start processes of their own (the gate may read a file in a child);
        # the workers' statistical profiler would take its share of the cores from the analysis; and
        # Dask's MALLOC_TRIM_THRESHOLD_=65536 both trims the heap after every free and (mallopt(3): any
        # explicit threshold) turns off glibc's dynamic mmap threshold, so every numpy temporary over
        # 128 KiB is mapped and unmapped again: measured on 150 vault files, 5.2 s of system time and
        # 1.5x the wall time of the same worker with both thresholds at 128 MiB (0.5 s system time)
        environ = {**dask.config.get("distributed.nanny.pre-spawn-environ", {}), **WORKER_ENVIRON}
        with dask.config.set({"distributed.scheduler.allowed-failures": LOCAL_ALLOWED_FAILURES,
                              "distributed.worker.daemon": False, "distributed.worker.profile.enabled": False,
                              "distributed.nanny.pre-spawn-environ": environ}):
            cluster = distributed.LocalCluster(n_workers=int(options.workers), threads_per_worker=1,
                                               processes=True, host="127.0.0.1", dashboard_address=None,
                                               silence_logs=logging.CRITICAL)
        try:
            client = distributed.Client(cluster, timeout=f"{options.timeout}s")
        except BaseException:
            cluster.close()
            raise
        return client, cluster
    try:
        client = distributed.Client(options.address, timeout=f"{options.timeout}s")
    except (OSError, TimeoutError) as exc:
        raise CadArtifactError(f"--scheduler: cannot reach the Dask scheduler at {options.address!r} within "
                               f"{options.timeout:g} s ({' '.join(str(exc).split()) or type(exc).__name__})") \
            from None
    except ValueError as exc:  # a malformed address
        raise OptionError("--scheduler", "'local' or a scheduler address such as tcp://host:8786",
                          options.address) from exc
    return client, None


@contextlib.contextmanager
def session(options: ClusterOptions):
    """A connected ``distributed.Client`` for the block (:func:`connect`), closed afterwards with its local cluster.

    Raises
    ------
    MissingDependencyError
        ``distributed`` is not installed.
    CadArtifactError
        The scheduler cannot be reached within ``options.timeout``.
    """
    client, cluster = connect(options)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
