"""The advise document (``cadartifact advise --json``, :func:`cadartifact.runs.advising.advise_files`): its
files, their faces (:mod:`.face`), the summary and, with ``--write-resampled``, what was written.

Versions: 2 added ``uncertainty`` and ``decision`` (``meets_tolerance`` true only for what conforms,
``value + U <= t``); 3 analyses and advises the spans the trimmed face uses (``advice.reasons.*.today`` counts
those spans' points) and adds ``outside_trim``, ``advice.joins``, ``advice.no_density``, ``advice.outside_trim``
and the comparison's ``advice`` flag; 4 is 3 with the keys added after 3's schema was published (a file's
``subdivided``, ``extraordinary`` and ``cage_advice``, the advice's ``retried``, ``written``'s refused faces,
surface types and measured figures; CHANGELOG.md lists them), and adds the document's ``exit_code``, the advice's
``advised_uncertainty`` and each extraordinary vertex's ``line``.
"""

from __future__ import annotations

from typing import Literal, NotRequired

from .cage import CageAdvice, ExtraordinaryVertexRecord
from .face import AdviseFace, Metric, Reading, SummaryCounts
from .keys import TypedDict

__all__ = ["ADVISE_SCHEMA", "SubdividedRecord", "AdviseFile", "AdviseSummary", "WrittenFace", "RefusedMeasure",
           "RefusedFace", "WrittenFile", "Written", "AdviseDocument"]

#: The ``schema`` key of the advise document (and of the gate document, which extends it).
ADVISE_SCHEMA = "cadartifact.advise/4"


class SubdividedRecord(TypedDict, closed=True):
    """An OBJ cage with faces outside its charts as read: what its first Catmull-Clark step brought into the
    analysis (SPEC §6)."""

    level: int
    """The subdivision level of those charts (1: after one step, where every face is a quad)."""
    charts: int
    """Charts on that level (numbered after the charts of the cage as read)."""
    quads: int
    """Quads of that level in those charts."""
    from_faces: dict[str, int]
    """Faces of the cage as read some of whose quads are analysed, per kind (``triangle``, ``n-gon``,
    ``quad``)."""


class AdviseFile(TypedDict, closed=True):
    """One file of the advise document."""

    path: str
    units: Literal["mm", "model"] | None
    """The unit of its faces (null: no analysable face)."""
    faces_total: int
    analysed_share: float | None
    """An OBJ cage: the share of its area in analysed charts (null: a B-rep file)."""
    subdivided: NotRequired[SubdividedRecord]
    """An OBJ cage whose triangles, n-gons or irregular quads were analysed after one subdivision step."""
    skipped: dict[str, int]
    """Faces not analysed, counted per kind (``plane``, ``triangle``, ...)."""
    warnings: list[str]
    faces: list[AdviseFace]
    extraordinary: NotRequired[list[ExtraordinaryVertexRecord]]
    """An OBJ cage: one record per extraordinary vertex."""
    cage_advice: NotRequired[CageAdvice]
    """An OBJ cage: the subdivision level per region and vertex, and the vertices that need more control."""


class AdviseSummary(SummaryCounts, closed=True):
    """Counts of faces over every file."""


class WrittenFace(TypedDict, closed=True):
    """One face written with its advised net, measured as it stands in the written model against the old face
    (model units, mm for STEP; null: not measured, an OBJ cage's face)."""

    face: int
    name: str | None
    distance_to_old: NotRequired[float | None]
    """The largest distance of the written face (samples inside its trim) to the old face, by projection."""
    distance_from_old: NotRequired[float | None]
    """The largest distance of the old face (samples inside its trim) to the written face, by projection."""
    max_distance: float | None
    """The larger of the two: the distance of the written face to the old one."""
    mean_distance: float | None
    """The mean over both directions' samples."""
    allowed_distance: NotRequired[float | None]
    """t + the old face's ripple (the peak the advice read for today's net) + the old face's largest edge tolerance
    (its border is known only to within it): the most ``max_distance`` may be."""
    edge_tolerance_before: NotRequired[float | None]
    """The largest tolerance of the face's edges in the input."""
    edge_tolerance: float | None
    """The largest tolerance of the face's edges as written (at most the input's + t)."""
    valid_before: NotRequired[bool | None]
    """BRepCheck's verdict on the face alone in the input."""
    valid: bool | None
    """BRepCheck's verdict on the written face alone."""
    pcurves: NotRequired[Literal["projected", "kept"] | None]
    """How the face's trim was put on its new surface: its edges' 3-D curves projected onto it, or its old pcurves
    kept (tried when the projected face measured unfaithful). Null: faces only."""
    model_valid: NotRequired[bool | None]
    """A B-rep source: whether the written model checks valid (absent for OBJ sources)."""
    surface_type: NotRequired[str | None]
    """Model mode: the kind of the input face's surface (``bspline``, ``torus``, ...)."""
    surface_type_written: NotRequired[str | None]
    """Model mode: the kind of the written face's surface as the file reads back (a replaced face is given as a
    B-spline; null: the written file's faces could not be matched one to one)."""
    file: NotRequired[str]
    """Several input files: the output file this face was written to."""


