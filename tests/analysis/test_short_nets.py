"""Short nets (5-10 points per direction) read what their surface really carries, not the curvature of the
smooth shape it fits (issue 23, item 5).

Independent road: least-squares clamped fits of known smooth shapes (a wide bump, a cylinder arc, a saddle,
low-frequency waves, a sphere patch; any size and direction), evaluated densely by the B-spline basis
(:func:`cadartifact.numerics.splines.basis_matrix`), and their distance to the shape itself: radial for the arc
and the sphere, along the graph's normal (to first order) for the others. The ripple is what no placement of
points can steer, so it stays within a small multiple of that distance (the band split's own constant on the
fit's error).

With the measured road's fifth-order bridge (``BRIDGE_ORDER = 5``, since 2026-12-03) these faces read at most
2.6x their distance (median 1.32-1.37 per seed; the third-order bridge before it: 4.3x, median 1.58), which is
tested, and the 6x4 arc is advised 6x4 again. Issue 23 asks for 1.3x on every face: not reached (strict xfails).
What is left is the band split's own constant on the fit's error and, on curved quadratic faces, the fit's
tangential error at half a cycle per span, which the Cartesian split turns partly into normal ripple
(``benchmarks/short_nets_tradeoff.py``; docs/model.md).
"""

import numpy as np
import pytest

import cadartifact as ca
from cadartifact.net import ControlNet, clamped_uniform_knots
from cadartifact.numerics.splines import basis_matrix

KINDS = ("bump", "arc", "saddle", "waves", "sphere")


def _shape(kind, rng):
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


def _fit(points, n, p, dense=121):
    """The least-squares clamped uniform fit of ``points`` on a dense parameter grid."""
    u = np.linspace(0, 1, dense)
    ku, kv = clamped_uniform_knots(n[0], p[0]), clamped_uniform_knots(n[1], p[1])
    Bu, Bv = basis_matrix(ku, p[0], u, n[0]), basis_matrix(kv, p[1], u, n[1])
    P = np.einsum("ia,abk,jb->ijk", np.linalg.pinv(Bu), points(u, u), np.linalg.pinv(Bv))
    return ControlNet(points=P, degrees=tuple(p), knots=(ku, kv))


def _distance(net, distance, m=241):
    """The fitted surface's largest distance to the shape, on an ``m x m`` grid by the B-spline basis."""
    u = np.linspace(0, 1, m)
    Bu = basis_matrix(net.knots[0], net.degrees[0], u, net.shape[0])
    Bv = basis_matrix(net.knots[1], net.degrees[1], u, net.shape[1])
    return float(distance(np.einsum("ia,abk,jb->ijk", Bu, net.points, Bv)).max())


def _family(seed, count, degrees=(2, 3)):
    rng = np.random.default_rng(seed)
    for i in range(count):
        p = tuple(int(d) for d in rng.integers(degrees[0], degrees[1] + 1, 2))
        n = tuple(int(rng.integers(max(5, d + 2), 11)) for d in p)
        points, distance, text = _shape(KINDS[i % len(KINDS)], rng)
        yield _fit(points, n, p), distance, f"{text}, degrees {p}, net {n}"


SHORT_NETS_OPEN = "issue 23 item 5: short nets read part of a smooth shape's curvature as ripple"


def _ratios(seed):
    """``(ripple / distance, label)`` of the family's 25 faces of one seed."""
    out = []
    for net, distance, text in _family(seed, 25):
        out.append((ca.budget(net).stats["total"].peak / _distance(net, distance), text))
    return out


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_short_nets_read_at_most_three_times_their_distance_to_the_smooth_shape(seed):
    """Nets of 5-10 points, degrees 2-3, five shapes at random sizes and directions: the ripple read is within
    3x the surface's distance to the shape on every face and 1.5x on the median (fifth-order bridge: 2.59x and
    1.32-1.37 over the three seeds; the third-order bridge read 4.27x and 1.58)."""
    ratios = _ratios(seed)
    for r, text in ratios:
        assert r <= 3.0, f"{text}: ripple {r:.2f}x its distance to the shape"
    assert np.median([r for r, _ in ratios]) <= 1.5, sorted(np.round([r for r, _ in ratios], 2))


@pytest.mark.xfail(strict=True, reason=SHORT_NETS_OPEN)
def test_short_nets_read_no_more_than_1_3_times_their_distance_on_every_face():
    """Issue 23's bound: 1.3x on every face of the family. Reached on 32-48 % of the faces per seed; the worst
    are arcs and spheres along quadratic directions (up to 2.6x: the fit's tangential error at half a cycle per
    span, split in Cartesian components, is partly read along the normal), then the split's constant on the
    fit's error."""
    worst = max(max(r for r, _ in _ratios(seed)) for seed in (11, 12, 13))
    assert worst <= 1.3


def _arc_6x4():
    """Issue 23's fuselage section: the 6x4 cubic least-squares fit of a 60 degree arc of radius 1500 mm, and its
    largest distance to the arc."""
    R, ang = 1500.0, np.radians(60)

    def points(u, v):
        a, t = np.broadcast_arrays(((u - 0.5) * ang)[:, None], v[None, :])
        return np.stack([R * np.sin(a), 400.0 * t, R * np.cos(a)], -1)

    net = _fit(points, (6, 4), (3, 3))
    return net, _distance(net, lambda P: np.abs(np.hypot(P[..., 0], P[..., 2]) - R))


def test_a_60_degree_arc_on_a_6x4_cubic_net_keeps_its_net():
    """The arc's fit lies within 0.035 mm of the arc, and at t = 0.05 it is advised 6x4, conforming (the
    third-order bridge read 0.148 mm of ripple, 4.2x the distance, and advised 7x4)."""
    net, d = _arc_6x4()
    assert d < 0.04
    a = ca.advise(net, tolerance=0.05)
    assert a.shape == (6, 4) and a.meets_tolerance


@pytest.mark.xfail(strict=True, reason=SHORT_NETS_OPEN)
def test_a_60_degree_arc_on_a_6x4_cubic_net_reads_no_more_ripple_than_its_distance():
    """Issue 23's bound on the arc: 1.3x its distance. It reads 0.048 mm, 1.37x."""
    net, d = _arc_6x4()
    assert ca.budget(net).stats["total"].peak <= 1.3 * d
