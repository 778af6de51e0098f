"""Write a whole B-rep model back to STEP with some faces' surfaces replaced by new nets.

The model is read with OCCT, its faces are walked in the order :func:`cadartifact.exchange.read`
numbers them (``TopExp_Explorer`` over the whole shape), and each replaced face gets a new TFace
on the new ``Geom_BSplineSurface`` that keeps the face's own wires. The edges stay shared with
the neighbouring faces; each edge of a replaced face gets its old pcurve again on the new
surface (valid because a replacement covers the same parameter range by contract), and
``ShapeFix_Edge.FixSameParameter`` then sets the edge tolerance to the gap between the edge's
3-D curve and the new surface. Untouched faces, face order, face and product names and the
file's length unit and distance uncertainty are kept; the header carries the provenance.

This module does no analysis: the distance it reports is a plain grid comparison of two surfaces.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import numpy as np

from ..dependencies import require
from ..errors import InputError, OptionError
from ..net import ControlNet
from .files import check_file

require("OCP", "writing STEP models")

from OCP.BRep import BRep_Builder, BRep_Tool  # noqa: E402
from OCP.BRepCheck import BRepCheck_Analyzer  # noqa: E402
from OCP.BRepLib import BRepLib  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.IFSelect import IFSelect_RetDone  # noqa: E402
from OCP.ShapeBuild import ShapeBuild_ReShape  # noqa: E402
from OCP.ShapeFix import ShapeFix_Edge, ShapeFix_Face  # noqa: E402
from OCP.Standard import Standard_Failure  # noqa: E402
from OCP.StepBasic import StepBasic_Product  # noqa: E402
from OCP.StepGeom import StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx  # noqa: E402
from OCP.STEPConstruct import STEPConstruct, STEPConstruct_UnitContext  # noqa: E402
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer  # noqa: E402
from OCP.TCollection import TCollection_HAsciiString  # noqa: E402
from OCP.TColStd import TColStd_SequenceOfAsciiString  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FORWARD, TopAbs_REVERSED  # noqa: E402
from OCP.TopExp import TopExp  # noqa: E402
from OCP.TopoDS import TopoDS, TopoDS_Iterator  # noqa: E402
from OCP.TopTools import TopTools_IndexedMapOfShape  # noqa: E402

from .occ import iter_faces, occ_surface, quiet_occt, surface_kind  # noqa: E402
from .step import set_header, write_settings  # noqa: E402

__all__ = ["write_model", "STEP_SUFFIXES", "check_step_output", "GRID"]

#: Output suffixes write_model accepts (any case).
STEP_SUFFIXES = (".step", ".stp")
#: Evaluations per direction of the old/new distance grid.
GRID = 41

#: STEP unit names (as OCCT's reader reports them) -> the ``write.step.unit`` value.
_UNITS = {"millimetre": "MM", "mm": "MM", "centimetre": "CM", "cm": "CM", "metre": "M", "m": "M",
          "kilometre": "KM", "km": "KM", "micrometre": "UM", "um": "UM", "inch": "INCH", "foot": "FT",
          "ft": "FT", "mile": "MI", "mil": "MIL", "microinch": "UIN"}
#: ``write.step.unit`` value -> its length in mm.
_MM = {"MM": 1.0, "CM": 10.0, "M": 1000.0, "KM": 1e6, "UM": 1e-3, "INCH": 25.4, "FT": 304.8, "MI": 1609344.0,
       "MIL": 0.0254, "UIN": 2.54e-5}


def check_step_output(out, parameter: str = "out") -> Path:
    """``out`` as a Path if it names a ``.step``/``.stp`` file in an existing folder, else :class:`OptionError`."""
    path = Path(out)
    if path.suffix.lower() not in STEP_SUFFIXES:
        raise OptionError(parameter, "a .step or .stp file (the model is written as STEP)", str(out))
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OptionError(parameter, "a file in an existing folder", str(out))
    return path


def _uncertainty(model, unit: str) -> float | None:
    """The distance uncertainty ``model`` declares, in mm: that of its first representation context in ``unit``
    (else its first with one). None without one, or with one that is not finite and positive."""
    found = []
    for i in range(1, model.NbEntities() + 1):
        entity = model.Value(i)
        if not isinstance(entity, StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx):
            continue
        context = STEPConstruct_UnitContext()
        context.ComputeFactors(entity.GlobalUnitAssignedContext())  # a missing angle unit is no matter here
        if entity.GlobalUncertaintyAssignedContext() is None or not context.LengthDone():
            continue
        context.ComputeTolerance(entity.GlobalUncertaintyAssignedContext())
        if context.HasUncertainty():
            found.append((context.LengthFactor(), context.Uncertainty() * context.LengthFactor()))
    same = [value for factor, value in found if math.isclose(factor, _MM.get(unit, 1.0), rel_tol=1e-9)]
    value = (same or [value for _, value in found] or [None])[0]
    return value if value is not None and math.isfinite(value) and value > 0 else None


def _read_source(path: Path):
    """(shape, face_name, length unit for write.step.unit, product names, distance uncertainty in mm or None) of a
    STEP/IGES/BREP model."""
    from . import formats, step

    record = formats.format_of(path)
    if not record.brep:
        raise OptionError("source", f"a STEP, IGES or BREP model (an {record.label} cage has no B-rep to keep: "
                          "write the faces only)", str(path))
    fmt = record.name
    if fmt != "step":
        reader = step.read_iges if fmt == "iges" else step.read_brep
        shape, face_name = reader(path)
        return shape, face_name, "MM", [], None
    reader = step.open_step(path)
    shape, face_name = reader.OneShape(), step._step_name(reader)
    lengths, angles, solids = TColStd_SequenceOfAsciiString(), TColStd_SequenceOfAsciiString(), \
        TColStd_SequenceOfAsciiString()
    unit = "MM"
    try:
        reader.FileUnits(lengths, angles, solids)
        if lengths.Length():
            unit = _UNITS.get(lengths.Value(1).ToCString().strip().lower(), "MM")
    except Standard_Failure:
        pass
    model = reader.WS().Model()
    products = []
    for i in range(1, model.NbEntities() + 1):
        entity = model.Value(i)
        if isinstance(entity, StepBasic_Product):
            products.append((entity.Id().ToCString() if entity.Id() else "",
                             entity.Name().ToCString() if entity.Name() else ""))
    return shape, face_name, unit, products, _uncertainty(model, unit)


def _check_range(index: int, surface, net: ControlNet, face=None) -> None:
    """The replacement must span the old surface's parameter range, or a part of it that covers the face's own uv
    box (the spans its trim uses, SPEC §4: the pcurves stay inside the new surface)."""
    new = occ_surface(net).Bounds()
    old = surface.Bounds()
    scale = max(1.0, *(abs(x) for x in old if np.isfinite(x)))
    tol = 1e-7 * scale
    same = all(abs(a - b) <= tol for a, b in zip(old, new))
    covers = False
    if face is not None and not same and all(np.isfinite(old)):
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        inside = old[0] - tol <= new[0] and new[1] <= old[1] + tol and old[2] - tol <= new[2] and new[3] <= old[3] + tol
        # a trim past an extension's join by less than the tolerance (model units) ends the advised surface short
        # of the pcurves by that much (at most a thousandth of the range here); the written model is checked
        su, sv = max(tol, 1e-3 * (old[1] - old[0])), max(tol, 1e-3 * (old[3] - old[2]))
        covers = inside and new[0] <= u0 + su and new[1] >= u1 - su and new[2] <= v0 + sv and new[3] >= v1 - sv
    if not all(np.isfinite(old)) or not (same or covers):
        raise OptionError(f"replacements[{index}]", "a net over the face's parameter range "
                          f"u [{old[0]:g}, {old[1]:g}] x v [{old[2]:g}, {old[3]:g}] or a part of it covering its "
                          "trimmed region", f"u [{new[0]:g}, {new[1]:g}] x v [{new[2]:g}, {new[3]:g}]")


def _distance(face, old_surface, new_surface, grid: int = GRID) -> tuple[float, float]:
    """Max and mean of ``|S_old(u, v) - S_new(u, v)|`` on a ``grid x grid`` lattice of the face's uv box."""
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    b = old_surface.Bounds()
    if not old_surface.IsUPeriodic():
        u0, u1 = max(u0, b[0]), min(u1, b[1])
    if not old_surface.IsVPeriodic():
        v0, v1 = max(v0, b[2]), min(v1, b[3])
    p, q = gp_Pnt(), gp_Pnt()
    d = []
    for u in np.linspace(u0, u1, grid).tolist():
        for v in np.linspace(v0, v1, grid).tolist():
            old_surface.D0(u, v, p)
            new_surface.D0(u, v, q)
            d.append(p.Distance(q))
    d = np.asarray(d)
    return float(d.max()), float(d.mean())


