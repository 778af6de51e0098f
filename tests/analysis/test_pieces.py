"""Issue 10: junctions, removable knots, rational faces and degree-1 directions, against known shapes.

Independent roads: OCCT re-expresses the surfaces (knot insertion to multiplicity p, segmenting) and
evaluates them; the pieces and the homogeneous analysis are cadartifact's.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cadartifact as ca
from cadartifact.net import ControlNet, clamped_uniform_knots
from cadartifact.analysis.pieces import junctions, split_net

pytest.importorskip("OCP")

from cadartifact.exchange.load import evaluate_grid, occ_surface  # noqa: E402
from cadartifact.exchange.occ import net_from_surface  # noqa: E402


def smooth_face(nu, nv, p, q, amp, freq, phase, size=100.0):
    """A clamped uniform face whose points sample a smooth known shape (a tilted wavy sheet)."""
    x, y = np.meshgrid(np.linspace(0, size, nu), np.linspace(0, 0.7 * size, nv), indexing="ij")
    z = amp * np.cos(2 * np.pi * freq * (x + 0.6 * y) / size * 3 + phase) + 0.1 * x
    return ControlNet.from_points(np.stack([x, y, z], -1), degrees=(p, q))


def bezier_form(net: ControlNet) -> ControlNet:
    """The same surface written as piecewise Bezier (OCCT raises every interior knot to multiplicity p)."""
    s = occ_surface(net)
    for i in range(2, s.NbUKnots()):
        s.IncreaseUMultiplicity(i, net.degrees[0])
    for i in range(2, s.NbVKnots()):
        s.IncreaseVMultiplicity(i, net.degrees[1])
    return net_from_surface(s, origin=net.origin)


def occt_grid(net: ControlNet, nu=23, nv=19):
    (ku, kv), (p, q) = net.knots, net.degrees
    u = np.linspace(ku[p], ku[len(ku) - p - 1], nu)
    v = np.linspace(kv[q], kv[len(kv) - q - 1], nv)
    return u, v, evaluate_grid(net, u, v)


# ---------------------------------------------------------------- splitting
@settings(max_examples=12, deadline=None)
@given(p=st.integers(2, 4), n_half=st.integers(7, 12), cuts=st.integers(1, 3), amp=st.floats(0.5, 5.0),
       seed=st.integers(0, 10 ** 6))
def test_pieces_reproduce_the_face_exactly(p, n_half, cuts, amp, seed):
    """Each piece, evaluated by OCCT on its own range, is the face there (OCCT's evaluation of the whole)."""
    face = _creased(p, n_half, amp, seed, cuts)
    pieces = split_net(face)
    assert len(pieces) == cuts + 1
    for piece in pieces:
        u = np.linspace(piece.lo[0], piece.hi[0], 5)
        v = np.linspace(piece.lo[1], piece.hi[1], 5)
        assert np.abs(evaluate_grid(piece.net, u, v) - evaluate_grid(face, u, v)).max() < 1e-9


def _creased(p, n_half, amp, seed, cuts=1):
    """Uniform runs of degree p meeting at ``cuts`` knots of multiplicity p (C0 creases)."""
    rng = np.random.default_rng(seed)
    half = n_half - p  # spans per run
    runs = cuts + 1
    n = runs * half + p - cuts * (p - 1) + (runs - 1) * (p - 1)
    inner = []
    for r in range(runs):
        inner += [r * half + k for k in range(1, half)]
        if r < cuts:
            inner += [(r + 1) * half] * p
    ku = np.concatenate([np.zeros(p + 1), inner, np.full(p + 1, runs * half)]) / (runs * half)
    n = len(ku) - p - 1
    x, y = np.meshgrid(np.linspace(0, 80, n), np.linspace(0, 40, 8), indexing="ij")
    z = amp * np.abs(np.sin(np.pi * runs * x / 80)) + 0.2 * amp * np.cos(x / 9 + rng.uniform(0, 6)) + 0.05 * y
    return ControlNet(points=np.stack([x, y, z], -1), degrees=(p, 3), knots=(ku, clamped_uniform_knots(8, 3)))


@settings(max_examples=10, deadline=None)
@given(p=st.integers(2, 4), nu=st.integers(7, 16), amp=st.floats(0.5, 5.0), freq=st.floats(0.3, 2.0),
       phase=st.floats(0, 6.28))
def test_piecewise_bezier_faces_carry_no_ripple_and_never_more_than_their_smooth_form(p, nu, amp, freq, phase):
    """SPEC §4: a knot of multiplicity p is a deliberate junction. Written as Bezier pieces (every span a piece of
    its own: nothing along it aliases), a face reports no ripple, never more than its smooth (uniform) form."""
    smooth = smooth_face(nu, 6, p, 3, amp, freq, phase)
    bez = bezier_form(smooth)
    assert bez.size > smooth.size
    b = ca.budget(bez)
    assert b.stats["total"].peak == 0.0
    assert b.stats["total"].peak <= ca.budget(smooth).stats["total"].peak + 1e-12
    # and the zero says why, with the pieces counted from the knots
    assert b.reason.endswith(f"no ripple by construction (u: {nu - p} Bezier pieces of degree {p}; "
                             f"v: 3 Bezier pieces of degree 3)")
    assert "by construction" not in ca.budget(smooth).reason


@pytest.mark.parametrize("p", [1, 2, 3, 5])
@pytest.mark.parametrize("pieces", [1, 2, 4])
def test_why_a_face_carries_no_ripple_is_read_off_its_knots(p, pieces):
    """One Bezier piece, several (every interior knot of multiplicity p, or more), degree 1, an exact direction:
    no ripple by construction; one interior knot below multiplicity p in a direction: None (it can ripple)."""
    from cadartifact.net import no_ripple_by_construction

    n = pieces * p + 1
    x, y = np.meshgrid(np.linspace(0, 50, n), np.linspace(0, 20, 4), indexing="ij")
    P = np.stack([x, y, 0.01 * x * y], -1)
    ku = np.concatenate([np.zeros(p + 1), np.repeat(np.arange(1, pieces), p), np.full(p + 1, pieces)]) / pieces
    face = ControlNet(points=P, degrees=(p, 3), knots=(ku, clamped_uniform_knots(4, 3)))
    u = (f"one Bezier piece of degree {p}" if pieces == 1 else f"{pieces} straight spans" if p == 1
         else f"{pieces} Bezier pieces of degree {p}")
    assert no_ripple_by_construction(face) == f"u: {u}; v: one Bezier piece of degree 3"
    assert no_ripple_by_construction(face.replace(exact=(None, "line"))) == f"u: {u}; v: exactly a line"
    if p > 1 and pieces > 1:  # one junction lowered below p: that direction's spans join smoothly and can ripple
        lowered = np.delete(ku, p + 1)
        joined = ControlNet(points=P[1:], degrees=(p, 3), knots=(lowered, clamped_uniform_knots(4, 3)))
        assert no_ripple_by_construction(joined) is None
    assert no_ripple_by_construction(ControlNet.from_points(P, degrees=None)) is None  # a cage


def test_the_text_says_why_a_piecewise_bezier_face_reads_zero(tmp_path):
    """The gate's and the advice's text name the faces that read zero by construction, and the advice's JSON note
    reason says so (its notes never read "no other density the search tried conforms" beside a zero)."""
    import json
    import subprocess
    import sys

    from cadartifact.exchange.load import write_step

    face = bezier_form(smooth_face(10, 6, 3, 3, 2.0, 0.7, 0.3))
    write_step([face], tmp_path / "pieces.step")
    line = "no ripple by construction (u: 7 Bezier pieces of degree 3; v: 3 Bezier pieces of degree 3): face 0"
    for command in (["gate", "--tol", "0.05"], ["advise", "--tol", "0.05"]):
        out = subprocess.run([sys.executable, "-m", "cadartifact.cli", *command, str(tmp_path / "pieces.step")],
                             capture_output=True, text=True, cwd=tmp_path)
        assert out.returncode == 0 and line in " ".join(out.stdout.split()), out.stdout  # wrapped at spaces
    doc = json.loads(subprocess.run([sys.executable, "-m", "cadartifact.cli", "advise", "--tol", "0.05", "--json",
                                     str(tmp_path / "pieces.step")], capture_output=True, text=True).stdout)
    record = doc["files"][0]["faces"][0]
    assert record["reason"].endswith(line.removesuffix(": face 0"))
    assert not any("no other density" in n for n in record["advice"]["notes"]), record["advice"]["notes"]


def _kinked(p, n_half, amp, seed):
    """Two uniform halves of degree p meeting at a knot of multiplicity p (a C0 crease), and the halves."""
    rng = np.random.default_rng(seed)
    n = 2 * n_half - 1
    x, y = np.meshgrid(np.linspace(0, 80, n), np.linspace(0, 40, 8), indexing="ij")
    z = amp * np.abs(x - 40) / 40 + 0.2 * amp * np.cos(x / 9 + rng.uniform(0, 6)) + 0.05 * y
    pts = np.stack([x, y, z], -1)
    half = n_half - p  # spans per half
    inner = np.concatenate([np.arange(1, half), np.full(p, half), half + np.arange(1, half)]) / (2 * half)
    ku = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    kv = clamped_uniform_knots(8, 3)
    face = ControlNet(points=pts, degrees=(p, 3), knots=(ku, kv))
    return face


@pytest.mark.parametrize("p,n_half,amp,seed", [(2, 9, 3.0, 0), (3, 10, 2.0, 1), (3, 14, 5.0, 2), (4, 12, 1.0, 3)])
def test_a_crease_is_not_ripple_the_halves_are_analysed_as_nets_of_their_own(p, n_half, amp, seed):
    """A face with a C0 crease reports what its two halves report, each cut out by OCCT (an independent
    split), and far less than the crease would read as ripple if the face were analysed whole."""
    face = _kinked(p, n_half, amp, seed)
    assert junctions(face.knots[0], p, face.shape[0], False) == [0.5]
    b = ca.budget(face)
    assert b.pieces == (2, 1)
    halves = []
    for lo, hi in ((0.0, 0.5), (0.5, 1.0)):
        seg = occ_surface(face)  # a new surface each call
        seg.Segment(lo, hi, 0.0, 1.0)
        halves.append(ca.budget(net_from_surface(seg, origin=face.origin)))
    expect = max(h.stats["total"].peak for h in halves)
    assert b.stats["total"].peak == pytest.approx(expect, rel=1e-6, abs=1e-12)
    from cadartifact.analysis.pieces import MAX_PIECES  # noqa: F401  (the whole-face reading, for scale)
    from cadartifact.analysis.budget import _budget_of
    from cadartifact.analysis.settings import RunSettings, resolve_scheme

    whole = _budget_of(face, face, resolve_scheme(face), RunSettings(), False)
    assert whole.stats["total"].peak > 3 * b.stats["total"].peak


def _arc_bezier(r, a0, a1, pieces):
    """G1 cubic Bezier pieces of a circular arc (the classical 4/3 tan(phi/4) handles)."""
    pts = []
    phi = (a1 - a0) / pieces
    k = 4 / 3 * np.tan(phi / 4) * r
    for s in range(pieces):
        t0, t1 = a0 + s * phi, a0 + (s + 1) * phi
        c0, c1 = r * np.array([np.cos(t0), np.sin(t0)]), r * np.array([np.cos(t1), np.sin(t1)])
        d0, d1 = np.array([-np.sin(t0), np.cos(t0)]), np.array([-np.sin(t1), np.cos(t1)])
        seg = [c0, c0 + k * d0, c1 - k * d1, c1]
        pts += seg if s == 0 else seg[1:]
    return np.array(pts)


@pytest.mark.slow
@pytest.mark.parametrize("radius,span,pieces,tol", [(1500.0, np.pi / 3, 3, 0.05), (800.0, np.pi / 2, 4, 0.05),
                                                    (2500.0, np.pi / 4, 5, 0.1)])
def test_a_piecewise_bezier_fuselage_skin_is_advised_one_uniform_net_within_the_tolerance(radius, span, pieces, tol):
    """A fuselage skin of bicubic Bezier pieces (G1 arcs, a tapering section): no ripple, and the advice is one
    uniform net of the face's degrees that OCCT evaluates within the tolerance of the face on the whole face."""
    nv = 4
    v = np.linspace(0, 1, nv)
    P = np.zeros((3 * pieces + 1, nv, 3))
    for b in range(nv):
        P[:, b, :2] = _arc_bezier(radius * (1 - 0.05 * v[b]), 0, span, pieces)
        P[:, b, 2] = 2000 * v[b]
    ku = np.concatenate([np.zeros(4), np.repeat(np.arange(1, pieces), 3), np.full(4, pieces)]).astype(float)
    face = ControlNet(points=P, degrees=(3, 3), knots=(ku, clamped_uniform_knots(nv, 3)))
    assert ca.budget(face).stats["total"].peak == 0.0
    a = ca.advise(face, tol, compare=False)
    adv = a.advised_net
    assert a.meets_tolerance and ca.net.knots_are_uniform(adv.knots[0], 3)
    assert distance_to(occt_grid(adv, 61, 9)[2], face).max() <= tol
    assert distance_to(occt_grid(face, 61, 9)[2], adv).max() <= tol  # and back: it covers the whole face


def distance_to(points: np.ndarray, net: ControlNet) -> np.ndarray:
    """OCCT's closest-point distance of each point to the surface of ``net`` (GeomAPI_ProjectPointOnSurf)."""
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt

    surf = occ_surface(net)
    flat = points.reshape(-1, 3)
    return np.array([GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, q)), surf).LowerDistance() for q in flat])


