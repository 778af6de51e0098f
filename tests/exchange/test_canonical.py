"""Canonical faces (issue 10 item 1): recognition in exchange/, zero ripple along exact directions, reports.

The independent road: built faces are checked against the analytic surface they were made from; real
faces against numpy least-squares fits (sphere, circle, line) of OCCT's evaluation on a denser grid than
the recogniser samples.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

pytest.importorskip("OCP")

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism  # noqa: E402
from OCP.Geom import (  # noqa: E402
    Geom_ConicalSurface,
    Geom_CylindricalSurface,
    Geom_Plane,
    Geom_RectangularTrimmedSurface,
    Geom_SphericalSurface,
    Geom_ToroidalSurface,
)
from OCP.GeomAPI import GeomAPI_PointsToBSpline  # noqa: E402
from OCP.GeomConvert import GeomConvert  # noqa: E402
from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt, gp_Vec  # noqa: E402
from OCP.TColgp import TColgp_Array1OfPnt  # noqa: E402

import cadartifact as ca  # noqa: E402
from cadartifact.exchange.load import evaluate_grid, from_shape, occ_surface, read, write_step  # noqa: E402
from cadartifact.exchange.canonical import NOT_CANONICAL, RTOL, recognise  # noqa: E402
from cadartifact.net import ControlNet  # noqa: E402
from cadartifact.testing.paths import REALDATA

STEP_DIR = REALDATA / "step"
STEP_FILES = sorted(STEP_DIR.glob("*"))
BOXED_SPHERE = STEP_DIR / "boxed_sphere.step"

RIPPLE = ("x1", "x2", "diagonal", "total")


# ---------------------------------------------------------------- independent fits (numpy)
def sphere_fit(points):
    """Centre, radius and worst distance of the least-squares sphere through ``(n, 3)`` points."""
    p = np.asarray(points, float).reshape(-1, 3)
    a = np.c_[2 * p, np.ones(len(p))]
    x = np.linalg.lstsq(a, (p ** 2).sum(1), rcond=None)[0]
    c = x[:3]
    r = math.sqrt(x[3] + c @ c)
    return c, r, float(np.abs(np.linalg.norm(p - c, axis=1) - r).max())


def line_residual(points):
    """Worst distance of ``(n, 3)`` points to their principal line."""
    p = np.asarray(points, float)
    d = p - p.mean(0)
    axis = np.linalg.svd(d, full_matrices=False)[2][0]
    return float(np.linalg.norm(d - np.outer(d @ axis, axis), axis=1).max())


def circle_fit(points):
    """Radius and worst distance of the least-squares circle (plane by SVD, then an algebraic fit)."""
    p = np.asarray(points, float)
    m = p.mean(0)
    _, _, vt = np.linalg.svd(p - m, full_matrices=False)
    xy, h = (p - m) @ vt[:2].T, (p - m) @ vt[2]
    a = np.c_[2 * xy, np.ones(len(xy))]
    x = np.linalg.lstsq(a, (xy ** 2).sum(1), rcond=None)[0]
    c = x[:2]
    r = math.sqrt(x[2] + c @ c)
    return r, float(np.hypot(np.linalg.norm(xy - c, axis=1) - r, h).max())


def number(label: str, key: str) -> float:
    return float(re.search(rf"{key}=([-+0-9.e]+)", label).group(1))


def dense_grid(net, n=33):
    u0, u1, v0, v1 = net.uv_bounds
    bu, bv = occ_surface(net).Bounds()[:2], occ_surface(net).Bounds()[2:]
    u = np.linspace(max(u0, bu[0]), min(u1, bu[1]), n)
    v = np.linspace(max(v0, bv[0]), min(v1, bv[1]), n)
    return evaluate_grid(net, u, v)


def size_of(grid) -> float:
    return float(np.linalg.norm(np.ptp(grid.reshape(-1, 3), axis=0)))


# ---------------------------------------------------------------- built faces
def _axis(draw_vec):
    v = np.asarray(draw_vec, float)
    return v / np.linalg.norm(v)


vectors = st.tuples(*[st.floats(-1, 1) for _ in range(3)]).filter(lambda v: np.linalg.norm(v) > 0.2)
positions = st.tuples(*[st.floats(-500, 500) for _ in range(3)])
radii = st.floats(0.05, 400)


def frame(axis, position) -> gp_Ax3:
    return gp_Ax3(gp_Pnt(*map(float, position)), gp_Dir(*map(float, _axis(axis))))


def bspline_patch(analytic, u0, u1, v0, v1):
    """The B-spline OCCT converts an analytic patch to (rational where the surface curves)."""
    return GeomConvert.SurfaceToBSplineSurface_s(Geom_RectangularTrimmedSurface(analytic, u0, u1, v0, v1))


def check_recognised(bs, kind: str, **sizes):
    label, exact = recognise(bs, bs.Bounds())
    assert exact == ("surface", "surface"), (label, exact)
    assert label.split()[0] == kind, label
    for key, value in sizes.items():
        assert number(label, key) == pytest.approx(value, rel=6e-4), label  # 4 significant digits
    return label


@settings(max_examples=12, deadline=None)
@given(axis=vectors, position=positions, half=st.floats(0.5, 300))
def test_bspline_plane(axis, position, half):
    bs = bspline_patch(Geom_Plane(frame(axis, position)), -half, 0.7 * half, -0.3 * half, half)
    assert check_recognised(bs, "plane") == "plane"


@settings(max_examples=12, deadline=None)
@given(axis=vectors, position=positions, r=radii, sweep=st.floats(0.3, 6.0), height=st.floats(0.2, 5.0))
def test_cylinder_patch(axis, position, r, sweep, height):
    bs = bspline_patch(Geom_CylindricalSurface(frame(axis, position), r), 0.1, 0.1 + sweep, 0.0, height * r)
    check_recognised(bs, "cylinder", r=r)


@settings(max_examples=12, deadline=None)
@given(axis=vectors, position=positions, r=radii, angle=st.floats(5, 70), sweep=st.floats(0.3, 6.0))
def test_cone_patch(axis, position, r, angle, sweep):
    alpha = math.radians(angle)
    bs = bspline_patch(Geom_ConicalSurface(frame(axis, position), alpha, r), 0.0, sweep, 0.0, 2.0 * r)
    label = check_recognised(bs, "cone")
    assert float(re.search(r"half-angle ([0-9.e+-]+)°", label).group(1)) == pytest.approx(angle, rel=6e-4)


@settings(max_examples=12, deadline=None)
@given(axis=vectors, position=positions, r=radii, ratio=st.floats(1.5, 8), su=st.floats(0.3, 6.0),
       sv=st.floats(0.3, 6.0))
def test_torus_patch(axis, position, r, ratio, su, sv):
    bs = bspline_patch(Geom_ToroidalSurface(frame(axis, position), ratio * r, r), 0.0, su, 0.2, 0.2 + sv)
    check_recognised(bs, "torus", R=ratio * r, r=r)


@settings(max_examples=12, deadline=None)
@given(axis=vectors, position=positions, r=radii, su=st.floats(0.3, 6.0), v0=st.floats(-1.4, 0.5),
       sv=st.floats(0.3, 1.0))
def test_sphere_patch(axis, position, r, su, v0, sv):
    bs = bspline_patch(Geom_SphericalSurface(frame(axis, position), r), 0.0, su, v0, min(v0 + sv, 1.5))
    check_recognised(bs, "sphere", r=r)


@pytest.mark.parametrize("r", [0.01, 12.5, 3000.0])
def test_sphere_face_through_the_reader(r):
    """The reader's road: a face on a converted sphere patch gets the label and exact flags on its net."""
    bs = bspline_patch(Geom_SphericalSurface(frame((0.2, -0.5, 1), (3 * r, 0, -r)), r), 0.3, 2.5, -0.6, 0.9)
    face = BRepBuilderAPI_MakeFace(bs, 1e-7).Face()
    (net,) = from_shape(face)
    assert net.canonical == f"sphere r={r:.4g}"
    assert net.exact == ("surface", "surface")
    b = ca.budget(net)
    assert all(b.stats[k].peak == 0.0 for k in RIPPLE)


