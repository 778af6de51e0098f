"""The PDQ criteria of one face (issue 25 item 1): each on faces built to hit it and to miss it, in seeded
families, with the threshold's edges.

Independent roads: OCCT evaluates the same surfaces (``Geom_BSplineSurface.D2``, ``GeomLProp_SLProps`` for the
principal curvatures, ``BRepGProp`` for the area, poles and degrees from the OCCT surface), and built faces are
checked against what they were built to be (flat rectangles of known area and width, circular arcs of known
radius, cosines with a known number of curvature zeros, trim boxes with a known number of patches outside).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRepGProp import BRepGProp  # noqa: E402
from OCP.GeomLProp import GeomLProp_SLProps  # noqa: E402
from OCP.GProp import GProp_GProps  # noqa: E402
from OCP.gp import gp_Pnt, gp_Vec  # noqa: E402

from cadartifact.analysis.quality import (  # noqa: E402
    CRITERIA,
    FACE_CRITERIA,
    DEFAULT_PROFILE,
    Limit,
    Profile,
    criteria,
    curvatures,
    inflections,
    judge,
    sample_face,
)
from cadartifact.exchange.occ import make_face, occ_surface  # noqa: E402
from cadartifact.net import ControlNet, clamped_uniform_knots  # noqa: E402

from cadartifact.testing.known_shapes import DIRECTIONS, known_face, shape_function  # noqa: E402


def by_key(net, profile=DEFAULT_PROFILE):
    return {c.key: c for c in criteria(net, profile)}


def random_net(rng, rational=False, nonuniform=True):
    """A random clamped B-spline face (degrees 2-5, 6-14 points, optional weights and chord-like knots)."""
    p, q = (int(d) for d in rng.integers(2, 6, 2))
    nu, nv = (int(n) for n in rng.integers(max(p, q) + 2, 15, 2))
    knots = []
    for n, d in ((nu, p), (nv, q)):
        if nonuniform:
            inner = np.sort(rng.uniform(0.05, 0.95, n - d - 1))
            knots.append(np.concatenate([np.zeros(d + 1), inner, np.ones(d + 1)]) * rng.uniform(0.5, 3))
        else:
            knots.append(clamped_uniform_knots(n, d))
    i, j = np.meshgrid(np.linspace(0, 50, nu), np.linspace(0, 40, nv), indexing="ij")
    z = 5 * np.sin(i / 17 + rng.uniform(0, 3)) * np.cos(j / 13) + rng.normal(0, 0.5, i.shape)
    pts = np.stack([i + rng.normal(0, 0.3, i.shape), j + rng.normal(0, 0.3, i.shape), z], axis=-1)
    w = rng.uniform(0.6, 1.6, (nu, nv)) if rational else None
    return ControlNet(points=pts, weights=w, degrees=(p, q), knots=tuple(knots))


def occ_d2(surface, u, v):
    P, d1u, d1v, d2u, d2v, d2uv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
    surface.D2(u, v, P, d1u, d1v, d2u, d2v, d2uv)
    vec = lambda x: np.array([x.X(), x.Y(), x.Z()])  # noqa: E731
    return vec(P), vec(d1u), vec(d1v), vec(d2u), vec(d2v), vec(d2uv)


# ---------------------------------------------------------------- the evaluation, against OCCT
@pytest.mark.parametrize("seed", range(6))
def test_derivatives_and_curvatures_match_occt(seed):
    """Point, first and second derivatives and the largest principal curvature on the criteria's own grid
    agree with OCCT's D2 and GeomLProp_SLProps (rational faces with non-uniform knots included)."""
    rng = np.random.default_rng(seed)
    net = random_net(rng, rational=seed % 2 == 1)
    fs = sample_face(net)
    cv = curvatures(fs)
    surface = occ_surface(net)
    scale = np.ptp(net.points.reshape(-1, 3), axis=0).max()
    for i in rng.choice(len(fs.u), 6):
        for j in rng.choice(len(fs.v), 6):
            occ = occ_d2(surface, fs.u[i], fs.v[j])
            ours = (fs.S[i, j], fs.Su[i, j], fs.Sv[i, j], fs.Suu[i, j], fs.Svv[i, j], fs.Suv[i, j])
            for a, b in zip(ours, occ):
                assert np.allclose(a, b, rtol=1e-7, atol=1e-9 * scale * max(1.0, np.abs(b).max() / scale))
            props = GeomLProp_SLProps(surface, fs.u[i], fs.v[j], 2, 1e-9)
            if props.IsCurvatureDefined() and cv["valid"][i, j]:
                kmax = max(abs(props.MaxCurvature()), abs(props.MinCurvature()))
                assert cv["kmax"][i, j] == pytest.approx(kmax, rel=1e-6, abs=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_area_matches_occt(seed):
    """The area (Gauss-Legendre per span piece over the trim box) agrees with BRepGProp's adaptive integration
    on the same face (its default, non-adaptive one is off by up to 3e-5 on these faces; ours agrees with the
    adaptive one to 1e-8)."""
    rng = np.random.default_rng(100 + seed)
    net = random_net(rng, rational=seed % 2 == 0)
    (ku, kv) = net.knots
    u0, u1 = sorted(rng.uniform(ku[0], ku[-1], 2))
    v0, v1 = sorted(rng.uniform(kv[0], kv[-1], 2))
    net = net.replace(uv_bounds=(u0, u1, v0, v1))
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(make_face(net), props, 1e-10)  # adaptive, to 1e-10 relative
    assert by_key(net)["area"].value == pytest.approx(props.Mass(), rel=1e-6)


# ---------------------------------------------------------------- waviness
def _zero_crossings(values):
    s = np.sign(values[np.abs(values) > 1e-9 * np.abs(values).max()])
    return int((np.diff(s) != 0).sum())


@pytest.mark.parametrize("seed", range(8))
def test_waviness_counts_the_inflections_of_known_cosines(seed):
    """A face sampling ``A cos(2 pi f X + phase)`` along u, v or the diagonal: the largest inflection count
    along an isoparametric line is the number of curvature sign changes OCCT's D2 gives along the same lines,
    and (to within one at the borders) the designed shape's number of zeros of ``cos`` across the face."""
    rng = np.random.default_rng(seed)
    p, q = (int(d) for d in rng.integers(3, 6, 2))
    n = int(rng.integers(30, 41))
    f = float(rng.uniform(0.03, 0.25))
    dname = ("u", "v", "diagonal")[seed % 3]
    phase = float(rng.uniform(0, 2 * np.pi))
    g = shape_function("cosine", f, DIRECTIONS[dname], phase, (n - p, n - q))
    net, _ = known_face((p, q), (n, n), g, amplitude=2.0)
    crit = by_key(net)["waviness"]
    # OCCT along the u and v lines of a grid of 12 lines each, 400 points per line
    surface = occ_surface(net)
    t = np.linspace(0, 1, 400)
    grid = np.array([occ_d2(surface, u, v)[0] for u in np.linspace(0, 1, 41) for v in np.linspace(0, 1, 41)])
    floor = 1.0 / (DEFAULT_PROFILE.flat_ratio * np.linalg.norm(np.ptp(grid, axis=0)))  # relative to the face's size
    worst = 0
    for line in np.linspace(0.02, 0.98, 12):
        for along in "uv":
            ks = []
            for x in t:
                u, v = (x, line) if along == "u" else (line, x)
                _, su, sv, suu, svv, _ = occ_d2(surface, u, v)
                nrm = np.cross(su, sv)
                nrm /= np.linalg.norm(nrm)
                ks.append((suu @ nrm) / (su @ su) if along == "u" else (svv @ nrm) / (sv @ sv))
            worst = max(worst, inflections(np.array(ks), floor)[0])
    assert crit.value == worst
    # the designed shape: the most zeros of g (of its curvature, -(2 pi f)^2 g for a cosine) along any line
    X = np.linspace(0, n - p, 4000)
    designed = max(max(_zero_crossings(g(X, y)), _zero_crossings(g(y, X))) for y in np.linspace(0, n - p, 60))
    assert abs(crit.value - designed) <= 1
    assert crit.verdict == judge(crit.value, DEFAULT_PROFILE.limit("waviness"), "above")
    assert crit.uv is not None and np.allclose(crit.xyz, sample_face(net, [crit.uv[0]], [crit.uv[1]]).S[0, 0])


@pytest.mark.parametrize("seed", range(6))
def test_waviness_hits_many_cosine_periods_and_misses_one_bump(seed):
    """Hit: 3 or more periods across the face (>= 5 inflections: fail). Miss: a single smooth dome (no
    inflection: pass), and a flat plane with noise below the flat radius (no sign: pass)."""
    rng = np.random.default_rng(50 + seed)
    p = int(rng.integers(3, 6))
    n = 36
    f = float(rng.uniform(3.2, 4.5)) / (n - p)
    wavy, _ = known_face((p, p), (n, n), shape_function("cosine", f, DIRECTIONS["u"], 0.3, (n - p, n - p)))
    assert by_key(wavy)["waviness"].verdict == "fail" and by_key(wavy)["waviness"].value >= 5
    dome, _ = known_face((p, p), (n, n), lambda X, Y: -((X / (n - p) - 0.5) ** 2 + (Y / (n - p) - 0.5) ** 2),
                         amplitude=float(rng.uniform(1, 20)))
    assert by_key(dome)["waviness"].value == 0 and by_key(dome)["waviness"].verdict == "pass"
    flat, _ = known_face((p, p), (n, n), lambda X, Y: 1e-9 * np.cos(3 * X + Y))
    assert by_key(flat)["waviness"].value == 0


def test_inflections_threshold_edges():
    """The count ignores samples within the flat band and reports the smaller lobe of the largest change."""
    k = np.array([0.0, 2.0, 3.0, 0.5e-5, -1.0, -0.5, 0.0, 0.4])
    assert inflections(k, 1e-5) == (2, 1.0, 4)
    assert inflections(k, 0.45)[0] == 1  # the 0.4 lobe is flat under this band
    assert inflections(np.zeros(5), 0.0) == (0, 0.0, -1)
    lim = Limit(warn=1, fail=3)
    assert [judge(x, lim, "above") for x in (1, 2, 3, 4)] == ["pass", "warn", "warn", "fail"]
    low = Limit(warn=0.02, fail=0.01)
    assert [judge(x, low, "below") for x in (0.02, 0.019, 0.01, 0.0099)] == ["pass", "warn", "warn", "fail"]


# ---------------------------------------------------------------- degree and control points
@pytest.mark.parametrize("seed", range(5))
def test_degree_and_counts_match_the_occt_surface(seed):
    rng = np.random.default_rng(200 + seed)
    p, q = int(rng.integers(1, 13)), int(rng.integers(1, 13))
    nu, nv = p + int(rng.integers(1, 30)), q + int(rng.integers(1, 30))
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    net = ControlNet.from_points(np.stack([i, j, np.sin(i + j)], -1).astype(float), degrees=(p, q))
    s = occ_surface(net)
    crit = by_key(net)
    assert crit["degree"].value == max(s.UDegree(), s.VDegree())
    assert crit["points"].value == max(s.NbUPoles(), s.NbVPoles())
    assert crit["points_total"].value == s.NbUPoles() * s.NbVPoles()
    expect = "fail" if max(p, q) > 11 else "warn" if max(p, q) > 7 else "pass"
    assert crit["degree"].verdict == expect


def test_degree_and_count_threshold_edges():
    i, j = np.meshgrid(np.arange(12), np.arange(9), indexing="ij")
    pts = np.stack([i, j, 0.1 * i * j], -1).astype(float)
    for p, verdict in ((7, "pass"), (8, "warn"), (11, "warn")):
        assert by_key(ControlNet.from_points(pts, degrees=(p, 2)))["degree"].verdict == verdict
    prof = Profile(name="t", limits=tuple((k, Limit(warn=11, fail=12) if k == "points" else
                                           Limit(warn=108, fail=116) if k == "points_total" else lim)
                                          for k, lim in DEFAULT_PROFILE.limits))
    crit = by_key(ControlNet.from_points(pts, degrees=(3, 3)), prof)
    assert (crit["points"].verdict, crit["points_total"].verdict) == ("warn", "pass")  # 12 > 11; 108 = 108
    crit = by_key(ControlNet.from_points(np.concatenate([pts, pts[-1:] + [1, 0, 0]]), degrees=(3, 3)), prof)
    assert (crit["points"].verdict, crit["points_total"].verdict) == ("fail", "fail")  # 13 > 12; 117 > 116


# ---------------------------------------------------------------- indistinct knots
@pytest.mark.parametrize("seed", range(6))
def test_indistinct_knots_hit_and_miss(seed):
    """A pair of knots ``delta`` apart: indistinct when ``delta`` is under the parameter share AND the span is
    under the model-unit limit on the surface; OCCT's evaluation along the span gives the same length."""
    rng = np.random.default_rng(300 + seed)
    p = int(rng.integers(2, 5))
    n = int(rng.integers(10, 16))
    inner = list(np.linspace(0, 1, n - p + 1)[1:-2])
    t0 = float(rng.uniform(0.1, 0.8))
    close = float(10 ** rng.uniform(-8, -5))
    knots_u = np.concatenate([np.zeros(p + 1), np.sort(inner[:-1] + [t0, t0 + close]), np.ones(p + 1)])
    nu = len(knots_u) - p - 1
    i, j = np.meshgrid(np.linspace(0, 100, nu), np.linspace(0, 60, 8), indexing="ij")
    net = ControlNet(points=np.stack([i, j, 3 * np.sin(i / 20)], -1), degrees=(p, 3),
                     knots=(knots_u, clamped_uniform_knots(8, 3)))
    crit = by_key(net)["knots"]
    assert crit.verdict == "fail" and crit.value < 0.01
    # OCCT: the span's length on the surface, the longest over v
    s = occ_surface(net)
    best = 0.0
    for v in np.linspace(0, 1, 41):
        pts = np.array([occ_d2(s, u, v)[0] for u in np.linspace(t0, t0 + close, 21)])
        best = max(best, np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
    assert crit.value == pytest.approx(best, rel=0.05)
    # miss: the same pair far apart in parameter is distinct whatever its length
    wide = np.concatenate([np.zeros(p + 1), np.sort(inner[:-1] + [t0, t0 + 0.05]), np.ones(p + 1)])
    assert by_key(net.replace(knots=(wide, net.knots[1])))["knots"].verdict == "pass"
    # close in parameter but long on the surface (a huge face): not indistinct
    big = net.replace(points=net.points * 1e7 / max(1.0, best * 1e3))
    if by_key(big)["knots"].value >= 0.02:
        assert by_key(big)["knots"].verdict == "pass"


# ---------------------------------------------------------------- unused patches
@pytest.mark.parametrize("seed", range(8))
def test_unused_patches_count_the_spans_outside_the_trim_box(seed):
    """Brute force: a patch is used when any of its points (1999 per direction, interior) lies inside the box."""
    rng = np.random.default_rng(400 + seed)
    net = random_net(rng, nonuniform=seed % 2 == 0)
    ku, kv = net.knots
    u0, u1 = sorted(rng.uniform(ku[0], ku[-1], 2))
    v0, v1 = (kv[0], kv[-1]) if seed % 3 == 0 else sorted(rng.uniform(kv[0], kv[-1], 2))
    trimmed = net.replace(uv_bounds=(u0, u1, v0, v1))
    du, dv = np.unique(ku), np.unique(kv)
    used = total = 0
    for a, b in zip(du[:-1], du[1:]):
        for c, d in zip(dv[:-1], dv[1:]):
            total += 1
            us, vs = np.linspace(a, b, 2001)[1:-1], np.linspace(c, d, 2001)[1:-1]
            used += bool(((us > u0) & (us < u1)).any() and ((vs > v0) & (vs < v1)).any())
    crit = by_key(trimmed)["unused"]
    assert crit.value == pytest.approx(1 - used / total)
    assert crit.verdict == judge(crit.value, DEFAULT_PROFILE.limit("unused"), "above")
    assert by_key(net)["unused"].value == 0 and by_key(net)["unused"].verdict == "pass"


# ---------------------------------------------------------------- tiny and narrow faces
@pytest.mark.parametrize("seed", range(6))
def test_area_and_width_of_flat_rectangles(seed):
    """A flat a x b rectangle (non-uniform parametrisation inside): area a b, width min(a, b); tiny and narrow
    faces fail, ordinary ones pass."""
    rng = np.random.default_rng(500 + seed)
    a, b = 10 ** rng.uniform(-3, 2, 2)
    nu, nv = (int(x) for x in rng.integers(4, 9, 2))
    su = np.concatenate([[0], np.sort(rng.uniform(0, 1, nu - 2)), [1]])
    sv = np.concatenate([[0], np.sort(rng.uniform(0, 1, nv - 2)), [1]])
    X, Y = np.meshgrid(a * su, b * sv, indexing="ij")
    net = ControlNet.from_points(np.stack([X, Y, np.zeros_like(X)], -1), degrees=(3, 2))
    crit = by_key(net)
    assert crit["area"].value == pytest.approx(a * b, rel=1e-9)
    assert crit["width"].value == pytest.approx(min(a, b), rel=1e-9)
    assert crit["area"].verdict == judge(a * b, DEFAULT_PROFILE.limit("area"), "below")
    assert crit["width"].verdict == judge(min(a, b), DEFAULT_PROFILE.limit("width"), "below")
    assert crit["radius"].value is not None and math.isinf(crit["radius"].value)  # flat: no curvature
    assert crit["radius"].verdict == "pass"


# ---------------------------------------------------------------- tiny curvature radius
@pytest.mark.parametrize("radius", [0.1, 0.3, 0.49, 0.51, 2.0, 40.0])
def test_min_radius_of_exact_cylinders(radius):
    """A quarter cylinder (rational quadratic arc, weights 1, sqrt(2)/2, 1) extruded: its smallest principal
    radius is ``radius`` exactly; under 0.5 (the default) it fails."""
    w = math.sqrt(0.5)
    arc = np.array([[radius, 0, 0], [radius, radius, 0], [0, radius, 0]])
    pts = np.stack([arc, arc + [0, 0, 5]], axis=1)
    net = ControlNet(points=pts, weights=np.array([[1, 1], [w, w], [1, 1]]), degrees=(2, 1),
                     knots=(np.array([0, 0, 0, 1, 1, 1.0]), np.array([0, 0, 1, 1.0])))
    crit = by_key(net)["radius"]
    assert crit.value == pytest.approx(radius, rel=1e-9)
    assert crit.verdict == ("fail" if radius < 0.5 else "pass")
    assert np.linalg.norm(np.asarray(crit.xyz)[:2]) == pytest.approx(radius, rel=1e-9)


@pytest.mark.parametrize("radius", [0.3, 1.0, 5.0, 120.0])
@pytest.mark.parametrize("sweep", [0.5, 1.0])
def test_min_radius_of_exact_spheres_with_a_pole(radius, sweep):
    """A sphere patch whose v = 0 edge collapses into the pole (a rational biquadratic: quarter arcs swept
    about the z axis by ``sweep`` of a quarter turn): every principal radius is ``radius``. At the pole one
    derivative is zero up to rounding and the fundamental forms there are noise: those samples have no
    normal, and the radius is the sphere's, not 0."""
    w = math.sqrt(0.5)
    meridian = np.array([[0, 0, radius], [radius, 0, radius], [radius, 0, 0]])  # pole to equator, in xz
    weights_m = np.array([1.0, w, 1.0])
    angle = sweep * math.pi / 2
    half = angle / 2
    # one rational quadratic arc about z of opening `angle`: middle weight cos(half), middle point at 1/cos(half)
    rot = [np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]) for a in (0, half, angle)]
    pts = np.empty((3, 3, 3))
    wts = np.empty((3, 3))
    for j, (R, wj, stretch) in enumerate(zip(rot, (1.0, math.cos(half), 1.0), (1.0, 1 / math.cos(half), 1.0))):
        for i in range(3):
            p = meridian[i].copy()
            p[:2] *= stretch
            pts[i, j] = R @ p
            wts[i, j] = weights_m[i] * wj
    knots = np.array([0, 0, 0, 1, 1, 1.0])
    net = ControlNet(points=pts, weights=wts, degrees=(2, 2), knots=(knots, knots))
    crit = by_key(net)["radius"]
    assert crit.value == pytest.approx(radius, rel=1e-6)
    assert crit.verdict == ("fail" if radius < 0.5 else "pass")
    assert "normal undefined" in crit.detail  # the pole's samples are named, not used


