"""Continuity between faces: G0 gap, G1 normal angle and G2 curvature jump along every edge two faces share.

The checkers' connection analysis (CATIA's Connect Checker, ModelCHECK's and Q-Checker's G0/G1/G2 checks of
VDA 4955) compares the two faces of a shared edge at points along it. Here, at ``samples`` parameters ``t``
spread evenly over the edge's range, each face is evaluated at the edge's own curve on that face (its pcurve,
``BRepAdaptor_Curve2d``), so nothing is projected:

* **G0 gap** ``|S1(c1(t)) - S2(c2(t))|`` (model units);
* **G1 angle** between the faces' oriented normals (degrees; a face's normal is ``S_u x S_v`` reversed with
  the face's orientation, and the second face's is reversed again when the shell's orientation is
  inconsistent at the edge, i.e. the edge runs the same way in both faces);
* **G2 jump** of the normal curvature *across* the edge, in the direction ``d = n x T`` (``T`` the edge's
  tangent): ``k = II(d, d) / I(d, d)`` on each face (do Carmo, 1976, sec. 3-2), absolute ``|k1 - k2|`` and
  relative ``|k1 - k2| / max(|k1|, |k2|)`` (CATIA's G2 ratio), the relative one 0 where both faces are flat
  (``max |k| <= 1 / flat_radius``).

An edge whose faces meet at a crease all along it (the smallest angle over the samples at least the profile's
``sharp_angle``, a box's edge) is *sharp by design*: reported as such, not judged on G1 or G2. Edges of one face
only (free boundaries), seams (one face on both sides), degenerate edges and edges of more than two faces are
counted, not measured.

The measure (:func:`shape_edges`) is free of thresholds; :func:`judge_edges` judges its records against a
:class:`~cadartifact.analysis.quality.Profile` (criteria ``edge_gap``, ``edge_angle``, ``edge_curvature`` of
:data:`~cadartifact.analysis.quality.CRITERIA`). OCCT is imported on first use: the reader child runs
:func:`file_edges` (``EDGES_FUNCTION``) beside its reads.

References: SASIG / VDA 4955 (ISO/PAS 26183) G0/G1 gap and tangency checks; Dassault Systemes, CATIA
*Connect Checker* (G0 in mm, G1 in degrees, G2 ratio ``|C1 - C2| / max(C1, C2)``); M. P. do Carmo, *Differential
Geometry of Curves and Surfaces*, 1976.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["EDGE_SAMPLES", "EDGES_FUNCTION", "file_edges", "shape_edges", "judge_edges", "edge_summary"]

#: Samples along each edge (the ends included).
EDGE_SAMPLES = 41
#: What the reader child runs for :func:`file_edges` (``module:function``).
EDGES_FUNCTION = f"{__name__}:file_edges"
#: Curvature at most this (1 / model units: a 100 m radius in mm) counts as flat for the relative G2 jump.
FLAT_CURVATURE = 1e-5
#: A sample where ``|S_u x S_v| <= NORMAL_FLOOR max(|S_u|, |S_v|)^2`` has no normal (a pole, a collapsed edge).
NORMAL_FLOOR = 1e-10


def file_edges(path, fmt: str, samples: int = EDGE_SAMPLES) -> dict:
    """The edges of a STEP/IGES/BREP file (:func:`shape_edges`) with their STEP records and lines.

    Parameters
    ----------
    path : path-like
    fmt : {"step", "iges", "brep"}
    samples : int

    Returns
    -------
    dict
        :func:`shape_edges`'s dict; with STEP each edge's ``entity`` is its ``EDGE_CURVE`` id and ``line`` the
        line of that record (None when unknown), ``face_entities`` the faces' ``ADVANCED_FACE`` ids.
    """
    from pathlib import Path

    from ..exchange import step

    path = Path(path)
    face_entity = edge_entity = None
    if fmt == "step":
        from ..exchange.step_text import entity_lines

        reader = step.open_step(path, reuse=True)  # the faces' read of this file in this process, if any
        shape = reader.OneShape()
        transfer = reader.WS().TransferReader()
        records = entity_lines(path)
        entities = step._model_entities(reader)  # kept alive: pybind11 then hands out these very wrappers
        numbers = {id(e): i for i, e in enumerate(entities, start=1)}

        seen = {}  # a face borders many edges: OCCT searches its results for each shape asked, so ask once

        def record_of(sub, keyword):
            key = (hash(sub), keyword)
            for shape, found in seen.get(key, ()):
                if shape.IsEqual(sub):  # OCCT prefers an equal shape (orientation too) to a same one
                    return found
            found = _record_of(sub, keyword)
            seen.setdefault(key, []).append((sub, found))
            return found

        def _record_of(sub, keyword):
            entity = transfer.EntityFromShapeResult(sub, 1)
            i = numbers.get(id(entity)) if entity is not None else None
            if i is None or not 0 < i <= len(records) or records[i - 1][2] != keyword:
                return None
            return records[i - 1][0], records[i - 1][1]

        face_entity = lambda f: (record_of(f, "ADVANCED_FACE") or (None,))[0]  # noqa: E731
        edge_entity = lambda e: record_of(e, "EDGE_CURVE") or (None, None)  # noqa: E731
        out = shape_edges(shape, face_entity=face_entity, edge_entity=edge_entity, samples=samples)
        del reader, entities
        return out
    shape = (step.read_iges(path) if fmt == "iges" else step.read_brep(path))[0]
    return shape_edges(shape, samples=samples)


def _faces(shape) -> tuple[list, dict]:
    """The faces in ``TopExp_Explorer`` order (the nets' ``origin.face``) and ``{hash: [index]}``."""
    from ..exchange.occ import iter_faces

    faces, where = [], {}
    for index, face in iter_faces(shape):
        faces.append(face)
        where.setdefault(hash(face), []).append(index)
    return faces, where


def _listed(shapes) -> list:
    """The shapes of a ``TopTools_ListOfShape``: ``First``/``Last`` where they are all (its Python iterator costs
    about half a millisecond a list, a quarter of the edge measurement on a file of 600 edges)."""
    n = shapes.Size()
    return [] if n == 0 else [shapes.First()] if n == 1 else [shapes.First(), shapes.Last()] if n == 2 else list(shapes)


def _index_of(face, faces: list, where: dict) -> int:
    return next(i for i in where.get(hash(face), []) if faces[i].IsSame(face))


def _orientation_in(face, edge):
    """The edge's orientation as the face uses it (composed with the face's own)."""
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer

    ex = TopExp_Explorer(face, TopAbs_EDGE)
    while ex.More():
        if ex.Current().IsSame(edge):
            return ex.Current().Orientation()
        ex.Next()
    return None


def shape_edges(shape, *, face_entity=None, edge_entity=None, samples: int = EDGE_SAMPLES,
                flat_curvature: float = FLAT_CURVATURE, faces=None) -> dict:
    """G0, G1 and G2 along every edge two faces of ``shape`` share.

    Parameters
    ----------
    shape : TopoDS_Shape
    face_entity : callable(face) -> int or None, optional
        A face's STEP id.
    edge_entity : callable(edge) -> (int or None, int or None), optional
        An edge's STEP id and line.
    samples : int
        Parameters along each edge (evenly spread over its range, the ends included).
    flat_curvature : float
        Where both faces' ``|k|`` are at most this (1 / model units), the relative jump is 0 (both flat).
    faces : collection of int, optional
        Only the edges of these faces (indices as ``origin.face``) are measured and counted; None: every edge.

    Returns
    -------
    dict
        ``{"edges": [record], "counted": {"shared", "free", "seam", "degenerate", "non_manifold", "failed"}}``
        (``shared``: measured; ``failed``: shared by two faces but OCCT could not evaluate it); a record is
        ``{"edge": index in OCCT's edge map (1-based), "entity", "line", "faces": [i, j] (face indices),
        "face_entities", "length", "samples", "orientation": "consistent" | "inconsistent",
        "gap": {"value", "at"}, "angle": {"value", "min", "at"},
        "curvature": {"jump", "jump_at", "relative", "k", "at"} | None}``,
        ``at = {"t": share of the edge's range, "xyz"}``; angles in degrees, curvatures in 1 / model units;
        ``relative``, ``k`` (both faces') and ``at`` are the largest relative jump's, ``jump_at`` the largest
        absolute jump's place.
        ``curvature`` is None when no sample has both normals.
    """
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from OCP.TopoDS import TopoDS
    from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape

    only = None if faces is None else set(faces)
    faces, where = _faces(shape)
    ancestors = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    counted = {"shared": 0, "free": 0, "seam": 0, "degenerate": 0, "non_manifold": 0, "failed": 0}
    records = []
    for k in range(1, ancestors.Extent() + 1):
        edge = TopoDS.Edge_s(ancestors.FindKey(k))
        owners = [TopoDS.Face_s(f) for f in _listed(ancestors.FindFromIndex(k))]
        if only is not None and not any(_index_of(f, faces, where) in only for f in owners):
            continue
        if BRep_Tool.Degenerated_s(edge):
            counted["degenerate"] += 1
            continue
        distinct = []
        for f in owners:
            if not any(f.IsSame(g) for g in distinct):
                distinct.append(f)
        n_own = len(owners)
        if len(distinct) <= 1:  # a free boundary, a seam, or an edge of no face (a wire: annotations)
            counted["seam" if n_own > 1 else "free"] += 1
            continue
        if len(distinct) > 2:
            counted["non_manifold"] += 1
            continue
        f1, f2 = distinct
        try:
            record = _edge_record(edge, f1, f2, samples, flat_curvature)
        except Exception:  # noqa: BLE001 - OCCT cannot evaluate this edge on a face (no pcurve): counted, not measured
            counted["failed"] += 1
            continue
        counted["shared"] += 1
        ident, line = edge_entity(edge) if edge_entity is not None else (None, None)
        i1, i2 = _index_of(f1, faces, where), _index_of(f2, faces, where)
        record.update(edge=k, entity=ident, line=line, faces=[i1, i2],
                      face_entities=[face_entity(f1), face_entity(f2)] if face_entity is not None else [None, None])
        records.append({key: record[key] for key in _ORDER})
    return {"edges": records, "counted": counted}


_ORDER = ("edge", "entity", "line", "faces", "face_entities", "length", "samples", "orientation", "gap", "angle",
          "curvature")


def _edge_record(edge, f1, f2, samples: int, flat_curvature: float) -> dict:
    from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d, BRepAdaptor_Surface
    from OCP.GCPnts import GCPnts_AbscissaPoint
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.TopAbs import TopAbs_REVERSED

    curve = BRepAdaptor_Curve(edge)
    a, b = curve.FirstParameter(), curve.LastParameter()
    ts = np.linspace(a, b, samples)
    o1, o2 = _orientation_in(f1, edge), _orientation_in(f2, edge)
    consistent = o1 is None or o2 is None or o1 != o2
    sides = []
    for face, flip in ((f1, False), (f2, not consistent)):
        sign = (-1.0 if face.Orientation() == TopAbs_REVERSED else 1.0) * (-1.0 if flip else 1.0)
        pc = BRepAdaptor_Curve2d(edge, face)
        surf = BRepAdaptor_Surface(face)
        P, D = np.full((samples, 3), np.nan), np.zeros((samples, 5, 3))
        p, du, dv, duu, dvv, duv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()  # D2 writes them
        for i, t in enumerate(ts):
            u, v = pc.Value(t).Coord()
            surf.D2(u, v, p, du, dv, duu, dvv, duv)
            P[i] = p.Coord()
            D[i] = du.Coord(), dv.Coord(), duu.Coord(), duv.Coord(), dvv.Coord()
        sides.append((P, D, sign))
    T = np.zeros((samples, 3))
    p, v = gp_Pnt(), gp_Vec()
    for i, t in enumerate(ts):
        curve.D1(t, p, v)
        T[i] = v.Coord()
    normals, curv = [], []
    for P, D, sign in sides:
        n, k = _normal_and_across(D, T, sign)
        normals.append(n)
        curv.append(k)
    P1, P2 = sides[0][0], sides[1][0]
    gap = np.linalg.norm(P1 - P2, axis=1)
    share = (ts - a) / (b - a) if b > a else np.zeros(samples)

    def at(i):
        return {"t": round(float(share[i]), 9), "xyz": [round(float(c), 9) for c in 0.5 * (P1[i] + P2[i])]}

    ig = int(np.nanargmax(gap))
    record = {"length": _num(GCPnts_AbscissaPoint.Length_s(curve)), "samples": samples,
              "orientation": "consistent" if consistent else "inconsistent",
              "gap": {"value": _num(gap[ig]), "at": at(ig)}, "angle": None, "curvature": None}
    cos = np.einsum("ij,ij->i", normals[0], normals[1])
    valid = np.isfinite(cos)
    if valid.any():
        ang = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
        ia = int(np.nanargmax(ang))
        record["angle"] = {"value": _num(ang[ia]), "min": _num(np.nanmin(ang)), "at": at(ia)}
        k1, k2 = curv
        jump = np.abs(k1 - k2)
        big = np.fmax(np.abs(k1), np.abs(k2))
        ok = np.isfinite(jump)
        if ok.any():
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.where(ok & (big > flat_curvature), jump / big, 0.0)
            ij, ir = int(np.argmax(np.where(ok, jump, -1.0))), int(np.argmax(rel))
            record["curvature"] = {"jump": _num(jump[ij]), "relative": _num(rel[ir]),
                                   "k": [_num(k1[ir]), _num(k2[ir])], "at": at(ir), "jump_at": at(ij)}
    return record


def _normal_and_across(D: np.ndarray, T: np.ndarray, sign: float) -> tuple[np.ndarray, np.ndarray]:
    """Oriented unit normals ``(m, 3)`` and the normal curvature across the edge ``(m,)`` (NaN without a normal).

    ``d = n x T`` normalised, written ``d = a S_u + b S_v`` (least squares), ``k = (L a^2 + 2 M a b + N b^2) /
    (E a^2 + 2 F a b + G b^2)`` with ``L, M, N = S_uu.n, S_uv.n, S_vv.n``.
    """
    Su, Sv, Suu, Suv, Svv = (D[:, i] for i in range(5))
    c = np.cross(Su, Sv)
    size = np.linalg.norm(c, axis=1)
    # relative to the larger derivative: at a collapsed edge (a sphere's pole) one derivative vanishes and the
    # direction of what is left of it is noise
    ok = size > NORMAL_FLOOR * np.fmax(np.linalg.norm(Su, axis=1), np.linalg.norm(Sv, axis=1)) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        n = sign * c / size[:, None]
        n[~ok] = np.nan
        d = np.cross(n, T)
        d /= np.linalg.norm(d, axis=1)[:, None]
        E, F, G = (np.einsum("ij,ij->i", x, y) for x, y in ((Su, Su), (Su, Sv), (Sv, Sv)))
        L, M, N = (np.einsum("ij,ij->i", x, n) for x in (Suu, Suv, Svv))
        du, dv = np.einsum("ij,ij->i", d, Su), np.einsum("ij,ij->i", d, Sv)
        det = E * G - F * F
        a_, b_ = (G * du - F * dv) / det, (E * dv - F * du) / det
        k = (L * a_ ** 2 + 2 * M * a_ * b_ + N * b_ ** 2) / (E * a_ ** 2 + 2 * F * a_ * b_ + G * b_ ** 2)
    return n, k


def _num(x):
    x = float(x)
    return round(x, 9) if math.isfinite(x) else None


# ---------------------------------------------------------------- judging
def judge_edges(records: list, profile, ignore_faces=()) -> list:
    """The edge records with their verdicts against a profile's ``edge_gap``, ``edge_angle`` and
    ``edge_curvature`` limits.

    Parameters
    ----------
    records : list of dict
        :func:`shape_edges`'s ``edges``.
    profile : Profile
    ignore_faces : collection of int
        Edges of these faces are left out.

    Returns
    -------
    list of dict
        Each record plus ``sharp`` (a crease all along the edge: the smallest angle >= ``profile.sharp_angle``;
        then G1 and G2 are not judged), ``verdict`` (the worst of its criteria's) and ``criteria``: one per edge
        criterion, ``{"criterion", "code", "evaluated", "value", "unit", "verdict", "threshold", "at", "detail",
        "reason"}`` as a face's criteria, ``at = {"t", "xyz"}``.
    """
    from .quality import CRITERIA, judge

    out = []
    for rec in records:
        if set(rec["faces"]) & set(ignore_faces):
            continue
        angle, curv = rec["angle"], rec["curvature"]
        sharp = angle is not None and angle["min"] is not None and angle["min"] >= profile.sharp_angle
        found = {"edge_gap": (rec["gap"]["value"], rec["gap"]["at"], f"largest distance between the faces along the "
                                                                      f"edge ({rec['samples']} samples)")}
        if sharp:
            why = f"sharp by design: a crease of {angle['min']:.4g} to {angle['value']:.4g} degrees all along the edge"
            found["edge_angle"] = found["edge_curvature"] = why
        elif angle is None:
            found["edge_angle"] = found["edge_curvature"] = "no sample has a normal on both faces"
        else:
            found["edge_angle"] = (angle["value"], angle["at"], f"normal angle {angle['min']:.4g} to "
                                                                f"{angle['value']:.4g} degrees along the edge")
            found["edge_curvature"] = (
                (curv["relative"], curv["at"], f"normal curvature across the edge {curv['k'][0]:.4g} and "
                                               f"{curv['k'][1]:.4g}; largest absolute jump {curv['jump']:.4g}")
                if curv is not None else "no sample has a curvature on both faces")
        crit = []
        for key in EDGE_CRITERIA:
            spec, lim, got = CRITERIA[key], profile.limit(key), found[key]
            item = {"criterion": key, "code": spec.code, "evaluated": False, "value": None, "unit": spec.unit,
                    "verdict": None, "threshold": None if lim is None else {"warn": lim.warn, "fail": lim.fail,
                                                                            "sense": spec.sense},
                    "at": None, "detail": "", "reason": None}
            if lim is None:
                item["reason"] = "off in this profile"
            elif isinstance(got, str):
                item["reason"] = got
            elif got[0] is None:
                item["reason"] = "not finite"
            else:
                item.update(evaluated=True, value=got[0], verdict=judge(got[0], lim, spec.sense), at=got[1],
                            detail=got[2])
            crit.append(item)
        verdicts = [c["verdict"] for c in crit if c["evaluated"]]
        verdict = "fail" if "fail" in verdicts else "warn" if "warn" in verdicts else "pass"
        out.append({**rec, "sharp": sharp, "verdict": verdict, "criteria": crit})
    return out


#: The edge criteria of :data:`cadartifact.analysis.quality.CRITERIA`, in report order.
EDGE_CRITERIA = ("edge_gap", "edge_angle", "edge_curvature")


def edge_summary(edges: list) -> dict:
    """``{"edges", "sharp", "warn", "fail"}`` counts of judged edge records."""
    return {"edges": len(edges), "sharp": sum(e["sharp"] for e in edges),
            "warn": sum(e["verdict"] == "warn" for e in edges), "fail": sum(e["verdict"] == "fail" for e in edges)}
