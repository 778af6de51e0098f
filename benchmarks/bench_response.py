"""Benchmark: limit responses on a 1024 x 1024 Omega grid, single core, against the brute-force path.

Run:  python benchmarks/bench_response.py [--size 1024] [--repeat 3]

For each named scheme, and for a user mask given only as an array (the 4-8 mask through
``Scheme.from_mask(..., detect_arrows=False)``, i.e. no closed forms; and a non-symmetric variant
with complex symbols), prints Omega-points per second of ``scheme.response(wx, wy, "limit")`` with
``wx`` of shape (1, N) and ``wy`` of shape (N, 1), and of the brute-force path measured in this same
run: ``sum_k m_k exp(-i pi (Omega + V).k)`` with one exponential per mask entry per point, for the
mask and the limit stencil at the four V (timed on a smaller grid, reported per point). Targets:
>= 20 M points/s for named schemes, >= 5 M for an arbitrary mask. A second table times the
continuous stage and the transfer to the K = 8 grid. BLAS is pinned to one thread.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402

import numpy as np  # noqa: E402
from timing import best_of  # noqa: E402  (benchmarks/timing.py, beside this script)

from cadartifact.theory.catalogue import SCHEME_NAMES, Scheme, scheme  # noqa: E402

SHIFTS = ((0, 0), (1, 0), (0, 1), (1, 1))




def brute_force_limit(s, wx, wy):
    """One complex exponential per mask (and stencil) entry per point, for the four V."""
    def naive(coef, tx, ty):
        k1 = np.arange(coef.shape[0]) - (coef.shape[0] - 1) / 2
        k2 = np.arange(coef.shape[1]) - (coef.shape[1] - 1) / 2
        out = 0
        for a in range(coef.shape[0]):
            for b in range(coef.shape[1]):
                if coef[a, b] != 0:
                    out = out + coef[a, b] * np.exp(-1j * np.pi * (tx * k1[a] + ty * k2[b]))
        return out

    return [naive(s.mask, wx + v1, wy + v2) / 4 * naive(s.limit_stencil, wx + v1, wy + v2) for v1, v2 in SHIFTS]


def skew_mask():
    m = np.array(scheme("4-8").mask)
    m[1, 2] += 0.01  # keep the coset sums: (1, 2) and (3, 2) share a coset
    m[3, 2] -= 0.01
    return m


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    n = args.size
    w = np.linspace(-0.5, 0.5, n)
    wx, wy = w[None, :], w[:, None]
    nb = 128
    wb = np.linspace(-0.5, 0.5, nb)
    bx, by = wb[None, :], wb[:, None]

    rows = [(name, scheme(name)) for name in SCHEME_NAMES]
    rows.append(("user mask (4-8 array)", Scheme.from_mask(scheme("4-8").mask, detect_arrows=False)))
    rows.append(("user mask, non-symmetric", Scheme.from_mask(skew_mask(), "skew", detect_arrows=False)))

    print(f"limit response on a {n}x{n} Omega grid, single thread (M Omega-points/s)")
    print(f"{'scheme':28s} {'fast':>10s} {'brute force':>12s} {'ratio':>8s}  target")
    for label, s in rows:
        s.response(wx[:, :8], wy[:8], "limit")  # warm caches
        t_fast = best_of(lambda: s.response(wx, wy, "limit"), args.repeat)
        t_brute = best_of(lambda: brute_force_limit(s, bx, by), 1)
        fast = n * n / t_fast / 1e6
        brute = nb * nb / t_brute / 1e6
        target = 5 if label.startswith("user") else 20
        ok = "ok" if fast >= target else "MISSED"
        print(f"{label:28s} {fast:10.1f} {brute:12.2f} {fast / brute:8.0f}  >= {target} {ok}")

    m = 256
    v = np.linspace(-0.5, 0.5, m)
    f = np.linspace(-4, 4, n)
    print(f"\ncontinuous stage ({m}x{m} grid) and transfer to K = 8 ({n}x{n} grid), M points/s")
    print(f"{'scheme':28s} {'continuous':>10s} {'transfer':>10s}")
    for label, s in rows[:5] + rows[5:6]:
        s.response(v[None, :4], v[:4, None], "continuous")  # warm caches (autocorrelation data)
        t_c = best_of(lambda: s.response(v[None, :], v[:, None], "continuous"), 1)
        t_t = best_of(lambda: s.transfer(f[None, :], f[:, None], 3), args.repeat)
        print(f"{label:28s} {m * m / t_c / 1e6:10.2f} {n * n / t_t / 1e6:10.1f}")


if __name__ == "__main__":
    main()
