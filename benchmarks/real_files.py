"""Per real STEP file: faces analysed, canonical, exact in one direction, split, pass / warn / fail at a tolerance.

Prints the README's table (markdown). Usage: ``python benchmarks/real_files.py [--tol 0.05] [--profile default]``.
With ``--profile`` (a built-in name or a profile TOML: ``cadartifact gate --profile``), one more column per PDQ
criterion that fires on some file: faces warning / failing on it (docs/quality-criteria.md).
Reads ``../shared/realdata/step`` beside the checkout.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cadartifact as ca
from cadartifact.exchange.load import read
from cadartifact.testing.paths import REAL_STEP as ROOT


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--profile", default=None, help="PDQ profile: 'default' or a profile TOML")
    args = ap.parse_args(argv)
    if not ROOT.exists():
        print(f"no real files at {ROOT}", file=sys.stderr)
        return 2
    profile = None
    if args.profile:
        from cadartifact.analysis.quality import CRITERIA, criteria
        from cadartifact.gate.profiles import resolve_profile

        profile = resolve_profile(args.profile, Path.cwd(), "--profile")
    rows, fired = [], set()
    for path in sorted(ROOT.glob("*")):
        nets = read(path).nets
        counts = dict(canonical=0, exact=0, split=0, passed=0, warned=0, failed=0)
        hits: dict = {}
        worst = 0.0
        for net in nets:
            b = ca.budget(net, tolerance=args.tol)
            v = b.stats["total"].peak
            worst = max(worst, v)
            if net.exact == ("surface", "surface"):
                counts["canonical"] += 1
            elif any(e is not None for e in net.exact):
                counts["exact"] += 1
            if b.pieces:
                counts["split"] += 1
            key = "failed" if v > args.tol else "warned" if v >= 0.8 * args.tol else "passed"
            counts[key] += 1
            for c in criteria(net, profile) if profile is not None else ():
                if c.verdict in ("warn", "fail"):
                    hits.setdefault(c.key, [0, 0])[c.verdict == "fail"] += 1
                    fired.add(c.key)
        rows.append((path.name, len(nets), counts, worst, hits))
    keys = [k for k in CRITERIA if k in fired] if profile is not None else []
    print(f"| file | B-spline faces analysed | canonical | exact along one direction | split at junctions | "
          f"pass | warn | fail (at {args.tol:g} mm) | largest ripple (mm) |"
          + "".join(f" {k} (warn/fail) |" for k in keys))
    print("|---|---|---|---|---|---|---|---|---|" + "---|" * len(keys))
    for name, n, counts, worst, hits in rows:
        print(f"| {name} | {n} | {counts['canonical']} | {counts['exact']} | {counts['split']} | "
              f"{counts['passed']} | {counts['warned']} | {counts['failed']} | {worst:.4f} |"
              + "".join(" {}/{} |".format(*hits.get(k, [0, 0])) for k in keys))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