class WorseEdge(TypedDict, closed=True):
    """An edge of a refused face whose continuity verdict (the gate's edge rules) the replacement made worse."""

    faces: list[int]
    """The two faces of the edge."""
    criterion: Literal["edge_gap", "edge_angle", "edge_curvature"]
    rule: str
    """The gate's rule id (CA131 G0, CA132 G1, CA133 G2)."""
    value: float | None
    """As written (model units, degrees or a share)."""
    before: float | None
    """In the input."""
    verdict: Literal["pass", "warn", "fail"]
    verdict_before: Literal["pass", "warn", "fail"]
    limit: float | None
    """The threshold crossed (when the input already failed: its value + a tenth of the fail threshold)."""


class RefusedMeasure(TypedDict, closed=True):
    """What the best replacement of a refused face measured, written (model units)."""

    distance_to_old: float | None
    distance_from_old: float | None
    max_distance: float | None
    allowed_distance: float | None
    edge_tolerance_before: float | None
    edge_tolerance: float | None
    valid_before: bool | None
    valid: bool | None
    edges: NotRequired[list[WorseEdge]]
    """Refused on the continuity between faces: the edges it made worse than in the input, the worst first."""


class RefusedFace(TypedDict, closed=True):
    """An advised face whose new net the writer refused: the face is kept as it was."""

    face: int
    reason: str
    """Why, as the writer's check says it (the net does not cover the face's trimmed region; written, it lies
    beyond t + the old face's ripple of the old face, its edges beyond the input's tolerance + t, BRepCheck
    rejects it where the input's passed, or it makes an edge's continuity verdict worse than the input's:
    "edge continuity: gap X mm > Y (input Z) ...")."""
    measured: NotRequired[RefusedMeasure | None]
    """What the replacement measured when it was refused on measured grounds (null: refused before it was built)."""


class SurfaceTypeChange(TypedDict, closed=True):
    """A face OCCT's STEP writer turned into another kind of surface than it was given."""

    face: int
    before: str
    """The kind in the input (a replaced face: ``bspline``, what it was given)."""
    after: str
    """The kind the written file reads back with (e.g. ``revolution`` for a degenerate torus)."""


class WrittenFile(TypedDict, closed=True):
    """One output file."""

    path: str | None
    """The file written (null: nothing written, every replacement was refused, or, faces only, no face conforms)."""
    source: str
    mode: Literal["model", "faces-only"]
    faces: list[WrittenFace]
    kept: list[int]
    """Faces not written as advised: their advice keeps today's net (model mode), or finds no net that conforms
    (an honest no; the face's advice says why). Model mode: left as they were; faces only: not written."""
    refused: list[RefusedFace]
    """Faces whose advised net cannot be written faithfully: kept as they were, with the reason; the other faces
    are written."""
    valid: bool | None
    surface_types: NotRequired[list[SurfaceTypeChange]]
    """Model mode, a file written: the faces whose surface kind the writer changed (replaced or not)."""


class Written(TypedDict, closed=True):
    """What ``--write-resampled`` wrote (:func:`cadartifact.runs.advising.write_advised`)."""

    mode: Literal["model", "faces-only", "mixed"]
    files: list[WrittenFile]
    path: str | None
    """The first output file (null: nothing written)."""
    faces: list[WrittenFace]
    """One input file: its faces; several: every file's, each with ``file``."""


class AdviseDocument(TypedDict, closed=True):
    """The advise document: per file and face, today's ripple budget against the tolerance and the density
    advice."""

    schema: Literal["cadartifact.advise/4"]
    tolerance: float
    units: Literal["mm", "model"]
    metric: Metric
    intent: Reading
    include_signal_error: bool
    files: list[AdviseFile]
    summary: AdviseSummary
    exit_code: Literal[0, 1]
    """The exit code of ``cadartifact advise`` for this document, which the command exits with: 0 when every face
    meets the tolerance today, 1 when some face does not (it needs another density, or it is undecided). Usage
    and input errors exit 2 and write no document; ``cadartifact demo`` exits 0 whatever it says."""
    written: NotRequired[Written]
    """Only with ``--write-resampled``."""
