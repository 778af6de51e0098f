"""Benchmark: ``cadartifact gate`` as whole processes, against OCCT's bare read of the same file (issue 11).

Run:  python benchmarks/bench_gate.py [--repeat 3] [--quick] [--tol 0.05]

Rows (each a ratio against a baseline measured in this same run):

- ``gate FILE --tol 0.05`` (the console script, text report to a pipe) vs a bare OCCT read+transfer
  process of the same file (``python -c`` importing OCP, ``STEPControl_Reader.ReadFile`` +
  ``TransferRoots``), per STEP file of ../shared/realdata/step and of benchmarks/synthetic_faces.py (extended and jointed faces, a 40-face non-uniform shell, a 45x12 quintic): median and worst ratio of the best
  of ``--repeat`` runs each, interleaved (target: median <= 1.2x, worst <= 1.5x).
- ``gate --jobs 2`` vs ``gate --jobs 1`` over every real file (STEP and OBJ): speed-up (target
  >= 1.7x), and the two JSON documents must be identical (results do not depend on ``--jobs``).

``--quick``: one run per measurement (about a minute); default three (about three minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import time

from timing import (REALDATA, best_process, cli_argv, machine, median_worst, occt_argv, print_targets,  # noqa: E402
                    bench_step_files)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one run per measurement")
    ap.add_argument("--tol", type=float, default=0.05)
    args = ap.parse_args()
    repeat = 1 if args.quick else args.repeat
    files = bench_step_files()
    if not files:
        raise SystemExit(f"no real STEP files in {REALDATA / 'step'}")
    print(f"{time.strftime('%Y-%m-%d %H:%M')}, {machine()}, best of {repeat}")
    print(f"{'file':34s} {'OCCT read':>10s} {'gate':>8s} {'ratio':>6s}")
    ratios = []
    for path in files:
        base, gate = float("inf"), float("inf")
        for _ in range(repeat):  # interleaved: a load spike hits both
            base = min(base, best_process(occt_argv(path), 1, ok=(0,))[0])
            gate = min(gate, best_process(cli_argv("gate", path, "--tol", args.tol), 1)[0])
        ratios.append(gate / base)
        print(f"{path.name:34s} {base:10.2f} {gate:8.2f} {gate / base:6.2f}")
    med, worst = median_worst(ratios)

    every = sorted(p for sub in ("step", "obj") if (REALDATA / sub).is_dir() for p in (REALDATA / sub).iterdir()
                   if p.is_file())
    common = ("gate", *every, "--tol", args.tol, "--format", "json")
    t1 = t2 = float("inf")
    for _ in range(repeat):
        w1, _, out1 = best_process(cli_argv(*common, "--jobs", 1), 1)
        w2, _, out2 = best_process(cli_argv(*common, "--jobs", 2), 1)
        t1, t2 = min(t1, w1), min(t2, w2)
    same = json.loads(out1) == json.loads(out2)
    faces = sum(len(e["faces"]) for e in json.loads(out1)["files"])
    print(f"\nall {len(every)} real files ({faces} faces): --jobs 1 {t1:.2f} s, --jobs 2 {t2:.2f} s, "
          f"identical documents: {same}")
    print_targets([
        ("gate FILE --tol 0.05 vs OCCT read process, median", f"{med:.2f}x", "<= 1.2x", med <= 1.2),
        ("gate FILE --tol 0.05 vs OCCT read process, worst", f"{worst:.2f}x", "<= 1.5x", worst <= 1.5),
        ("gate --jobs 2 vs --jobs 1, all real files", f"{t1 / t2:.2f}x", ">= 1.7x", t1 / t2 >= 1.7),
    ])
    if not same:
        raise SystemExit("the documents of --jobs 1 and --jobs 2 differ")


if __name__ == "__main__":
    main()