def _replace_surface(face, surface):
    """A new face on ``surface`` (global coordinates) with ``face``'s wires, edges keeping their pcurves."""
    builder = BRep_Builder()
    new_face = TopoDS.Face_s(face.EmptyCopied())
    it = TopoDS_Iterator(face, False, False)  # the wires as stored: relative orientation and location
    while it.More():
        builder.Add(new_face, it.Value())
        it.Next()
    local = surface
    if not face.Location().IsIdentity():
        local = surface.Transformed(face.Location().Inverted().Transformation())
    builder.UpdateFace(new_face, local, face.Location(), BRep_Tool.Tolerance_s(face))
    edges = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(new_face, TopAbs_EDGE, edges)
    fixed = []
    for i in range(1, edges.Extent() + 1):
        edge = TopoDS.Edge_s(edges.FindKey(i))
        tol = BRep_Tool.Tolerance_s(edge)
        if BRep_Tool.IsClosed_s(edge, face):  # a seam: one pcurve per orientation
            forward = TopoDS.Edge_s(edge.Oriented(TopAbs_FORWARD))
            c1 = BRep_Tool.CurveOnSurface_s(forward, face, 0.0, 0.0)
            c2 = BRep_Tool.CurveOnSurface_s(TopoDS.Edge_s(edge.Oriented(TopAbs_REVERSED)), face, 0.0, 0.0)
            builder.UpdateEdge(forward, c1, c2, new_face, tol)
        else:
            curve = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0)
            if curve is None:
                raise InputError(None, "an edge of the face has no curve on its surface")
            builder.UpdateEdge(edge, curve, new_face, tol)
        builder.SameParameter(edge, False)
        fixed.append(edge)
    return new_face, fixed