def test_recognise_off():
    bs = bspline_patch(Geom_SphericalSurface(frame((0, 0, 1), (0, 0, 0)), 5.0), 0.3, 2.5, -0.6, 0.9)
    from cadartifact.exchange.occ import nets_from_shape

    (net,), *_ = nets_from_shape(BRepBuilderAPI_MakeFace(bs, 1e-7).Face(), recognise=False)
    assert net.canonical is None and net.exact == (None, None)


# ---------------------------------------------------------------- revolved and extruded faces
def spline_edge(points):
    arr = TColgp_Array1OfPnt(1, len(points))
    for i, p in enumerate(points, start=1):
        arr.SetValue(i, gp_Pnt(*map(float, p)))
    return BRepBuilderAPI_MakeEdge(GeomAPI_PointsToBSpline(arr).Curve()).Edge()


def test_revolved_spline_is_circular_around_the_axis(tmp_path):
    cq = pytest.importorskip("cadquery")
    w = (cq.Workplane("XZ").spline([(2, 0), (3, 2), (2.5, 4), (4, 6)], includeCurrent=False)
         .lineTo(0, 6).lineTo(0, 0).close().revolve(360))
    nets = [n for n in from_shape(w, convert=True) if n.origin.kind == "converted"]
    assert len(nets) == 1
    (net,) = nets
    assert net.canonical == "revolved: circular in u"
    assert net.exact == ("circle", None)
    # independent road: every sampled row along u is a circle about the z axis (the revolve's axis)
    grid = dense_grid(net)
    tol = RTOL * size_of(grid)
    for row in grid.transpose(1, 0, 2):
        radius, off = circle_fit(row)
        assert off <= tol
        assert radius == pytest.approx(np.hypot(row[:, 0], row[:, 1]).mean(), rel=1e-9)
    b = ca.budget(net)
    assert b.stats["x1"].peak == 0.0
    # a second, independent reason for the zero: OCCT's circle is piecewise Bezier along u (knots of
    # multiplicity p), so even unrecognised it reads no ripple there (issue 10 found 0.65 mm before)
    assert ca.budget(net.replace(canonical=None, exact=(None, None))).stats["x1"].peak <= 1e-9 * size_of(grid)
    # a B-spline revolve as CAD writes it (a STEP file of the same B-spline): the same recognition
    out = write_step([net], tmp_path / "revolve.step")
    (back,) = read(out).nets
    assert back.origin.kind == "bspline"
    assert (back.canonical, back.exact) == (net.canonical, net.exact)


