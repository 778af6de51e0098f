"""Benchmark: the gate over a vault of >= 1000 files, one process, a Dask LocalCluster, a warm cache.

Run:  python benchmarks/bench_vault.py [--files 1000] [--large 8] [--tol 0.05] [--keep DIR]

Builds a vault in a temporary folder from the samples and the small real files (../shared/realdata
OBJ cages, and ``--large`` copies of its smallest STEP file): every copy has a few control points
moved by up to 1e-3 model units in the file's text, so that every file has different bytes (a
cache hit must be earned, not shared). Then gates it

1. with ``--jobs 1`` and a cold ``--cache`` (the baseline, measured in this same run),
2. with ``--scheduler local`` at 1 worker and at 2 workers (start-up of the cluster included),
3. with ``--jobs 1`` again on the now warm cache,

through :func:`cadartifact.gate.run.run_gate` (what the command line calls), and prints files per
second, the scaling ratio of 2 workers over 1 (target >= 1.7) and the warm-cache speed-up over the
cold run (target >= 20). All four runs must give the same JSON document byte for byte.
"""

from __future__ import annotations

import argparse
import os
import random
import re
import shutil
import tempfile
import time
from pathlib import Path

from cadartifact.testing.paths import REALDATA, SAMPLES

SMALL = [SAMPLES / n for n in ("cage.obj", "car_hood_coarse.step", "clean_panel.step", "hull_freeform.step",
                               "wavy_panel_diagonal.step")]
SMALL_REAL = ["obj/blub_control_mesh.obj", "obj/catmark_xord_boundary.obj", "obj/catmark_xord_interior.obj"]
LARGE_REAL = "step/MAINBODY_BACK.stp"

_STEP_POINT = re.compile(r"CARTESIAN_POINT\('[^']*',\(([^)]*)\)\)")
_OBJ_VERTEX = re.compile(r"^v ([^\n]*)$", re.M)


class Template:
    """A file's text and the spans of its point coordinates, perturbed copy by copy."""

    def __init__(self, path: Path):
        self.path = path
        self.text = path.read_text(errors="surrogateescape")
        pattern = _OBJ_VERTEX if path.suffix.lower() == ".obj" else _STEP_POINT
        self.spans = [m.span(1) for m in pattern.finditer(self.text)]
        if not self.spans:
            raise SystemExit(f"{path}: no point to perturb")

    def copy(self, rng: random.Random, moves: int = 3) -> str:
        chosen = sorted(rng.sample(range(len(self.spans)), min(moves, len(self.spans))))
        out, last = [], 0
        for k in chosen:
            a, b = self.spans[k]
            obj = self.path.suffix.lower() == ".obj"
            sep = " " if obj else ","
            values = self.text[a:b].split() if obj else [v.strip() for v in self.text[a:b].split(",")]
            i = rng.randrange(min(3, len(values)))  # x, y or z (an OBJ vertex may carry a colour after)
            values[i] = repr(float(values[i]) + rng.uniform(-1e-3, 1e-3))
            out += [self.text[last:a], sep.join(values)]
            last = b
        out.append(self.text[last:])
        return "".join(out)


def build_vault(folder: Path, n: int, large: int, seed: int = 0) -> list[Path]:
    """``n`` small files (and ``large`` copies of the smallest real STEP) with perturbed points."""
    rng = random.Random(seed)
    small = SMALL + [REALDATA / r for r in SMALL_REAL if (REALDATA / r).is_file()]
    templates = [Template(p) for p in small]
    files = []
    for k in range(n):
        t = templates[k % len(templates)]
        sub = folder / f"lot{k // 100:03d}"
        sub.mkdir(parents=True, exist_ok=True)
        f = sub / f"{t.path.stem}_{k:05d}{t.path.suffix}"
        f.write_text(t.copy(rng), errors="surrogateescape")
        files.append(f)
    if large and (REALDATA / LARGE_REAL).is_file():
        t = Template(REALDATA / LARGE_REAL)
        (folder / "large").mkdir(exist_ok=True)
        for k in range(large):
            f = folder / "large" / f"{t.path.stem}_{k:03d}{t.path.suffix}"
            f.write_text(t.copy(rng), errors="surrogateescape")
            files.append(f)
    return files


def main():
    from cadartifact.gate.run import build_document, gate_file, run_gate
    from cadartifact.gate.cache import GateCache
    from cadartifact.gate.cluster import ClusterOptions
    from cadartifact.gate.policy import Policy, base_settings, check_cli
    from cadartifact.gate.reports import to_json

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=1000, help="small files in the vault")
    ap.add_argument("--large", type=int, default=8, help=f"copies of {LARGE_REAL} (when present)")
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--keep", type=Path, help="build the vault here and keep it")
    args = ap.parse_args()

    folder = args.keep or Path(tempfile.mkdtemp(prefix="cadartifact-vault-"))
    try:
        t0 = time.perf_counter()
        files = build_vault(folder / "vault", args.files, args.large)
        t_build = time.perf_counter() - t0
        size = sum(f.stat().st_size for f in files)
        print(f"vault: {len(files)} files, {size / 1e6:.1f} MB, built in {t_build:.1f} s; tolerance {args.tol}; "
              f"{os.cpu_count()} CPU(s)")
        policy = Policy(source=None)
        cli = check_cli({"tolerance": args.tol})
        settings = [policy.settings_for(f, cli) for f in files]
        base = base_settings(policy, cli)
        gate_file(str(SMALL[1]), settings[0])  # load OCP and the core once, outside the timings

        def timed(label, **kw):
            first = []

            def progress(entry, cached=False):
                if not first:
                    first.append(time.perf_counter())

            t, c0 = time.perf_counter(), os.times()
            entries = run_gate(files, settings, progress=progress, **kw)
            dt, c1 = time.perf_counter() - t, os.times()
            # CPU time of this process and of the (reaped) cluster processes: on a shared machine the
            # wall time says how much of the cores we got, the CPU time how much work was done
            cpu = sum(getattr(c1, k) - getattr(c0, k) for k in ("user", "system", "children_user", "children_system"))
            load = os.getloadavg()[0]
            print(f"  {label:34s} {dt:8.2f} s  {len(files) / dt:8.1f} files/s   CPU {cpu:6.1f} s   first result "
                  f"after {first[0] - t:5.2f} s   (load average {load:.1f})", flush=True)
            return dt, to_json(build_document(entries, base, policy))

        cache = folder / "cache"
        t_cold, doc_cold = timed("--jobs 1, cold --cache (baseline)", jobs=1, cache=GateCache(cache))
        t_one, doc_one = timed("--scheduler local, 1 worker", cluster=ClusterOptions("local", workers=1))
        t_two, doc_two = timed("--scheduler local, 2 workers", cluster=ClusterOptions("local", workers=2))
        t_warm, doc_warm = timed("--jobs 1, warm --cache", jobs=1, cache=GateCache(cache))
        same = doc_cold == doc_one == doc_two == doc_warm
        errors = doc_cold.count('"verdict": "error"')
        print(f"scaling, 2 workers over 1:     {t_one / t_two:5.2f}x  (target >= 1.7x)")
        print(f"local cluster of 1 over --jobs 1: {t_cold / t_one:5.2f}x  (the cost of Dask)")
        print(f"warm cache over cold:          {t_cold / t_warm:5.1f}x  (target >= 20x)")
        print(f"identical JSON documents (4 runs): {same}; entries with verdict error: {errors}")
        if not same:
            raise SystemExit(1)
    finally:
        if args.keep is None:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
