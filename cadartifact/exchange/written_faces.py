"""A face on a new surface, its edges still on it, and what the written face measures against the old one.

The parameter map between the old and the new surface is not assumed: a refitted surface (the advised net) is
fitted to the intent in the intent's own parametrisation, which is not the old surface's where the old knots are
not uniform, so the old pcurves, evaluated on the new surface, address other points (0.1-31 mm off on a real
hull). Each edge's pcurve on the new surface is instead rebuilt by projecting the edge's 3-D curve onto it
(``ShapeFix_Edge.FixAddPCurve``, i.e. ``ShapeConstruct_ProjectCurveOnSurface``), so the trim stays where it was
in space. An edge shared with another face keeps its 3-D curve (the neighbour's pcurves and the shared edge stay
consistent; its tolerance becomes its gap to the new surface). An edge bounding this face only (a free border)
takes the new surface's curve: its 3-D curve is rebuilt from the projected pcurve (``BRepLib.BuildCurve3d``).
Seams keep their old pcurves (the new surface spans the old one's parameter range there). A degenerate edge (one
point in space) keeps its old pcurve where that still maps to its vertex on the new surface (a pole the refit
kept); elsewhere it is left out of its wire, which stays closed through its vertex, where its neighbours'
projected pcurves end: a sewn shell's degenerate slivers reaching 0.005 into an extension (in uv) otherwise
addressed points of the new surface 0.235 mm past the old face (and a constant pcurve in their place leaves a
wire BRepCheck calls not closed).
A face that measures unfaithful so is tried once more with its old pcurves kept (the other explicit map: the new
surface addressed in the old one's parameters, right where the refit kept the parametrisation).

:func:`measure` gives what the written face is: its distance to the old face both ways by projection
(:mod:`.face_distance`), the largest edge tolerance before and after, BRepCheck before and after;
:func:`refusal` says why a face should be kept instead (SPEC §5: within t + the old face's ripple of the old face,
plus its edge tolerance since its border is known only to within it; edge tolerances within the input's + t;
BRepCheck no worse).
"""

from __future__ import annotations

import numpy as np

from ..dependencies import require

require("OCP", "writing STEP models")

from OCP.BRep import BRep_Builder, BRep_Tool  # noqa: E402
from OCP.BRepLib import BRepLib  # noqa: E402
from OCP.ShapeFix import ShapeFix_Edge  # noqa: E402
from OCP.Standard import Standard_Failure  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_FORWARD, TopAbs_REVERSED  # noqa: E402
from OCP.TopExp import TopExp  # noqa: E402
from OCP.TopoDS import TopoDS, TopoDS_Iterator, TopoDS_Wire  # noqa: E402
from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape, TopTools_IndexedMapOfShape  # noqa: E402

from ..errors import InputError  # noqa: E402
from .face_distance import distance_to_face, edge_tolerance, face_samples, face_valid  # noqa: E402

__all__ = ["free_edges", "replace_surface", "measure", "refusal", "MEASURED_KEYS"]

#: The keys :func:`measure` gives (the ``written`` record's per-face figures).
MEASURED_KEYS = ("distance_to_old", "distance_from_old", "max_distance", "mean_distance", "edge_tolerance_before",
                 "edge_tolerance", "valid_before", "valid")


def free_edges(shape) -> TopTools_IndexedMapOfShape:
    """The edges of ``shape`` that bound one face only (its free borders)."""
    ancestors = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    free = TopTools_IndexedMapOfShape()
    for i in range(1, ancestors.Extent() + 1):
        faces = TopTools_IndexedMapOfShape()
        for face in ancestors.FindFromIndex(i):
            faces.Add(face)
        if faces.Extent() == 1:
            free.Add(ancestors.FindKey(i))
    return free


def _edges(face) -> list:
    edges = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(face, TopAbs_EDGE, edges)
    return [TopoDS.Edge_s(edges.FindKey(i)) for i in range(1, edges.Extent() + 1)]