def test_bezier_plane():
    from OCP.Geom import Geom_BezierSurface
    from OCP.TColgp import TColgp_Array2OfPnt

    # irregular poles in one plane (a Bézier plane), then the same with one pole lifted off it
    o, e1, e2 = np.array([1.0, -2.0, 3.0]), np.array([0.6, 0.8, 0.0]), np.array([0.0, 0.6, 0.8])
    poles = TColgp_Array2OfPnt(1, 3, 1, 4)
    for i in range(3):
        for j in range(4):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*(o + (2.0 * i + 0.3 * j * j) * e1 + (1.5 * j + 0.2 * i * i) * e2)))
    assert recognise(Geom_BezierSurface(poles)) == ("plane", ("surface", "surface"))
    poles.SetValue(2, 2, gp_Pnt(*(np.array(poles.Value(2, 2).Coord()) + 0.5 * np.cross(e1, e2))))
    assert recognise(Geom_BezierSurface(poles)) == NOT_CANONICAL


@pytest.mark.parametrize("direction", [(0, 0, 7.0), (1.0, -2.0, 5.0)])
def test_extruded_spline_is_straight_along_the_extrusion(direction):
    edge = spline_edge([(0, 0, 0), (2, 1.5, 0), (4, -1, 0.5), (6, 2, 0), (8, 0, 1)])
    prism = BRepPrimAPI_MakePrism(edge, gp_Vec(*direction)).Shape()
    (net,) = from_shape(prism, convert=True)
    assert net.canonical == "extruded: straight in v"
    assert net.exact == (None, "line")
    grid = dense_grid(net)
    tol = RTOL * size_of(grid)
    d = np.asarray(direction) / np.linalg.norm(direction)
    for col in grid:  # along v: straight lines parallel to the extrusion
        assert line_residual(col) <= tol
        assert abs(abs((col[-1] - col[0]) @ d) - np.linalg.norm(col[-1] - col[0])) <= tol
    assert ca.budget(net).stats["x2"].peak == 0.0


