"""Read STEP, IGES and BREP files into OCCT shapes, and write nets to STEP.

Every reader checks the file first (exists, is a file, not empty), silences
OCCT's console printers, and turns a failed read or an empty transfer into a
one-line :class:`~cadartifact.errors.FileFormatError` naming the file.
"""

from __future__ import annotations

import contextlib
import math
import os
import tempfile
from pathlib import Path

from ..dependencies import require
from ..errors import FileFormatError, InputError, OptionError
from ..net import ControlNet
from .files import check_file
from .occ import make_face, quiet_occt

require("OCP", "reading and writing STEP/IGES/BREP files")

from OCP.BRep import BRep_Builder  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.IFSelect import IFSelect_RetDone  # noqa: E402
from OCP.IGESControl import IGESControl_Reader  # noqa: E402
from OCP.Interface import Interface_Static  # noqa: E402
from OCP.Standard import Standard_Failure  # noqa: E402
from OCP.StepBasic import StepBasic_Product  # noqa: E402
from OCP.STEPConstruct import STEPConstruct  # noqa: E402
from OCP.StepShape import StepShape_FaceSurface  # noqa: E402
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer  # noqa: E402
from OCP.TCollection import TCollection_HAsciiString  # noqa: E402
from OCP.TopoDS import TopoDS_Compound, TopoDS_Shape, TopoDS_Shell  # noqa: E402

__all__ = ["check_file", "open_step", "read_step", "read_step_audited", "set_header", "read_iges",
           "read_iges_audited", "read_brep", "write_step", "write_settings", "DEFAULT_UNCERTAINTY"]

#: The distance uncertainty written when none is given: OCCT's confusion distance, 1e-7 in its internal unit (mm).
DEFAULT_UNCERTAINTY = 1e-7


@contextlib.contextmanager
def occt_path(path: Path):
    """A file name OCCT can open: ``path`` itself, or a UTF-8 symlink to it in a temporary folder.

    OCP passes names to OCCT as UTF-8 strings; a name that is not valid UTF-8 (Linux allows any bytes,
    Python keeps them as surrogates) cannot cross, so OCCT reads it through a link with a plain name.
    """
    name = str(path)
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        pass
    else:
        yield name
        return
    with tempfile.TemporaryDirectory(prefix="cadartifact-") as tmp:
        link = os.path.join(tmp, "input" + "".join(path.suffixes[-1:]).encode("ascii", "replace").decode())
        try:
            os.symlink(os.path.abspath(os.fsencode(path)), os.fsencode(link))
        except OSError as exc:
            raise InputError(path, f"file name is not valid UTF-8 and cannot be linked ({exc.strerror})") from None
        yield link


def _checks(check_list) -> dict[int, list[str]]:
    """OCCT check messages (fails first, then warnings) by model entity number."""
    out: dict[int, list[str]] = {}
    check_list.Start()
    while check_list.More():
        check = check_list.Value()
        msgs = [check.CFail(j) for j in range(1, check.NbFails() + 1)]
        msgs += [check.CWarning(j) for j in range(1, check.NbWarnings() + 1)]
        msgs = [" ".join(str(m).split()) for m in msgs if str(m).strip()]
        if msgs:
            out.setdefault(int(check_list.Number()), []).extend(msgs)
        check_list.Next()
    return out


def _model_entities(reader: STEPControl_Reader) -> list:
    """The reader's model entities in model order (entity ``i`` is ``[i - 1]``): one pass over the
    model, which on big files costs a tenth of a second, shared by the face audit and the id lookup."""
    model = reader.WS().Model()
    return [model.Value(i) for i in range(1, model.NbEntities() + 1)]


