"""Short nets (5-10 points per direction) read what their surface really carries, not the curvature of the
smooth shape it fits (issue 23, item 5).

Independent road (cadartifact/testing/short_fits.py): least-squares clamped fits of known smooth shapes (a wide bump,
a cylinder arc, a saddle,
low-frequency waves, a sphere patch; any size and direction), evaluated densely by the B-spline basis
(:func:`cadartifact.numerics.splines.basis_matrix`), and their distance to the shape itself: radial for the arc
and the sphere, along the graph's normal (to first order) for the others. The ripple is what no placement of
points can steer, so it stays within a small multiple of that distance (the band split's own constant on the
fit's error).

With the measured road's fifth-order bridge (``BRIDGE_ORDER = 5``, since 2026-12-03) these faces read at most
2.6x their distance (median 1.32-1.37 per seed; the third-order bridge before it: 4.3x, median 1.58), and the 6x4
arc is advised 6x4 again. The Cartesian split of SPEC §4 stays; the bound is the split's own constant on the fit's
error: median <= 1.4 and worst <= 3 (issue 23's 1.3x on every face is dropped). What is left above 1 is that
constant and, on curved quadratic faces, the fit's tangential error at half a cycle per span, which the Cartesian
split turns partly into normal ripple (``benchmarks/short_nets_tradeoff.py``; docs/model.md).

Degrees 4-5 do not meet that bound (strict xfail below): their least-squares fits lie far closer to the shape
(1e-7-1e-4 of its size) while the split, cutting at half a cycle per span, reads content a short high-degree
direction's points steer, so the ratio reaches 22.8x (median 1.76 over degrees 2-5). The measured alternative, a cut
at half a cycle per control point counted in index space (``fields.SPLIT_CUT = "index"``), meets it; it is not the
road's (docs/model.md, "Where the split cuts").
"""

import numpy as np
import pytest

import cadartifact as ca
from cadartifact.analysis.trim_region import insert_knot
from cadartifact.net import ControlNet
from cadartifact.testing.short_fits import distance_to_shape, family, fit

HIGH_DEGREES_OPEN = ("degrees 4-5: the split cuts at half a cycle per span, below what a short high-degree "
                     "direction's points steer (up to 22.8x the distance, median 1.76 over degrees 2-5); the "
                     "index-space cut meets the bound but breaks the advice's fixed point (docs/model.md)")


def _ratios(seed, degrees=(2, 3)):
    """``(ripple / distance, label)`` of the family's 25 faces of one seed."""
    out = []
    for net, distance, text in family(seed, 25, degrees):
        out.append((ca.budget(net).stats["total"].peak / distance_to_shape(net, distance), text))
    return out


@pytest.mark.slow
def test_short_nets_read_within_the_splits_own_constant_of_their_distance_to_the_smooth_shape():
    """Nets of 5-10 points, degrees 2-3, five shapes at random sizes and directions, three seeds of 25 faces: the
    ripple read is within 3x the surface's distance to the shape on every face and 1.4x on the median of the 75
    (the border convention's 32-span continuation: 2.77x and 1.386, per seed 1.52 / 1.41 / 1.31; the former
    continuation over twice the face: 2.59x and 1.35; the third-order bridge read 4.27x and 1.58)."""
    ratios = [r for seed in (11, 12, 13) for r in _ratios(seed)]
    for r, text in ratios:
        assert r <= 3.0, f"{text}: ripple {r:.2f}x its distance to the shape"
    assert np.median([r for r, _ in ratios]) <= 1.4, sorted(np.round([r for r, _ in ratios], 2))


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=HIGH_DEGREES_OPEN)
def test_short_nets_of_degrees_2_to_5_read_within_the_splits_own_constant():
    """The same bound on degrees 2-5 (three seeds of 25 faces, 2026-12-06: median 1.76, worst 22.8x, a 3x5-degree bump
    within 1.4e-3 mm reading 0.033 mm)."""
    ratios = [r for seed in (11, 12, 13) for r, _ in _ratios(seed, (2, 5))]
    assert max(ratios) <= 3.0 and np.median(ratios) <= 1.4