# ---------------------------------------------------------------- removable knots
@settings(max_examples=8, deadline=None)
@given(p=st.integers(2, 5), q=st.integers(2, 3), seed=st.integers(0, 10 ** 6))
def test_knots_inserted_into_a_bezier_direction_add_no_ripple(p, q, seed):
    """A Bezier direction has no knot structure however it is written: after OCCT inserts knots into it, it
    still reports no ripple along it."""
    rng = np.random.default_rng(seed)
    gu, gv = np.meshgrid(np.arange(p + 1.0), np.arange(q + 1.0), indexing="ij")
    pts = rng.normal(size=(p + 1, q + 1, 3)) + 10 * np.stack([gu, gv, np.zeros_like(gu)], -1)
    face = ControlNet.from_points(pts, degrees=(p, q))
    s = occ_surface(face)
    for x in (0.3, 0.5, 0.8):
        s.InsertUKnot(x, 1, 1e-12, True)
        s.InsertVKnot(x, 1, 1e-12, True)
    more = net_from_surface(s, origin=face.origin)
    assert more.shape == (p + 4, q + 4)
    assert ca.budget(more).stats["total"].peak < 1e-9 * 10 * max(p, q)


# ---------------------------------------------------------------- rational faces
@settings(max_examples=10, deadline=None)
@given(n=st.integers(12, 24), p=st.integers(2, 3), wamp=st.floats(0.05, 0.45), seed=st.integers(0, 10 ** 6))
def test_rational_periodic_nets_both_roads_agree(n, p, wamp, seed):
    """SPEC §4: in homogeneous coordinates the uniform theory applies exactly; on periodic rational nets the
    predicted (spectral) and measured (exact NURBS evaluation) roads agree to 1e-9."""
    rng = np.random.default_rng(seed)
    nu, nv = n, n + 3
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    th, ph = 2 * np.pi * i / nu, 2 * np.pi * j / nv
    r = 10 + 2 * np.cos(ph)
    P = np.stack([r * np.cos(th), r * np.sin(th), 2 * np.sin(ph) + 0.2 * np.cos(2 * np.pi * rng.uniform(0.1, 0.4) * i
                                                                                + 2 * np.pi * 0.2 * j)], -1)
    W = 1 + wamp * np.cos(th + rng.uniform(0, 6)) * np.cos(2 * ph)
    knots = tuple(np.arange(m + 2 * p + 1, dtype=float) / m for m in (nu, nv))
    net = ControlNet(points=P, weights=W, degrees=(p, p), knots=knots, periodic=(True, True))
    b = ca.budget(net, method="both")
    assert "homogeneous" in b.reason
    assert b.check["max_abs_diff"] <= 1e-9


