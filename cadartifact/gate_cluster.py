"""The gate on a Dask cluster (``cadartifact gate --scheduler ADDRESS``).

Each file is one Dask task running :func:`cadartifact.gate.gate_file` on a worker; the entries that
come back are the records the local gate builds, put back in input order, so every report is the
same byte for byte as ``--jobs 1`` whatever the cluster, the worker count or the completion order.
``--scheduler local`` starts a :class:`distributed.LocalCluster` of ``--jobs`` worker processes with
one thread each (the analysis holds the GIL; one BLAS thread per worker, as in the local pool).

Files travel by path (the workers must see the same paths: shared storage) or, with ``ship=True``,
as bytes: the worker writes them to a temporary file of the same name and reads that, and the
entry is relocated to the original path.

Faults: tasks are submitted with ``retries`` (for exceptions) and the scheduler re-runs the task of
a worker that died. A task whose workers kept dying (Dask's ``KilledWorker``, after
``distributed.scheduler.allowed-failures`` deaths) is then re-run alone, so that a file merely
sharing a dying worker with the culprit is not blamed; a file that still kills its workers becomes
an ``error`` entry ("worker died N times on this file") and the run fails closed.

``distributed`` is imported only here, and only when a scheduler is asked for: the optional extra
``pip install "cadartifact[dask]"``.
"""

from __future__ import annotations

import os
import uuid
from dataclasses import dataclass

from .errors import CadArtifactError, MissingDependencyError, OptionError

__all__ = ["ClusterOptions", "EXTRA", "require_distributed", "run_on_cluster"]

EXTRA = 'pip install "cadartifact[dask]"'

#: Test hook: ``NAME`` (a file's base name) makes the worker gating it exit at once, every time;
#: ``NAME:MARKER`` only while the file MARKER does not exist (it is created first: one death).
#: Several specs are separated by commas.
KILL_ENV = "CADARTIFACT_TEST_WORKER_EXIT"

#: Worker deaths a task is allowed on the local cluster before Dask gives up on it.
LOCAL_ALLOWED_FAILURES = 2


@dataclass(frozen=True)
class ClusterOptions:
    """Where and how to run the gate on Dask.

    Attributes
    ----------
    address : str
        ``"local"`` or a scheduler address (``tcp://host:8786``, ``host:8786``).
    workers : int
        Worker processes of the local cluster (ignored for a remote scheduler).
    ship : bool
        Send the files' bytes instead of their paths.
    timeout : float
        Seconds to wait for the scheduler.
    retries : int
        Dask task retries on an exception.
    """

    address: str
    workers: int = 1
    ship: bool = False
    timeout: float = 10.0
    retries: int = 2

    def __post_init__(self):
        if not isinstance(self.address, str) or not self.address.strip():
            raise OptionError("--scheduler", "'local' or a scheduler address such as tcp://host:8786", self.address)
        if not (self.timeout > 0):
            raise OptionError("--scheduler-timeout", "a number of seconds > 0", self.timeout)
        if int(self.workers) < 1:
            raise OptionError("--jobs", "a number of processes >= 1", self.workers)

    def run(self, tasks: list, done) -> list:
        return run_on_cluster(tasks, self, done)


def require_distributed():
    """Import ``distributed`` or raise :class:`MissingDependencyError` naming the extra."""
    try:
        import distributed
    except ImportError as exc:
        raise MissingDependencyError(f"--scheduler needs dask.distributed, which could not be imported ({exc}); "
                                     f"install it with: {EXTRA}") from None
    return distributed


