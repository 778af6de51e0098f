"""Where a designed mask beats 4-8 and where it does not (docs/scheme-design.md): the energy artifact as a share
of the signal (the paper's normalisation), RMS over the Nyquist square and over the low band |w| <= 0.25, at single
frequencies, and the least signal response on |w| <= 0.25. Run: python benchmarks/design_vs_4_8.py"""

from __future__ import annotations

import numpy as np

from cadartifact.theory.catalogue import scheme
from cadartifact.theory.design import design

POINTS = ((0.1, 0.2), (0.25, 0.25), (0.4, 0.1), (0.45, 0.45))


def figures(s, n=96):
    out = {}
    for label, lim in (("Nyquist", 0.5), ("low band", 0.25)):
        w = (np.arange(n) + 0.5) * (lim / n)
        r = s.response(w[None, :], w[:, None], "limit")
        out[label] = 100 * float(np.sqrt(np.mean((np.asarray(r.energy) / np.abs(np.asarray(r.signal))) ** 2)))
    for wx, wy in POINTS:
        r = s.response(wx, wy, "limit")
        out[f"({wx:g}, {wy:g})"] = 100 * float(r.energy / r.signal)
    w = (np.arange(n) + 0.5) * (0.25 / n)
    out["signal min"] = float(np.min(s.response(w[None, :], w[:, None], "limit").signal))
    return out


def main():
    rows = {"4-8": figures(scheme("4-8")), "bicubic": figures(scheme("bicubic"))}
    for label, kw in (("6x6 C1 signal", dict(normalisation="signal")),
                      ("6x6 C1 absolute", dict(normalisation="absolute"))):
        rows[label] = figures(design(support=(6, 6), degree=2, continuity=1, **kw).scheme)
    cols = list(next(iter(rows.values())))
    print("| scheme | " + " | ".join(cols) + " |")
    print("|---" * (len(cols) + 1) + "|")
    for name, r in rows.items():
        print(f"| {name} | " + " | ".join(f"{r[c]:.4g}" for c in cols) + " |")


if __name__ == "__main__":
    main()
