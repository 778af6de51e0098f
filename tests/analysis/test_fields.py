"""Artifact fields and budgets: predicted vs measured, and both vs SPEC §3 responses."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cadartifact as ca
from cadartifact.analysis.budget import budget
from cadartifact.analysis.fields import design_intent, measured_fields, predicted_fields
from cadartifact.net import ControlNet, clamped_uniform_knots, greville

NAMED = ["bilinear", "bicubic", "4-3", "4-8", "kobbelt"]


def sinusoid_cage(n, k, amp=0.3):
    """A periodic net carrying A cos(2 pi W.J) in z with W = k/n (exactly periodic)."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    w = (k[0] / n, k[1] / n)
    z = amp * np.cos(2 * np.pi * (w[0] * i + w[1] * j))
    pts = np.stack([0.01 * np.sin(2 * np.pi * i / n), 0.01 * np.cos(2 * np.pi * j / n), z], axis=-1)
    return ControlNet(points=pts, periodic=(True, True)), w


def rms(f):
    return float(np.sqrt(np.mean(f ** 2)))


@pytest.mark.parametrize("name", NAMED + ["bspline(2,3)", "box(2,2,1,1)"])
@pytest.mark.parametrize("k", [(2, 3), (5, 1), (7, 6)])
def test_sinusoid_predicted_equals_measured_and_spec(name, k):
    s = ca.scheme(name)
    net, w = sinusoid_cage(16, k)
    it = design_intent(net, s, levels=1)
    pred, meas = predicted_fields(it, s), measured_fields(it, s)
    for band in ("signal_error", "x1", "x2", "diagonal", "lateral", "total"):
        np.testing.assert_allclose(pred.bands[band], meas.bands[band], atol=1e-9 * 0.3)
    amp = 0.3
    z = lambda band: pred.bands[band][..., 2]
    if not any(s.dual):
        # refined vertices (levels=1) carry exactly the paper's alpha, beta, gamma, delta
        r = s.response(w[0], w[1], stage="limit")
        sig, x1, x2, dg, lat = float(r.signal), float(r.x1), float(r.x2), float(r.diagonal), float(r.lateral)
    else:
        # dual axes: the net's own points are sampled (Z/2), not the dual refined vertices
        sig, x1, x2, dg = (float(s.transfer(w[0] + a, w[1] + b, 1)) for a, b in ((0, 0), (1, 0), (0, 1), (1, 1)))
        n = np.hypot(*w)
        lat = np.sqrt(((x1 * w[1] / n) ** 2 + (x2 * w[0] / n) ** 2 + (dg * abs(w[0] ** 2 - w[1] ** 2) / (2 * n * n)) ** 2) / 3)
    assert rms(z("x1")) * np.sqrt(2) == pytest.approx(amp * abs(x1), abs=1e-12)
    assert rms(z("x2")) * np.sqrt(2) == pytest.approx(amp * abs(x2), abs=1e-12)
    assert rms(z("diagonal")) * np.sqrt(2) == pytest.approx(amp * abs(dg), abs=1e-12)
    assert rms(z("signal_error")) * np.sqrt(2) == pytest.approx(amp * abs(sig - 1), abs=1e-12)
    # lateral field: ripple components weighted by SPEC's factors; its RMS is sqrt(3) x Response.lateral
    assert rms(z("lateral")) * np.sqrt(2) == pytest.approx(amp * np.sqrt(3) * lat, abs=1e-12)


@pytest.mark.parametrize("name", ["bicubic", "4-8", "bspline(2,2)"])
def test_sinusoid_continuous_stage_at_fine_levels(name):
    """On a K = 32 grid the ripple RMS approaches the continuous surface's alias sums (SPEC §3)."""
    s = ca.scheme(name)
    net, w = sinusoid_cage(8, (1, 2))
    b = budget(net, s, method="both", levels=5, component="vector", keep_fields=True)
    r = s.response(w[0], w[1], stage="continuous")
    z = lambda band: b.fields.bands[band][..., 2]
    assert rms(z("x1")) * np.sqrt(2) == pytest.approx(0.3 * float(r.x1), rel=2e-3)
    assert rms(z("x2")) * np.sqrt(2) == pytest.approx(0.3 * float(r.x2), rel=2e-3)
    assert b.check["max_abs_diff"] < 1e-9


