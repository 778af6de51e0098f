"""STEP/IGES/BREP reading, checked against OCCT read independently (minimal OCP loops here)."""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface, Geom_RectangularTrimmedSurface  # noqa: E402
from OCP.IFSelect import IFSelect_RetDone  # noqa: E402
from OCP.STEPControl import STEPControl_Reader  # noqa: E402
from OCP.TopAbs import TopAbs_FACE  # noqa: E402
from OCP.TopExp import TopExp_Explorer  # noqa: E402
from OCP.TopoDS import TopoDS  # noqa: E402

from cadartifact.exchange.load import LoadWarning, from_shape, load, read, write_step  # noqa: E402
from cadartifact.net import ControlNet, NetOrigin  # noqa: E402
from cadartifact.testing.paths import REALDATA

STEP_FILES = sorted((REALDATA / "step").glob("*"))


# ---------------------------------------------------------------- the independent road: plain OCP
@functools.lru_cache(maxsize=None)
def occt_faces(path: str):
    """Every face's surface as OCCT gives it: list of (index, basis surface or None, uv bounds)."""
    reader = STEPControl_Reader()
    assert reader.ReadFile(path) == IFSelect_RetDone
    reader.TransferRoots()
    explorer = TopExp_Explorer(reader.OneShape(), TopAbs_FACE)
    out, index = [], 0
    while explorer.More():
        face = TopoDS.Face_s(explorer.Current())
        surface = BRep_Tool.Surface_s(face)
        while isinstance(surface, Geom_RectangularTrimmedSurface):
            surface = surface.BasisSurface()
        keep = surface if isinstance(surface, (Geom_BSplineSurface, Geom_BezierSurface)) else None
        out.append((index, keep, BRepTools.UVBounds_s(face)))
        index += 1
        explorer.Next()
    return out


@functools.lru_cache(maxsize=None)
def cached_read(path: str):
    return read(path)


def _sequence(array1) -> np.ndarray:
    return np.array([array1.Value(i) for i in range(array1.Lower(), array1.Upper() + 1)])


def check_net_against_surface(net: ControlNet, surface) -> None:
    nu, nv = surface.NbUPoles(), surface.NbVPoles()
    assert net.shape == (nu, nv)
    assert net.degrees == (surface.UDegree(), surface.VDegree())
    for i in range(1, nu + 1):
        for j in range(1, nv + 1):
            p = surface.Pole(i, j)
            assert tuple(net.points[i - 1, j - 1]) == (p.X(), p.Y(), p.Z())
    rational = surface.IsURational() or surface.IsVRational()
    assert net.rational == rational
    if rational:
        for i in range(1, nu + 1):
            for j in range(1, nv + 1):
                assert net.weights[i - 1, j - 1] == surface.Weight(i, j)
    if isinstance(surface, Geom_BezierSurface):
        assert net.origin.kind == "bezier"
        for k, p in zip(net.knots, net.degrees):
            assert list(k) == [0.0] * (p + 1) + [1.0] * (p + 1)
        return
    assert net.origin.kind == "bspline"
    for d, flat, n, p, periodic in (("U", net.knots[0], nu, net.degrees[0], net.periodic[0]),
                                    ("V", net.knots[1], nv, net.degrees[1], net.periodic[1])):
        assert periodic == getattr(surface, f"Is{d}Periodic")()
        count = getattr(surface, f"Nb{d}Knots")()
        knots = [getattr(surface, f"{d}Knot")(i) for i in range(1, count + 1)]
        mults = [getattr(surface, f"{d}Multiplicity")(i) for i in range(1, count + 1)]
        occ_seq = _sequence(getattr(surface, f"{d}KnotSequence")())
        if not periodic:
            assert list(flat) == list(np.repeat(knots, mults))
            assert list(flat) == list(occ_seq)
            continue
        # periodic: OCCT's sequence is a prefix, the whole has n + 2p + 1 knots, continued with the period
        assert len(flat) == n + 2 * p + 1
        assert list(flat[:len(occ_seq)]) == list(occ_seq)
        period = knots[-1] - knots[0]
        np.testing.assert_allclose(flat[n:] - flat[:-n], period, rtol=0, atol=1e-12 * max(1.0, abs(period)))
        # one period of the sequence holds every knot with its multiplicity
        inner = flat[p:n + p + 1]
        for x, m in zip(knots[1:-1], mults[1:-1]):
            assert np.count_nonzero(inner == x) == m


