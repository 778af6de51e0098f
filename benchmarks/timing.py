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


# ---------------------------------------------------------------- whole processes (issue 11's rows)
import os  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from cadartifact.testing.paths import REALDATA  # noqa: E402,F401  (the benchmarks import it from here)

#: The baseline process: OCCT's bare STEP read + transfer of the file, nothing else (same interpreter).
OCCT_READ = ("import sys\n"
             "from OCP.STEPControl import STEPControl_Reader\n"
             "r = STEPControl_Reader()\n"
             "r.ReadFile(sys.argv[1])\n"
             "r.TransferRoots()\n"
             "r.OneShape()\n")


def occt_argv(path) -> list:
    """``python -c <OCCT_READ> FILE``: the bare OCCT read+transfer process of ``path``."""
    return [sys.executable, "-c", OCCT_READ, str(path)]


def cli_argv(*args) -> list:
    """The ``cadartifact`` console script of this interpreter's environment (``python -m`` without one)."""
    script = Path(sys.executable).with_name("cadartifact")
    head = [str(script)] if script.exists() else [sys.executable, "-m", "cadartifact.cli"]
    return head + [str(a) for a in args]


def run_process(argv, ok=(0, 1)) -> tuple[float, int, bytes]:
    """Wall seconds, peak RSS (bytes, the largest process of the child's tree that was waited for) and
    stdout of one process; stderr discarded. ``os.wait4`` gives this child's own rusage, so peaks of
    earlier runs do not leak in (``RUSAGE_CHILDREN`` keeps the maximum over every child so far)."""
    import time

    env = dict(os.environ)
    # the processes run as on a user's machine: Python caches compiled modules (an editable install has
    # no precompiled bytecode, and a PYTHONDONTWRITEBYTECODE left in the environment would make every run
    # recompile the package's modules, 0.1-0.2 s that the OCCT baseline, whose modules come precompiled
    # from its wheel, never pays)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    start = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in ok:
        raise SystemExit(f"{' '.join(map(str, argv))}: exit {proc.returncode}")
    return wall, usage.ru_maxrss * 1024, out


def best_process(argv, repeat: int, ok=(0, 1)) -> tuple[float, int, bytes]:
    """Best wall time of ``repeat`` runs, the largest peak RSS, the last stdout."""
    runs = [run_process(argv, ok) for _ in range(repeat)]
    return min(r[0] for r in runs), max(r[1] for r in runs), runs[-1][2]


def real_step_files() -> list:
    folder = REALDATA / "step"
    return sorted(p for p in folder.iterdir() if p.is_file()) if folder.is_dir() else []


def bench_step_files() -> list:
    """The real STEP files and the synthetic ones of :mod:`synthetic_faces` (extended and jointed faces, a
    non-uniform shell of 40 faces, a 45x12 quintic), written once per run into a temporary folder."""
    import atexit
    import shutil
    import tempfile

    from synthetic_faces import write_all

    folder = tempfile.mkdtemp(prefix="cadartifact-bench-")
    atexit.register(shutil.rmtree, folder, True)
    return real_step_files() + write_all(folder)


def median_worst(ratios) -> tuple[float, float]:
    return statistics.median(ratios), max(ratios)


def print_targets(rows) -> None:
    """``rows``: ``(what, figure text, target text, met: bool | None)``; a table with met / not met."""
    w = [max(len(r[i]) for r in rows + [("what", "figure", "target", None)]) for i in range(3)]
    print(f"\n{'what':{w[0]}}  {'figure':{w[1]}}  {'target':{w[2]}}  met")
    for what, fig, target, met in rows:
        print(f"{what:{w[0]}}  {fig:{w[1]}}  {target:{w[2]}}  {'-' if met is None else 'met' if met else 'NOT MET'}")


def machine() -> str:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{os.cpu_count()} CPU(s), load average {load:.2f} at start"
