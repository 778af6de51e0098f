"""How far one trimmed B-rep face lies from another, geometrically: by projection, both ways, trims respected.

A face is sampled inside its trim: a ``GRID x GRID`` lattice of its uv box (finer on a B-spline face of many knot
spans: ``PER_SPAN`` points per span, so that no span's ripple peak falls between lattice points) kept where OCCT's 2-D classifier
(``BRepTopAdaptor_FClass2d``) puts it inside the face, plus :data:`EDGE_SAMPLES` points along each of its edges
(the edge's pcurve on the face's surface: the boundary as the face itself sees it). Each sample is projected onto
the other face: onto its surface (``ShapeAnalysis_Surface.ValueOfUV``, the nearest point), and when that foot
lies outside the other face's trim, the distance to the face itself is taken instead
(``BRepExtrema_DistShapeShape`` of the point and the face, which respects the trim). The directed distance
``d(A -> B) = max over samples a of A of dist(a, B)``; the distance of the two faces is the larger of the two
directions (the Hausdorff distance of the sampled faces), independent of either face's parametrisation.

The edge figures of a face: the largest tolerance of its edges (OCCT's promise that each edge's 3-D curve lies
within it of every surface the edge bounds) and BRepCheck's verdict on the face alone.

References
----------
OCCT reference manual: ShapeAnalysis_Surface, BRepTopAdaptor_FClass2d, BRepExtrema_DistShapeShape, BRepCheck_Analyzer.
"""

from __future__ import annotations

import numpy as np

from ..dependencies import require

require("OCP", "measuring written faces")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex  # noqa: E402
from OCP.BRepCheck import BRepCheck_Analyzer  # noqa: E402
from OCP.BRepExtrema import BRepExtrema_DistShapeShape  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.BRepTopAdaptor import BRepTopAdaptor_FClass2d  # noqa: E402
from OCP.Geom import Geom_BSplineSurface  # noqa: E402
from OCP.gp import gp_Pnt, gp_Pnt2d  # noqa: E402
from OCP.ShapeAnalysis import ShapeAnalysis_Surface  # noqa: E402
from OCP.Standard import Standard_Failure  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE, TopAbs_IN, TopAbs_ON, TopAbs_OUT  # noqa: E402
from OCP.TopExp import TopExp  # noqa: E402
from OCP.TopoDS import TopoDS  # noqa: E402
from OCP.TopTools import TopTools_IndexedMapOfShape  # noqa: E402

__all__ = ["face_samples", "distance_to_face", "face_distance", "edge_tolerance", "face_valid", "GRID",
           "EDGE_SAMPLES"]

#: Lattice points per direction of a face's uv box (kept where inside the trim).
GRID = 41
#: Points along each edge of a face.
EDGE_SAMPLES = 32
#: Lattice points per knot span of a B-spline face, when that gives more than :data:`GRID` (at most :data:`MAX_GRID`).
PER_SPAN = 6
MAX_GRID = 121


def _edges(face) -> list:
    edges = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(face, TopAbs_EDGE, edges)
    return [TopoDS.Edge_s(edges.FindKey(i)) for i in range(1, edges.Extent() + 1)]


def _spans(surface, lo: float, hi: float, k: int) -> int:
    """Knot spans of a B-spline ``surface`` along direction ``k`` inside ``[lo, hi]`` (1 for other surfaces)."""
    from .occ import surface_kind

    _, bspline = surface_kind(surface)
    if not isinstance(bspline, Geom_BSplineSurface):
        return 1
    count = bspline.NbUKnots() if k == 0 else bspline.NbVKnots()
    knots = [bspline.UKnot(i) if k == 0 else bspline.VKnot(i) for i in range(1, count + 1)]
    return max(1, sum(1 for a, b in zip(knots, knots[1:]) if b > lo and a < hi))


def _lattice(surface, box, grid: int) -> tuple[int, int]:
    """Lattice points per direction: ``grid``, or :data:`PER_SPAN` per knot span of the face's surface inside its uv
    box when that is more (a ripple peaks once or twice per span; a fixed lattice over many spans steps over them),
    at most :data:`MAX_GRID`."""
    u0, u1, v0, v1 = box
    return tuple(int(min(MAX_GRID, max(grid, PER_SPAN * _spans(surface, lo, hi, k) + 1)))
                 for k, (lo, hi) in enumerate(((u0, u1), (v0, v1))))


