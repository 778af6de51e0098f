"""One interface for running a function over items: ``executor.map(function, items, done) -> results``.

Results come back in the items' order whatever the completion order, so a document does not depend on the
backend. :class:`SerialExecutor` runs in this process; :class:`ProcessPool` in local worker processes, and a
worker that dies (a crash in native code) costs only the item that killed it. The Dask backend is
:mod:`cadartifact.execution.dask`.
"""

from __future__ import annotations

import os
import sys
from typing import Callable, Protocol

__all__ = ["Executor", "ProcessPool", "SerialExecutor", "pool_context", "workers_can_start"]


class Executor(Protocol):
    """What runs a function over items."""

    def map(self, function: Callable, items: list, done: Callable | None = None) -> list:
        """``[function(item) for item in items]`` in the items' order; ``done(result)`` as each is known."""


class SerialExecutor:
    """Every item in this process, in order."""

    def map(self, function: Callable, items: list, done: Callable | None = None) -> list:
        """``function(item)`` per item, in order; ``done(result)`` after each."""
        out = []
        for item in items:
            out.append(function(item))
            if done:
                done(out[-1])
        return out


def pool_context():
    """The start method of worker processes: a fork server where there is one, else spawn.

    Not fork: OCCT is not fork-safe once loaded, and the parent may hold threads (rich's refresh thread)."""
    import multiprocessing as mp

    methods = mp.get_all_start_methods()
    return mp.get_context("forkserver" if "forkserver" in methods else "spawn")


def workers_can_start() -> bool:
    """Whether spawned workers can re-create ``__main__`` (they re-import it by path).

    A program read from stdin (``__file__ == "<stdin>"``) cannot be: every worker would die at start,
    so such callers are served in-process.
    """
    main = sys.modules.get("__main__")
    if getattr(getattr(main, "__spec__", None), "name", None):
        return True
    path = getattr(main, "__file__", None)
    return path is None or os.path.isfile(path)


class ProcessPool:
    """Items in a pool of local worker processes.

    Parameters
    ----------
    workers : int
        Processes (at most one per item).
    initializer : callable, optional
        Run once in each worker as it starts, with ``initargs``.
    initargs : tuple
    crashed : callable(item) -> result, optional
        The result of an item whose worker died even when it ran alone. Without it the
        :class:`~concurrent.futures.process.BrokenProcessPool` is raised.
    cost : callable(item) -> float, optional
        An estimate of the item's cost: the costliest go first, which balances the workers' loads.

    Notes
    -----
    After a worker dies, the items left are rerun one per pool, so that only the culprit is blamed.
    """

    def __init__(self, workers: int, *, initializer: Callable | None = None, initargs: tuple = (),
                 crashed: Callable | None = None, cost: Callable | None = None):
        self.workers = max(1, int(workers))
        self.initializer, self.initargs = initializer, tuple(initargs)
        self.crashed, self.cost = crashed, cost

    def map(self, function: Callable, items: list, done: Callable | None = None) -> list:
        """``function(item)`` per item in the workers (``function`` and the items picklable); results in order."""
        from concurrent.futures import ProcessPoolExecutor, as_completed
        from concurrent.futures.process import BrokenProcessPool

        results: list = [None] * len(items)
        pending = list(range(len(items)))
        isolate = False
        while pending:
            # after a crash, rerun what is left one item per pool, so the culprit is known
            batches = [[i] for i in pending] if isolate else [pending]
            pending = []
            for batch in batches:
                with ProcessPoolExecutor(max_workers=1 if isolate else min(self.workers, len(batch)),
                                         mp_context=pool_context(), initializer=self.initializer,
                                         initargs=self.initargs) as ex:
                    order = sorted(batch, key=lambda i: -self.cost(items[i])) if self.cost else batch
                    futures = {ex.submit(function, items[i]): i for i in order}
                    for fut in as_completed(futures):
                        i = futures[fut]
                        try:
                            results[i] = fut.result()
                        except BrokenProcessPool:
                            if not isolate:
                                pending.append(i)
                                continue
                            if self.crashed is None:
                                raise
                            results[i] = self.crashed(items[i])
                        if done:
                            done(results[i])
            pending.sort()
            isolate = True
        return results