@pytest.mark.parametrize("name", NAMED + ["bspline(2,2)", "bspline(3,3)"])
def test_polynomial_cage_reports_zero_artifact(name):
    s = ca.scheme(name)
    d = s.reproduction_degree
    i, j = np.meshgrid(np.arange(11.0), np.arange(9.0), indexing="ij")
    z = 0.02 * i ** min(d, 3) - 0.05 * (i * j if d >= 2 else j) + 0.3 * j + 1
    net = ControlNet(points=np.stack([3 * i, 2 * j + 0.1 * i, z], axis=-1))
    for method in ("predicted", "measured"):
        b = budget(net, s, method=method, component="vector")
        scale = np.abs(net.points).max()
        for band in ("x1", "x2", "diagonal", "lateral", "total"):
            assert b.stats[band].peak <= 1e-9 * scale, (method, band, b.stats[band].peak)


def _greville_net(degrees, shape, z):
    (p, q), (nu, nv) = degrees, shape
    ku, kv = clamped_uniform_knots(nu, p), clamped_uniform_knots(nv, q)
    gu, gv = greville(ku, p, nu), greville(kv, q, nv)
    X, Y = 90.0 * gu[:, None] + 0 * gv[None, :], 60.0 * gv[None, :] + 0 * gu[:, None]
    return ControlNet(points=np.stack([X, Y, z(X, Y)], axis=-1), degrees=(p, q), knots=(ku, kv))


@pytest.mark.parametrize("degrees", [(3, 3), (2, 3), (3, 2), (5, 4)])
def test_polynomial_clamped_face_zero_artifact(degrees):
    """A clamped face whose points sample a polynomial at their Greville abscissae: no predicted ripple
    (degree <= the scheme's); bilinear ones none on the real surface either; higher degrees only the
    clamped end spans' own structure (the Greville points are not the polynomial's blossoms), below
    1e-3 of the shape."""
    d = min(degrees)
    z = lambda x, y: 0.001 * x ** d + 0.0005 * x * y - 2e-4 * y ** 2 + 5  # noqa: E731
    net = _greville_net(degrees, (12, 10), z)
    size = float(np.ptp(net.points[..., 2]))
    assert budget(net, method="predicted").stats["total"].peak <= 1e-9 * size
    assert budget(net, method="measured").stats["total"].peak <= 1e-3 * size
    flat = _greville_net(degrees, (12, 10), lambda x, y: 0.01 * x * y - 0.2 * x + 3)
    for method in ("predicted", "measured"):
        assert budget(flat, method=method).stats["total"].peak <= 1e-9 * 60


def test_face_road_agrees_with_prediction_on_interior():
    """A uniform clamped bicubic face sampling a ridge: the real surface (NURBS evaluation, measured road)
    and the spectral prediction agree on the interior to 0.1 % of the shape's amplitude (what the split
    of the clamped borders leaks inward; the ripple itself is 0.2 % of it here)."""
    net = _greville_net((3, 3), (24, 20), lambda x, y: 2.0 * np.cos(2 * np.pi * (x + y) / 30.0))
    b = budget(net, method="both")
    assert b.method == "measured" and b.check["method"] == "predicted"
    assert b.check["max_abs_diff"] < 1e-3 * 2.0


@settings(max_examples=25, deadline=None)
@given(st.floats(0.01, 10.0), st.floats(-50, 50), st.integers(0, 3))
def test_budget_scales_linearly_and_ignores_offsets(scale, shift, seed):
    """Ripple is linear in the net and blind to rigid translation (property)."""
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(9.0), np.arange(7.0), indexing="ij")
    z = rng.normal(size=i.shape)
    pts = np.stack([i, j, z], axis=-1)
    a = budget(ControlNet.from_points(pts), component="vector")
    b = budget(ControlNet.from_points(pts * scale + shift), component="vector")
    for k in ("x1", "x2", "diagonal", "total"):
        assert b.stats[k].peak == pytest.approx(a.stats[k].peak * scale, rel=1e-7, abs=1e-12)


