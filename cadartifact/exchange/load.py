"""Control nets from CAD and mesh files: STEP, IGES, BREP (via OCCT) and OBJ cages.

Format code converts to and from :class:`~cadartifact.net.ControlNet` and does no
analysis. Importing this module loads numpy only; OCP is imported the first time
a STEP/IGES/BREP file or shape is handled.

>>> from cadartifact.exchange import read
>>> result = read("samples/wavy_panel_diagonal.step")            # doctest: +SKIP
>>> result.nets[0].shape, result.skipped                          # doctest: +SKIP
((12, 12), {})

Bad or degenerate nets
----------------------
A face whose poles are not finite or all coincide is skipped with a warning
(counted as ``"degenerate"`` in ``skipped``); a file with no analysable face is
a warning, not an error. Files that cannot be read raise
:class:`~cadartifact.errors.InputError` subclasses with a ``"PATH: problem"`` message.

Corrupt files
-------------
STEP text is pre-scanned for numbers no real model holds (:mod:`.step_scan`) before OCCT sees
it; faces the STEP/IGES transfer dropped are counted as ``skipped["dropped"]`` with one warning
each naming the entity and OCCT's check message; and OCCT's readers run in a child process
(:mod:`cadartifact.execution.child`), so a reader that crashes or hangs raises ``FileFormatError`` for that file.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import OptionError
from ..net import ControlNet
from .messages import LoadWarning, warn
from . import formats
from .files import SUPPORTED_EXTENSIONS, LoadResult
from .quadmesh import Chart, QuadMesh

__all__ = [
    "LoadResult",
    "LoadWarning",
    "QuadMesh",
    "Chart",
    "SUPPORTED_EXTENSIONS",
    "read",
    "load",
    "from_shape",
    "write_step",
    "write_model",
    "occ_surface",
    "evaluate_grid",
]

def read(path: str | os.PathLike, *, convert: bool = False, timeout: float | None = None,
         idle: tuple = ()) -> LoadResult:
    """Read every control net in a file.

    Parameters
    ----------
    path : str or path-like
        ``.step/.stp``, ``.iges/.igs``, ``.brep/.brp`` or ``.obj`` (any case): the formats of
        :data:`cadartifact.exchange.formats.FORMATS`.
    convert : bool
        Convert revolution/extrusion/offset and other non-analytic freeform faces to
        B-splines with OCCT (kind ``"converted"``) instead of skipping them.
    timeout : float, optional
        Seconds OCCT's reader may take on a STEP/IGES/BREP file (default: the reader child's configured
        ``read_timeout``, 120 unless the run says otherwise: :func:`cadartifact.execution.child.configured`).
    idle : tuple of str, optional
        Modules the reader child imports while idle after the read (the work the caller will send it next).

    Returns
    -------
    LoadResult
        Faces the STEP transfer dropped are counted as ``skipped["dropped"]``, one warning each
        naming the entity and OCCT's check message (the gate fails such a file). B-rep nets carry
        ``canonical``/``exact`` when the face is exactly a canonical surface or exactly straight or
        circular along a direction (:mod:`cadartifact.exchange.canonical`).

    Raises
    ------
    UnsupportedFormatError
        Unknown extension (the message lists the supported ones).
    InputError, FileFormatError
        Missing, empty, truncated or malformed file; impossible numbers in a STEP file (see
        :mod:`cadartifact.exchange.step_scan`); non-manifold OBJ; OBJ without quads; the
        reader crashed or gave no answer in time.
    """
    path = Path(path)
    record = formats.format_of(path)
    if not record.brep:  # read in this process
        return record.read(path)
    fmt = record.name
    from ..execution import child
    from .reader_start import PRELOAD, read_request
    from .files import check_file

    check_file(path)
    child.read_timeout(timeout)  # a bad timeout is a usage error before any work
    if child.enabled() and fmt == "step":
        # the text checks run here while the child reads (two cores, one file); their record heads map the
        # model's entity numbers to the file's ids
        heads: list = []

        def scan():
            heads.extend(_prescan(path))

        result = child.call(*read_request(path, fmt, convert), path=path, what="STEP", timeout=timeout,
                            during=scan, idle=idle, preload=PRELOAD)
        _file_ids(result, heads)
    elif child.enabled() and fmt == "iges":
        from .iges_refs import check_iges_text, faces_missing

        declared: list = []
        result = child.call(*read_request(path, fmt, convert), path=path, what="IGES", timeout=timeout,
                            during=lambda: declared.append(check_iges_text(path)), idle=idle, preload=PRELOAD)
        result = faces_missing(path, result, declared[0])
    elif child.enabled():
        result = child.call(*read_request(path, fmt, convert), path=path, what=record.label, timeout=timeout,
                            idle=idle, preload=PRELOAD)
    else:
        result = read_occt(path, fmt, convert)
    for message in result.warnings:
        warn(message)
    return result


def _prescan(path: Path) -> list[tuple[str, str]]:
    """The STEP text's checks: impossible numbers (:func:`~cadartifact.exchange.step_scan.check_step_text`), then
    broken references (:func:`~cadartifact.exchange.step_refs.check_references`), on one cleaned copy of the
    text (:func:`~cadartifact.exchange.step_scan.clean_data`). Returns the record heads ``[(id, KEYWORD)]``."""
    from .step_refs import check_references
    from .step_scan import check_step_text, clean_data, data_section, record_heads
    from .step_text import remember_face_lines

    with open(path, "rb") as fh:
        text = fh.read().decode("latin-1")
    data = data_section(text)
    clean = clean_data(data)
    heads = record_heads(clean)
    arities: dict = {}  # the B-spline surfaces' parameter counts: parsed once, by the number scan
    check_step_text(path, text, heads, clean, arities)
    check_references(path, text, heads, clean, arities)
    remember_face_lines(path, text, data, clean)  # the faces' lines for reports, without a second full pass
    return heads


def _file_ids(result: LoadResult, heads) -> None:
    """Turn the model entity numbers a ``prescanned`` read left in ``origin.entity`` into the file's ids (OCCT
    numbers a model's entities in file order; None when the record there is not an ``ADVANCED_FACE``)."""
    from dataclasses import replace

    for net in result.nets:
        number = net.origin.entity
        ident = None
        if number is not None and 0 < number <= len(heads) and heads[number - 1][1].upper() == "ADVANCED_FACE":
            ident = int(heads[number - 1][0])
        origin = replace(net.origin, entity=ident)
        object.__setattr__(net, "origin", origin)  # just unpickled, not shared: no need to validate the net again