@settings(max_examples=8, deadline=None)
@given(nu=st.integers(10, 20), wamp=st.floats(0.05, 0.3), seed=st.integers(0, 10 ** 6))
def test_rational_ripple_is_the_surface_minus_its_intent_to_first_order(nu, wamp, seed):
    """The first-order projection of homogeneous ripple, dS = (dH_xyz - S dH_w)/H_w, matches the exact
    difference of the real surface (exact NURBS) and the projected intent up to second order."""
    rng = np.random.default_rng(seed)
    base = smooth_face(nu, 9, 3, 3, 1.0, 1.0, rng.uniform(0, 6))
    W = 1 + wamp * rng.uniform(-1, 1, size=base.shape)
    net = base.replace(weights=W)
    b = ca.budget(net, keep_fields=True)
    f = b.fields
    exact = f.surface - f.intent
    first = f.bands["total"]
    ripple = float(np.linalg.norm(first, axis=-1).max())
    size = 100.0
    assert np.linalg.norm(exact - first, axis=-1).max() <= 1e-6 * size + 50 * ripple ** 2 / size + 1e-3 * ripple


def test_constant_weights_read_like_the_polynomial_face():
    net = smooth_face(14, 9, 3, 3, 2.0, 1.2, 0.4)
    a, b = ca.budget(net), ca.budget(net.replace(weights=np.full(net.shape, 0.7)))
    assert b.stats["total"].peak == pytest.approx(a.stats["total"].peak, rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("radius,height,periodic", [(12.5, 30.0, False), (40.0, 5.0, False), (3.0, 8.0, True)])
def test_an_exact_rational_circle_extruded_reads_no_ripple(radius, height, periodic):
    """The NURBS circle (degree 2, weights sqrt(2)/2, knots of multiplicity 2) swept along a line: the quarter
    arcs are pieces of their own (junctions), so nothing reads as ripple; a full periodic circle is opened at
    its junctions."""
    s2 = np.sqrt(0.5)
    ang = np.arange(9) * np.pi / 4
    ring = np.stack([np.cos(ang), np.sin(ang)], -1) / np.where(np.arange(9) % 2 == 1, s2, 1.0)[:, None]
    w_ring = np.where(np.arange(9) % 2 == 1, s2, 1.0)
    z = np.linspace(0, height, 4)
    if periodic:
        # 8 poles, OCCT's flat periodic sequence (n + 2p + 1 knots, t[i + n] = t[i] + 1)
        ring, w_ring = ring[:8], w_ring[:8]
        ku = np.array([-1, -1, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5], float) / 4
    else:
        ku = np.array([0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4], float) / 4
    P = np.concatenate([np.repeat(radius * ring[:, None, :], 4, axis=1),
                        np.broadcast_to(z[None, :, None], (len(ring), 4, 1))], axis=-1)
    W = np.repeat(w_ring[:, None], 4, axis=1)
    net = ControlNet(points=P, weights=W, degrees=(2, 1), knots=(ku, np.array([0, 0, 1, 2, 3, 3], float) / 3),
                     periodic=(periodic, False))
    u = np.linspace(net.knots[0][2], net.knots[0][len(net.knots[0]) - 3], 50)
    pts = evaluate_grid(net, u, np.array([0.5]))
    assert np.allclose(np.linalg.norm(pts[..., :2], axis=-1), radius, rtol=1e-12)  # it is the circle (OCCT)
    b = ca.budget(net)
    assert b.stats["total"].peak < 1e-9 * radius


# ---------------------------------------------------------------- degree 1
@settings(max_examples=10, deadline=None)
@given(nv=st.integers(4, 30), q=st.integers(1, 3), amp=st.floats(0.1, 5.0), seed=st.integers(0, 10 ** 6))
def test_degree_one_directions_carry_no_ripple(nv, q, amp, seed):
    """A degree-1 direction has a junction at every knot (a polyline's corners are deliberate): no ripple along
    it, whether it has 2 points (a ruled face) or many."""
    rng = np.random.default_rng(seed)
    nu = int(rng.integers(2, 6))
    x, y = np.meshgrid(np.linspace(0, 50, nu), np.linspace(0, 80, nv), indexing="ij")
    z = amp * np.sin(y / 7 + rng.uniform(0, 6)) + 0.3 * x
    net = ControlNet.from_points(np.stack([x, y, z], -1), degrees=(1, q))
    b = ca.budget(net)
    assert b.stats["x1"].peak == 0.0 and b.stats["diagonal"].peak == 0.0
    if q == 1:
        assert b.stats["total"].peak == 0.0


@pytest.mark.slow
@settings(max_examples=6, deadline=None)
@given(nv=st.integers(5, 30), q=st.integers(1, 3), twist=st.floats(0.0, 0.2), seed=st.integers(0, 10 ** 6))
def test_a_straight_degree_one_direction_is_never_advised_more_points(nv, q, twist, seed):
    """SPEC §4: a degree-1 direction whose intent is straight reports zero ripple and more points along it can
    never help: the advice keeps at most today's count there."""
    rng = np.random.default_rng(seed)
    nu = int(rng.integers(2, 5))
    x, y = np.meshgrid(np.linspace(0, 40, nu), np.linspace(0, 90, nv), indexing="ij")
    z = 3 * np.sin(y / 9 + rng.uniform(0, 6)) + twist * x * y / 10
    net = ControlNet.from_points(np.stack([x, y, z], -1), degrees=(1, q))
    a = ca.advise(net, 0.05, compare=False, verify=False)
    assert a.shape[0] <= nu
    assert a.current.stats["x1"].peak == 0.0


# ---------------------------------------------------------------- regressions found in review
def test_a_face_kept_under_another_scheme_is_verified_as_that_scheme_reads_it():
    x, y = np.meshgrid(np.linspace(0, 100, 12), np.linspace(0, 70, 10), indexing="ij")
    z = 2 * np.cos(2 * np.pi * (x + 0.6 * y) / 100 * 3) + 0.1 * x
    net = ControlNet.from_points(np.stack([x, y, z], -1), degrees=(2, 2))
    a = ca.advise(net, 0.05, scheme="bicubic", compare=False)  # crashed: face parameters on the cage's frames
    assert a.kept_today and a.verification["method"] == "today"


def test_a_periodic_direction_left_whole_keeps_its_trimmed_range_across_the_seam():
    p, n = 3, 12
    ku = np.arange(n + 2 * p + 1, dtype=float) / n  # uniform periodic, no junction
    kv = np.array([0, 0, 0, 0, 0.25, 0.5, 0.5, 0.5, 0.75, 1, 1, 1, 1.0])  # a junction at 0.5
    th = 2 * np.pi * np.arange(n) / n
    pts = np.stack(np.broadcast_arrays(10 * np.cos(th)[:, None], 10 * np.sin(th)[:, None],
                                       np.arange(9.0)[None, :] * 3), -1)
    net = ControlNet(points=pts, degrees=(p, p), knots=(ku, kv), periodic=(True, False), uv_bounds=(0.8, 1.2, 0, 1))
    pieces = split_net(net)
    assert len(pieces) == 2 and all(pc.net.uv_bounds[:2] == (0.8, 1.2) for pc in pieces)


def test_the_rms_of_a_split_face_does_not_depend_on_keeping_its_fields():
    face = _creased(3, 10, 2.0, 4, cuts=2)
    a, b = ca.budget(face), ca.budget(face, keep_fields=True)
    assert a.pieces == (3, 1)
    for k in ("total", "x1", "lateral"):
        assert a.stats[k].rms == pytest.approx(b.stats[k].rms, rel=1e-12)
        assert a.stats[k].peak == b.stats[k].peak
