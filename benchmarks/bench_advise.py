"""Benchmark: whole ``advise`` per real STEP file against OCCT's own read+transfer, and per-face advice time.

Run:  python benchmarks/bench_advise.py [--repeat 3]

Prints, per file, the best-of-N seconds of OCCT's bare ``STEPControl_Reader`` read + transfer
(the baseline, measured in this same run) and of cadartifact's load + advise of every B-spline face,
with the ratio (target < 1.5x with the fast options: no scheme comparison, no OCCT verification;
the default options are shown too). Then per-face advice time for synthetic nets up to 100x100.
Every run starts with cold caches (``advice.clear_caches``), as a gate that opens each file once.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from timing import best_of  # noqa: E402  (benchmarks/timing.py, beside this script)

REALDATA = Path(__file__).resolve().parents[2] / "shared" / "realdata" / "step"




def occt_read(path):
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    r = STEPControl_Reader()
    assert r.ReadFile(str(path)) == IFSelect_RetDone
    r.TransferRoots()
    return r.OneShape()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    import cadartifact as ca
    from cadartifact.exchange import load
    from cadartifact.advice import clear_caches

    ca.load  # warm imports
    print(f"{'file':34s} {'faces':>5s} {'OCCT read':>10s} {'advise fast':>12s} {'ratio':>6s} {'advise full':>12s} {'ratio':>6s}")
    if REALDATA.is_dir():
        for path in sorted(REALDATA.iterdir()):
            base = best_of(lambda: occt_read(path), args.repeat)
            nets = load(path)

            def fast():
                clear_caches()  # cold: a gate analyses each file once
                for n in load(path):
                    ca.advise(n, 0.05, compare=False, verify=False)

            def full():
                clear_caches()
                for n in load(path):
                    ca.advise(n, 0.05)

            tf = best_of(fast, args.repeat)
            tF = best_of(full, 1)
            print(f"{path.name:34s} {len(nets):5d} {base:10.3f} {tf:12.3f} {tf / base:6.2f} {tF:12.3f} {tF / base:6.2f}")
    else:
        print(f"(no real data at {REALDATA})")

    print("\nper-face advice, predicted path (no comparison, no verification), best of", args.repeat)
    print(f"{'net':>9s} {'ms/face':>9s}")
    rng = np.random.default_rng(0)
    for n in (10, 30, 60, 100):
        i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        z = np.cos(2 * np.pi * (i + 0.5 * j) / (n / 3.0)) + 0.01 * rng.normal(size=i.shape)
        net = ca.ControlNet.from_points(np.stack([i * 1.0, j * 1.0, z], axis=-1), degrees=(3, 3))
        def one():
            clear_caches()  # cold: every face of a file has its own sizes
            ca.advise(net, 0.05, compare=False, verify=False)

        t = best_of(one, args.repeat)
        print(f"{n:4d}x{n:<4d} {t * 1e3:9.1f}")


if __name__ == "__main__":
    main()
