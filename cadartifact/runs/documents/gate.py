"""The gate document (``cadartifact gate --format json``, :func:`cadartifact.gate.run.build_document`): the advise
document's keys, each face's verdict and PDQ criteria, each file's policy and verdict, the summary and the exit
code.

Versions: 3 added the PDQ criteria (``profile``, per face ``criteria`` and ``ripple_verdict``); 4 is 3 with the
keys added after 3's schema was published (``baseline``, a file's ``edges``, ``edges_counted``, ``extraordinary``,
``extraordinary_failure``, ``subdivided`` and ``cage_advice``, ``summary.edges``, the profile's ``flat_ratio`` and
``sharp_angle``; CHANGELOG.md lists them), and adds the advice's ``advised_uncertainty`` and each extraordinary
vertex's ``line``.
"""

from __future__ import annotations

from typing import Annotated, Literal, NotRequired

from .cage import CageAdvice, ExtraordinaryVertexRecord
from .face import AdviceRecord, FaceRecord, Metric, Reading, SummaryCounts
from .advise import SubdividedRecord
from .keys import Pair, Triple, TypedDict

__all__ = ["GATE_SCHEMA", "FaceVerdict", "Verdict", "Sense", "Threshold", "CriterionAt", "CriterionRecord",
           "GateFace", "EdgeAt", "EdgeGap", "EdgeAngle", "EdgeCurvature", "EdgeCriterion", "GateEdge", "EdgeCounts",
           "EdgeSummary", "ProfileRecord", "PolicyRecord", "GateFile", "CriterionCounts", "FaceCounts", "FileCounts",
           "VerdictCounts", "GateSummary", "BaselineFinding", "BaselineRecord", "GateDocument"]

#: The ``gate`` key of the gate document.
GATE_SCHEMA = "cadartifact.gate/4"

#: A face's verdict.
FaceVerdict = Literal["pass", "warn", "fail"]
#: A file's verdict, and the run's (``error``: a file could not be read or analysed).
Verdict = Literal["pass", "warn", "fail", "error"]
#: ``above``: a value above the threshold is bad; ``below``: a value below it.
Sense = Literal["above", "below"]


class Threshold(TypedDict, closed=True):
    """A criterion's thresholds (null: none at that level)."""

    warn: float | None
    fail: float | None
    sense: Sense


class CriterionAt(TypedDict, closed=True):
    """Where the face is worst under a criterion."""

    uv: Annotated[list[float | None], Pair]
    xyz: Annotated[list[float | None], Triple] | None


class CriterionRecord(TypedDict, closed=True):
    """One PDQ criterion on one face (:mod:`cadartifact.analysis.quality`)."""

    criterion: str
    """The criterion's key (``waviness``, ``degree``, ...)."""
    code: str
    """Its PDQ code (``G-SU-WV``) or the checkers' name for it."""
    evaluated: bool
    """False: ``reason`` says why it could not be (or that the profile turns it off)."""
    value: float | None
    unit: str
    verdict: FaceVerdict | None
    """Null when not evaluated."""
    threshold: Threshold | None
    at: CriterionAt | None
    """Null where the criterion has no place (degree, counts)."""
    detail: str
    reason: str | None


class GateFace(FaceRecord, closed=True):
    """A face of the gate document: its record, its verdict and, where the policy asks, its advice."""

    advice: AdviceRecord | None
    """Null: not computed (``advice_skipped`` says why)."""
    verdict: FaceVerdict
    """The worst of the ripple's verdict and the PDQ criteria's."""
    verdict_reason: str
    """One line with the numbers."""
    value: float
    """The number compared with the tolerance: ``budget[total | deviation][metric]``."""
    advice_skipped: str | None
    """Why the advice was not computed (null: it was)."""
    ripple_verdict: FaceVerdict
    """The ripple's verdict (``verdict`` is the worst of it and the PDQ criteria's)."""
    criteria: list[CriterionRecord] | None
    """Null without a PDQ profile."""


class ProfileRecord(TypedDict, extra_items=Threshold | None):  # type: ignore[call-arg]  # mypy: no extra_items yet
    """A PDQ profile: per criterion key its thresholds (null: the criterion is off), besides the keys below."""

    name: str
    source: str | None
    """The profile file (null: built in)."""
    flat_ratio: float
    """Waviness: curvature under 1 / (flat_ratio * the face's size) has no sign."""
    flat_radius: float | None
    """Waviness: an absolute flat radius instead (null: relative to the face)."""
    knot_parameter: float | None
    """Indistinct knots: also under this share of the parameter range (null: the length alone decides)."""
    sharp_angle: float
    """Continuity between faces: a crease of at least this many degrees all along an edge is sharp by design."""