def _shape_faces(shape: TopoDS_Shape) -> list:
    """The faces of ``shape`` as :class:`TopExp_Explorer` visits them (a face placed twice, twice)."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer

    faces = []
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        faces.append(explorer.Current())
        explorer.Next()
    return faces


def _face_records(entities: list) -> list[int]:
    """The model numbers of the face entities (``ADVANCED_FACE``, ``FACE_SURFACE``) among ``entities``."""
    return [i for i, e in enumerate(entities, start=1) if isinstance(e, StepShape_FaceSurface)]


def _numbers(entities: list) -> dict[int, int]:
    """``{id(entity): model number}``: OCP's ``model.Number(entity)`` answers 0, and pybind11 gives one wrapper per
    C++ object, so ids identify them."""
    return {id(e): i for i, e in enumerate(entities, start=1)}


def _records_of(transfer, faces, number: dict[int, int]) -> set:
    """The model numbers (``number``: :func:`_numbers`) of the entities ``faces`` were transferred from (OCCT's
    lookup scans every transferred entity per face: call it only where a count says something is wrong)."""
    got = set()
    for face in faces:
        entity = transfer.EntityFromShapeResult(face, 1)
        if entity is not None:
            got.add(number.get(id(entity)))
    return got


#: OCCT's warning on a face record it made no face of (``StepToTopoDS_TranslateShell``: the face is left out of
#: its shell, and the shell, the solid and the rest of the file transfer as if it were not there).
NO_FACE_MADE = "not mapped to TopoDS"


def _faces_not_made(transfer, declared: list[int]) -> list[int]:
    """The face records (model numbers, of ``declared``) on which the transfer's check list has OCCT's warning
    that no face was made of them (:data:`NO_FACE_MADE`). One pass over the check list (tens of entries on
    real files: 2 ms on NIST CTC-02's 487 faces)."""
    records = set(declared)
    checks = transfer.TransientProcess().CheckList(False)
    out = []
    checks.Start()
    while checks.More():
        number = int(checks.Number())
        if number in records:
            check = checks.Value()
            if any(NO_FACE_MADE in str(check.CWarning(j)) for j in range(1, check.NbWarnings() + 1)):
                out.append(number)
        checks.Next()
    return sorted(set(out))


def _dropped_faces(path: Path, reader: STEPControl_Reader, shape: TopoDS_Shape, ids=None,
                   entities=None, faces=None, records=None) -> list[str]:
    """One message per face entity (ADVANCED_FACE / FACE_SURFACE) of the file that is not in the transferred shape.

    Each names the entity (``#id``) and OCCT's own check messages on it and its surface (the
    transfer process's check list, then the model's syntax checks).
    """
    session = reader.WS()
    if entities is None:
        entities = _model_entities(reader)
    declared = _face_records(entities) if records is None else records
    if not declared:
        return []
    transfer = session.TransferReader()
    faces = _shape_faces(shape) if faces is None else faces
    number = None
    if len(faces) >= len(declared):
        # As many faces as the file declares. Mapping each face back to its entity costs a fifth of a second on
        # a 500-face file (OCCT's lookup scans every transferred entity per face) and fails for assemblies
        # whose parts are placed through CONTEXT_DEPENDENT_SHAPE_REPRESENTATION. But the count can hide a
        # lost face: loose surfaces beside a solid, or a face OCCT's repair split, make up for it. OCCT warns
        # on each face record it could not make a face of: those are read from the transfer's check list.
        dropped = _faces_not_made(transfer, declared)
    else:
        number = _numbers(entities)
        got = _records_of(transfer, faces, number)
        dropped = [i for i in declared if i not in got]
    if not dropped:
        return []
    number = number or _numbers(entities)
    checks = _checks(transfer.TransientProcess().CheckList(False))
    for k, msgs in _checks(session.ModelCheckList(False)).items():
        checks.setdefault(k, []).extend(msgs)
    if ids is None:
        from .step_scan import record_ids

        with open(path, "rb") as fh:
            ids = record_ids(fh.read().decode("latin-1"))
    label = (lambda i: ids[i - 1]) if len(ids) == len(entities) else (lambda i: f"model entity {i}")
    out = []
    for i in dropped:
        face = entities[i - 1]
        related = [i]
        geometry = face.FaceGeometry() if hasattr(face, "FaceGeometry") else None
        if geometry is not None and id(geometry) in number:
            related.append(number[id(geometry)])
        said = [f"{label(k)}: {m}" for k in related for m in checks.get(k, [])]
        why = "; ".join(said) if said else "no check message (face not reachable from a shape, or not translated)"
        kind = "ADVANCED_FACE" if face.DynamicType().Name() == "StepShape_AdvancedFace" else "FACE_SURFACE"
        out.append(f"face {label(i)} ({kind}) was dropped by OCCT's STEP transfer: {why[:300]}")
    return out


#: Distinct faces beyond which the face records that came out as no face of their own are not named (naming maps
#: each face back to its entity, and OCCT's lookup scans every transferred entity per face: 0.9 s at 4 000 faces).
NAME_SPLIT_FACES_UP_TO = 2000


def _faces_beyond_records(path: Path, reader: STEPControl_Reader, entities: list, faces: list,
                          records: list[int]) -> list[str]:
    """A message when OCCT's transferred shape has more distinct faces than the file has face records, or none.

    Faces are told apart by their geometry and topology, not their placement (an assembly that places a part
    twice transfers each face record twice, sharing one face: that is not counted). A file of no face record
    (loose surfaces in a geometric set) has nothing to compare. Faces beyond the records are either faces of
    other entities (loose surfaces beside a solid) or the pieces of a face OCCT's shape repair split, whose
    geometry is broken (a vertex moved, a corrupt control point of an edge curve: the fuzz campaign of seed 2732,
    one face record transferred as 2 or 3 faces, the gate's report silent). The faces are kept (they are what
    OCCT made of the file); the message names the face records that came out as no face of their own (up to
    :data:`NAME_SPLIT_FACES_UP_TO` faces), the split ones.
    """
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopTools import TopTools_IndexedMapOfShape

    if not records or len(faces) <= len(records):
        return []  # no record to compare with, or no more faces than records (the common case: no map built)
    distinct = TopTools_IndexedMapOfShape()
    unplaced = TopLoc_Location()
    for face in faces:
        distinct.Add(face.Located(unplaced))
    extra = distinct.Extent() - len(records)
    if extra <= 0:
        return []
    head = (f"OCCT's transferred shape has {distinct.Extent()} distinct faces, {extra} more than the file's "
            f"{len(records)} face records (ADVANCED_FACE, FACE_SURFACE)")
    if distinct.Extent() > NAME_SPLIT_FACES_UP_TO:
        return [f"{head}: faces of other entities, or faces OCCT's repair split (not named: more than "
                f"{NAME_SPLIT_FACES_UP_TO} faces); the faces analysed are OCCT's"]
    mapped = _records_of(reader.WS().TransferReader(), (distinct.FindKey(k) for k in range(1, distinct.Extent() + 1)),
                         _numbers(entities))
    from .step_scan import declared_faces

    with open(path, "rb") as fh:
        text = fh.read().decode("latin-1")
    # the k-th face entity of the model is the k-th face record of the text (file order), even where a broken
    # record elsewhere shifted OCCT's entity numbers
    ids = [f"#{i}" for i in declared_faces(text)]
    label = dict(zip(records, ids)) if len(ids) == len(records) else {i: f"model entity {i}" for i in records}
    lost = [label[i] for i in records if i not in mapped]
    if not lost:  # every record is a face of its own: the others come from other entities (loose surfaces)
        return [f"{head}: faces of other entities than face records (loose surfaces?); every face record is "
                "analysed as itself"]
    return [f"{head}: its repair split a face whose geometry is broken; face record{'s' if len(lost) > 1 else ''} "
            f"{', '.join(lost[:5])}{' ...' if len(lost) > 5 else ''} came out as no face of "
            f"{'their' if len(lost) > 1 else 'its'} own; the faces analysed are OCCT's, not the file's"]


def _step_name(reader: STEPControl_Reader, path=None, *, entities=None, model_numbers: bool = False):
    """A face -> name lookup through the STEP entity the face was transferred from.

    The returned callable also has ``.entity(face)``: the entity's ``#id`` in the file (None when
    unknown). OCCT numbers a model's entities in file order; :func:`step_text.entity_lines` gives the
    ids in that order, and an id is only reported when the file's record there is an ``ADVANCED_FACE``.
    With ``model_numbers``, ``.entity(face)`` is the face's model entity number instead (the caller maps
    it to the file's id with :func:`step_text.face_id_from_model`; the reader child does so, to leave the text
    scan to the parent, which scans while the child reads).
    """
    from .step_text import entity_lines, face_id_from_model

    session = reader.WS()  # the lookup needs the reader's session alive: keep references to both
    transfer = session.TransferReader()
    state = {}

    def face_name(face, _keep=(reader, session)) -> str | None:
        entity = transfer.EntityFromShapeResult(face, 1)
        if entity is None or not hasattr(entity, "Name"):
            return None
        name = entity.Name()
        text = name.ToCString() if name is not None else ""
        return text or None

    def face_entity(face, _keep=(reader, session)) -> int | None:
        if path is None and not model_numbers:
            return None
        if not state:
            # pybind hands out the same Python object for the same entity: index the model's faces by it
            every = entities if entities is not None else _model_entities(reader)
            state["faces"] = {value: i for i, value in enumerate(every, start=1)
                              if type(value).__name__ == "StepShape_AdvancedFace"}
            if not model_numbers:
                state["records"] = entity_lines(path)  # [(id, line, keyword)] in file order
        entity = transfer.EntityFromShapeResult(face, 1)
        i = state["faces"].get(entity) if entity is not None else None
        if model_numbers or i is None:
            return i
        return face_id_from_model(state["records"], i)

    face_name.entity = face_entity
    return face_name


#: This process's last STEP read kept (``read_step``), ``{(path, size, mtime_ns): reader}``, for a second look at the
#: same unchanged file: the quality gate measures a file's edges after its faces in the same reader child.
_LAST_READ: dict = {}


def open_step(path, *, reuse: bool = False, keep: bool = False) -> STEPControl_Reader:
    """A STEP reader that has read and transferred ``path`` (same checks and errors as :func:`read_step`).
    ``keep``: kept as this process's last read; ``reuse``: that reader if it read this very file, unchanged
    (same size and modification time); its caller must not change the shape."""
    path = check_file(path)
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if reuse and key in _LAST_READ:
        return _LAST_READ[key]
    reader = STEPControl_Reader()
    with quiet_occt(), occt_path(path) as name:
        status = reader.ReadFile(name)
        if status != IFSelect_RetDone:
            raise FileFormatError(path, "not a readable STEP file (OCCT's parser rejected it: "
                                  "truncated, corrupt or not STEP)")
        if reader.NbRootsForTransfer() == 0:
            raise FileFormatError(path, "STEP file has no shape to transfer")
        try:
            reader.TransferRoots()
        except Standard_Failure as exc:
            raise FileFormatError(path, f"STEP transfer failed: {exc}") from None
        if reader.NbShapes() == 0 or reader.OneShape().IsNull():
            raise FileFormatError(path, "STEP file has no shape to transfer")
    if keep:
        _LAST_READ.clear()
        _LAST_READ[key] = reader
    return reader


def read_step(path) -> tuple[TopoDS_Shape, object]:
    """Read a STEP file.

    Returns
    -------
    shape : TopoDS_Shape
        All roots (OCCT's ``OneShape``), in mm (OCCT's default unit conversion).
    face_name : callable(face) -> str or None
        The ``ADVANCED_FACE`` name of a face, None when empty.

    Raises
    ------
    InputError, FileFormatError
        Missing/empty file, a file OCCT's STEP parser rejects (status != RetDone:
        truncated, not STEP, binary), or a file without transferable shapes.
    """
    shape, face_name, _, _ = read_step_audited(path)
    return shape, face_name


def read_step_audited(path, ids=None, *, model_numbers: bool = False
                      ) -> tuple[TopoDS_Shape, object, list[str], list[str]]:
    """:func:`read_step`, plus one message per face of the file the transfer dropped (see :func:`_dropped_faces`)
    and the warnings of :func:`_faces_beyond_records` (faces OCCT made that no face record gives).

    ``ids``: the file's record ids in order (:func:`~cadartifact.exchange.step_scan.record_ids`), if known.
    ``model_numbers``: see :func:`_step_name`.
    """
    path = check_file(path)
    reader = open_step(path, keep=True)
    shape = reader.OneShape()
    with quiet_occt():
        entities = _model_entities(reader)
        faces, records = _shape_faces(shape), _face_records(entities)
        dropped = _dropped_faces(path, reader, shape, ids, entities, faces, records)
        return (shape, _step_name(reader, path, entities=entities, model_numbers=model_numbers), dropped,
                [] if dropped else _faces_beyond_records(path, reader, entities, faces, records))


def read_iges(path) -> tuple[TopoDS_Shape, None]:
    """Read an IGES file (no face names). Same errors as :func:`read_step`."""
    shape, face_name, dropped = read_iges_audited(path)
    if shape is None:
        raise FileFormatError(path, f"IGES file has no shape to transfer ({dropped[0][:200]})")
    return shape, face_name


def read_iges_audited(path) -> tuple[TopoDS_Shape | None, None, list[str]]:
    """:func:`read_iges`, plus one message per entity OCCT's transfer skipped ("... transfer failed :
    entity skipped", with its check messages and those of the entities it refers to).

    A file whose every face was skipped gives no shape (``None``) and the messages, not an error, so
    that the caller can report the dropped faces.
    """
    path = check_file(path)
    reader = IGESControl_Reader()
    with quiet_occt(), occt_path(path) as name:
        status = reader.ReadFile(name)
        if status != IFSelect_RetDone:
            raise FileFormatError(path, "not a readable IGES file (OCCT's parser rejected it: "
                                  "truncated, corrupt or not IGES)")
        try:
            reader.TransferRoots()
        except Standard_Failure as exc:
            raise FileFormatError(path, f"IGES transfer failed: {exc}") from None
        checks = _checks(reader.WS().TransferReader().TransientProcess().CheckList(False))
        skipped = [k for k, msgs in sorted(checks.items()) if any("entity skipped" in m for m in msgs)]
        others = [f"D{2 * k - 1}: {m}" for k, msgs in sorted(checks.items()) if k not in skipped for m in msgs]
        dropped = [f"IGES entity D{2 * k - 1} was dropped by OCCT's transfer: "
                   + "; ".join(checks[k] + others[:3])[:300] for k in skipped]
        if reader.NbShapes() == 0 or reader.OneShape().IsNull():
            if dropped:
                return None, None, dropped
            raise FileFormatError(path, "IGES file has no shape to transfer")
        return reader.OneShape(), None, dropped


def _check_brep_text(path: Path) -> None:
    """Reject truncated or foreign text before OCCT sees it (its BREP reader can loop forever on them).

    A BREP file written by OCCT ends with a ``TShapes N`` section of ``N`` records,
    each closed by a sub-shape list ending in ``*``, followed by the root reference
    ``+i l``.
    """
    try:
        text = path.read_text(encoding="ascii", errors="strict")
    except (UnicodeDecodeError, OSError):
        raise FileFormatError(path, "not a BREP file (binary or unreadable text)") from None
    if "CASCADE Topology" not in text[:200]:
        raise FileFormatError(path, "not a BREP file (no 'CASCADE Topology' header)")
    head, sep, tail = text.partition("\nTShapes ")
    lines = tail.split("\n")
    try:
        count = int(lines[0].split()[0])
    except (IndexError, ValueError):
        count = -1
    body = [line.strip() for line in lines[1:] if line.strip()]
    closed = sum(1 for line in body if line.endswith("*"))
    root = body[-1].split() if body else []
    root_ok = len(root) == 2 and root[0][:1] in "+-" and root[0][1:].isdigit() and root[1].isdigit()
    if not sep or count < 0 or closed != count or not root_ok:
        raise FileFormatError(path, "truncated or corrupt BREP file")


def read_brep(path) -> tuple[TopoDS_Shape, None]:
    """Read an OCCT native (text) BREP file (no face names). Same errors as :func:`read_step`."""
    path = check_file(path)
    _check_brep_text(path)
    shape = TopoDS_Shape()
    with quiet_occt(), occt_path(path) as name:
        try:
            ok = BRepTools.Read_s(shape, name, BRep_Builder())
        except Standard_Failure as exc:
            raise FileFormatError(path, f"not a readable BREP file: {exc}") from None
    if not ok or shape.IsNull():
        raise FileFormatError(path, "not a readable BREP file (truncated or corrupt)")
    return shape, None


@contextlib.contextmanager
def write_settings(unit: str = "MM", uncertainty: float | None = None):
    """OCCT's STEP write settings for one ``Transfer``: length unit and uncertainty; the session's restored after.

    Left alone, OCCT writes as ``UNCERTAINTY_MEASURE_WITH_UNIT`` 1.5 x the average of the shape's tolerances,
    rounded up to 1-2-5 (``write.precision.mode`` 0): one infinite edge or vertex tolerance makes that 5e+199 file
    units, a file no reader accepts. The value is set instead (mode 2): ``uncertainty`` in mm (OCCT divides by the
    unit's factor), or :data:`DEFAULT_UNCERTAINTY` when it is None, not finite or not positive.
    """
    if uncertainty is None or not math.isfinite(uncertainty) or uncertainty <= 0:
        uncertainty = DEFAULT_UNCERTAINTY
    saved = (Interface_Static.CVal_s("write.step.unit"), Interface_Static.IVal_s("write.precision.mode"),
             Interface_Static.RVal_s("write.precision.val"))
    Interface_Static.SetCVal_s("write.step.unit", unit)
    Interface_Static.SetIVal_s("write.precision.mode", 2)
    Interface_Static.SetRVal_s("write.precision.val", float(uncertainty))
    try:
        yield
    finally:
        Interface_Static.SetCVal_s("write.step.unit", saved[0])
        Interface_Static.SetIVal_s("write.precision.mode", saved[1])
        Interface_Static.SetRVal_s("write.precision.val", saved[2])


def _name_products(writer: STEPControl_Writer, name: str) -> None:
    """Name the STEP products after the file: OCCT's default carries a per-process counter,
    which would make the same nets give different files."""
    model = writer.Model()
    label = TCollection_HAsciiString(name or "cadartifact")
    for i in range(1, model.NbEntities() + 1):
        entity = model.Value(i)
        if isinstance(entity, StepBasic_Product):
            entity.SetId(label)
            entity.SetName(label)


def set_header(writer: STEPControl_Writer, name: str, provenance: dict | None) -> None:
    """Fill the STEP header (FILE_NAME, FILE_DESCRIPTION) of a writer's model with provenance.

    Parameters
    ----------
    writer : STEPControl_Writer
        After ``Transfer`` and before ``Write``.
    name : str
        FILE_NAME's name (the file's name).
    provenance : dict str -> str or float, or None
        FILE_DESCRIPTION holds one ``key=value`` line per entry (floats as ``%g``);
        ``"authorization"`` goes to FILE_NAME's authorisation instead. FILE_NAME's originating
        system is ``cadartifact <version>``. None leaves OCCT's header as it is.
    """
    if provenance is None:
        return
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.Interface import Interface_HArray1OfHAsciiString

    from .. import __version__

    header = APIHeaderSection_MakeHeader(writer.Model())
    lines = [f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
             for k, v in provenance.items() if k != "authorization"] or ["cadartifact"]
    description = Interface_HArray1OfHAsciiString(1, len(lines))
    for i, line in enumerate(lines, start=1):
        description.SetValue(i, TCollection_HAsciiString(line))
    header.SetDescription(description)
    header.SetName(TCollection_HAsciiString(name))
    header.SetOriginatingSystem(TCollection_HAsciiString(f"cadartifact {__version__}"))
    header.SetAuthorisation(TCollection_HAsciiString(str(provenance.get("authorization", "cadartifact"))))


def write_step(nets, path, *, provenance: dict | None = None, unit: str = "MM",
               uncertainty: float | None = None) -> Path:
    """Write B-spline nets to a STEP file, one face each, in one shell.

    Parameters
    ----------
    nets : ControlNet or iterable of ControlNet
        Cages (``form == "cage"``) are skipped. A net with ``uv_bounds`` becomes a face
        bounded by that parameter rectangle; ``origin.name`` becomes the ``ADVANCED_FACE``
        name, so it reads back as the face name.
    path : str or path-like
        Output file (``.step``/``.stp``).
    provenance : dict, optional
        Header provenance (see :func:`set_header`); None keeps OCCT's default header.
    unit : str
        The file's length unit as OCCT's ``write.step.unit`` names it (``"MM"``, ``"CM"``, ``"INCH"``, ...); the
        nets are in mm (OCCT's internal unit) and are converted.
    uncertainty : float, optional
        The distance uncertainty to declare, in mm (a source model's own); None: :data:`DEFAULT_UNCERTAINTY`.

    Returns
    -------
    Path
        The file written.

    Notes
    -----
    Reading the file back gives the same poles, weights, knots and multiplicities for
    non-periodic nets. STEP has no periodic B-spline: OCCT writes periodic nets
    unrolled (same surface, more poles).

    Raises
    ------
    OptionError
        No B-spline net to write.
    InputError
        The file cannot be written.
    """
    if isinstance(nets, ControlNet):
        nets = [nets]
    nets = [n for n in nets if n.is_bspline]
    if not nets:
        raise OptionError("nets", "at least one B-spline net (cages cannot be written to STEP)", "none")
    path = Path(path)
    builder = BRep_Builder()
    shell = TopoDS_Shell()
    builder.MakeShell(shell)
    faces = [make_face(net) for net in nets]
    for face in faces:
        builder.Add(shell, face)
    compound = TopoDS_Compound()
    builder.MakeCompound(compound)
    builder.Add(compound, shell)
    writer = STEPControl_Writer()
    with quiet_occt():
        with write_settings(unit, uncertainty):
            status = writer.Transfer(compound, STEPControl_AsIs)
        if status != IFSelect_RetDone:
            raise InputError(path, "OCCT could not translate the nets to STEP")
        _name_products(writer, path.stem)
        set_header(writer, path.name, provenance)
        finder = writer.WS().TransferWriter().FinderProcess()
        for net, face in zip(nets, faces):
            if net.origin.name:
                entity = STEPConstruct.FindEntity_s(finder, face)
                if entity is not None and hasattr(entity, "SetName"):
                    entity.SetName(TCollection_HAsciiString(net.origin.name))
        try:
            status = writer.Write(str(path))
        except Standard_Failure as exc:
            raise InputError(path, f"cannot write STEP: {exc}") from None
    if status != IFSelect_RetDone or not path.exists():
        raise InputError(path, "cannot write STEP file (check the folder exists and is writable)")
    return path
