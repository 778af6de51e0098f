"""Cross-check (issue 25 item 3): the waviness criterion (G-SU-WV) beside the ripple, on known-shape families and
on the real files.

Run:  python benchmarks/pdq_crosscheck.py [--count 240] [--tol 0.05] [--seed 25]

Families: clamped faces of 100 x 80 mm whose control points sample a known shape of amplitude 1 mm at their
Greville abscissae (cadartifact/testing/known_shapes.py: cosines, sums of two cosines, Gaussian bumps; directions u, v,
diagonal, 30 degrees; degrees 2-5; nets of 14-40 points; content from 0.03 to 0.45 cycles per control point).
Per face: the ripple (``budget(...).stats["total"].peak``, the surface reading, the face's own degrees) and the
waviness (the most inflections of the normal curvature along one isoparametric line, default profile).
Printed: per frequency band the share of faces whose ripple exceeds the tolerance and the inflection counts of
those over and under it; the rank correlation of the two; the 2 x 2 table of "ripple over tolerance" against
"waviness fails (more than 3 inflections)". Then, per STEP face of the samples and the real files, where the two disagree (one fails, the
other does not) and the numbers that say why.
"""

from __future__ import annotations

import argparse

import numpy as np

from cadartifact.testing.paths import REAL_STEP as REALDATA, ROOT


def rank_correlation(a, b) -> float:
    ra, rb = np.argsort(np.argsort(a)), np.argsort(np.argsort(b))
    return float(np.corrcoef(ra, rb)[0, 1])


def families(count: int, seed: int):
    from cadartifact.testing.known_shapes import DIRECTIONS, known_face, shape_function

    rng = np.random.default_rng(seed)
    for _ in range(count):
        p, q = (int(d) for d in rng.integers(2, 6, 2))
        nu, nv = (int(n) for n in rng.integers(14, 41, 2))
        f = float(rng.uniform(0.03, 0.45))
        dname = str(rng.choice(list(DIRECTIONS)))
        kind = str(rng.choice(("cosine", "sum", "bump")))
        g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (nu - p, nv - q), rng)
        net, _ = known_face((p, q), (nu, nv), g)
        yield net, f, f"{kind} {dname} f={f:.2f} ({p},{q}) {nu}x{nv}"


def main(argv=None) -> int:
    import cadartifact as ca
    from cadartifact.analysis.quality import DEFAULT_PROFILE, criteria

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=240)
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--seed", type=int, default=25)
    args = ap.parse_args(argv)
    fail_at = DEFAULT_PROFILE.limit("waviness").fail
    rows = []
    for net, f, what in families(args.count, args.seed):
        ripple = ca.budget(net).stats["total"].peak
        wav = next(c for c in criteria(net) if c.key == "waviness")
        rows.append((f, ripple, wav.value, what))
    f, ripple, wav = (np.array([r[i] for r in rows]) for i in range(3))
    over = ripple > args.tol
    print(f"{len(rows)} known faces (amplitude 1 mm), tolerance {args.tol:g} mm, waviness fails above {fail_at:g}")
    print("| content (cycles per control point) | faces | ripple over tolerance | inflections, faces over "
          "(median, range) | inflections, faces within (median, range) |")
    print("|---|---|---|---|---|")
    for lo, hi in ((0.0, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.4), (0.4, 0.5)):
        band = (f >= lo) & (f < hi)
        if not band.any():
            continue

        def stats(mask):
            x = wav[band & mask]
            return "-" if not len(x) else f"{np.median(x):g} ({x.min():g}-{x.max():g})"

        print(f"| {lo:.1f}-{hi:.1f} | {band.sum()} | {over[band].sum()} ({100 * over[band].mean():.0f} %) | "
              f"{stats(over)} | {stats(~over)} |")
    print(f"\nrank correlation (ripple, inflections): {rank_correlation(ripple, wav):.2f}; "
          f"(content frequency, inflections): {rank_correlation(f, wav):.2f}; "
          f"(content frequency, ripple): {rank_correlation(f, ripple):.2f}")
    wfail = wav > fail_at
    print("\n| | waviness fails | waviness does not fail |\n|---|---|---|")
    print(f"| ripple over tolerance | {(over & wfail).sum()} | {(over & ~wfail).sum()} |")
    print(f"| ripple within | {(~over & wfail).sum()} | {(~over & ~wfail).sum()} |")

    if not REALDATA.is_dir():
        print(f"\nno real files at {REALDATA}")
        return 0
    from cadartifact.exchange.load import read

    print(f"\nSample and real STEP faces where ripple (> {args.tol:g} mm) and waviness (> {fail_at:g}) disagree:")
    print("| file | face | net | ripple (mm) | inflections | largest sign change (1/mm) | min radius |")
    print("|---|---|---|---|---|---|---|")
    agree = total = 0
    samples = sorted((ROOT / "cadartifact" / "samples").glob("*.step"))
    for path in samples + sorted(REALDATA.iterdir()):
        for net in read(str(path)).nets:
            total += 1
            r = ca.budget(net).stats["total"].peak
            crit = {c.key: c for c in criteria(net)}
            w = crit["waviness"]
            if not w.evaluated:
                continue
            if (r > args.tol) == (w.value > fail_at):
                agree += 1
                continue
            amp = w.detail.split("largest sign change ")[1].split(" ")[0] if "largest" in w.detail else "-"
            print(f"| {path.name} | {net.origin.face} | {net.shape[0]}x{net.shape[1]} | {r:.3g} | {w.value:g} | "
                  f"{amp} | {crit['radius'].value:.3g} |")
    print(f"\n{agree} of {total} sample and real faces agree")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
