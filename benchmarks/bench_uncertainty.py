"""Benchmark: the cost of the intent's uncertainty U (issue 22) as a share of the advice's own time.

Run:  python benchmarks/bench_uncertainty.py [--reading net|surface|both] [--files N] [--repeat 1] [--profile]

Per B-spline face of ``samples/*.step`` and of the first ``--files`` real STEP files of
../shared/realdata/step (read in place), in this process: ``advise_for(net, settings, compare=False,
verify=False)`` at ``--tol`` (0.05 mm) with the reading asked for, caches cleared before each face
(``advice.advise.clear_caches()``: every per-axis operator cache, a cold face as a gate run meets it). The time
spent inside :func:`cadartifact.analysis.uncertainty.intent_uncertainty` during that same call is timed by a
wrapper, so the ratio needs no second run:

    share = U time / (advise time - U time)

(U over the rest of the advice; issue 22 asks U to cost at most a quarter of today's advise time). Figures
per file and in all; best of ``--repeat`` runs per face. ``--gate``: also a gate face that gets no advice (today's budget, then today's U: U over the
budget alone). ``--profile``: cProfile of U's calls, the top
entries by cumulative time. Timings on a shared machine are noisy; the ratio is taken inside each call.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from timing import REALDATA, real_step_files

ROOT = Path(__file__).resolve().parents[1]


def _files(count: int) -> list:
    return sorted((ROOT / "samples").glob("*.step")) + real_step_files()[:count]


def _nets(path):
    from cadartifact.exchange.load import read

    return [n for n in read(path).nets if n.is_bspline]


class _Timer:
    """Wraps ``intent_uncertainty`` (the module attribute every caller imports at call time) and sums its
    wall time; nested calls (a split face's pieces) are counted once."""

    def __init__(self, profile=None):
        import cadartifact.analysis.uncertainty as mod

        self.mod, self.inner, self.total, self.depth, self.profile = mod, mod.intent_uncertainty, 0.0, 0, profile

    def __enter__(self):
        def timed(*a, **k):
            self.depth += 1
            start = time.perf_counter()
            try:
                if self.profile is not None and self.depth == 1:
                    return self.profile.runcall(self.inner, *a, **k)
                return self.inner(*a, **k)
            finally:
                self.depth -= 1
                if self.depth == 0:
                    self.total += time.perf_counter() - start

        self.mod.intent_uncertainty = timed
        return self

    def __exit__(self, *exc):
        self.mod.intent_uncertainty = self.inner


def _clear():
    from cadartifact.advice.advise import clear_caches

    clear_caches()


def face_times(net, settings, repeat: int, profile=None) -> tuple[float, float]:
    """``(advise seconds, U seconds)`` of one cold face, the run with the smallest advise time."""
    from cadartifact.advice.advise import advise_for

    best = None
    for _ in range(repeat):
        _clear()
        with _Timer(profile) as tm:
            start = time.perf_counter()
            advise_for(net, settings, compare=False, verify=False)
            wall = time.perf_counter() - start
        if best is None or wall < best[0]:
            best = (wall, tm.total)
    return best


def gate_times(net, settings, repeat: int) -> tuple[float, float]:
    """``(budget seconds, U seconds)`` of one cold face as the gate's verdict computes it without advice
    (:func:`cadartifact.runs.face.start_face`: today's budget, then today's U), best of ``repeat``."""
    from cadartifact.advice.decision import face_uncertainty
    from cadartifact.analysis.budget import budget_for

    best = None
    for _ in range(repeat):
        _clear()
        start = time.perf_counter()
        current = budget_for(net, settings, keep_fields=settings.reading == "surface")
        mid = time.perf_counter()
        face_uncertainty(net, settings, current)
        end = time.perf_counter()
        if best is None or mid - start < best[0]:
            best = (mid - start, end - mid)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--reading", choices=("net", "surface", "both"), default="both")
    ap.add_argument("--files", type=int, default=3, help="real STEP files (first N by name)")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--gate", action="store_true",
                    help="also U over today's budget alone (a gate face that gets no advice)")
    args = ap.parse_args(argv)
    import os

    from cadartifact.analysis.settings import RunSettings

    profile = None
    if args.profile:
        import cProfile

        profile = cProfile.Profile()
    readings = ("net", "surface") if args.reading == "both" else (args.reading,)
    files = _files(args.files)
    if not REALDATA.exists():
        print(f"(no real files at {REALDATA}: samples only)", file=sys.stderr)
    print(f"{time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}, "
          f"tol {args.tol:g}, best of {args.repeat}")
    print("| reading | file | faces | advise (s) | U (s) | U / (advise - U) |")
    print("|---|---|---|---|---|---|")
    for reading in readings:
        settings = RunSettings(tolerance=args.tol, intent=reading)
        A = Us = 0.0
        faces = 0
        for path in files:
            a = u = 0.0
            nets = _nets(path)
            for net in nets:
                wa, wu = face_times(net, settings, args.repeat, profile)
                a, u = a + wa, u + wu
            faces += len(nets)
            A, Us = A + a, Us + u
            print(f"| {reading} | {path.name} | {len(nets)} | {a:.2f} | {u:.2f} | {u / max(a - u, 1e-12):.1%} |")
            sys.stdout.flush()
        print(f"| {reading} | **all** | {faces} | {A:.2f} | {Us:.2f} | **{Us / max(A - Us, 1e-12):.1%}** |")
        if args.gate:
            B = G = 0.0
            for path in files:
                for net in _nets(path):
                    b, g = gate_times(net, settings, args.repeat)
                    B, G = B + b, G + g
            print(f"| {reading} | gate, no advice: today's budget {B:.2f} s, U {G:.2f} s | {faces} | | | "
                  f"U / budget {G / max(B, 1e-12):.1%} |")
    print(f"load at the end {os.getloadavg()[0]:.2f}")
    if profile is not None:
        import pstats

        pstats.Stats(profile).sort_stats("cumulative").print_stats(25)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
