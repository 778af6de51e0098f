"""Short nets (5-10 points per direction) read what their surface really carries, not the curvature of the
smooth shape it fits (issue 23, item 5).

Independent road: least-squares clamped fits of known smooth shapes (a wide bump, a cylinder arc, a saddle,
low-frequency waves, a sphere patch; any size and direction), evaluated densely by the B-spline basis
(:func:`cadartifact.numerics.splines.basis_matrix`), and their distance to the shape itself: radial for the arc
and the sphere, along the graph's normal (to first order) for the others. The ripple is what no placement of
points can steer, so it stays within a small multiple of that distance (the band split's own constant on the
fit's error).

Both tests are expected to fail today (strict xfail): the measured road reads up to 4.3x the distance (median
1.58x on these seeds) and advises the 6x4 arc 7x4. A trend of degree 6 on directions of 3-11 spans (instead of
the scheme's degree, or half the spans) brings them to 2.7x and 1.20x and keeps the arc's 6x4 with the real
faces' invariance intact, but it absorbs genuine ripple (a zigzag on the points of a 6-point direction reads
0.40x of today's reading; ``benchmarks/short_nets_tradeoff.py``), lowers the largest real-file peaks, and 1.3x
on every face is not reached by it: not applied (issue 23, item 5).
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


@pytest.mark.xfail(strict=True, reason=SHORT_NETS_OPEN)
@pytest.mark.parametrize("seed", [11, 12, 13])
def test_short_nets_read_no_more_ripple_than_their_distance_to_the_smooth_shape(seed):
    """Nets of 5-10 points, degrees 2-3, five shapes at random sizes and directions: the ripple read is within
    3x the surface's distance to the shape on every face and 1.3x on the median (today: 4.27x and 1.58 over the
    three seeds; with a degree-6 trend 2.71x and 1.20, one seed's median 1.36). Where it comes from
    (``benchmarks/short_nets_tradeoff.py``): on cubic directions of 6-7 points, the shape's own leakage (the
    smooth shape alone reads 3.1-3.7x, the fit's error 0.9-1.1x); on quadratic ones, the split's constant on the
    fit's error (2.4-2.7x). The degree-6 trend reads a genuine zigzag on 6-point directions at 0.40x of today's
    reading, so it is not applied. Issue 23 asks for 1.3x on every face: not reached (see CHANGELOG)."""
    ratios = []
    for net, distance, text in _family(seed, 25):
        d = _distance(net, distance)
        r = ca.budget(net).stats["total"].peak
        ratios.append(r / d)
        assert r <= 3.0 * d, f"{text}: ripple {r:.3g} against distance {d:.3g} ({r / d:.2f}x)"
    assert np.median(ratios) <= 1.3, np.round(sorted(ratios), 2)


@pytest.mark.xfail(strict=True, reason=SHORT_NETS_OPEN)
def test_a_60_degree_arc_on_a_6x4_cubic_net_keeps_its_net():
    """Issue 23's fuselage section: the 6x4 cubic least-squares fit of a 60 degree arc of radius 1500 mm lies
    within 0.035 mm of the arc; it reads no more ripple than that and is advised 6x4 at t = 0.05 (was 7x4:
    it read 0.148 mm, 4.2x its distance to the arc)."""
    R, ang = 1500.0, np.radians(60)

    def points(u, v):
        a, t = np.broadcast_arrays(((u - 0.5) * ang)[:, None], v[None, :])
        return np.stack([R * np.sin(a), 400.0 * t, R * np.cos(a)], -1)

    net = _fit(points, (6, 4), (3, 3))
    d = _distance(net, lambda P: np.abs(np.hypot(P[..., 0], P[..., 2]) - R))
    assert d < 0.04
    assert ca.budget(net).stats["total"].peak <= 1.3 * d
    a = ca.advise(net, tolerance=0.05)
    assert a.shape == (6, 4) and a.meets_tolerance
