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

The connection is the execution wing's Dask backend (:mod:`cadartifact.execution.dask`, which imports
``distributed`` only when a scheduler is asked for: the optional extra ``pip install "cadartifact[dask]"``); the
options are :class:`~cadartifact.execution.settings.ClusterOptions`, part of the run's
:class:`~cadartifact.execution.settings.ExecutionSettings`.
"""

from __future__ import annotations

import os
import uuid

from ..execution.dask import EXTRA, require_distributed, session
from ..execution.settings import ClusterOptions

__all__ = ["ClusterOptions", "EXTRA", "require_distributed", "run_on_cluster"]


# ---------------------------------------------------------------- worker side
def _maybe_die(path: str, specs: str) -> None:
    """The test hook :attr:`ClusterOptions.worker_exit <cadartifact.execution.settings.ClusterOptions>`."""
    for spec in filter(None, specs.split(",")):
        name, _, marker = spec.partition(":")
        if os.path.basename(path) != name:
            continue
        if marker:
            try:
                os.close(os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            except FileExistsError:
                continue
        os._exit(17)


def gate_task(gate_file, path: str, payload: bytes | None, settings, verify: bool, part=None,
              worker_exit: str = "", reuse: bool = True) -> dict:
    """Gate one file (or with ``part = (r, k)`` one face batch of it: :func:`cadartifact.gate.run.merge_parts`)
    on a worker with ``gate_file`` (:func:`cadartifact.gate.run.gate_file`, passed by the run: this module does
    not import it); ``payload`` is its bytes with ``--ship`` (else read ``path``); ``worker_exit``: the test hook
    :attr:`ClusterOptions.worker_exit <cadartifact.execution.settings.ClusterOptions>`."""
    _maybe_die(path, worker_exit)
    if payload is None:
        return gate_file(path, settings, verify, part=part, reuse=reuse)
    import tempfile

    with tempfile.TemporaryDirectory(prefix="cadartifact-ship-") as tmp:
        local = os.path.join(tmp, os.path.basename(path) or "input")
        with open(local, "wb") as fh:
            fh.write(payload)
        entry = gate_file(local, settings, verify, part=part, reuse=reuse)
    return _relocate_shipped(entry, local, path)


def gate_batch(gate_file, items: list, version: str | None = None, execution=None) -> list:
    """Gate ``(path, payload, settings, verify, part, worker_exit)`` items one after the other on a worker (one
    Dask task) with ``gate_file``, its reader child run under ``execution`` (the run's
    :class:`~cadartifact.execution.settings.ExecutionSettings`; None: the worker's own).

    Small files go several to a task: a Dask task costs milliseconds of scheduling, as much as
    gating a small STEP file. ``version``: the client's cadartifact version; a worker running another
    one refuses (its results would differ, and be cached under the client's version).
    """
    from .. import __version__

    if version is not None and version != __version__:
        raise RuntimeError(f"the worker runs cadartifact {__version__}, the client {version}: install the same "
                           "version on both")
    from ..execution.child import configured

    with configured(execution):
        return [gate_task(gate_file, *item, reuse=True if execution is None else execution.reuse_faces)
                for item in items]


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


def _killed_entry(gate, path: str, settings, deaths: int) -> dict:
    return gate._error_entry(path, settings, f"{path}: worker died {deaths} times on this file (a crash in the "
                                        "analysis, or the worker ran out of memory)")


def _failed_entry(gate, task, exc: Exception) -> dict:
    path, settings, _ = task
    return gate._error_entry(path, settings, f"{path}: analysis failed on the cluster ({type(exc).__name__}: {exc})")


def run_on_cluster(tasks: list, options: ClusterOptions, done, execution=None, gate=None) -> list:
    """Gate ``(path, settings, verify)`` tasks on Dask; entries in input order.

    Parameters
    ----------
    tasks : list of tuple
    options : ClusterOptions
    done : callable
        ``done(entry)`` after each file, in completion order.
    execution : ExecutionSettings, optional
        The run's (the workers' reader children run under it: its read timeout, isolation).
    gate : module
        :mod:`cadartifact.gate.run`, which calls this (:func:`~cadartifact.gate.run.run_gate`): its ``gate_file``,
        ``merge_parts``, ``_error_entry``; passed, not imported, since the run imports this module.

    Raises
    ------
    MissingDependencyError
        ``distributed`` is not installed.
    CadArtifactError
        The scheduler cannot be reached within ``options.timeout``.
    """
    if not tasks:
        return []
    with session(options) as client:
        return _run(client, tasks, options, done, execution, gate)


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


def _parts(tasks: list, threads: int, forced: int | None = None) -> int:
    """Face batches per big file: as many as leave no thread idle when there are fewer files than
    threads (each batch reads the file again, so a busy cluster gains nothing from them), else 1.
    ``forced`` (:attr:`ClusterOptions.face_batches <cadartifact.execution.settings.ClusterOptions>`) sets the
    count (tests, benchmarks)."""
    if forced is not None:
        return max(1, min(MAX_PARTS, int(forced)))
    return max(1, min(MAX_PARTS, threads // max(1, len(tasks))))


def _run(client, tasks: list, options: ClusterOptions, done, execution, gate) -> list:
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
                if part is None or part[0] == 0:
                    results[i] = gate.gate_file(path, settings, verify)
                    done(results[i])
                continue
            items.append((path, payload, settings, verify, part, options.worker_exit))
            sent.append(i)
        if not items:
            return None, sent
        where = f"{sent[0]}" if part is None else f"{sent[0]}-part{part[0]}"
        fut = client.submit(gate_batch, gate.gate_file, items, __version__, execution, key=f"cadartifact-gate-{tag}-{where}-{token}",
                            retries=options.retries, pure=False)
        return fut, sent

    threads = sum(client.nthreads().values()) or 1
    # a bounded window of tasks in flight keeps shipped bytes from piling up in the client and the
    # scheduler; by path, the whole vault is submitted at once (cheaper for the scheduler)
    window = max(16, 4 * threads) if options.ship else None
    futures, killed = {}, []
    pending = as_completed()
    # a big file alone on a cluster with idle threads goes as face batches (read again by each), merged here
    k = _parts(tasks, threads, options.face_batches)
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
            results[i] = gate.merge_parts([got[r] for r in range(part[1])], tasks[i][1])
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
            entries = [_failed_entry(gate, tasks[i], exc) for i in batch]
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
            results[i] = _killed_entry(gate, tasks[i][0], tasks[i][1], exc.allowed_failures + 1)
        except Exception as exc:
            results[i] = _failed_entry(gate, tasks[i], exc)
        done(results[i])
    return results