# ---------------------------------------------------------------- what cannot be evaluated
def test_cage_and_degenerate_faces_say_why_nothing_is_silent():
    i, j = np.meshgrid(np.arange(5), np.arange(4), indexing="ij")
    cage = ControlNet.from_points(np.stack([i, j, 0 * i], -1).astype(float), degrees=None)
    out = criteria(cage)
    assert [c.key for c in out] == list(FACE_CRITERIA)
    assert {c.key for c in out if c.evaluated} == {"points", "points_total"}
    assert all(c.reason and "cage" in c.reason and c.verdict is None for c in out if not c.evaluated)
    # every point on one line: the normal is undefined everywhere
    line = ControlNet.from_points(np.stack([i + j, i + j, i + j], -1).astype(float), degrees=(2, 2))
    crit = by_key(line)
    for key in ("waviness", "radius"):
        assert not crit[key].evaluated and "normal is undefined" in crit[key].reason
    # a criterion the profile turns off is reported as off
    off = Profile(name="off", limits=tuple((k, None if k == "unused" else lim) for k, lim in DEFAULT_PROFILE.limits))
    got = by_key(ControlNet.from_points(np.stack([i, j, 0.1 * i * j], -1).astype(float)), off)
    assert not got["unused"].evaluated and got["unused"].reason == "off in this profile"


