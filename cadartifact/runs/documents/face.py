"""One face's record in the advise and gate documents: today's budget, its uncertainty and decision, where the
ripple peaks, and the density advice.

Every record is a :class:`~typing.TypedDict`: the documents stay the plain dicts they always were (the JSON is
written from them as it is), and a type checker sees their keys. Each key's docstring is its description in
the published JSON Schema (:func:`cadartifact.runs.documents.json_schema`). A key that is ``NotRequired`` may be
absent; a key typed ``... | None`` is always there and may be ``null``. Lengths in model units (the face's
``units``), shares as fractions of the tolerance.
"""

from __future__ import annotations

from typing import Annotated, Literal, NotRequired

from .keys import Pair, Triple, TypedDict

__all__ = ["SummaryCounts", "Metric", "Reading", "Decision", "PeakRms", "Budget", "Shares", "AdvisedBudget", "AdvisedShares",
           "UncertaintyRecord", "OutsideTrim", "PeakAt", "FaceRecord", "AdviseFace", "AdviceRecord", "TodayScore",
           "Reason", "Reasons", "Verification", "CoarserCheck", "ComparisonRow", "JoinPiece", "Join", "Joins",
           "NoDensity", "BestFound", "Retried", "AdvisedUncertainty"]

#: The statistic a tolerance is compared with.
Metric = Literal["peak", "rms"]
#: The reading of the design intent (SPEC §4).
Reading = Literal["surface", "net"]
#: The ISO 14253-1 decision on a value with the intent's uncertainty U against the tolerance.
Decision = Literal["conforms", "undecided", "does not conform"]
#: A number the analysis computed, or null where it was not finite.
Number = float | None


class PeakRms(TypedDict, closed=True):
    """One statistic of a field over the analysed region (model units; null: not finite)."""

    peak: Number
    rms: Number


class Budget(TypedDict, closed=True):
    """Today's ripple budget per component. ``total`` is x1 + x2 + diagonal; ``lateral`` the part of the ripple
    running across features; ``deviation`` everything the surface differs from the intent (ripple and signal
    error)."""

    x1: PeakRms
    x2: PeakRms
    diagonal: PeakRms
    lateral: PeakRms
    total: PeakRms
    signal_error: PeakRms
    deviation: PeakRms


class Shares(TypedDict, closed=True):
    """Each component of the budget under the document's metric, as a share of the tolerance."""

    x1: Number
    x2: Number
    diagonal: Number
    lateral: Number
    total: Number
    signal_error: Number
    deviation: Number


class AdvisedBudget(TypedDict, closed=True):
    """The advised net: its own ripple budget, its ``deviation`` from the intent and ``boundary``, the distance of
    its border curves from today's."""

    x1: PeakRms
    x2: PeakRms
    diagonal: PeakRms
    lateral: PeakRms
    total: PeakRms
    signal_error: PeakRms
    deviation: PeakRms
    boundary: PeakRms


class AdvisedShares(TypedDict, closed=True):
    """:class:`AdvisedBudget` under the metric, as shares of the tolerance."""

    x1: Number
    x2: Number
    diagonal: Number
    lateral: Number
    total: Number
    signal_error: Number
    deviation: Number
    boundary: Number


class UncertaintyRecord(TypedDict, closed=True):
    """The intent's expanded uncertainty U (model units)."""

    peak: Number
    """U over the face."""
    u: Number
    """The share of the u direction."""
    v: Number
    """The share of the v direction."""
    reading: Reading
    coverage_factor: Number
    """The coverage factor k applied to the spread."""
    estimated: bool
    """False: no estimate exists (the surface reading), U is 0."""


class OutsideTrim(TypedDict, closed=True):
    """Shares of the surface's parameter range outside the trimmed face: those spans are not analysed or
    advised."""

    u: float
    v: float
    share: float
    """Share of the parameter area."""


class PeakAt(TypedDict, closed=True):
    """Where the ripple of a face beyond the tolerance (or that warns) peaks."""

    value: Number
    """The peak (model units)."""
    index: Annotated[list[float], Pair]
    """Analysis coordinates (spans) on the fine grid."""
    uv: Annotated[list[float], Pair] | None
    """Surface parameters (null for a subdivision cage)."""
    xyz: Annotated[list[Number], Triple]
    """The point of the face there (cages: of the limit surface)."""


