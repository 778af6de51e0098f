"""Fuzz campaign: seeded mutations of the samples and real files through the gate, counts per class.

    python benchmarks/fuzz_campaign.py [-n 10000] [--seed 14] [--all] [--read-timeout 10] [--max-seconds S]

Generates ``n`` inputs with ``tests/fuzzing.py`` (round-robin over its mutation kinds, sources at
random: the samples, IGES files written from them and from MAINBODY_BACK (``fuzzing.iges_sources``; ``--no-iges``
leaves them out), and the real files under 150 KB, or every real file with ``--all``) and gates
each in this process with :func:`cadartifact.gate.run.gate_file` (the STEP reader runs in its child
process). Prints the count per outcome class (pass / warn / fail / error:<why>) and per mutation
kind, and every contract violation (:func:`fuzzing.check_entry`): an unexpected exception, a report
with fewer or more faces than the file declares, a non-finite number, a message that is not one line;
and, as a class of its own, every silent loss (:func:`fuzzing.silent_loss`: fewer faces analysed than the
unmutated file, exit 0, no warning or note).
A hang is a reader stopped after ``--read-timeout`` seconds (class ``error:timeout``); a crash is a
reader child that died (``error:crash``); neither ends the run. Exit 1 when any violation or silent loss was found.
``--max-seconds``: stop generating inputs after that time (a shared machine) and report on the inputs run.
"""

from __future__ import annotations

import argparse
import collections
import sys
import tempfile
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))

import fuzzing  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=10_000, help="inputs (default 10 000)")
    parser.add_argument("--seed", type=int, default=14)
    parser.add_argument("--all", action="store_true", help="also the real files over 150 KB (slow)")
    parser.add_argument("--read-timeout", type=float, default=10.0, help="seconds per file for the reader")
    parser.add_argument("--tol", type=float, default=0.05)
    parser.add_argument("--no-iges", action="store_true", help="no IGES sources")
    parser.add_argument("--max-seconds", type=float, default=None, help="stop after this long; report what ran")
    parser.add_argument("--progress", type=int, default=1000, help="a progress line every N inputs")
    args = parser.parse_args(argv)

    from cadartifact.gate.run import gate_file
    from cadartifact.gate.policy import FileSettings

    warnings.simplefilter("ignore")
    settings = FileSettings(tolerance=args.tol)
    sources = fuzzing.default_sources(small=not args.all)
    iges_folder = tempfile.TemporaryDirectory(prefix="cadartifact-fuzz-iges-")
    if not args.no_iges:
        sources += fuzzing.iges_sources(Path(iges_folder.name))
    print(f"fuzz campaign: {args.n} inputs, seed {args.seed}, {len(sources)} sources "
          f"({', '.join(s.name for s in sources)}), read timeout {args.read_timeout:g} s", flush=True)
    classes: collections.Counter = collections.Counter()
    by_kind: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    violations = []
    slowest = (0.0, "")
    start = time.perf_counter()
    # faces each unmutated source gives: a mutant that analyses fewer, exits 0 and says nothing is a silent loss
    baseline = {src.name: fuzzing.faces_analysed(gate_file(str(src), settings, read_timeout=args.read_timeout))
                for src in sources}
    silent = []
    ran = 0
    with tempfile.TemporaryDirectory(prefix="cadartifact-fuzz-") as tmp:
        for i, case in enumerate(fuzzing.mutations(sources, args.n, seed=args.seed)):
            if args.max_seconds is not None and time.perf_counter() - start > args.max_seconds:
                print(f"  stopped after {args.max_seconds:g} s (--max-seconds): {i} of {args.n} inputs run", flush=True)
                break
            ran = i + 1
            path = fuzzing.write_case(case, Path(tmp) / str(i % 64))
            t0 = time.perf_counter()
            entry = gate_file(str(path), settings, read_timeout=args.read_timeout)
            dt = time.perf_counter() - t0
            slowest = max(slowest, (dt, f"{case.source} {case.kind}"))
            cls = fuzzing.classify(entry, case)
            if fuzzing.silent_loss(entry, baseline.get(case.source)):
                cls = "silent-loss"
                silent.append(f"#{i} {case.source} {case.kind}: {fuzzing.faces_analysed(entry)} faces analysed, "
                              f"{baseline[case.source]} in the unmutated file, verdict {entry['verdict']}")
            classes[cls] += 1
            by_kind[case.kind][cls] += 1
            for problem in fuzzing.check_entry(entry, path, case):
                violations.append(f"#{i} {case.source} {case.kind}: {problem}")
            path.unlink()
            if (i + 1) % args.progress == 0:
                print(f"  {i + 1} inputs, {time.perf_counter() - start:.0f} s, {len(violations)} violations, "
                      f"{len(silent)} silent losses; " + ", ".join(f"{c} {n}" for c, n in sorted(classes.items())),
                      flush=True)
    iges_folder.cleanup()
    elapsed = time.perf_counter() - start
    print(f"\n{ran} inputs (of {args.n} asked) in {elapsed:.0f} s ({1e3 * elapsed / max(ran, 1):.0f} ms each; "
          f"slowest {slowest[0]:.1f} s: {slowest[1]})")
    print("\noutcome class           count")
    for cls, n in sorted(classes.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"  {cls:22s}{n:6d}")
    print("\nper mutation kind: " + "; ".join(
        f"{k}: " + ", ".join(f"{c} {n}" for c, n in sorted(v.items())) for k, v in sorted(by_kind.items())))
    print(f"\nsilent losses (fewer faces analysed than the unmutated file, exit 0, nothing said): {len(silent)}")
    for v in silent[:50]:
        print("  " + v)
    print(f"\ncontract violations: {len(violations)}")
    for v in violations[:50]:
        print("  " + v)
    crashes, hangs = classes.get("error:crash", 0), classes.get("error:timeout", 0)
    print(f"\nsummary: 0 tracebacks escaped (gate_file returned for every input); "
          f"{classes.get('error:unexpected-exception', 0)} unexpected exceptions caught; "
          f"{crashes} reader crashes and {hangs} reader hangs turned into error entries (the run went on); "
          f"{sum(1 for v in violations if 'faces reported' in v)} reports with a face count other than declared")
    return 1 if violations or silent else 0


if __name__ == "__main__":
    sys.exit(main())