def test_records_are_json_ready():
    import json

    rng = np.random.default_rng(7)
    net = random_net(rng, rational=True)
    for c in criteria(net):
        d = c.to_dict()
        json.dumps(d, allow_nan=False)
        assert d["code"] == CRITERIA[c.key][0] and d["threshold"]["sense"] == CRITERIA[c.key][3]


@pytest.mark.parametrize("seed", range(4))
def test_basis_derivatives_match_scipy(seed):
    """:func:`cadartifact.numerics.splines.basis_derivatives` (The NURBS Book A2.3, numpy) against
    scipy's BSpline derivatives on random clamped knot vectors with double knots, degrees 1-6, and the
    range's ends; order 0 equals :func:`basis_matrix`."""
    from scipy.interpolate import BSpline

    from cadartifact.numerics.splines import basis_derivatives, basis_matrix

    rng = np.random.default_rng(700 + seed)
    for _ in range(10):
        p = int(rng.integers(1, 7))
        n = p + int(rng.integers(2, 10))
        inner = np.sort(rng.uniform(0, 1, n - p - 1))
        if len(inner) > 2:
            inner[2] = inner[1]
        t = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)]) * 3 - 1
        x = np.concatenate([rng.uniform(-1, 2, 40), [-1, 2]])
        D = basis_derivatives(t, p, x, n)
        spl = BSpline(t, np.eye(n), p)
        for d in range(3):
            ref = spl(x, nu=d) if d <= p else np.zeros_like(D[d])
            assert np.allclose(D[d], ref, rtol=1e-9, atol=1e-9 * max(1.0, np.abs(ref).max()))
        assert np.allclose(D[0], basis_matrix(t, p, x, n), atol=1e-12)
