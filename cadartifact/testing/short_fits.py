"""Short least-squares fits of known smooth shapes: the family of tests/analysis/test_short_nets.py and
benchmarks/short_nets_tradeoff.py, benchmarks/measured_gap_floor.py.

Least-squares clamped fits (5-10 points per direction, degrees 2-3) of a wide bump, a cylinder arc, a saddle,
low-frequency waves and a sphere patch (any size and direction), evaluated densely by the B-spline basis
(:func:`cadartifact.numerics.splines.basis_matrix`), and their distance to the shape itself: radial for the arc
and the sphere, along the graph's normal (to first order) for the others.
"""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots
from cadartifact.numerics.splines import basis_matrix

KINDS = ("bump", "arc", "saddle", "waves", "sphere")


def shape(kind, rng):
    """``(points(u, v) -> (a, b, 3), distance(P) -> (...))`` of a known smooth shape, and a label."""
    S = float(np.exp(rng.uniform(np.log(20), np.log(2000))))
    Sx, Sy = S, S * rng.uniform(0.5, 1.5)
    th = rng.uniform(0, np.pi)
    c, s = np.cos(th), np.sin(th)
    if kind in ("bump", "saddle", "waves"):
        A = S * rng.uniform(0.01, 0.15)
        if kind == "bump":
            cx, cy = rng.uniform(0.3, 0.7, 2)
            w = rng.uniform(0.5, 1.0)

            def g(X, Y):
                return A * np.exp(-((X / Sx - cx) ** 2 + (Y / Sy - cy) ** 2) / w ** 2)
        elif kind == "saddle":
            def g(X, Y):
                return A * (((c * X + s * Y) / S - 0.3) ** 2 - ((-s * X + c * Y) / S - 0.4) ** 2)
        else:
            f, ph = rng.uniform(0.2, 0.6), rng.uniform(0, 2 * np.pi)

            def g(X, Y):
                return A * np.cos(2 * np.pi * f * (c * X + s * Y) / S + ph)

        def points(u, v):
            X, Y = np.broadcast_arrays(Sx * u[:, None], Sy * v[None, :])
            return np.stack([X, Y, g(X, Y)], -1)

        def distance(P):
            X, Y, Z = P[..., 0], P[..., 1], P[..., 2]
            h = 1e-4 * S
            gx = (g(X + h, Y) - g(X - h, Y)) / (2 * h)
            gy = (g(X, Y + h) - g(X, Y - h)) / (2 * h)
            return np.abs(Z - g(X, Y)) / np.sqrt(1 + gx ** 2 + gy ** 2)
        return points, distance, f"{kind} size {S:.0f} at {np.degrees(th):.0f} deg"
    if kind == "arc":
        R, ang, along = S * rng.uniform(0.5, 3), np.radians(rng.uniform(20, 90)), int(rng.integers(2))

        def points(u, v):
            a, t = ((u - 0.5) * ang)[:, None], v[None, :]
            if along:
                a, t = ((v - 0.5) * ang)[None, :], u[:, None]
            a, t = np.broadcast_arrays(a, t)
            return np.stack([R * np.sin(a), Sy * t, R * np.cos(a)], -1)

        def distance(P):
            return np.abs(np.hypot(P[..., 0], P[..., 2]) - R)
        return points, distance, f"arc R {R:.0f} {np.degrees(ang):.0f} deg along {'uv'[along]}"
    R, a1, a2 = S * rng.uniform(1, 3), *np.radians(rng.uniform(20, 60, 2))

    def points(u, v):
        a, b = np.broadcast_arrays(((u - 0.5) * a1)[:, None], ((v - 0.5) * a2)[None, :])
        return np.stack([R * np.sin(a) * np.cos(b), R * np.sin(b), R * np.cos(a) * np.cos(b)], -1)

    def distance(P):
        return np.abs(np.linalg.norm(P, axis=-1) - R)
    return points, distance, f"sphere R {R:.0f}"


def fit(points, n, p, dense=121):
    """The least-squares clamped uniform fit of ``points`` on a dense parameter grid."""
    u = np.linspace(0, 1, dense)
    ku, kv = clamped_uniform_knots(n[0], p[0]), clamped_uniform_knots(n[1], p[1])
    Bu, Bv = basis_matrix(ku, p[0], u, n[0]), basis_matrix(kv, p[1], u, n[1])
    P = np.einsum("ia,abk,jb->ijk", np.linalg.pinv(Bu), points(u, u), np.linalg.pinv(Bv))
    return ControlNet(points=P, degrees=tuple(p), knots=(ku, kv))


def distance_to_shape(net, distance, m=241):
    """The fitted surface's largest distance to the shape, on an ``m x m`` grid by the B-spline basis."""
    u = np.linspace(0, 1, m)
    Bu = basis_matrix(net.knots[0], net.degrees[0], u, net.shape[0])
    Bv = basis_matrix(net.knots[1], net.degrees[1], u, net.shape[1])
    return float(distance(np.einsum("ia,abk,jb->ijk", Bu, net.points, Bv)).max())


def family(seed, count, degrees=(2, 3)):
    """``(net, distance, label)`` of ``count`` seeded fits: a shape of each kind in turn, degrees and sizes drawn."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        p = tuple(int(d) for d in rng.integers(degrees[0], degrees[1] + 1, 2))
        n = tuple(int(rng.integers(max(5, d + 2), 11)) for d in p)
        points, distance, text = shape(KINDS[i % len(KINDS)], rng)
        yield fit(points, n, p), distance, f"{text}, degrees {p}, net {n}"
