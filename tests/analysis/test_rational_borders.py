"""The predicted road at clamped borders of rational faces (issue 23, item 5; cadartifact/analysis/clamped.py).

A clamped direction is read from its uniform-equivalent points ``Q = C P`` (the uniform B-spline equal to the
face on its domain), continued past the ends by a lattice bridge. Checks: the change of basis is exact, the
predicted surface is the face's, and the predicted road's ripple is within 10 % of the measured road's given a long
continuation, and on the median of a border-free truth, on a family of rational clamped faces (cadartifact/testing/rational_faces.py: degrees 2-4, 6-14 points, weights varying
10-45 %).
"""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cadartifact.analysis import fields as F
from cadartifact.analysis.baseband import baseband_at
from cadartifact.analysis.budget import budget
from cadartifact.analysis.clamped import clamped_syntheses, clamped_synthesis, uniform_equivalent
from cadartifact.analysis.intent import design_intent, from_homogeneous
from cadartifact.analysis.measure import real_surface
from cadartifact.analysis.settings import resolve_scheme
from cadartifact.net import ControlNet, clamped_uniform_knots
from cadartifact.numerics.splines import basis_matrix
from cadartifact.testing.rational_faces import border_free_truth, rational_face

BANDS = ("x1", "x2", "diagonal", "lateral", "total")
FAMILY = range(24)


def _ratios(seeds, gap=None):
    """Per face, predicted over measured peak of each band (the measured road continued over ``gap`` spans, if
    given)."""
    old = F.MEASURED_GAP
    try:
        if gap is not None:
            F.MEASURED_GAP = gap
        out = []
        for s in seeds:
            net = rational_face(s)
            p, m = budget(net, method="predicted"), budget(net, method="measured")
            out.append({k: p.stats[k].peak / m.stats[k].peak for k in BANDS})
        return out
    finally:
        F.MEASURED_GAP = old


@settings(max_examples=30, deadline=None)
@given(p=st.integers(1, 5), extra=st.integers(0, 12), seed=st.integers(0, 2 ** 16))
def test_uniform_equivalent_points_give_the_same_curve(p, extra, seed):
    """The uniform B-spline of ``Q = C P`` is the clamped B-spline of ``P`` on its domain; ``C`` is the identity
    but for its first and last ``p`` rows."""
    n = p + 1 + extra
    spans = n - p
    P = np.random.default_rng(seed).normal(size=(n, 2))
    C = uniform_equivalent(n, p)
    x = np.linspace(0.0, spans, 8 * spans + 1)
    clamped = basis_matrix(clamped_uniform_knots(n, p, 0.0, float(spans)), p, x, n) @ P
    uniform = basis_matrix(np.arange(-p, n + 1, dtype=float), p, x, n) @ (C @ P)
    assert np.abs(clamped - uniform).max() <= 1e-11 * np.abs(P).max()
    inner = slice(p, n - p)
    if n > 2 * p:
        assert np.array_equal(C[inner], np.eye(n)[inner])


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 10 ** 6))
def test_predicted_surface_is_the_face(seed):
    """Base band plus ripple of the predicted road is the real rational surface on the domain (to rounding),
    for dual (even) degrees too."""
    net = rational_face(seed)
    sch = resolve_scheme(net, None)
    it = design_intent(net, sch, 3)
    assert clamped_syntheses(it, sch) is not None
    pf = F.predicted_fields(it, sch, "surface")
    real = from_homogeneous(real_surface(it, sch))
    assert np.abs(pf.surface - real).max() <= 1e-9 * np.ptp(net.points)
    smooth = pf.intent + pf.bands["total"]
    assert np.abs(smooth - real).max() <= 1e-3 * np.ptp(net.points)  # first-order projection of the ripple
    # the surface reading's intent anywhere (the advice samples it) is the fields' own on the fine grid
    assert np.abs(baseband_at(pf, pf.x, pf.y) - pf.intent).max() <= 1e-9 * np.ptp(net.points)


def test_within_ten_percent_of_the_measured_road_with_a_long_bridge():
    """Against the measured road given a long continuation (a gap of 100 spans, 8-25x these faces), the total, x2
    and lateral ripple of every face are within 10 % (before: the predicted road read 1.5-8.6x the measured one's
    total on this family); x1 and the diagonal ripple (the product of two directions' small bands) within 15 %
    (worst 10.8 % and 11.0 %, 2026-12-05: the even period of the measured road's convention puts a bin at half a
    cycle per span, which an odd one did not)."""
    rows = _ratios(FAMILY, gap=100)
    for s, r in zip(FAMILY, rows):
        for k in BANDS:
            assert abs(r[k] - 1.0) <= (0.15 if k in ("diagonal", "x1") else 0.10), (s, k, r[k])