def replace_surface(face, surface, free=None, project: bool = True):
    """A new face on ``surface`` (global coordinates) with ``face``'s wires, each edge's pcurve on it rebuilt.

    Parameters
    ----------
    face : TopoDS_Face
        The face as it stands in the model (its edges are updated in place: work on a copy of the model).
    surface : Geom_Surface
    free : TopTools_IndexedMapOfShape, optional
        The model's free edges (:func:`free_edges`): those take the new surface's curve as their 3-D curve.
    project : bool
        Rebuild each pcurve by projecting the edge's 3-D curve (the default); False: keep the old pcurves (the
        new surface addressed in the old one's parameters: right where the refit kept the parametrisation,
        which the writer tries when the projected face measures unfaithful).

    Returns
    -------
    (TopoDS_Face, list of TopoDS_Edge)
        The new face and its edges (for ``ShapeFix_Edge.FixSameParameter``).
    """
    builder = BRep_Builder()
    new_face = TopoDS.Face_s(face.EmptyCopied())
    collapsed = [edge for edge in _edges(face) if BRep_Tool.Degenerated_s(edge) and not _on_vertex(edge, face, surface)]
    it = TopoDS_Iterator(face, False, False)  # the wires as stored: relative orientation and location
    while it.More():
        builder.Add(new_face, _without(it.Value(), collapsed) if collapsed else it.Value())
        it.Next()
    local = surface
    if not face.Location().IsIdentity():
        local = surface.Transformed(face.Location().Inverted().Transformation())
    builder.UpdateFace(new_face, local, face.Location(), BRep_Tool.Tolerance_s(face))
    old_surface, location = BRep_Tool.Surface_s(face), face.Location()
    fix = ShapeFix_Edge()
    edges = []
    for edge in _edges(new_face):
        tol = BRep_Tool.Tolerance_s(edge)
        if BRep_Tool.IsClosed_s(edge, face):  # a seam: one pcurve per orientation, on the same parameter range
            forward = TopoDS.Edge_s(edge.Oriented(TopAbs_FORWARD))
            c1 = BRep_Tool.CurveOnSurface_s(forward, face, 0.0, 0.0)
            c2 = BRep_Tool.CurveOnSurface_s(TopoDS.Edge_s(edge.Oriented(TopAbs_REVERSED)), face, 0.0, 0.0)
            builder.UpdateEdge(forward, c1, c2, new_face, tol)
        elif BRep_Tool.Degenerated_s(edge):  # a pole the refit kept: its old pcurve maps to its vertex still
            builder.UpdateEdge(edge, BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0), new_face, tol)
        else:
            projected = False
            if project:
                try:
                    projected = fix.FixAddPCurve(edge, new_face, False)
                except Standard_Failure:
                    projected = False
            if not projected:  # asked, no 3-D curve to project (degenerate) or the projection failed: the old pcurve
                old = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0)
                if old is None:
                    raise InputError(None, "an edge of the face has no curve on its surface")
                builder.UpdateEdge(edge, old, new_face, tol)
            if (projected or not project) and free is not None and free.Contains(edge):
                # a free border follows the new surface: drop the old pcurve and 3-D curve, rebuild it from the new
                builder.UpdateEdge(edge, None, old_surface, location, tol)
                builder.UpdateEdge(edge, None, tol)
                if not BRepLib.BuildCurve3d_s(edge, 1e-7):
                    raise InputError(None, "a free edge's curve could not be rebuilt on the new surface")
        builder.SameParameter(edge, False)
        edges.append(edge)
    return new_face, edges