# ---------------------------------------------------------------- worker side
def _maybe_die(path: str) -> None:
    for spec in filter(None, os.environ.get(KILL_ENV, "").split(",")):
        name, _, marker = spec.partition(":")
        if os.path.basename(path) != name:
            continue
        if marker:
            try:
                os.close(os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            except FileExistsError:
                continue
        os._exit(17)


def gate_task(path: str, payload: bytes | None, settings, verify: bool) -> dict:
    """Gate one file on a worker; ``payload`` is its bytes with ``--ship`` (else read ``path``)."""
    from .gate import gate_file

    _maybe_die(path)
    if payload is None:
        return gate_file(path, settings, verify)
    import tempfile

    from .gate_cache import relocate

    with tempfile.TemporaryDirectory(prefix="cadartifact-ship-") as tmp:
        local = os.path.join(tmp, os.path.basename(path) or "input")
        with open(local, "wb") as fh:
            fh.write(payload)
        entry = gate_file(local, settings, verify)
    return _relocate_shipped(entry, local, path)


def _relocate_shipped(entry: dict, local: str, path: str) -> dict:
    # the temporary folder's name is random, so every occurrence of it names the shipped file
    def sub(obj):
        if isinstance(obj, str):
            return obj.replace(local, path)
        if isinstance(obj, dict):
            return {k: sub(v) for k, v in obj.items()}
        if isinstance(obj, list):
            return [sub(v) for v in obj]
        if isinstance(obj, tuple):
            return tuple(sub(v) for v in obj)
        return obj

    return sub(entry)


# ---------------------------------------------------------------- client side
def _connect(options: ClusterOptions):
    """A ``(client, cluster or None)`` pair; one-line errors for an unreachable scheduler."""
    import logging

    distributed = require_distributed()
    import dask

    # the cluster's own chatter (a worker restarted after a death...) would bury the gate's report
    for name in ("distributed", "distributed.nanny", "distributed.scheduler", "distributed.worker"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
    if options.address == "local":
        from .gate import _workers_can_start

        if not _workers_can_start():  # spawned workers re-import __main__ by path: '<stdin>' cannot be
            raise CadArtifactError("--scheduler local: worker processes cannot be started from a program read "
                                   "from standard input; run it from a file, or give a scheduler address")
        with dask.config.set({"distributed.scheduler.allowed-failures": LOCAL_ALLOWED_FAILURES}):
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


def _size(path: str) -> int:
    try:
        return os.path.getsize(path)
    except OSError:
        return 0


def _payload(path: str) -> bytes | None:
    try:
        with open(path, "rb") as fh:
            return fh.read()
    except OSError:
        return None


def _killed_entry(path: str, settings, deaths: int) -> dict:
    from .gate import _error_entry

    return _error_entry(path, settings, f"{path}: worker died {deaths} times on this file (a crash in the "
                                        "analysis, or the worker ran out of memory)")


def _failed_entry(task, exc: Exception) -> dict:
    from .gate import _error_entry

    path, settings, _ = task
    return _error_entry(path, settings, f"{path}: analysis failed on the cluster ({type(exc).__name__}: {exc})")


def run_on_cluster(tasks: list, options: ClusterOptions, done) -> list:
    """Gate ``(path, settings, verify)`` tasks on Dask; entries in input order.

    Parameters
    ----------
    tasks : list of tuple
    options : ClusterOptions
    done : callable
        ``done(entry)`` after each file, in completion order.

    Raises
    ------
    MissingDependencyError
        ``distributed`` is not installed.
    CadArtifactError
        The scheduler cannot be reached within ``options.timeout``.
    """
    if not tasks:
        return []
    client, cluster = _connect(options)
    try:
        return _run(client, tasks, options, done)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _run(client, tasks: list, options: ClusterOptions, done) -> list:
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    token = uuid.uuid4().hex[:12]
    results: list = [None] * len(tasks)

    def submit(i: int, tag: str):
        """A future for task ``i``, or None when it was settled here (a file --ship cannot read)."""
        path, settings, verify = tasks[i]
        payload = _payload(path) if options.ship else None
        if options.ship and payload is None:  # unreadable here: reported as the local gate reports it
            from .gate import gate_file

            results[i] = gate_file(path, settings, verify)
            done(results[i])
            return None
        return client.submit(gate_task, path, payload, settings, verify, key=f"cadartifact-gate-{tag}-{i}-{token}",
                             retries=options.retries, pure=False)

    # biggest files first (a cheap proxy for their cost) balances the workers' loads; a bounded
    # window of tasks in flight keeps shipped bytes from piling up in the client and the scheduler
    order = sorted(range(len(tasks)), key=lambda i: -_size(tasks[i][0]))
    threads = sum(client.nthreads().values()) or 1
    window = max(16, 4 * threads)
    futures, killed = {}, []
    pending = as_completed()
    queue = iter(order)

    def top_up():
        while len(futures) < window:
            i = next(queue, None)
            if i is None:
                return
            fut = submit(i, "a")
            if fut is not None:
                futures[fut] = i
                pending.add(fut)

    top_up()
    while futures:
        fut = next(pending)
        i = futures.pop(fut)
        try:
            results[i] = fut.result()
        except KilledWorker:
            killed.append(i)  # perhaps only a neighbour of the culprit on a dying worker: re-run alone below
        except Exception as exc:  # fail closed: an unexpected failure must not let the file pass
            results[i] = _failed_entry(tasks[i], exc)
        if results[i] is not None:
            done(results[i])
        fut.release()
        top_up()
    for i in sorted(killed):
        fut = submit(i, "alone")
        if fut is None:
            continue
        try:
            results[i] = fut.result()
        except KilledWorker as exc:
            results[i] = _killed_entry(tasks[i][0], tasks[i][1], exc.allowed_failures + 1)
        except Exception as exc:
            results[i] = _failed_entry(tasks[i], exc)
        done(results[i])
    return results