def test_against_the_measured_road_as_it_stands():
    """Against the measured road as it stands (its bridge spans 32 spans past the face): the median is within 10 % and most
    faces are; no face is off by the factors of before (the worst was 8.6x)."""
    total = np.array([r["total"] for r in _ratios(FAMILY)])
    assert abs(np.median(total) - 1.0) <= 0.10
    assert np.mean(np.abs(total - 1.0) <= 0.10) >= 0.5
    assert total.max() <= 2.0 and total.min() >= 0.4


TRUTH_FAMILY = range(120)


@pytest.mark.slow
def test_against_the_border_free_truth():
    """Judged against a border-free truth (each face drawn 12 spans longer at every border and cut back, the longer
    face read over the region the face covers: ``rational_faces.border_free_truth``), on the faces whose true ripple
    is at least 0.2 of the family's largest (21 of 120; where it is tiny the longer face's own reading dominates the
    ratio): the predicted road's median is within 10 % of the truth (1.098) and every face within 25 % (0.86-1.23),
    closer than the measured road as it stands (median 1.145, range 0.88-1.47). Every face within 10 % is not
    reached by either road (43 % and 38 % of the faces): the rest is the border convention's own latitude."""
    rows = []
    for seed in TRUTH_FAMILY:
        face, truth = border_free_truth(seed)
        rows.append((budget(face, method="predicted").stats["total"].peak / truth,
                     budget(face, method="measured").stats["total"].peak / truth, truth))
    r = np.array(rows)
    big = r[:, 2] >= 0.2 * r[:, 2].max()
    predicted, measured = r[big, 0], r[big, 1]
    assert big.sum() >= 15
    assert abs(np.median(predicted) - 1.0) <= 0.10, np.round(np.sort(predicted), 3)
    assert np.all(np.abs(predicted - 1.0) <= 0.25), np.round(np.sort(predicted), 3)
    assert np.median(np.abs(predicted - 1.0)) <= np.median(np.abs(measured - 1.0))


def test_only_rational_clamped_faces_take_the_new_road():
    """Non-rational faces, equal weights and periodic rational directions keep the uniform synthesis."""
    net = rational_face(3)
    sch = resolve_scheme(net, None)
    plain = net.replace(weights=None)
    assert clamped_syntheses(design_intent(plain, sch, 3), sch) is None
    same = net.replace(weights=np.full(net.shape, 2.0))
    assert clamped_syntheses(design_intent(same, sch, 3), sch) is None
    # a face read under another scheme (its poles a cage) keeps the uniform synthesis too
    other = resolve_scheme(net, "bicubic") if net.degrees != (3, 3) else resolve_scheme(net, "bilinear")
    assert clamped_syntheses(design_intent(net, other, 3), other) is None


def test_a_ripple_free_direction_has_no_ripple_and_its_own_operators():
    """A Bezier direction (one span) reads no ripple along it on the predicted road, as on the measured road;
    the synthesis cache tells a ripple-free direction from one of the same size that is not."""
    rng = np.random.default_rng(5)
    nu, nv, p, q = 9, 4, 3, 3
    i, j = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    pts = np.stack([60 * i, 40 * j, 3 * np.sin(7 * i) + 2 * j ** 2 + 0.1 * rng.normal(size=i.shape)], axis=-1)
    w = 1.0 + 0.3 * rng.random((nu, nv))
    net = ControlNet(points=pts, weights=w, degrees=(p, q),
                     knots=(clamped_uniform_knots(nu, p), clamped_uniform_knots(nv, q)))
    pb, mb = budget(net, method="predicted"), budget(net, method="measured")
    assert pb.stats["x2"].peak == 0.0 and pb.stats["diagonal"].peak == 0.0
    assert mb.stats["x2"].peak == 0.0
    assert abs(pb.stats["total"].peak / mb.stats["total"].peak - 1.0) <= 0.10
    sch = resolve_scheme(net, None)
    it = design_intent(net, sch, 3)
    import dataclasses

    free = clamped_synthesis(dataclasses.replace(it.frames[0], polynomial=True), p, p, sch, 0)
    rippled = clamped_synthesis(it.frames[0], p, p, sch, 0)
    assert not np.any(free[1]) and np.any(rippled[1])
    assert np.allclose(free[0], rippled[0] + rippled[1], rtol=0, atol=1e-12)  # both the face, split or not