class TodayScore(TypedDict, closed=True):
    """Today's net scored the way the candidates are."""

    peak: Number
    rms: Number
    boundary: Number


class Reason(TypedDict, closed=True):
    """Why the advised count of one direction is what it is."""

    today: int
    advised: int
    change: int
    coarser_value: Number
    """The value one point fewer would give (null: at the fewest points the degree allows)."""
    binding: bool
    reason: str


class Reasons(TypedDict, closed=True):
    """Per direction."""

    u: Reason
    v: Reason


class CoarserCheck(TypedDict, closed=True):
    """The net one step coarser in the binding direction, measured the same way."""

    shape: Annotated[list[int], Pair]
    value: float
    meets: bool


class Verification(TypedDict, closed=True):
    """The advised net measured on the real surface (OCCT), or today's net kept as the advice (``today``)."""

    method: Literal["occt", "today"]
    levels: int
    region: Literal["face"]
    value: float
    rms: float
    meets: bool
    coarser: NotRequired[CoarserCheck]
    """With a binding direction (OCCT only)."""
    samples: NotRequired[float]
    """The net reading: the largest distance of the advised surface from today's control points."""


class ComparisonRow(TypedDict, closed=True):
    """One scheme's advice in the scheme comparison."""

    net: Annotated[list[int], Pair]
    points: int
    meets_tolerance: bool
    objective: Literal["deviation", "ripple"]
    advice: bool
    """True: this row is the advice itself."""


class JoinPiece(TypedDict, closed=True):
    """One piece between a direction's joins."""

    range: Annotated[list[float], Pair]
    today_spans: int
    advised_spans: int
    points: int
    deviation: float
    meets_tolerance: bool


class Join(TypedDict, closed=True):
    """A direction whose joins (interior knots of multiplicity >= p) the advice keeps."""

    joins: list[float]
    multiplicity: int
    today_spans: list[int]
    plan: Literal["per piece", "proportional", "today's"]
    advised_spans: list[int]
    pieces: list[JoinPiece] | None


class Joins(TypedDict, total=False, closed=True):
    """The directions whose joins the advice keeps (empty: none)."""

    u: Join
    v: Join


class BestFound(TypedDict, closed=True):
    """The best density the search found."""

    net: Annotated[list[int], Pair]
    value: float
    uncertainty: float


class NoDensity(TypedDict, closed=True):
    """No density within the search's limits conforms: the best found, and why."""

    why: list[Literal["crease", "uncertainty", "stops improving", "growth limit"]]
    best: BestFound
    reason: str


class Retried(TypedDict, closed=True):
    """The search's own-ripple reading found no density; the deviation alone, verified on OCCT's surface, did."""

    net: Annotated[list[int], Pair]
    """The net that verified (the advice, unless each piece's spans found on their own saved points since)."""
    value: float
    """Its deviation from the intent on OCCT's surface."""
    read: float
    """Its deviation as the search's check grid reads it."""
    own_ripple: float
    """Its own ripple as its budget reads it (what kept the search from it)."""
    tried: list[Annotated[list[int], Pair]]
    """The nets measured on OCCT, in order."""


class AdvisedUncertainty(TypedDict, closed=True):
    """The expanded uncertainty U (model units) the claim on the advised net used: a candidate conforms at
    value + U <= t."""

    peak: Number
    """U of the advised net's value."""
    reading: Reading
    coverage_factor: Number
    """The coverage factor k reported with it."""
    estimated: bool
    """False: no estimate exists (a cage's surface reading), U is 0."""
    construction: str
    """How U was built: surface reading, the largest change of the intent over the border convention's period
    variants plus its grid term, which bounds every candidate's change of value, or its bound; net reading, a
    candidate's value against the intent (``k SPREAD_SCALE D``, wider than today's value's U); or today's U,
    today's net kept."""