def face_samples(face, grid: int = GRID, edge_samples: int = EDGE_SAMPLES) -> np.ndarray:
    """Points of ``face`` inside its trim.

    Parameters
    ----------
    face : TopoDS_Face
    grid : int
        Lattice points per direction of the face's uv box, at least (a B-spline face: :data:`PER_SPAN` per knot span
        inside the box when that is more, at most :data:`MAX_GRID`).
    edge_samples : int
        Points along each edge (its pcurve on the face, evaluated on the face's surface).

    Returns
    -------
    points : (m, 3) float
        Model coordinates (mm for STEP), location applied.
    """
    surface = BRep_Tool.Surface_s(face)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    tol = BRep_Tool.Tolerance_s(face)
    classifier = BRepTopAdaptor_FClass2d(face, tol)
    nu, nv = _lattice(surface, (u0, u1, v0, v1), grid)
    points, p = [], gp_Pnt()
    for u in np.linspace(u0, u1, nu).tolist():
        for v in np.linspace(v0, v1, nv).tolist():
            if classifier.Perform(gp_Pnt2d(u, v)) in (TopAbs_IN, TopAbs_ON):
                surface.D0(u, v, p)
                points.append((p.X(), p.Y(), p.Z()))
    for edge in _edges(face):
        if BRep_Tool.Degenerated_s(edge):
            continue
        curve = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0)
        if curve is None:
            continue
        first, last = BRep_Tool.Range_s(edge, face)
        for t in np.linspace(first, last, edge_samples).tolist():
            uv = curve.Value(t)
            surface.D0(uv.X(), uv.Y(), p)
            points.append((p.X(), p.Y(), p.Z()))
    return np.asarray(points, float).reshape(-1, 3)


def distance_to_face(points: np.ndarray, face) -> np.ndarray:
    """Distance of each point to ``face`` (its surface inside its trim).

    The nearest point of the face's surface (``ShapeAnalysis_Surface.ValueOfUV``) when it lies inside the
    trim; else the distance to the face itself (``BRepExtrema_DistShapeShape``, trims respected).

    Parameters
    ----------
    points : (m, 3) float
    face : TopoDS_Face

    Returns
    -------
    (m,) float
    """
    surface = BRep_Tool.Surface_s(face)
    tol = BRep_Tool.Tolerance_s(face)
    analysis = ShapeAnalysis_Surface(surface)
    classifier = BRepTopAdaptor_FClass2d(face, tol)
    out = np.empty(len(points))
    for k, (x, y, z) in enumerate(np.asarray(points, float).tolist()):
        point = gp_Pnt(x, y, z)
        try:
            uv = analysis.ValueOfUV(point, 1e-9)
            inside = classifier.Perform(uv) != TopAbs_OUT
            gap = analysis.Gap()
        except Standard_Failure:
            inside = False
        if inside:
            out[k] = gap
            continue
        extrema = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(point).Vertex(), face)
        out[k] = extrema.Value() if extrema.IsDone() else np.inf
    return out


def face_distance(a, b, grid: int = GRID) -> tuple[float, float]:
    """``(d(a -> b), d(b -> a))``: the largest distance of ``a``'s samples (:func:`face_samples`) to ``b``, and
    of ``b``'s to ``a`` (:func:`distance_to_face`). Model units."""
    ab = distance_to_face(face_samples(a, grid), b)
    ba = distance_to_face(face_samples(b, grid), a)
    return float(ab.max(initial=0.0)), float(ba.max(initial=0.0))


def edge_tolerance(face) -> float:
    """The largest tolerance of ``face``'s edges (model units)."""
    return float(max((BRep_Tool.Tolerance_s(edge) for edge in _edges(face)), default=0.0))


def face_valid(face) -> bool:
    """BRepCheck's verdict on ``face`` alone."""
    return bool(BRepCheck_Analyzer(face).IsValid())
