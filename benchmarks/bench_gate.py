"""Benchmark: ``cadartifact gate`` over the real files, one process against a process pool.

Run:  python benchmarks/bench_gate.py [--jobs N] [--tol 0.05] [--exclude NAME ...]

Gates every file of ../shared/realdata (STEP and OBJ) with ``run_gate(jobs=1)`` (the baseline,
measured in this same run) and with ``jobs=N`` (default: CPU count), prints the wall times, the
speed-up ratio and the per-file times of the serial run, and checks that both runs give the same
document (the gate's promise: results independent of ``--jobs``). Parallelism is over files, so the
pool's time is bounded below by the slowest file; ``--exclude linkrods.step`` shows the scaling on
the others.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

REALDATA = Path(__file__).resolve().parents[2] / "shared" / "realdata"


def main():
    from cadartifact.gate import build_document, gate_file, run_gate
    from cadartifact.gate_policy import Policy, base_settings, check_cli

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--exclude", nargs="*", default=[], help="file names to leave out")
    args = ap.parse_args()
    if not REALDATA.exists():
        raise SystemExit(f"{REALDATA} not found")
    files = sorted(p for sub in ("step", "obj") for p in (REALDATA / sub).iterdir()
                   if p.is_file() and p.name not in args.exclude)
    policy = Policy(source=None)
    cli = check_cli({"tolerance": args.tol})
    settings = [policy.settings_for(f, cli) for f in files]

    per_file = {}
    t0 = time.perf_counter()
    serial = []
    for f, s in zip(files, settings):
        t = time.perf_counter()
        serial.append(gate_file(str(f), s))
        per_file[f.name] = time.perf_counter() - t
    t_serial = time.perf_counter() - t0

    t0 = time.perf_counter()
    pooled = run_gate(files, settings, jobs=args.jobs)
    t_pool = time.perf_counter() - t0

    base = base_settings(policy, cli)
    same = json.dumps(build_document(serial, base, policy)) == json.dumps(build_document(pooled, base, policy))
    faces = sum(len(e["faces"]) for e in serial)
    print(f"{len(files)} files, {faces} faces, tolerance {args.tol}, {os.cpu_count()} CPU(s)")
    for name, t in sorted(per_file.items(), key=lambda kv: -kv[1]):
        print(f"  {name:40s} {t:7.2f} s (jobs=1)")
    print(f"jobs=1 (baseline): {t_serial:7.2f} s")
    print(f"jobs={args.jobs}:            {t_pool:7.2f} s   speed-up {t_serial / t_pool:4.2f}x")
    print(f"identical documents: {same}")
    if not same:
        a = json.dumps(build_document(serial, base, policy), indent=1).splitlines()
        b = json.dumps(build_document(pooled, base, policy), indent=1).splitlines()
        import difflib

        print("\n".join(list(difflib.unified_diff(a, b, "jobs=1", f"jobs={args.jobs}", n=2))[:40]))
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