class AdviceRecord(TypedDict, closed=True):
    """The density advice: the fewest control points whose best net stays within the tolerance."""

    net: Annotated[list[int], Pair]
    """The advised net (n'u, n'v)."""
    points: int
    intent: Reading
    objective: Literal["deviation", "ripple"]
    budget: AdvisedBudget
    share: AdvisedShares
    today: TodayScore
    meets_tolerance: bool
    """The advised net conforms."""
    uncertainty: UncertaintyRecord | None
    decision: Decision
    """The advised net's."""
    today_decision: Decision
    verifiable: bool
    """False: U alone is near the tolerance, no net can conform (a note says so)."""
    binding: Literal["u", "v"] | None
    reasons: Reasons
    kept_today: bool
    verification: Verification | None
    comparison: dict[str, ComparisonRow]
    """Per scheme name (empty: not compared)."""
    notes: list[str]
    joins: Joins
    outside_trim: OutsideTrim | None
    no_density: NoDensity | None
    comparison_note: NotRequired[str]
    """Why the schemes were not compared."""
    advised_uncertainty: NotRequired[AdvisedUncertainty]
    """The U of the advised net's decision (a kept net: today's ``uncertainty.peak``; a candidate: its own).
    Absent where none applies: an exact face or the ripple objective under the surface reading, a net reading with
    no estimate."""
    retried: NotRequired[Retried]
    """Present when the advice was found by the retry before an honest no (the verified deviation)."""


class FaceRecord(TypedDict):
    """What the advise and gate documents say of every face: today's net, its budget and decision (the keys
    :class:`AdviseFace` and :class:`~cadartifact.runs.documents.gate.GateFace` share; open, so that they may add
    theirs)."""

    face: int
    """The face's index in its file (an OBJ cage: the chart's)."""
    name: str | None
    """The face's name in its file (STEP: the ADVANCED_FACE's), or null."""
    kind: str
    """What the net is: ``bspline``, ``bezier``, ``converted`` (a revolution, extrusion or offset face made a
    B-spline), ``quad-chart`` (a chart of a subdivision cage)."""
    net: Annotated[list[int], Pair]
    """Control points (nu, nv)."""
    degrees: Annotated[list[int], Pair] | None
    """Null for a cage."""
    rational: bool
    """The net carries weights (a rational surface, NURBS)."""
    units: Literal["mm", "model"]
    """The unit of every length of the record: ``mm`` (B-rep files) or ``model`` (OBJ cages)."""
    entity: int | None
    """STEP: the face's #id in the file."""
    canonical: str | None
    """What the face exactly is (``sphere r=12.5``, ``revolved: circular in u``)."""
    exact: Annotated[list[Literal["line", "circle", "surface"] | None], Pair]
    """Per direction (u, v): exactly straight or circular (no artifact), or null."""
    scheme: str
    """The subdivision or B-spline scheme the net was read under (``bspline(3,3)``, ``bicubic``, ...)."""
    method: Literal["predicted", "measured"]
    """The road: predicted from the scheme's spectral response (uniform nets) or measured on the surface."""
    uniform: bool
    """Uniform knots and constant weights, or a cage."""
    intent: Reading
    """The reading of the design intent: the surface less its ripple, or the shape the points sample."""
    reason: str
    """Why this road (predicted or measured) was taken."""
    notes: list[str]
    """What the analysis could not judge, or did differently, in plain words."""
    budget: Budget
    """Today's ripple and deviation per component."""
    share: Shares
    """The budget under the metric as shares of the tolerance."""
    meets_tolerance: bool
    """Conforms: value + U <= tolerance."""
    uncertainty: UncertaintyRecord | None
    decision: Decision
    """Today's net (ISO 14253-1)."""
    outside_trim: OutsideTrim | None
    """Null: untrimmed."""
    entity_line: int | None
    """STEP: the line of the face's entity."""
    peak_at: PeakAt | None
    """Faces beyond the tolerance: where the ripple peaks."""


class AdviseFace(FaceRecord, closed=True):
    """A face of the advise document: its record and its advice."""

    advice: AdviceRecord


class SummaryCounts(TypedDict):
    """Counts of faces over every file of a run (the advise and gate documents' summaries)."""

    files: int
    faces: int
    within: int
    """Faces that conform."""
    exceeding: int
    """Faces that do not conform."""
    undecided: int
    """Faces the decision rule left undecided."""
    unreachable: int
    """Faces for which no density within the search's limits conforms."""