# ---------------------------------------------------------------- real files
@pytest.mark.realdata
@pytest.mark.parametrize("path", STEP_FILES, ids=lambda p: p.name)
def test_real_step_matches_occt_per_index(path):
    faces = occt_faces(str(path))
    result = cached_read(str(path))
    expected = [(i, s, uv) for i, s, uv in faces if s is not None]
    assert result.faces_total == len(faces)
    assert len(result.nets) == len(expected)
    assert sum(result.skipped.values()) == len(faces) - len(expected)
    for net, (index, surface, uv) in zip(result.nets, expected):
        assert net.origin.face == index
        assert net.origin.file == str(path)
        assert net.unit == "mm"
        np.testing.assert_array_equal(net.uv_bounds, uv)
        check_net_against_surface(net, surface)
    assert load(path)[0].points.tobytes() == result.nets[0].points.tobytes()


@pytest.mark.realdata
def test_real_step_summary_facts():
    """Facts from SOURCES.md, reached through the loader."""
    by_name = {p.name: cached_read(str(p)) for p in STEP_FILES}
    ctc = by_name["nist_ctc_02_asme1_ap242-1.stp"]
    assert len(ctc.nets) == 22
    assert sum(1 for n in ctc.nets if any(n.periodic)) == 6
    assert sum(1 for n in ctc.nets if n.weights_vary) == 20
    assert len(by_name["boxed_sphere.step"].nets) == 42
    assert sum(1 for n in by_name["boxed_sphere.step"].nets if n.rational) == 34
    assert len(by_name["linkrods.step"].nets) == 18
    ftc = by_name["nist_ftc_07_asme1_rd.stp"].nets
    assert len(ftc) == 20 and all(n.degrees == (3, 3) and not n.rational for n in ftc)
    main = by_name["MAINBODY_BACK.stp"]
    assert len(main.nets) == 6 and {n.origin.name for n in main.nets} == {"*VOL1"}
    assert main.skipped == {"plane": 9, "cylinder": 16}


# ---------------------------------------------------------------- write / read round trip
def _net(nu=7, nv=6, degrees=(3, 2), rational=False, name="panel", seed=0):
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    pts = np.stack([10.0 * i, 12.0 * j, rng.normal(size=(nu, nv))], -1)
    w = rng.uniform(0.6, 1.4, size=(nu, nv)) if rational else None
    return ControlNet.from_points(pts, degrees, weights=w, origin=NetOrigin(name=name, kind="bspline"))


def _assert_same(a: ControlNet, b: ControlNet, rtol=1e-13):
    # STEP stores reals as text with about 15 significant digits
    scale = np.abs(a.points).max()
    assert a.shape == b.shape and a.degrees == b.degrees and a.periodic == b.periodic
    np.testing.assert_allclose(b.points, a.points, rtol=0, atol=rtol * 10 * scale)
    for ka, kb in zip(a.knots, b.knots):
        np.testing.assert_allclose(kb, ka, rtol=0, atol=rtol * 10 * max(1.0, np.abs(ka).max()))
        assert len(ka) == len(kb)
    assert (a.weights is None) == (b.weights is None)
    if a.weights is not None:
        np.testing.assert_allclose(b.weights, a.weights, rtol=rtol * 10)


@pytest.mark.parametrize("rational", [False, True])
def test_write_step_round_trip(tmp_path, rational):
    nets = [_net(rational=rational, name="first"), _net(5, 9, (2, 3), rational=rational, name="second", seed=1)]
    path = write_step(nets, tmp_path / "out.step")
    back = read(path)
    assert back.faces_total == 2 and back.skipped == {}
    assert [n.origin.name for n in back.nets] == ["first", "second"]
    for a, b in zip(nets, back.nets):
        _assert_same(a, b)


def test_write_step_keeps_uv_bounds_and_skips_cages(tmp_path):
    net = _net().replace(uv_bounds=(0.1, 0.8, 0.2, 0.9))
    cage = ControlNet.from_points(np.random.default_rng(2).normal(size=(3, 3)), None)
    path = write_step([net, cage], tmp_path / "trim.step")
    (back,) = load(path)
    np.testing.assert_allclose(back.uv_bounds, net.uv_bounds, atol=1e-9)
    with pytest.raises(Exception, match="nets"):
        write_step([cage], tmp_path / "none.step")


