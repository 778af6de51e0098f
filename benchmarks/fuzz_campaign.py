"""Fuzz campaign: seeded mutations of the samples and real files through ``cadartifact gate``, counts per class.

    nice -n 10 python benchmarks/fuzz_campaign.py [-n 10000] [--seed 14] [--batch 100] [--all] [--read-timeout 10]
                                                  [--advise none|failing] [--max-seconds S]

Generates ``n`` inputs with ``cadartifact/testing/fuzzing.py`` (round-robin over its mutation kinds, sources at
random: the
samples, IGES files written from them and from MAINBODY_BACK (``fuzzing.iges_sources``; ``--no-iges`` leaves them
out), and the real files under 150 KB, or every real file with ``--all``) and gates them **in batches**: one
``python -m cadartifact gate --format json --jobs 1`` process per ``--batch`` files (its JSON report has one entry
per file; OCCT reads in that process's reader child, which a crash or a hang of one file replaces). Per input:

- ``traceback``: a Python traceback on the gate process's stderr, or an entry ``analysis failed (...)`` (an
  unexpected exception the gate caught: it failed closed, but it is a bug);
- ``crash``: the gate process itself died (a signal, or an exit code other than 0/1/2, or no report);
- ``hang``: the gate process gave no report within its time limit (``error:timeout`` is the reader stopped
  after ``--read-timeout`` seconds: an error entry, the documented outcome);
- ``false-pass``: a pass of a mutant whose unmutated file did not pass (failed, or was an error);
- ``silent-loss``: fewer faces analysed than the unmutated file, exit 0, nothing said
  (:func:`fuzzing.silent_loss`);
- otherwise the entry's class (pass / warn / fail / ``error:<why>``, :func:`fuzzing.classify`), and every
  contract violation of the entry (:func:`fuzzing.check_entry`; an error message that does not name its file is
  one too).

**A batch cannot hide a crash**: a batch whose process died, hung, printed a traceback, or whose report does not
hold exactly one entry per file it was given is run again **one file per process**, so the crash, hang or
traceback is attributed to its input and the batch's other inputs still get their entry.

``--advise none`` (the default) skips the density advice of failing faces: the verdict and the face counts do not
depend on it (``gate --advise``), and the campaign fuzzes the readers and the verdict; ``--advise failing`` runs it
too (slower). ``--max-seconds``: stop starting batches after that time (a shared machine) and report on the inputs
run. Exit 1 when any violation, traceback, crash, hang, false pass or silent loss was found.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cadartifact.testing import fuzzing

#: Classes that are findings (the exit code is 1 when any is non-zero), beside the contract violations.
FINDINGS = ("traceback", "crash", "hang", "false-pass", "silent-loss")


def _env() -> dict:
    env = dict(os.environ)
    env.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", COLUMNS="200")
    return env


def gate_process(paths: list[Path], args, folder: Path, timeout: float, deadline: float | None = None
                 ) -> tuple[str, object]:
    """Run one gate process on ``paths``: ``("ok", entries)``, or ``("crash"|"hang"|"traceback", detail)``, or
    ``("late", None)`` when ``deadline`` (``time.perf_counter``) came first (the inputs are not counted)."""
    report = folder / "report.json"
    report.unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "cadartifact", "gate", "--format", "json", "--output", str(report), "--jobs", "1",
           "--tol", repr(args.tol), "--read-timeout", repr(args.read_timeout), "--advise", args.advise,
           *map(str, paths)]
    late = deadline is not None and deadline - time.perf_counter() < timeout
    try:
        proc = subprocess.run(cmd, cwd=folder, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=max(1.0, deadline - time.perf_counter()) if late else timeout)
    except subprocess.TimeoutExpired:
        if late:
            return "late", None
        return "hang", f"no report in {timeout:.0f} s"
    stderr = proc.stderr.decode("utf-8", "replace")
    if "Traceback (most recent call last)" in stderr:
        return "traceback", stderr.strip().splitlines()[-1][:300]
    if proc.returncode < 0 or proc.returncode not in (0, 1, 2):
        return "crash", f"exit code {proc.returncode}"
    if not report.exists():
        if proc.returncode == 2 and len(paths) == 1:  # a usage error of the whole run (no report): one line?
            lines = stderr.strip().splitlines()
            return "ok", [{"path": str(paths[0]), "verdict": "error", "error": stderr.strip(), "faces": [],
                           "_usage": len(lines)}]
        return "crash", f"exit code {proc.returncode} and no report"
    try:
        entries = json.loads(report.read_text())["files"]
    except (ValueError, KeyError) as exc:
        return "crash", f"unreadable report ({exc})"
    if [e.get("path") for e in entries] != [str(p) for p in paths]:
        return "crash", f"{len(entries)} entries for {len(paths)} files"
    return "ok", entries


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=10_000, help="inputs (default 10 000)")
    parser.add_argument("--seed", type=int, default=14)
    parser.add_argument("--batch", type=int, default=100,
                        help="files per gate process (default 100; smaller near --max-seconds)")
    parser.add_argument("--all", action="store_true", help="also the real files over 150 KB (slow)")
    parser.add_argument("--read-timeout", type=float, default=10.0, help="seconds per file for the reader")
    parser.add_argument("--tol", type=float, default=0.05)
    parser.add_argument("--advise", default="none", choices=("none", "failing", "all"),
                        help="the gate's density advice (default none: the verdict does not need it)")
    parser.add_argument("--no-iges", action="store_true", help="no IGES sources")
    parser.add_argument("--max-seconds", type=float, default=None, help="stop after this long; report what ran")
    parser.add_argument("--progress", type=int, default=1000, help="a progress line every N inputs (about)")
    args = parser.parse_args(argv)

    sources = fuzzing.default_sources(small=not args.all)
    work = Path(tempfile.mkdtemp(prefix="cadartifact-fuzz-"))
    if not args.no_iges:
        sources += fuzzing.iges_sources(work / "iges")
    print(f"fuzz campaign: {args.n} inputs, seed {args.seed}, batches of {args.batch} per gate process, "
          f"{len(sources)} sources ({', '.join(s.name for s in sources)}), read timeout {args.read_timeout:g} s, "
          f"advise {args.advise}", flush=True)
    start = time.perf_counter()
    batch_timeout = lambda k: 120 + k * (4 + args.read_timeout)  # noqa: E731  (k reader timeouts in a row fit)
    # the unmutated sources: faces analysed (a mutant that analyses fewer, exits 0 and says nothing is a silent
    # loss) and verdict (a mutant that passes where its source did not is a false pass)
    status, entries = gate_process(sources, args, work, batch_timeout(len(sources)))
    if status != "ok":
        print(f"the unmutated sources did not gate: {status} ({entries})")
        return 1
    baseline = {src.name: (fuzzing.faces_analysed(e), e["verdict"]) for src, e in zip(sources, entries)}
    print("sources: " + ", ".join(f"{k} {v[1]} ({v[0]} faces)" for k, v in baseline.items()), flush=True)

    classes: collections.Counter = collections.Counter()
    by_kind: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    findings: dict[str, list[str]] = collections.defaultdict(list)
    violations: list[str] = []
    reruns = named = errors = 0
    ran = 0
    next_progress = args.progress
    cases = fuzzing.mutations(sources, args.n, seed=args.seed)
    stopped = False
    while ran < args.n:
        if args.max_seconds is not None and time.perf_counter() - start > args.max_seconds:
            print(f"  stopped after {args.max_seconds:g} s (--max-seconds): {ran} of {args.n} inputs run", flush=True)
            stopped = True
            break
        size = min(args.batch, args.n - ran)
        if args.max_seconds is not None and ran:  # a batch that fits in the time left, at the pace so far
            pace = (time.perf_counter() - start) / ran
            size = max(1, min(size, int((args.max_seconds - (time.perf_counter() - start)) / pace)))
        batch = [c for _, c in zip(range(size), cases)]
        folder = work / "batch"
        shutil.rmtree(folder, ignore_errors=True)
        paths = [fuzzing.write_case(case, folder / str(ran + k)) for k, case in enumerate(batch)]
        deadline = None if args.max_seconds is None else start + args.max_seconds + 120
        status, entries = gate_process(paths, args, folder, batch_timeout(len(paths)), deadline)
        if status == "late":  # --max-seconds (and 2 minutes of grace) reached inside this batch: not counted
            print(f"  stopped by --max-seconds inside the batch at #{ran} ({len(batch)} inputs not counted)",
                  flush=True)
            stopped = True
            break
        if status == "ok":
            results = [("ok", e) for e in entries]
        else:  # attribute it: one process per file (the other files get their entries)
            reruns += 1
            print(f"  batch at #{ran}: {status} ({entries}); re-run one file per process", flush=True)
            alone = [gate_process([p], args, folder, batch_timeout(1)) for p in paths]  # no deadline: attribute
            results = [(status, entry[0] if status == "ok" else entry) for status, entry in alone]
        for k, (case, path, (status, entry)) in enumerate(zip(batch, paths, results)):
            i = ran + k
            label = f"#{i} {case.source} {case.kind}"
            if status != "ok":
                cls = status
                findings[cls].append(f"{label}: {entry}")
            else:
                cls = fuzzing.classify(entry, case)
                faces, verdict = baseline[case.source]
                if cls == "error:unexpected-exception":
                    cls = "traceback"
                    findings[cls].append(f"{label}: {entry['error'][:300]}")
                elif fuzzing.silent_loss(entry, faces):
                    cls = "silent-loss"
                    findings[cls].append(f"{label}: {fuzzing.faces_analysed(entry)} faces analysed, {faces} in the "
                                         f"unmutated file, verdict {entry['verdict']}")
                elif entry["verdict"] == "pass" and verdict != "pass":
                    cls = "false-pass"
                    findings[cls].append(f"{label}: pass, the unmutated file {verdict}")
                problems = fuzzing.check_entry(entry, path, case)
                if entry["verdict"] == "error":
                    errors += 1
                    if entry["error"].startswith(str(path)):
                        named += 1
                    else:
                        problems.append(f"error message does not name the file: {entry['error'][:200]}")
                    if entry.get("_usage", 1) != 1:
                        problems.append(f"usage error of {entry['_usage']} lines: {entry['error'][:200]}")
                violations.extend(f"{label}: {p}" for p in problems if "unexpected exception" not in p)
            classes[cls] += 1
            by_kind[case.kind][cls] += 1
        ran += len(batch)
        shutil.rmtree(folder, ignore_errors=True)
        if ran >= next_progress:
            next_progress += args.progress
            print(f"  {ran} inputs, {time.perf_counter() - start:.0f} s, {len(violations)} violations, "
                  + ", ".join(f"{c} {sum(classes[c] for c in [c])}" for c in FINDINGS) + "; "
                  + ", ".join(f"{c} {n}" for c, n in sorted(classes.items()) if c not in FINDINGS), flush=True)
    shutil.rmtree(work, ignore_errors=True)
    elapsed = time.perf_counter() - start
    print(f"\n{ran} inputs (of {args.n} asked{', stopped by --max-seconds' if stopped else ''}) in {elapsed:.0f} s "
          f"({1e3 * elapsed / max(ran, 1):.0f} ms each), {-(-ran // args.batch)} batches, {reruns} re-run one file "
          f"per process")
    print("\noutcome class           count")
    for cls, n in sorted(classes.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"  {cls:22s}{n:6d}")
    print("\nper mutation kind: " + "; ".join(
        f"{k}: " + ", ".join(f"{c} {n}" for c, n in sorted(v.items())) for k, v in sorted(by_kind.items())))
    print(f"\nfindings: " + ", ".join(f"{c} {classes.get(c, 0)}" for c in FINDINGS))
    for cls in FINDINGS:
        for v in findings[cls][:30]:
            print(f"  {cls}: {v}")
    print(f"\ncontract violations: {len(violations)}")
    for v in violations[:50]:
        print("  " + v)
    print(f"\nsummary: {ran} inputs; {classes.get('traceback', 0)} tracebacks, {classes.get('crash', 0)} crashes and "
          f"{classes.get('hang', 0)} hangs of the gate process; {classes.get('false-pass', 0)} false passes; "
          f"{classes.get('silent-loss', 0)} silent losses; {errors} error entries, {named} naming their file; "
          f"{classes.get('error:crash', 0)} reader crashes and {classes.get('error:timeout', 0)} reader timeouts "
          f"turned into error entries (the run went on); {len(violations)} contract violations")
    return 1 if violations or any(classes.get(c) for c in FINDINGS) else 0


if __name__ == "__main__":
    sys.exit(main())
