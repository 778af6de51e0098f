"""Cost of recognising canonical faces (cadartifact.exchange.canonical) against OCCT's read, in the same run.

    python benchmarks/bench_canonical.py [--repeat N]

Per real STEP file (../shared/realdata/step): best-of-N wall time of OCCT's
``STEPControl_Reader.ReadFile + TransferRoots`` (the baseline), of the face walk and net extraction
``nets_from_shape(recognise=False)``, and of the same with recognition (``recognise=True``). The
recognition's cost is the difference: per analysable face, and as a share of the baseline read.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

from timing import best_of  # benchmarks/timing.py, beside this script

from cadartifact.testing.paths import REALDATA


def occt_read(path: Path):
    from OCP.STEPControl import STEPControl_Reader

    from cadartifact.exchange.occ import quiet_occt

    reader = STEPControl_Reader()
    with quiet_occt():
        reader.ReadFile(str(path))
        reader.TransferRoots()
    return reader.OneShape()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    files = sorted((REALDATA / "step").glob("*")) if REALDATA.exists() else []
    if not files:
        print(f"{REALDATA / 'step'} not present: nothing to measure")
        return 0
    from cadartifact.exchange.occ import nets_from_shape

    warnings.simplefilter("ignore")
    occt_read(files[0])  # warm up OCCT's STEP schema tables
    print(f"canonical-face recognition (best of {args.repeat}, interleaved) against OCCT read+transfer")
    print(f"{'file':34s} {'nets':>5s} {'canon':>6s} {'occt ms':>9s} {'extract ms':>11s} {'+recog ms':>10s} "
          f"{'ms/face':>8s} {'% of read':>10s}")
    shares = []
    for path in files:
        shape = occt_read(path)
        read_t, plain_t, recog_t = [], [], []
        for _ in range(args.repeat):  # interleaved: machine-load drift hits all three alike
            read_t.append(best_of(lambda: occt_read(path), 1))
            plain_t.append(best_of(lambda: nets_from_shape(shape, recognise=False), 1))
            recog_t.append(best_of(lambda: nets_from_shape(shape, recognise=True), 1))
        nets = nets_from_shape(shape)[0]
        canonical = sum(1 for n in nets if n.canonical)
        cost = max(min(recog_t) - min(plain_t), 0.0)
        share = cost / min(read_t)
        shares.append(share)
        print(f"{path.name:34s} {len(nets):5d} {canonical:6d} {1e3 * min(read_t):9.1f} {1e3 * min(plain_t):11.1f} "
              f"{1e3 * cost:10.1f} {1e3 * cost / max(len(nets), 1):8.2f} {100 * share:9.1f}%")
    print(f"recognition cost: {100 * min(shares):.1f}-{100 * max(shares):.1f} % of OCCT's read")
    return 0


if __name__ == "__main__":
    start = time.perf_counter()
    code = main()
    print(f"({time.perf_counter() - start:.1f} s)")
    sys.exit(code)
