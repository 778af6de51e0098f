"""Write a whole B-rep model back to STEP with some faces' surfaces replaced by new nets.

The model is read with OCCT, its faces are walked in the order :func:`cadartifact.exchange.read`
numbers them (``TopExp_Explorer`` over the whole shape), and each replaced face gets a new TFace
on the new ``Geom_BSplineSurface`` that keeps the face's own wires, on a copy of the model. The
edges stay shared with the neighbouring faces; each edge's pcurve on the new surface is rebuilt by
projecting its 3-D curve (:mod:`.written_faces`: the old pcurves address other points where the new
surface is parametrised otherwise), and ``ShapeFix_Edge.FixSameParameter`` then sets the edge
tolerance to the gap between the edge's 3-D curve and the new surface.

What is written is what was measured (SPEC §5): each replaced face, as it stands in the fixed model,
is measured against the old face by projection both ways with the trims respected
(:mod:`.face_distance`), with its edge tolerances and BRepCheck before and after. A face beyond its
allowed distance (t + the old face's ripple + its edges' tolerance), with an edge tolerance beyond
the input's + t, or that BRepCheck rejects where the input's passed, is kept as it was (with the reason and what it measured)
and the model is built again without it. Then the caller's ``edge_check`` (the gate's continuity rules between
faces, passed down from :mod:`cadartifact.runs.advising`: this layer imports no analysis) names the replaced faces
that make an edge's verdict worse than the input's; those are kept too, until it names none. Rational nets are
written with their weights. Untouched faces, face order, face and product names and the file's length unit and
distance uncertainty are kept; the header carries the provenance. The written file is read back and each face's
kind of surface compared with what it was given (OCCT's STEP writer turns a degenerate torus into a surface of
revolution).
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

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepCheck import BRepCheck_Analyzer  # noqa: E402
from OCP.BRepLib import BRepLib  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
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
from OCP.TopTools import TopTools_IndexedMapOfShape  # noqa: E402

from .occ import iter_faces, occ_surface, quiet_occt, surface_kind  # noqa: E402
from .step import set_header, write_settings  # noqa: E402
from .written_faces import free_edges, measure, refusal, replace_surface  # noqa: E402

__all__ = ["write_model", "STEP_SUFFIXES", "check_step_output"]

#: Output suffixes write_model accepts (any case).
STEP_SUFFIXES = (".step", ".stp")

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
                faces_only: bool = False, refused: dict | None = None, allowed: dict | None = None,
                tolerance: float | None = None, measurements: dict | None = None, edge_check=None,
                types: dict | None = None) -> list[dict]:
    """Write ``source`` to STEP with the surfaces of some faces replaced.

    Parameters
    ----------
    source : str or path-like
        The original STEP/IGES/BREP model.
    replacements : dict int -> ControlNet
        0-based face index (as ``ControlNet.origin.face`` of :func:`cadartifact.exchange.read`)
        -> a B-spline net (rational or not: its weights are written per pole) over the same parameter
        range as that face's surface.
    out : str or path-like
        A ``.step``/``.stp`` file in an existing folder (checked before anything is read).
    provenance : dict str -> str or float, optional
        Written as ``key=value`` lines of the header's FILE_DESCRIPTION (e.g. tool, version,
        tolerance, intent); ``"authorization"`` goes to FILE_NAME's authorisation field.
    faces_only : bool
        Write only the replacement nets, one untrimmed face each
        (:func:`cadartifact.exchange.step.write_step`), instead of the whole model.
    refused : dict, optional
        Given (an empty dict to fill): a replacement the per-face checks refuse (a cage, a face without a surface, a net that does not cover the face's trimmed region) is not
        raised but recorded here as ``face index -> reason`` and that face is kept as it is; the
        other faces are written. If every replacement is refused, nothing is written (``[]``).
        The same for a face the written model measures unfaithful (below).
    allowed : dict int -> float, optional
        Per face, the largest distance the written face may lie from the old one (``t`` + the old
        face's ripple, model units), to which the old face's largest edge tolerance is added (its
        border is known only to within it); a face beyond that is refused (kept). Absent: not checked.
    tolerance : float, optional
        ``t``: a written face whose largest edge tolerance exceeds the input's + ``t`` is refused.
        None: not checked. A face BRepCheck rejects where the input's passed is always refused.
    measurements : dict, optional
        Given (an empty dict to fill): face index -> the figures (as in the records) of a
        replacement refused on measured grounds, with ``allowed_distance`` (and ``edges``: the
        edges it made worse, when refused by ``edge_check``).
    edge_check : callable, optional
        ``edge_check(source shape, written shape, {face index: measured figures}) -> {face index:
        (reason, [edge records])}``: the replaced faces that make the continuity between faces worse
        than in the input (the layer above passes the gate's edge rules here; this layer measures
        no continuity itself). Run once the other checks pass; a face it names is refused (kept) and
        the model is built again without it, until it names none. None: not checked.
    types : dict, optional
        Given (an empty dict to fill): face index -> (surface kind in the input, kind read back from the
        written file) of every face OCCT's STEP writer turned into another kind of surface than the one
        it was given (a replaced face: a B-spline; another face: its input's own; e.g. a degenerate torus
        written as a surface of revolution).

    Returns
    -------
    list of dict
        One per replaced face, in face order: ``{"face": int, "name": str | None,
        "distance_to_old", "distance_from_old", "max_distance", "mean_distance",
        "allowed_distance", "edge_tolerance_before", "edge_tolerance", "valid_before", "valid",
        "pcurves", "model_valid", "surface_type", "surface_type_written"}`` (:func:`cadartifact.exchange.written_faces.measure`): the written face
        against the old one by projection both ways, trims respected (model units, mm for STEP),
        its edges' largest tolerance and BRepCheck's verdict on the face in the input and as
        written, ``model_valid`` on the whole written shape; ``pcurves``: ``"projected"`` (the edges'
        3-D curves projected onto the new surface) or ``"kept"`` (the old pcurves, tried when the
        projected face measured unfaithful); ``surface_type`` / ``surface_type_written``: the input face's
        surface kind and the written face's as the file reads back (None: not compared). ``faces_only``: the untrimmed new
        face against the old one; no edge figures, ``model_valid`` None.

    Raises
    ------
    OptionError
        ``out`` not .step/.stp or not in an existing folder; a face index the model has not;
        a net that is a cage or over another parameter range (unless ``refused`` is given);
        an OBJ source.
    InputError
        The source cannot be read, or the file cannot be written (nothing is left behind); a face
        measured unfaithful when ``refused`` is not given.
    """
    out = check_step_output(out)
    source = check_file(source)
    if os.path.realpath(out) == os.path.realpath(source) or (out.exists() and os.path.samefile(out, source)):
        raise InputError(out, f"is the source model {source}: writing would overwrite it (write to another file)")
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

    free = free_edges(shape)
    allowed = dict(allowed or {})
    kept_pcurves: set = set()  # faces tried again with their old pcurves
    first: dict = {}  # their projected attempt: (why it failed, what it measured)
    while True:  # replace, measure, keep the faces that fail (shared edges: the others are built again)
        result, model_valid, measured = _replace(shape, faces, replacements, free, out, kept_pcurves)
        limits = {index: _limit(allowed.get(index), measured[index]) for index in replacements}
        failed = {index: why for index in replacements
                  if (why := refusal(measured[index], limits[index], tolerance)) is not None}
        if not failed and edge_check is not None:  # the edges the replaced faces share, judged as the gate does
            for index, (why, edges) in edge_check(shape, result, measured).items():
                failed[index] = why
                measured[index] = dict(measured[index], edges=edges)
        if not failed:
            break
        retry = set(failed) - kept_pcurves
        if retry:  # the projected pcurves failed: once more with the old ones, before a face is kept
            kept_pcurves |= retry
            first.update({index: (failed[index], measured[index]) for index in retry})
            continue
        # a face that fails on its own (its distance, BRepCheck) goes first: an edge tolerance may be its
        # neighbour's doing (a shared edge), so a face failing on that alone is built again without them
        own = {index for index in failed if not _edges_only(measured[index], limits[index])}
        for index, why in failed.items():
            if own and index not in own:
                continue
            projected, best = first.get(index, (None, measured[index]))
            if projected is not None and projected != why:
                why = f"with its edges projected onto it: {projected}; with its old pcurves: {why}"
                if measured[index]["max_distance"] + measured[index]["edge_tolerance"] < \
                        best["max_distance"] + best["edge_tolerance"]:
                    best = measured[index]
            measured[index] = best
            if refused is None:
                raise InputError(out, f"face {index}: the advised net cannot be written faithfully: {why}")
            refusals[index] = why
            if measurements is not None:
                measurements[index] = dict(measured[index], allowed_distance=_limit(allowed.get(index),
                                                                                    measured[index]))
            del replacements[index]
        if refused is not None:
            refused.update(sorted(refusals.items()))
        if not replacements:
            return []
        kept_pcurves, first = set(), {}  # the others are tried afresh without the faces kept
    new_faces = list(iter_faces(result))
    names = []
    if face_name is not None:
        for (_, before), (_, after) in zip(faces, new_faces):
            name = face_name(before)
            if name:
                names.append((after, name))
    _write(result, out, unit=unit, uncertainty=uncertainty, names=names, products=products, source=source,
           provenance=provenance)
    before = [surface_kind(BRep_Tool.Surface_s(face))[0] for _, face in faces]
    after = _kinds_read_back(out, len(faces))
    expected = ["bspline" if i in replacements else kind for i, kind in enumerate(before)]  # what it was given
    if types is not None and after is not None:
        types.update({i: (before[i], after[i]) for i in range(len(faces)) if after[i] != expected[i]})
    return [{"face": index, "name": face_name(faces[index][1]) if face_name else None, **measured[index],
             "allowed_distance": _limit(allowed.get(index), measured[index]),
             "pcurves": "kept" if index in kept_pcurves else "projected", "model_valid": model_valid,
             "surface_type": before[index], "surface_type_written": None if after is None else after[index]}
            for index in sorted(replacements)]


def _kinds_read_back(out: Path, count: int) -> list | None:
    """The surface kind of each face of the written file as OCCT reads it back (None when the face count differs:
    no face-by-face comparison)."""
    shape = _read_source(out)[0]
    kinds = [surface_kind(BRep_Tool.Surface_s(face))[0] for _, face in iter_faces(shape)]
    return kinds if len(kinds) == count else None


def _edges_only(record, limit) -> bool:
    """Whether a face's only failing figure is its edge tolerance (it lies within ``limit`` and BRepCheck passes
    it as it passed the input)."""
    return (limit is None or record["max_distance"] <= limit) and (record["valid"] or not record["valid_before"])


def _limit(allowed, record):
    """The distance a written face may lie from the old one: ``allowed`` (t + its ripple) plus the old face's
    largest edge tolerance (its border is known only to within it: the new trim follows the edges' 3-D curves,
    the old face's border its pcurves). None when ``allowed`` is."""
    return None if allowed is None else float(allowed) + record["edge_tolerance_before"]


def _replace(shape, faces: list, replacements: dict, free, out: Path, kept_pcurves=frozenset()):
    """``(result, model valid, {face index: measure(...)})``: a copy of ``shape`` with the replaced faces on their
    new surfaces, their edges' pcurves rebuilt (kept on the faces of ``kept_pcurves``) and tolerances set
    (``ShapeFix_Edge.FixSameParameter``)."""
    with quiet_occt():
        copier = BRepBuilderAPI_Copy(shape, True, False)  # the edges are updated in place: never the source's
        model = copier.Shape()
        copied = list(iter_faces(model))
        free_copy = TopTools_IndexedMapOfShape()
        for i in range(1, free.Extent() + 1):
            free_copy.Add(copier.Modified(free.FindKey(i)).First())
        reshape = ShapeBuild_ReShape()
        to_fix = []
        for index in sorted(replacements):
            new_face, edges = replace_surface(copied[index][1], occ_surface(replacements[index]), free_copy,
                                              project=index not in kept_pcurves)
            to_fix.extend(edges)
            reshape.Replace(copied[index][1], new_face)
        result = reshape.Apply(model)
        fix = ShapeFix_Edge()
        for edge in to_fix:
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
        measured = {index: measure(faces[index][1], new_faces[index][1]) for index in replacements}
    return result, model_valid, measured


def _write_faces_only(source: Path, replacements: dict, old: dict, out: Path, provenance: dict, unit: str,
                      uncertainty) -> list[dict]:
    """Today's output: the replacement nets alone, one untrimmed face each, in the source's unit and uncertainty."""
    from .occ import make_face
    from .step import write_step

    nets = [replacements[i] for i in sorted(replacements)]
    write_step(nets, out, provenance={"source": source.name, **provenance}, unit=unit, uncertainty=uncertainty)
    records = []
    for index in sorted(replacements):
        face, _ = old[index]
        net = replacements[index]
        with quiet_occt():
            record = measure(face, make_face(net))
        records.append({"face": index, "name": net.origin.name, **record, "edge_tolerance": None,
                        "edge_tolerance_before": None, "allowed_distance": None, "pcurves": None,
                        "model_valid": None})
    return records
