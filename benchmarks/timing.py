"""Shared timing helper for the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

import time


def best_of(fn, repeat: int) -> float:
    """Best (smallest) wall time in seconds of ``repeat`` calls of ``fn()``."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)