# ---------------------------------------------------------------- negatives
def test_freeform_bumpy_surface_is_not_canonical():
    i, j = np.meshgrid(np.arange(9.0), np.arange(8.0), indexing="ij")
    z = 0.8 * np.sin(1.3 * i) * np.cos(0.9 * j) + 0.05 * i * j
    net = ControlNet.from_points(np.stack([i, j, z], -1))
    assert recognise(occ_surface(net)) == NOT_CANONICAL


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_perturbed_sphere_is_not_canonical(seed):
    r = 20.0
    bs = bspline_patch(Geom_SphericalSurface(frame((0.3, 0.1, 1), (5, -2, 1)), r), 0.2, 2.8, -0.8, 1.1)
    assert recognise(bs, bs.Bounds())[0] == f"sphere r={r:.4g}"  # exact before the perturbation
    rng = np.random.default_rng(seed)
    for a in range(1, bs.NbUPoles() + 1):
        for b in range(1, bs.NbVPoles() + 1):
            p = np.array(bs.Pole(a, b).Coord()) + rng.normal(size=3) * (1e-3 * r / math.sqrt(3))
            bs.SetPole(a, b, gp_Pnt(*p))
    assert recognise(bs, bs.Bounds()) == NOT_CANONICAL


def test_occt_failure_is_not_recognised():
    class Broken:
        def Bounds(self):
            raise RuntimeError("OCCT says no")

    assert recognise(Broken()) == NOT_CANONICAL


# ---------------------------------------------------------------- real files
@pytest.fixture(scope="module")
def boxed_sphere(realdata):
    return read(BOXED_SPHERE)


@pytest.mark.realdata
def test_boxed_sphere_spheres_exactly(boxed_sphere):
    """Exactly the faces that a least-squares sphere fits (to 1e-6 of their size) are recognised, with
    the fitted radius; their budget is zero in every ripple direction."""
    recognised, fitted = {}, {}
    for net in boxed_sphere.nets:
        grid = dense_grid(net, 17)
        _, r, off = sphere_fit(grid)
        if off <= RTOL * size_of(grid):
            fitted[net.origin.face] = r
        if net.canonical:
            recognised[net.origin.face] = net.canonical
            assert net.exact == ("surface", "surface")
    assert len(recognised) == 10
    assert set(recognised) == set(fitted)
    for face, label in recognised.items():
        assert label.startswith("sphere r=")
        assert number(label, "r") == pytest.approx(fitted[face], rel=6e-4)
    assert sorted(set(recognised.values())) == ["sphere r=0.29", "sphere r=5"]
    for net in boxed_sphere.nets:
        if net.canonical:
            b = ca.budget(net)
            assert all(b.stats[k].peak == 0.0 for k in RIPPLE), net.origin.label()