@pytest.mark.slow
def test_the_index_space_cut_would_meet_the_bound_on_degrees_2_to_5(monkeypatch):
    """The measured alternative (``fields.SPLIT_CUT = "index"``, docs/model.md "Where the split cuts"): the bound holds
    on degrees 2-5 (2026-12-06: median 1.21, worst 2.69x; per seed 1.21 / 1.21 / 1.20) and on three more seeds
    (14-16: medians 1.04-1.09, worst 2.69x)."""
    from cadartifact.analysis import fields

    monkeypatch.setattr(fields, "SPLIT_CUT", "index")
    for seeds in ((11, 12, 13), (14, 15, 16)):
        ratios = [r for seed in seeds for r, _ in _ratios(seed, (2, 5))]
        assert max(ratios) <= 3.0 and np.median(ratios) <= 1.4, (seeds, max(ratios), np.median(ratios))


def _midpoints(net, axis):
    """The same surface with a knot inserted at every span's midpoint along ``axis`` (twice the spans)."""
    t, p = np.asarray(net.knots[axis], float), net.degrees[axis]
    P = np.moveaxis(net.points, axis, 0)
    for u in sorted({(a + b) / 2 for a, b in zip(t[p:-p - 1], t[p + 1:-p]) if b > a}):
        t, P = insert_knot(t, P, p, u)
    knots = list(net.knots)
    knots[axis] = t
    return ControlNet(points=np.moveaxis(P, 0, axis), degrees=net.degrees, knots=tuple(knots))


@pytest.mark.slow
@pytest.mark.parametrize("cut", ["span", "index"])
def test_short_nets_read_no_more_ripple_with_twice_the_spans(cut, monkeypatch):
    """SPEC §4 invariance on short nets: the same surface with a knot at every span's midpoint reads within 1 % of
    its ripple (2026-12-06, 50 faces of degrees 2-5, both directions: at most 0.49 % and 1.3e-6 of the face's size
    cut at half a cycle per span; 0.45 % and 1.1e-7 with the index-space cut, where the cut moves with the spans;
    the rise is the border convention's, not the cut's)."""
    from cadartifact.analysis import fields

    monkeypatch.setattr(fields, "SPLIT_CUT", cut)
    for seed in (11, 12):
        for net, _, text in family(seed, 25, (2, 5)):
            v0 = ca.budget(net).stats["total"].peak
            for axis in (0, 1):
                v1 = ca.budget(_midpoints(net, axis)).stats["total"].peak
                assert v1 <= 1.01 * v0, (text, axis, v0, v1)


def _arc_6x4():
    """Issue 23's fuselage section: the 6x4 cubic least-squares fit of a 60 degree arc of radius 1500 mm, and its
    largest distance to the arc."""
    R, ang = 1500.0, np.radians(60)

    def points(u, v):
        a, t = np.broadcast_arrays(((u - 0.5) * ang)[:, None], v[None, :])
        return np.stack([R * np.sin(a), 400.0 * t, R * np.cos(a)], -1)

    net = fit(points, (6, 4), (3, 3))
    return net, distance_to_shape(net, lambda P: np.abs(np.hypot(P[..., 0], P[..., 2]) - R))


def test_a_60_degree_arc_on_a_6x4_cubic_net_reads_its_distance_within_the_conventions_limit():
    """The arc's fit lies within 0.035 mm of the arc and reads 0.058 mm, 1.66x its distance, under the split's
    border convention (a continuation of 32 spans past each border; within the SPEC's worst 3). That is the long
    continuation's limit (1.667x at 96 spans); the former continuation over twice the face (6 spans here) read
    1.37x, and moved with every lattice point of its period (docs/model.md "The `surface` reading's border
    convention"). At t = 0.065 the fit keeps its 6x4 net, conforming; at t = 0.06 its reading (0.058 + U) is
    undecided, as the gate decides it, and the advice, which claims a net only where the gate would confirm it
    (its own ripple with its U), takes 7x4."""
    net, d = _arc_6x4()
    assert d < 0.04
    assert ca.budget(net).stats["total"].peak <= 1.7 * d
    a = ca.advise(net, tolerance=0.065)
    assert a.shape == (6, 4) and a.meets_tolerance
    a = ca.advise(net, tolerance=0.06)
    assert a.to_dict()["today_decision"] == "undecided" and a.shape == (7, 4) and a.meets_tolerance
