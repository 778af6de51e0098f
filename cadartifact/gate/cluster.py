"""The gate on a Dask cluster (``cadartifact gate --scheduler ADDRESS``).

Each file is gated by :func:`cadartifact.gate.run.gate_file` on a worker, in a Dask task of its own
when it is big, or with a few other small files (a Dask task costs milliseconds, as much as a small
STEP file: :func:`_batches`); the entries that come back are the records the local gate builds, put back in input order, so every report is the
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

from ..errors import CadArtifactError, MissingDependencyError, OptionError

__all__ = ["ClusterOptions", "EXTRA", "require_distributed", "run_on_cluster"]

EXTRA = 'pip install "cadartifact[dask]"'

#: Test hook: ``NAME`` (a file's base name) makes the worker gating it exit at once, every time;
#: ``NAME:MARKER`` only while the file MARKER does not exist (it is created first: one death).
#: Several specs are separated by commas.
KILL_ENV = "CADARTIFACT_TEST_WORKER_EXIT"

#: Environment of the local cluster's workers (see :func:`_connect`; remote workers: set it where they start).
WORKER_ENVIRON = {"MALLOC_TRIM_THRESHOLD_": "134217728", "MALLOC_MMAP_THRESHOLD_": "134217728"}

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


def gate_task(path: str, payload: bytes | None, settings, verify: bool, part=None) -> dict:
    """Gate one file (or with ``part = (r, k)`` one face batch of it: :func:`cadartifact.gate.run.merge_parts`)
    on a worker; ``payload`` is its bytes with ``--ship`` (else read ``path``)."""
    from .run import gate_file

    _maybe_die(path)
    if payload is None:
        return gate_file(path, settings, verify, part=part)
    import tempfile

    with tempfile.TemporaryDirectory(prefix="cadartifact-ship-") as tmp:
        local = os.path.join(tmp, os.path.basename(path) or "input")
        with open(local, "wb") as fh:
            fh.write(payload)
        entry = gate_file(local, settings, verify, part=part)
    return _relocate_shipped(entry, local, path)


def gate_batch(items: list, version: str | None = None) -> list:
    """Gate ``(path, payload, settings, verify)`` items one after the other on a worker (one Dask task).

    Small files go several to a task: a Dask task costs milliseconds of scheduling, as much as
    gating a small STEP file. ``version``: the client's cadartifact version; a worker running another
    one refuses (its results would differ, and be cached under the client's version).
    """
    from .. import __version__

    if version is not None and version != __version__:
        raise RuntimeError(f"the worker runs cadartifact {__version__}, the client {version}: install the same "
                           "version on both")
    return [gate_task(*item) for item in items]


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
        from .run import _workers_can_start

        if not _workers_can_start():  # spawned workers re-import __main__ by path: '<stdin>' cannot be
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
    from .run import _error_entry

    return _error_entry(path, settings, f"{path}: worker died {deaths} times on this file (a crash in the "
                                        "analysis, or the worker ran out of memory)")


def _failed_entry(task, exc: Exception) -> dict:
    from .run import _error_entry

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


#: A task holds files until their bytes add up to this much (a file as big or bigger goes alone) ...
BATCH_BYTES = 256 * 1024
#: ... or it holds this many files.
BATCH_FILES = 16


def _batches(tasks: list, threads: int) -> list:
    """Task indices grouped into Dask tasks: biggest files first, small files batched.

    Biggest first (size: a cheap proxy for cost) balances the workers' loads, and the small ones
    batched at the end keep the tail short; a batch is also kept small enough that every thread
    gets a few of them.
    """
    order = sorted(range(len(tasks)), key=lambda i: -_size(tasks[i][0]))
    per_thread = max(1, len(tasks) // (4 * max(1, threads)))
    limit = min(BATCH_FILES, per_thread)
    out, batch, held = [], [], 0
    for i in order:
        size = _size(tasks[i][0])
        if batch and (held + size > BATCH_BYTES or len(batch) >= limit):
            out.append(batch)
            batch, held = [], 0
        batch.append(i)
        held += size
    if batch:
        out.append(batch)
    return out


#: A file this big or bigger is also split into face batches when the cluster has more threads than files.
SPLIT_BYTES = BATCH_BYTES
#: At most this many face batches per file (each batch reads the file again).
MAX_PARTS = 8


def _parts(tasks: list, threads: int) -> int:
    """Face batches per big file: as many as leave no thread idle when there are fewer files than
    threads (each batch reads the file again, so a busy cluster gains nothing from them), else 1.
    ``CADARTIFACT_FACE_BATCHES`` sets the count (tests, benchmarks)."""
    forced = os.environ.get("CADARTIFACT_FACE_BATCHES", "").strip()
    if forced:
        try:
            return max(1, min(MAX_PARTS, int(forced)))
        except ValueError:
            raise OptionError("CADARTIFACT_FACE_BATCHES", "a whole number of face batches", forced) from None
    return max(1, min(MAX_PARTS, threads // max(1, len(tasks))))


def _run(client, tasks: list, options: ClusterOptions, done) -> list:
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    from .. import __version__

    token = uuid.uuid4().hex[:12]
    results: list = [None] * len(tasks)

    def submit(batch: list, tag: str, part=None):
        """A future for the files of ``batch`` that could be sent (--ship settles unreadable ones here)."""
        items, sent = [], []
        for i in batch:
            path, settings, verify = tasks[i]
            if options.ship and part is not None:  # a split file's bytes are read once for all its batches
                if i not in payloads:
                    payloads[i] = _payload(path)
                payload = payloads[i] if part[0] < part[1] - 1 else payloads.pop(i)
            else:
                payload = _payload(path) if options.ship else None
            if options.ship and payload is None:  # unreadable here: reported as the local gate reports it
                from .run import gate_file

                if part is None or part[0] == 0:
                    results[i] = gate_file(path, settings, verify)
                    done(results[i])
                continue
            items.append((path, payload, settings, verify, part))
            sent.append(i)
        if not items:
            return None, sent
        where = f"{sent[0]}" if part is None else f"{sent[0]}-part{part[0]}"
        fut = client.submit(gate_batch, items, __version__, key=f"cadartifact-gate-{tag}-{where}-{token}",
                            retries=options.retries, pure=False)
        return fut, sent

    threads = sum(client.nthreads().values()) or 1
    # a bounded window of tasks in flight keeps shipped bytes from piling up in the client and the
    # scheduler; by path, the whole vault is submitted at once (cheaper for the scheduler)
    window = max(16, 4 * threads) if options.ship else None
    futures, killed = {}, []
    pending = as_completed()
    # a big file alone on a cluster with idle threads goes as face batches (read again by each), merged here
    k = _parts(tasks, threads)
    queue_items = []
    for batch in _batches(tasks, threads):
        if k > 1 and len(batch) == 1 and _size(tasks[batch[0]][0]) >= SPLIT_BYTES:
            queue_items += [(batch, (r, k)) for r in range(k)]
        else:
            queue_items.append((batch, None))
    queue = iter(queue_items)
    parts: dict = {}  # file index -> {r: entry}
    payloads: dict = {}  # --ship: a split file's bytes until its last batch is submitted

    def top_up():
        while window is None or len(futures) < window:
            item = next(queue, None)
            if item is None:
                return
            batch, part = item
            fut, sent = submit(batch, "a", part)
            if fut is not None:
                futures[fut] = (sent, part)
                pending.add(fut)

    def finished(i: int, entry: dict, part) -> None:
        if part is None:
            results[i] = entry
            done(entry)
            return
        if i in killed:
            return  # re-run whole below
        got = parts.setdefault(i, {})
        got[part[0]] = entry
        if len(got) == part[1]:
            from .run import merge_parts

            results[i] = merge_parts([got[r] for r in range(part[1])], tasks[i][1])
            done(results[i])

    top_up()
    while futures:
        fut = next(pending)
        batch, part = futures.pop(fut)
        try:
            entries = fut.result()
        except KilledWorker:
            # perhaps only neighbours of the culprit on a dying worker: re-run alone (and whole) below,
            # unless a failed batch has already failed the file
            killed += [i for i in batch if i not in killed and results[i] is None]
            entries = None
        except Exception as exc:  # fail closed: an unexpected failure must not let the files pass
            entries = [_failed_entry(tasks[i], exc) for i in batch]
            if part is not None:  # one failed batch fails the file: no merge, no re-run
                for i, entry in zip(batch, entries):
                    parts.pop(i, None)
                    if i in killed:
                        killed.remove(i)
                    if results[i] is None:
                        results[i] = entry
                        done(entry)
                entries = None
        for i, entry in zip(batch, entries or ()):
            if results[i] is None:
                finished(i, entry, part)
        fut.release()
        top_up()
    for i in sorted(killed):
        fut, _ = submit([i], "alone")
        if fut is None:
            continue
        try:
            results[i] = fut.result()[0]
        except KilledWorker as exc:
            results[i] = _killed_entry(tasks[i][0], tasks[i][1], exc.allowed_failures + 1)
        except Exception as exc:
            results[i] = _failed_entry(tasks[i], exc)
        done(results[i])
    return results
