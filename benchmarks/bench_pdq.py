"""Benchmark: what the PDQ criteria (``gate --profile default``, issue 25) add to ``cadartifact gate``.

Run:  python benchmarks/bench_pdq.py [--repeat 3] [--quick] [--tol 0.05]

Per real file of ../shared/realdata (STEP and OBJ): the console script ``gate FILE --tol 0.05 --jobs 1`` with
``--profile default`` against the same command without a profile (the gate before issue 25), both measured in
this run, interleaved, best of ``--repeat`` each; the ratio is with / without (target: at most 1.2 on each file).
A second column gives the criteria's own time in this process (:func:`cadartifact.analysis.quality.criteria`
over the file's analysable faces, read once) and the number of faces.
"""

from __future__ import annotations

import argparse
import time

from timing import REALDATA, best_process, cli_argv, machine, median_worst, print_targets  # noqa: E402


def criteria_seconds(path) -> tuple[float, int]:
    from cadartifact.analysis.quality import criteria
    from cadartifact.exchange.load import read

    nets = read(str(path)).nets
    criteria(nets[0]) if nets else None  # imports (scipy) out of the timing
    t = time.perf_counter()
    for net in nets:
        criteria(net)
    return time.perf_counter() - t, len(nets)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one run per measurement")
    ap.add_argument("--tol", type=float, default=0.05)
    args = ap.parse_args()
    repeat = 1 if args.quick else args.repeat
    files = sorted(p for sub in ("step", "obj") if (REALDATA / sub).is_dir() for p in (REALDATA / sub).iterdir()
                   if p.is_file())
    if not files:
        raise SystemExit(f"no real files in {REALDATA}")
    print(f"{time.strftime('%Y-%m-%d %H:%M')}, {machine()}, best of {repeat}")
    print(f"{'file':34s} {'faces':>5s} {'gate':>7s} {'+pdq':>7s} {'ratio':>6s} {'criteria in-process':>20s}")
    ratios = []
    for path in files:
        base, pdq = float("inf"), float("inf")
        common = ("gate", path, "--tol", args.tol, "--jobs", "1", "--format", "json")
        for _ in range(repeat):  # interleaved: a load spike hits both
            base = min(base, best_process(cli_argv(*common), 1)[0])
            pdq = min(pdq, best_process(cli_argv(*common, "--profile", "default"), 1)[0])
        own, faces = criteria_seconds(path)
        ratios.append(pdq / base)
        print(f"{path.name:34s} {faces:5d} {base:7.2f} {pdq:7.2f} {pdq / base:6.3f} {own:19.3f}s")
    med, worst = median_worst(ratios)
    print_targets([("gate --profile default / gate, median", f"{med:.3f}", "<= 1.2", med <= 1.2),
                   ("gate --profile default / gate, worst file", f"{worst:.3f}", "<= 1.2", worst <= 1.2)])


if __name__ == "__main__":
    main()