class PolicyRecord(TypedDict, closed=True):
    """The settings one file was gated under (:class:`cadartifact.gate.policy.FileSettings`)."""

    tolerance: float
    metric: Metric
    warn_fraction: float
    include_signal_error: bool
    scheme: str | None
    """Null: each face's own degrees (Catmull-Clark for cages)."""
    measured: Literal["warn", "fail"]
    undecided: FaceVerdict
    intent: Reading
    convert: bool
    min_analysed_share: float
    advise: Literal["failing", "all", "none"]
    ignore_faces: list[int]
    profile: ProfileRecord | None


class EdgeAt(TypedDict, closed=True):
    """A place along an edge."""

    t: float
    """Share of the edge's parameter range (0 at its start, 1 at its end)."""
    xyz: Annotated[list[float | None], Triple]
    """The midpoint of the two faces' points there."""


class EdgeGap(TypedDict, closed=True):
    """G0: the largest distance between the faces along the edge (model units)."""

    value: float | None
    at: EdgeAt


class EdgeAngle(TypedDict, closed=True):
    """G1: the angle between the faces' oriented normals along the edge (degrees)."""

    value: float | None
    """The largest."""
    min: float | None
    """The smallest (a crease all along the edge: sharp by design when at least the profile's sharp_angle)."""
    at: EdgeAt


class EdgeCurvature(TypedDict, closed=True):
    """G2: the jump of the normal curvature across the edge (1 / model units)."""

    jump: float | None
    """The largest absolute jump ``|k1 - k2|``."""
    jump_at: EdgeAt
    relative: float | None
    """The largest relative jump ``|k1 - k2| / max(|k1|, |k2|)`` (0 where both faces are flat)."""
    k: Annotated[list[float | None], Pair]
    """Both faces' normal curvatures across the edge where the relative jump is largest."""
    at: EdgeAt


class EdgeCriterion(TypedDict, closed=True):
    """One criterion of continuity between faces on one edge."""

    criterion: str
    code: str
    evaluated: bool
    value: float | None
    unit: str
    verdict: FaceVerdict | None
    threshold: Threshold | None
    at: EdgeAt | None
    detail: str
    reason: str | None


class GateEdge(TypedDict, closed=True):
    """An edge two faces share, its continuity and verdict (:mod:`cadartifact.analysis.edges`)."""

    edge: int
    """Index in OCCT's map of the shape's edges (1-based)."""
    entity: int | None
    """The STEP ``EDGE_CURVE`` record's id (null: not STEP, or unknown)."""
    line: int | None
    """The line of that record."""
    faces: Annotated[list[int], Pair]
    """The two faces' indices (``face`` of the face records)."""
    face_entities: Annotated[list[int | None], Pair]
    length: float | None
    samples: int
    orientation: Literal["consistent", "inconsistent"]
    """Whether the shell's orientation agrees across the edge (inconsistent: one normal was reversed to compare)."""
    gap: EdgeGap
    angle: EdgeAngle | None
    curvature: EdgeCurvature | None
    sharp: bool
    """Sharp by design (a crease all along the edge): G1 and G2 not judged."""
    verdict: FaceVerdict
    criteria: list[EdgeCriterion]


class EdgeCounts(TypedDict, closed=True):
    """The file's edges by kind: shared by two faces (measured), free, seams, degenerate, non-manifold, failed."""

    shared: int
    free: int
    seam: int
    degenerate: int
    non_manifold: int
    failed: int
    """Shared by two faces, but OCCT could not evaluate the edge on them (no curve on a face): not measured."""


class GateFile(TypedDict, closed=True):
    """One file of the gate document; a file that could not be read has ``error`` and no faces."""

    path: str
    units: Literal["mm", "model"] | None
    faces_total: int | None
    """Null: the file could not be read."""
    analysed_share: NotRequired[float | None]
    """An OBJ cage: the share of its area in analysed charts (absent when the file could not be read)."""
    subdivided: NotRequired[SubdividedRecord]
    """An OBJ cage whose triangles, n-gons or irregular quads were analysed after one subdivision step."""
    skipped: dict[str, int]
    warnings: list[str]
    notes: list[str]
    ignored_faces: list[int]
    policy: PolicyRecord | None
    faces: list[GateFace]
    verdict: Verdict
    error: NotRequired[str]
    """Why the file could not be read or analysed (verdict ``error``)."""
    share_failure: NotRequired[str]
    """An OBJ cage whose analysed share is below the policy's ``min_analysed_share`` (it fails)."""
    edges: NotRequired[list[GateEdge] | None]
    """With a PDQ profile: the edges two faces share, judged (null: not a B-rep file); absent without one."""
    edges_counted: NotRequired[EdgeCounts | None]
    """With a PDQ profile: the file's edges by kind (null: not a B-rep file)."""
    extraordinary: NotRequired[list[ExtraordinaryVertexRecord]]
    """An OBJ cage: one record per extraordinary vertex."""
    cage_advice: NotRequired[CageAdvice]
    """An OBJ cage: the subdivision level per region and vertex, and the vertices that need more control."""
    extraordinary_failure: NotRequired[str]
    """An OBJ cage with extraordinary vertices whose defect exceeds the tolerance (it fails)."""