def _write(shape, out: Path, *, unit: str, uncertainty, names, products, source: Path, provenance: dict) -> None:
    """Write ``shape`` to ``out`` atomically (temporary file + rename) in ``unit``, declaring ``uncertainty`` (mm)."""
    writer = STEPControl_Writer()
    with quiet_occt():
        with write_settings(unit, uncertainty):
            status = writer.Transfer(shape, STEPControl_AsIs)
        if status != IFSelect_RetDone:
            raise InputError(out, "OCCT could not translate the model to STEP")
        model = writer.Model()
        written = [model.Value(i) for i in range(1, model.NbEntities() + 1)
                   if isinstance(model.Value(i), StepBasic_Product)]
        for k, entity in enumerate(written):
            ident, name = products[k] if k < len(products) else (out.stem, out.stem)
            entity.SetId(TCollection_HAsciiString(ident or out.stem))
            entity.SetName(TCollection_HAsciiString(name or ident or out.stem))
        finder = writer.WS().TransferWriter().FinderProcess()
        for face, name in names:
            entity = STEPConstruct.FindEntity_s(finder, face)
            if entity is not None and hasattr(entity, "SetName"):
                entity.SetName(TCollection_HAsciiString(name))
        set_header(writer, out.name, {"source": source.name, **provenance})
        folder = out.parent if str(out.parent) else Path(".")
        fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".step", dir=folder)
        os.close(fd)
        try:
            try:
                status = writer.Write(tmp)
            except Standard_Failure as exc:
                raise InputError(out, f"cannot write STEP: {exc}") from None
            if status != IFSelect_RetDone:
                raise InputError(out, "cannot write STEP file (check the folder is writable)")
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, out)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)