def read_occt(path: Path, fmt: str, convert: bool = False, prescanned: bool = False) -> LoadResult:
    """Read a STEP/IGES/BREP file in this process, without issuing warnings (the reader child's job).

    STEP text is pre-scanned for impossible numbers first (:func:`~cadartifact.exchange.step_scan.check_step_text`).
    ``prescanned``: the caller scans the text itself (while this runs in the reader child), so the scan is
    skipped here and each net's ``origin.entity`` is left as the face's model entity number, for the
    caller to map to the file's id (:func:`_file_ids`).
    """
    from .files import check_file

    path = check_file(path)
    dropped: list[str] = []
    beyond: list[str] = []  # STEP: faces OCCT made that no face record gives (said, kept)
    ids = None
    if fmt == "step" and not prescanned:
        ids = ["#" + i for i, _ in _prescan(path)]
    from . import occ, step

    if fmt == "step":
        shape, face_name, dropped, beyond = step.read_step_audited(path, ids, model_numbers=prescanned)
    elif fmt == "iges":
        if not prescanned:
            from .iges_refs import check_iges_text

            declared = check_iges_text(path)
        shape, face_name, dropped = step.read_iges_audited(path)
    else:
        shape, face_name = step.read_brep(path)
    if shape is None:  # every face dropped
        nets, total, skipped, messages = [], 0, {}, []
    else:
        nets, total, skipped, messages = occ.nets_from_shape(shape, file=str(path), convert=convert,
                                                             face_name=face_name)
    if dropped:
        skipped["dropped"] = len(dropped)
        total += len(dropped)
        messages.extend(f"{path}: {m}" for m in dropped)
    messages.extend(f"{path}: {m}" for m in beyond)
    if not nets:
        kinds = ", ".join(f"{k} {n}" for k, n in sorted(skipped.items())) or "none"
        hint = "" if convert or dropped else "; try convert=True (--convert) for revolution/extrusion/offset faces"
        messages.append(f"{path}: no analysable face among {total} faces (skipped: {kinds}){hint}")
    result = LoadResult(path=path, nets=nets, faces_total=total, skipped=skipped, warnings=messages)
    if fmt == "iges" and not prescanned:
        from .iges_refs import faces_missing

        result = faces_missing(path, result, declared)
    return result


def load(path: str | os.PathLike, *, convert: bool = False) -> list[ControlNet]:
    """The control nets of a file: ``read(path, convert=convert).nets``."""
    return read(path, convert=convert).nets