class CriterionCounts(TypedDict, closed=True):
    """Faces per outcome of one PDQ criterion."""

    warn: int
    fail: int
    not_evaluated: int


# "pass" is a keyword: the functional form
FaceCounts = TypedDict("FaceCounts", {"pass": int, "warn": int, "fail": int}, closed=True)
FaceCounts.__doc__ = "Faces per verdict."
FileCounts = TypedDict("FileCounts", {"pass": int, "warn": int, "fail": int, "error": int}, closed=True)
FileCounts.__doc__ = "Files per verdict."


class VerdictCounts(TypedDict, closed=True):
    """Files and faces per verdict."""

    files: FileCounts
    faces: FaceCounts


class EdgeSummary(TypedDict, closed=True):
    """The shared edges measured over every file: all, sharp by design, warning, failing."""

    edges: int
    sharp: int
    warn: int
    fail: int


class GateSummary(SummaryCounts, closed=True):
    """Counts over every file."""

    criteria: NotRequired[dict[str, CriterionCounts]]
    """Per PDQ criterion (only with a profile)."""
    edges: NotRequired[EdgeSummary]
    """Continuity between faces (only with a profile)."""
    errors: int
    """Files that could not be read or analysed."""
    verdicts: VerdictCounts


class BaselineFinding(TypedDict, closed=True):
    """A finding as a baseline lists it (``gate --update-baseline``)."""

    fingerprint: str
    """The hash of ``path``, ``record`` and ``criterion`` (SARIF ``partialFingerprints``, GitLab's ``fingerprint``)."""
    rule: str
    """The SARIF rule (``CA001``...)."""
    level: Literal["error", "warning", "note"]
    path: str
    """The file, relative to the run's root, ``/``-separated."""
    record: str
    """The face's STEP record (``#1234``), ``face N`` without one, ``""`` for the whole file."""
    criterion: str
    """``ripple``, or the rule's name."""
    value: float | None
    uncertainty: float | None
    """The reading's uncertainty U (null: none)."""
    sense: Sense
    """``above``: a higher value is worse; ``below``: a lower one."""
    previous: NotRequired[float | None]
    """A worse finding: the baseline's value."""


class BaselineRecord(TypedDict, closed=True):
    """This run's findings against a baseline (``gate --baseline``)."""

    source: str
    """The baseline file."""
    new: list[BaselineFinding]
    """Findings the baseline does not have."""
    worse: list[BaselineFinding]
    """Findings whose reading got worse beyond its uncertainty."""
    known: int
    """Findings the baseline has, not worse."""
    fixed: list[BaselineFinding]
    """The baseline's findings this run no longer has."""
    exit_code: Literal[0, 1, 2]
    """2: a file could not be read; 1: a new or worse finding fails; else 0."""


class GateDocument(TypedDict, closed=True):
    """The gate document: pass / warn / fail per face and file, and the exit code."""

    schema: Literal["cadartifact.advise/4"]
    gate: Literal["cadartifact.gate/4"]
    tolerance: float | None
    """The run's tolerance (with tolerances only in the policy's overrides, the first file's)."""
    units: Literal["mm", "model"]
    metric: Metric
    include_signal_error: bool
    intent: Reading
    warn_fraction: float
    measured: Literal["warn", "fail"]
    undecided: FaceVerdict
    scheme: str | None
    profile: ProfileRecord | None
    """The PDQ profile's thresholds (null: no criteria)."""
    policy: str | None
    """The policy file (null: none)."""
    files: list[GateFile]
    summary: GateSummary
    verdict: Verdict
    exit_code: Literal[0, 1, 2]
    """With a baseline, the baseline's (``baseline.exit_code``)."""
    baseline: NotRequired[BaselineRecord]
    """Only with ``--baseline``."""