def test_non_uniform_face_is_measured_and_says_so():
    i, j = np.meshgrid(np.arange(8.0), np.arange(6.0), indexing="ij")
    pts = np.stack([i, j, np.sin(i) * np.cos(j)], axis=-1)
    net = ControlNet.from_points(pts, degrees=(3, 3))
    ku = net.knots[0].copy()
    ku[4] = 0.1  # uneven interior spacing
    uneven = net.replace(knots=(ku, net.knots[1]))
    b = budget(uneven)
    assert b.method == "measured" and "knots are not uniform" in b.reason
    w = np.ones(net.shape)
    w[3, 2] = 2.0
    b = budget(net.replace(weights=w))
    assert b.method == "measured" and "homogeneous coordinates" in b.reason


def test_both_readings_share_the_ripple():
    """The surface reading (default) and the net reading report the same ripple; only the signal error
    (zero for the surface reading) and so the deviation differ."""
    net = _greville_net((3, 3), (16, 14), lambda x, y: 3 * np.cos(2 * np.pi * x / 25.0))
    s_, n_ = budget(net, component="vector"), budget(net, intent="net", component="vector")
    for k in ("x1", "x2", "diagonal", "total"):
        assert s_.stats[k].peak == pytest.approx(n_.stats[k].peak, rel=1e-12)
    assert s_.stats["signal_error"].peak == 0.0 and n_.stats["signal_error"].peak > 0.01
    assert s_.intent == "surface" and n_.intent == "net"


def test_budget_options_are_checked():
    net = ControlNet.from_points(np.random.default_rng(0).normal(size=(6, 6)))
    with pytest.raises(ca.errors.OptionError, match="metric"):
        budget(net, metric="max")
    with pytest.raises(ca.errors.OptionError, match="intent"):
        budget(net, intent="design")
    with pytest.raises(ca.errors.OptionError, match="tolerance"):
        budget(net, tolerance=-1)
    with pytest.raises(ca.errors.OptionError, match="method"):
        budget(net, method="guess")


@pytest.mark.parametrize("method", ["predicted", "measured"])
def test_a_direction_straight_in_the_intent_has_no_ripple(method):
    """An extruded shape (constant along u, a sinusoid along v): no ripple along u on either road, for a
    cage and for a face of degree 1 in u (SPEC §4: each direction's intent reproduces its polynomials,
    past the net's borders too)."""
    i, j = np.meshgrid(np.arange(10.0), np.arange(12.0), indexing="ij")
    z = 0.3 * np.sin(2 * np.pi * 0.2 * j)
    cage = ControlNet(points=np.stack([i, j, z], axis=-1))
    b = budget(cage, "catmull-clark", method=method)
    assert b.stats["x1"].peak < 1e-12 and b.stats["diagonal"].peak < 1e-12 and b.stats["x2"].peak > 1e-4
    face = _greville_net((1, 3), (6, 14), lambda x, y: 0.02 * x + np.sin(2 * np.pi * y / 25.0))
    b = budget(face, method=method)
    assert b.stats["x1"].peak < 1e-9 * 60, b.stats["x1"].peak


def test_a_single_span_direction_has_no_ripple_along_it():
    """A direction of one polynomial piece (2 points of degree 1, or a Bezier direction) has no knots, so no
    X1 or diagonal ripple on the real surface; the other direction's ripple is still there."""
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(2, 6, 3))
    pts[..., 0] += 10.0 * np.arange(2)[:, None]
    pts[..., 1] += 10.0 * np.arange(6)[None, :]
    b = budget(ControlNet.from_points(pts, degrees=(1, 3)), method="measured")
    assert b.stats["x1"].peak == 0.0 and b.stats["diagonal"].peak == 0.0 and b.stats["x2"].peak > 1e-3
