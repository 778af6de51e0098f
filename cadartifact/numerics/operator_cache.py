"""Per-axis operators kept between faces and candidates (least recently used dropped first).

A density search, a scheme comparison and a file of similar faces ask for the same per-direction
operators (intent extensions, candidate bases, scheme syntheses) many times: they depend on a
direction's geometry only, never on the points, so one build serves every net of that size.
"""

from __future__ import annotations

import threading

__all__ = ["OperatorCache", "clear_all"]

_ALL: list = []


class OperatorCache:
    """A bounded mapping ``key -> operator`` in least-recently-used order.

    Parameters
    ----------
    size : int
        Operators kept; the least recently used go first.
    shared : bool
        A module-level cache, emptied by :func:`clear_all`; False for one computation's own (it goes
        with the computation).
    """

    def __init__(self, size: int, shared: bool = True):
        self.size = int(size)
        self._items: dict = {}
        # a Dask worker's threads share the caches: the reorder and the eviction must not interleave
        self._lock = threading.Lock()
        if shared:
            _ALL.append(self)

    def get(self, key, build):
        """The operator of ``key``, built by ``build()`` the first time (and after eviction).

        Safe from several threads; two may build the same operator at once (both results are equal,
        one is kept), since ``build`` runs outside the lock.
        """
        with self._lock:
            got = self._items.pop(key, None)
            if got is not None:
                self._items[key] = got  # most recently used last
                return got
        got = build()
        with self._lock:
            self._items[key] = got
            while len(self._items) > self.size:
                self._items.pop(next(iter(self._items)))
        return got

    def peek(self, key):
        """The operator of ``key`` if kept (then the most recently used), else None; nothing is built."""
        with self._lock:
            got = self._items.pop(key, None)
            if got is not None:
                self._items[key] = got
            return got

    def clear(self) -> None:
        """Drop every operator."""
        with self._lock:
            self._items.clear()

    def __len__(self) -> int:
        return len(self._items)


def clear_all() -> None:
    """Empty every operator cache (benchmarks measure cold runs)."""
    for cache in _ALL:
        cache.clear()