def _on_vertex(edge, old_face, surface) -> bool:
    """Whether a degenerate edge's old pcurve maps to its vertex on ``surface`` (global coordinates), within the
    edge's tolerance at 9 points: a pole the refit kept."""
    old = BRep_Tool.CurveOnSurface_s(edge, old_face, 0.0, 0.0)
    if old is None:
        return True  # nothing to map: the edge is left as it is
    first, last = BRep_Tool.Range_s(edge, old_face)
    vertex = BRep_Tool.Pnt_s(TopExp.FirstVertex_s(edge))
    reach = max(BRep_Tool.Tolerance_s(edge), 1e-7)
    return all(surface.Value(uv.X(), uv.Y()).Distance(vertex) <= reach
               for uv in (old.Value(s) for s in np.linspace(first, last, 9).tolist()))


def _without(wire, edges):
    """``wire`` (as the face stores it) without ``edges``: degenerate edges of one vertex, so the wire stays closed
    through that vertex. The wire itself when it has none of them."""
    it = TopoDS_Iterator(wire, False, False)
    kept, dropped = [], False
    while it.More():
        edge = it.Value()
        if any(edge.IsSame(e) for e in edges):
            dropped = True
        else:
            kept.append(edge)
        it.Next()
    if not dropped:
        return wire
    builder = BRep_Builder()
    new = TopoDS_Wire()
    builder.MakeWire(new)
    for edge in kept:
        builder.Add(new, edge)
    new.Closed(wire.Closed())
    new.Location(wire.Location())
    return new.Oriented(wire.Orientation())


def measure(old_face, new_face) -> dict:
    """What ``new_face`` (as written) measures against ``old_face`` (as read).

    Returns
    -------
    dict
        ``distance_to_old``: the largest distance of the new face's samples (inside its trim) to the old face;
        ``distance_from_old``: of the old face's to the new; ``max_distance``: the larger; ``mean_distance``: the
        mean over both sample sets (:mod:`.face_distance`); ``edge_tolerance_before`` / ``edge_tolerance``: the
        largest tolerance of the face's edges in the input / as written; ``valid_before`` / ``valid``: BRepCheck
        on the face alone. Model units (mm for STEP).
    """
    to_old = distance_to_face(face_samples(new_face), old_face)
    from_old = distance_to_face(face_samples(old_face), new_face)
    both = np.concatenate([to_old, from_old])
    return {"distance_to_old": float(to_old.max(initial=0.0)), "distance_from_old": float(from_old.max(initial=0.0)),
            "max_distance": float(both.max(initial=0.0)), "mean_distance": float(both.mean()) if both.size else 0.0,
            "edge_tolerance_before": edge_tolerance(old_face), "edge_tolerance": edge_tolerance(new_face),
            "valid_before": face_valid(old_face), "valid": face_valid(new_face)}


def refusal(record: dict, allowed_distance: float | None, tolerance: float | None) -> str | None:
    """Why a written face must be kept as it was (None: it may be written).

    Parameters
    ----------
    record : dict
        :func:`measure`'s figures.
    allowed_distance : float, optional
        ``t + `` the old face's ripple (the value the advice read for today's net) + the old face's largest edge
        tolerance: the new face must lie within it of the old face, both ways. None: not checked.
    tolerance : float, optional
        ``t``: each edge's tolerance may rise to the input's + ``t``. None: not checked.
    """
    why = []
    if allowed_distance is not None and not record["max_distance"] <= allowed_distance:
        why.append(f"it lies {record['max_distance']:.4g} from the old face, beyond t + the old face's ripple "
                   f"+ its edge tolerance = {allowed_distance:.4g}")
    if tolerance is not None and not record["edge_tolerance"] <= record["edge_tolerance_before"] + tolerance:
        why.append(f"its edges end {record['edge_tolerance']:.4g} off it (edge tolerance; the input's "
                   f"{record['edge_tolerance_before']:.3g} + t = {record['edge_tolerance_before'] + tolerance:.4g})")
    if record["valid_before"] and not record["valid"]:
        why.append("BRepCheck rejects the written face (the input's passes)")
    return "; ".join(why) or None