@pytest.mark.realdata
def test_gate_and_advise_report_the_label(tmp_path):
    from typer.testing import CliRunner

    from cadartifact.cli.app import app

    out = tmp_path / "gate.json"
    result = CliRunner().invoke(app, ["gate", str(BOXED_SPHERE), "--tol", "0.05", "--format", "json",
                                      "--output", str(out), "--jobs", "1"])
    assert result.exit_code == 0, result.output
    doc = json.loads(out.read_text())
    faces = doc["files"][0]["faces"]
    spheres = [f for f in faces if f["canonical"]]
    assert len(spheres) == 10
    assert all(f["exact"] == ["surface", "surface"] and f["budget"]["total"]["peak"] == 0.0 for f in spheres)
    assert all(f["canonical"] is None and f["exact"] == [None, None] for f in faces if f not in spheres)
    from rich.console import Console

    from cadartifact.gate.reports import render_text

    console = Console(record=True, width=120)
    render_text(doc, console)
    assert "canonical: sphere r=5: faces 190, 191" in console.export_text()
    from cadartifact.runs.advising import advise_files
    from cadartifact.runs.terminal import render

    adv = advise_files([BOXED_SPHERE], 0.05, compare=False, verify=False)
    labels = {f["face"]: f["canonical"] for f in adv["files"][0]["faces"]}
    assert {k: v for k, v in labels.items() if v} == {f["face"]: f["canonical"] for f in spheres}
    console = Console(record=True, width=120)
    render(adv, console)
    assert "canonical: sphere r=0.29: faces 3, 15, 35, 47, 83, 95, 115, 127" in console.export_text()


#: Per real file, the recognised labels and how many faces carry each (issue 10 item 1's figures).
REAL_COUNTS = {
    "MAINBODY_BACK.stp": {},
    "boxed_sphere.step": {"sphere r=0.29": 8, "sphere r=5": 2},
    "linkrods.step": {"cylinder r=0.125": 4, "swept: circular in u": 11, "extruded: straight in v": 2},
    "nist_ctc_02_asme1_ap242-1.stp": {"swept: circular in v": 4, "ruled: straight in u": 2},
    "nist_ftc_07_asme1_rd.stp": {},
}


@pytest.mark.realdata
@pytest.mark.parametrize("path", STEP_FILES, ids=lambda p: p.name)
def test_real_exact_directions_hold_on_a_denser_grid(path):
    """Every direction the reader calls exact is, on 33 isocurves of OCCT's evaluation (not the
    recogniser's samples), a line or circle within 1e-6 of the face's size (numpy fits).

    NIST CTC-02 also has 12 faces that are circular to 1e-15 on their knots and 1e-6 to 2.5e-5 of
    their size between them (approximated sweeps): not recognised, as they must not be.
    """
    nets = read(path).nets
    counts: dict = {}
    for net in nets:
        if net.canonical:
            counts[net.canonical] = counts.get(net.canonical, 0) + 1
    if path.name in REAL_COUNTS:
        assert counts == REAL_COUNTS[path.name]
    for net in nets:
        if net.canonical is None:
            continue
        grid = dense_grid(net)
        tol = RTOL * size_of(grid)
        if net.exact == ("surface", "surface"):
            kind = net.canonical.split()[0]
            if kind == "sphere":
                _, r, off = sphere_fit(grid)
                assert off <= tol and r == pytest.approx(number(net.canonical, "r"), rel=6e-4)
            elif kind == "cylinder":  # circles of the label's radius one way, lines the other
                rows = [grid[:, j] for j in range(grid.shape[1])]
                cols = [grid[i] for i in range(grid.shape[0])]
                circles, lines = (rows, cols) if line_residual(cols[0]) <= tol else (cols, rows)
                assert all(line_residual(c) <= tol for c in lines)
                for c in circles:
                    r, off = circle_fit(c)
                    assert off <= tol and r == pytest.approx(number(net.canonical, "r"), rel=6e-4)
            continue
        for direction, kind in enumerate(net.exact):
            if kind is None:
                continue
            curves = grid.transpose(1, 0, 2) if direction == 0 else grid  # along u: fixed v
            for c in curves:
                if np.linalg.norm(np.ptp(c, axis=0)) <= tol:
                    continue  # a collapsed isocurve
                off = line_residual(c) if kind == "line" else circle_fit(c)[1]
                assert off <= tol, (net.origin.label(), direction, kind, off / size_of(grid))