@pytest.mark.realdata
def test_real_nets_round_trip_through_write_step(tmp_path):
    src = cached_read(str(REALDATA / "step" / "boxed_sphere.step")).nets
    path = write_step(src, tmp_path / "boxed.step")
    back = read(path).nets
    assert len(back) == len(src)
    for a, b in zip(src, back):
        _assert_same(a.replace(uv_bounds=None), b)


# ---------------------------------------------------------------- in-memory shapes (CadQuery hook)
def test_from_shape_cadquery_spline_face_and_raw_shape():
    cq = pytest.importorskip("cadquery")
    wp = cq.Workplane().parametricSurface(lambda u, v: (40 * u, 30 * v, 3 * np.sin(4 * u) * np.cos(3 * v)), N=8)
    nets = from_shape(wp, name="wp")
    assert len(nets) == 1 and nets[0].origin.kind == "bspline" and nets[0].origin.label() == "wp#0"
    raw = from_shape(wp.val().wrapped)
    assert raw[0].points.tobytes() == nets[0].points.tobytes()
    surface = BRep_Tool.Surface_s(TopoDS.Face_s(wp.val().wrapped))
    check_net_against_surface(nets[0], surface)
    # a loft between splines gives B-spline faces; planes of the solid are skipped
    lofted = cq.Solid.makeLoft([cq.Wire.makePolygon([(0, 0, 0), (10, 0, 0), (10, 10, 0), (0, 10, 0)], close=True),
                                cq.Wire.makeCircle(4, cq.Vector(5, 5, 10), cq.Vector(0, 0, 1))])
    loft_nets = from_shape(lofted)
    assert loft_nets and all(n.origin.kind == "bspline" for n in loft_nets)
    assert from_shape([wp, lofted])[0].points.tobytes() == nets[0].points.tobytes()


def test_from_shape_skips_analytic_and_converts_freeform():
    cq = pytest.importorskip("cadquery")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LoadWarning)
        assert from_shape(cq.Workplane().box(1, 2, 3)) == []
    assert any("no analysable face" in str(w.message) for w in caught)
    revolved = (cq.Workplane("XZ").spline([(1, 0), (2, 1), (1.5, 2), (2, 3)]).lineTo(0, 3).lineTo(0, 0)
                .close().revolve())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LoadWarning)
        assert from_shape(revolved) == []
    converted = from_shape(revolved, convert=True)
    assert len(converted) == 1 and converted[0].origin.kind == "converted"
    # the converted net describes the same surface: points of the original face lie on it
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf

    from cadartifact.exchange.load import occ_surface

    target = occ_surface(converted[0])
    (face,) = [f for f in revolved.faces().vals() if f.geomType() == "REVOLUTION"]
    original = BRep_Tool.Surface_s(face.wrapped)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face.wrapped)
    for u in np.linspace(u0, u1, 5):
        for v in np.linspace(v0, v1, 4):
            projection = GeomAPI_ProjectPointOnSurf(original.Value(u, v), target)
            assert projection.LowerDistance() < 1e-6
    with pytest.raises(Exception, match="obj"):
        from_shape(object())


def test_degenerate_face_is_skipped_with_a_warning():
    from OCP.BRep import BRep_Builder
    from OCP.gp import gp_Pnt
    from OCP.TColgp import TColgp_Array2OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
    from OCP.TopoDS import TopoDS_Face

    poles = TColgp_Array2OfPnt(1, 2, 1, 2)
    for i in (1, 2):
        for j in (1, 2):
            poles.SetValue(i, j, gp_Pnt(1, 2, 3))  # every pole at the same point
    knots, mults = TColStd_Array1OfReal(1, 2), TColStd_Array1OfInteger(1, 2)
    for k in (1, 2):
        knots.SetValue(k, k - 1.0)
        mults.SetValue(k, 2)
    face = TopoDS_Face()
    BRep_Builder().MakeFace(face, Geom_BSplineSurface(poles, knots, knots, mults, mults, 1, 1), 1e-7)
    with pytest.warns(LoadWarning) as caught:
        assert from_shape(face, name="flat") == []
    messages = [str(w.message) for w in caught]
    assert any("degenerate net, all control points coincide" in m for m in messages)
    assert any("no analysable face among 1 faces (skipped: degenerate 1)" in m for m in messages)