def write_model(source, replacements: dict, out, *, provenance: dict | None = None,
                faces_only: bool = False, refused: dict | None = None) -> list[dict]:
    """Write ``source`` to STEP with the surfaces of some faces replaced.

    Parameters
    ----------
    source : str or path-like
        The original STEP/IGES/BREP model.
    replacements : dict int -> ControlNet
        0-based face index (as ``ControlNet.origin.face`` of :func:`cadartifact.exchange.read`)
        -> a non-rational B-spline net over the same parameter range as that face's surface.
    out : str or path-like
        A ``.step``/``.stp`` file in an existing folder (checked before anything is read).
    provenance : dict str -> str or float, optional
        Written as ``key=value`` lines of the header's FILE_DESCRIPTION (e.g. tool, version,
        tolerance, intent); ``"authorization"`` goes to FILE_NAME's authorisation field.
    faces_only : bool
        Write only the replacement nets, one untrimmed face each
        (:func:`cadartifact.exchange.step.write_step`), instead of the whole model.
    refused : dict, optional
        Given (an empty dict to fill): a replacement the per-face checks refuse (a cage or rational
        net, a face without a surface, a net that does not cover the face's trimmed region) is not
        raised but recorded here as ``face index -> reason`` and that face is kept as it is; the
        other faces are written. If every replacement is refused, nothing is written (``[]``).

    Returns
    -------
    list of dict
        One per replaced face, in face order: ``{"face": int, "name": str | None,
        "max_distance": float, "mean_distance": float, "edge_tolerance": float, "valid": bool,
        "model_valid": bool}``.
        The distances are ``|S_old(u, v) - S_new(u, v)|`` on a 41 x 41 lattice of the face's
        trimmed uv box (model units, mm for STEP); ``edge_tolerance`` is the largest tolerance
        of the face's edges after the fix; ``valid`` is BRepCheck's verdict on the written face
        (on the new face alone when ``faces_only``), ``model_valid`` on the whole written shape.

    Raises
    ------
    OptionError
        ``out`` not .step/.stp or not in an existing folder; a face index the model has not;
        a net that is a cage, rational, or over another parameter range (unless ``refused`` is given);
        an OBJ source.
    InputError
        The source cannot be read, or the file cannot be written (nothing is left behind).
    """
    out = check_step_output(out)
    source = check_file(source)
    provenance = dict(provenance or {})
    asked = dict(replacements)
    refusals = {}

    def refuse(index, exc: OptionError) -> None:
        if refused is None:
            raise exc
        refusals[index] = f"expected {exc.expected}, received {exc.received}"

    for index, net in asked.items():
        if not isinstance(net, ControlNet) or not net.is_bspline:
            refuse(index, OptionError(f"replacements[{index}]", "a B-spline ControlNet (degrees and knots)",
                                      type(net).__name__))
        elif net.rational:
            refuse(index, OptionError(f"replacements[{index}]", "a non-rational net", "a net with weights"))
    shape, face_name, unit, products, uncertainty = _read_source(source)
    faces = list(iter_faces(shape))
    missing = sorted(set(asked) - set(range(len(faces))))
    if missing:
        raise OptionError("replacements", f"face indices of {source.name} (0..{len(faces) - 1})", missing[0])
    old = {}
    for index in sorted(set(asked) - set(refusals)):
        face = faces[index][1]
        kind, basis = surface_kind(BRep_Tool.Surface_s(face))
        try:
            if basis is None:
                raise OptionError(f"replacements[{index}]", "a face with a surface", "a face without one")
            _check_range(index, basis, asked[index], face)
        except OptionError as exc:
            refuse(index, exc)
            continue
        old[index] = (face, basis)
    if refused is not None:
        refused.update(sorted(refusals.items()))
    replacements = {index: asked[index] for index in old}
    if asked and not replacements:  # every replacement refused: the model would be today's, write nothing
        return []
    if faces_only:
        return _write_faces_only(source, replacements, old, out, provenance, unit, uncertainty)

    reshape = ShapeBuild_ReShape()
    new_surfaces = {}
    to_fix = []
    for index in sorted(replacements):
        face, _ = old[index]
        surface = occ_surface(replacements[index])
        new_surfaces[index] = surface
        with quiet_occt():
            new_face, edges = _replace_surface(face, surface)
        to_fix.append(edges)
        reshape.Replace(face, new_face)
    with quiet_occt():
        result = reshape.Apply(shape)
        fix = ShapeFix_Edge()
        for edges in to_fix:
            for edge in edges:
                fix.FixSameParameter(edge)
        BRepLib.UpdateTolerances_s(result, False)
        # ShapeFix_Face only on a replaced face BRepCheck rejects: the rest of the model stays as it was read
        context = ShapeBuild_ReShape()
        refixed = False
        for index, face in iter_faces(result):
            if index in replacements and not BRepCheck_Analyzer(face).IsValid():
                fixer = ShapeFix_Face(face)
                fixer.SetContext(context)
                fixer.Perform()
                refixed = True
        if refixed:
            result = context.Apply(result)
        model_valid = bool(BRepCheck_Analyzer(result).IsValid())
    new_faces = list(iter_faces(result))
    if len(new_faces) != len(faces):  # ShapeFix must not split or merge faces: refuse rather than renumber
        raise InputError(out, f"fixing the model changed its face count ({len(faces)} -> {len(new_faces)}); "
                         "nothing written")
    names = []
    if face_name is not None:
        for (_, before), (_, after) in zip(faces, new_faces):
            name = face_name(before)
            if name:
                names.append((after, name))
    _write(result, out, unit=unit, uncertainty=uncertainty, names=names, products=products, source=source,
           provenance=provenance)
    records = []
    for index in sorted(replacements):
        face, basis = old[index]
        written = new_faces[index][1]
        dmax, dmean = _distance(face, basis, new_surfaces[index])
        edges = TopTools_IndexedMapOfShape()
        TopExp.MapShapes_s(written, TopAbs_EDGE, edges)
        tol = max((BRep_Tool.Tolerance_s(TopoDS.Edge_s(edges.FindKey(i))) for i in range(1, edges.Extent() + 1)),
                  default=0.0)
        records.append({"face": index, "name": face_name(face) if face_name else None, "max_distance": dmax,
                        "mean_distance": dmean, "edge_tolerance": float(tol),
                        "valid": bool(BRepCheck_Analyzer(written).IsValid()), "model_valid": model_valid})
    return records


def _write_faces_only(source: Path, replacements: dict, old: dict, out: Path, provenance: dict, unit: str,
                      uncertainty) -> list[dict]:
    """Today's output: the replacement nets alone, one untrimmed face each, in the source's unit and uncertainty."""
    from .occ import make_face
    from .step import write_step

    nets = [replacements[i] for i in sorted(replacements)]
    write_step(nets, out, provenance={"source": source.name, **provenance}, unit=unit, uncertainty=uncertainty)
    records = []
    for index in sorted(replacements):
        face, basis = old[index]
        net = replacements[index]
        dmax, dmean = _distance(face, basis, occ_surface(net))
        records.append({"face": index, "name": net.origin.name, "max_distance": dmax, "mean_distance": dmean,
                        "edge_tolerance": None,
                        "valid": bool(BRepCheck_Analyzer(make_face(net)).IsValid()), "model_valid": None})
    return records