def _shapes_of(obj) -> list:
    """The OCP shapes of a Workplane / cq Shape / TopoDS_Shape / sequence of those."""
    if isinstance(obj, (list, tuple)):
        return [s for item in obj for s in _shapes_of(item)]
    if hasattr(obj, "vals") and hasattr(obj, "objects"):  # cadquery Workplane
        return [s for item in obj.vals() if hasattr(item, "wrapped") for s in _shapes_of(item)]
    wrapped = getattr(obj, "wrapped", obj)  # cadquery Shape
    from OCP.TopoDS import TopoDS_Shape

    if isinstance(wrapped, TopoDS_Shape):
        return [] if wrapped.IsNull() else [wrapped]
    return []


def from_shape(obj, *, convert: bool = False, name: str | None = None) -> list[ControlNet]:
    """Control nets of an in-memory shape, without a file round trip.

    Parameters
    ----------
    obj : cadquery.Workplane, cadquery.Shape, OCP TopoDS_Shape, or a list of these
        A Workplane contributes the faces of all its objects (``Workplane.vals()``).
    convert : bool
        As in :func:`read`.
    name : str, optional
        Label stored in each net's ``origin.file`` (reports show ``name#face``); faces of
        in-memory shapes carry no names.

    Returns
    -------
    list of ControlNet
        Face indices count every face in ``TopExp_Explorer`` order over the compound of
        the given shapes. A shape with no analysable face gives ``[]`` and a warning.

    Raises
    ------
    OptionError
        ``obj`` holds no shape.
    """
    from ..dependencies import require

    require("OCP", "reading CadQuery/OCP shapes")
    shapes = _shapes_of(obj)
    if not shapes:
        raise OptionError("obj", "a cadquery Workplane or Shape, or an OCP TopoDS_Shape, holding a shape",
                          type(obj).__name__)
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound

    from . import occ

    if len(shapes) == 1:
        shape = shapes[0]
    else:
        builder = BRep_Builder()
        shape = TopoDS_Compound()
        builder.MakeCompound(shape)
        for s in shapes:
            builder.Add(shape, s)
    nets, total, skipped, messages = occ.nets_from_shape(shape, file=name, convert=convert)
    if not nets:
        kinds = ", ".join(f"{k} {n}" for k, n in sorted(skipped.items())) or "none"
        messages.append(f"{name or '<shape>'}: no analysable face among {total} faces (skipped: {kinds})")
    for message in messages:
        warn(message)
    return nets


def write_step(nets, path: str | os.PathLike) -> Path:
    """Write B-spline nets to STEP, one face each (see :func:`cadartifact.exchange.step.write_step`)."""
    from .step import write_step as _write

    return _write(nets, path)


def write_model(source, replacements, out, *, provenance=None, faces_only: bool = False) -> list:
    """The whole model of ``source`` written to STEP with some faces' surfaces replaced.

    See :func:`cadartifact.exchange.model_writer.write_model`.
    """
    from .model_writer import write_model as _write

    return _write(source, replacements, out, provenance=provenance, faces_only=faces_only)


def occ_surface(net: ControlNet):
    """The exact OCCT ``Geom_BSplineSurface`` of a net (see :func:`cadartifact.exchange.occ.occ_surface`)."""
    from .occ import occ_surface as _surface

    return _surface(net)


#: The function the reader child runs to evaluate (``module:function``; fault-injection tests replace it).
EVALUATE = "cadartifact.exchange.occ:evaluate_grid"


def evaluate_grid(net: ControlNet, u, v):
    """OCCT's evaluation of the net's surface on the outer grid ``u x v``: ``(len(u), len(v), 3)``.

    See :func:`cadartifact.exchange.occ.evaluate_grid`. OCCT evaluates in the reader child
    (:mod:`cadartifact.execution.child`, same function, same numbers), like its reads: a crash or a hang there (a
    surface OCCT cannot evaluate) raises :class:`~cadartifact.execution.child.ChildFailed` naming the
    file and the face, which costs that face an error entry and not the run (the gate's peak locations,
    the advice's verification). The child is the warm one of the read (a pipe round trip), or a new one.
    In the child itself, or with isolation off (the run's settings), OCCT evaluates in this process.
    """
    from ..execution import child
    from .reader_start import PRELOAD

    if child.enabled() and not child.serving():
        import numpy as np

        args = (net, np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        face = net.origin.face
        actor = "OCCT's evaluation of " + (f"face {face}" if face is not None else "the surface")
        return child.call(EVALUATE, args, path=net.origin.file or "<net>", what="OCCT", actor=actor, preload=PRELOAD)
    from .occ import evaluate_grid as _evaluate

    return _evaluate(net, u, v)
