"""The advise document (``cadartifact advise --json``, :func:`cadartifact.runs.advising.advise_files`): its
files, their faces (:mod:`.face`), the summary and, with ``--write-resampled``, what was written.

Versions: 2 added ``uncertainty`` and ``decision`` (``meets_tolerance`` true only for what conforms,
``value + U <= t``); 3 analyses and advises the spans the trimmed face uses (``advice.reasons.*.today`` counts
those spans' points) and adds ``outside_trim``, ``advice.joins``, ``advice.no_density``, ``advice.outside_trim``
and the comparison's ``advice`` flag.
"""

from __future__ import annotations

from typing import Literal, NotRequired

from .cage import CageAdvice, ExtraordinaryVertexRecord
from .face import AdviseFace, Metric, Reading, SummaryCounts
from .keys import TypedDict

__all__ = ["ADVISE_SCHEMA", "AdviseFile", "AdviseSummary", "WrittenFace", "RefusedFace", "WrittenFile", "Written", "AdviseDocument"]

#: The ``schema`` key of the advise document (and of the gate document, which extends it).
ADVISE_SCHEMA = "cadartifact.advise/3"


class AdviseFile(TypedDict, closed=True):
    """One file of the advise document."""

    path: str
    units: Literal["mm", "model"] | None
    """The unit of its faces (null: no analysable face)."""
    faces_total: int
    analysed_share: float | None
    """An OBJ cage: the share of its area in analysed charts (null: a B-rep file)."""
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
    """One face written with its advised net."""

    face: int
    name: str | None
    max_distance: float | None
    mean_distance: float | None
    edge_tolerance: float | None
    valid: bool | None
    model_valid: NotRequired[bool | None]
    """A B-rep source: whether the written model checks valid (absent for OBJ sources)."""
    file: NotRequired[str]
    """Several input files: the output file this face was written to."""


class RefusedFace(TypedDict, closed=True):
    """An advised face whose new net the writer refused: the face is kept as it was."""

    face: int
    reason: str
    """Why, as the writer's check says it (e.g. the net does not cover the face's trimmed region)."""


class WrittenFile(TypedDict, closed=True):
    """One output file."""

    path: str | None
    """The file written (null: nothing written, every replacement was refused)."""
    source: str
    mode: Literal["model", "faces-only"]
    faces: list[WrittenFace]
    kept: list[int]
    """Faces whose advice keeps today's net: left as they were."""
    refused: list[RefusedFace]
    """Faces whose advised net cannot be written faithfully: kept as they were, with the reason; the other faces
    are written."""
    valid: bool | None


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

    schema: Literal["cadartifact.advise/3"]
    tolerance: float
    units: Literal["mm", "model"]
    metric: Metric
    intent: Reading
    include_signal_error: bool
    files: list[AdviseFile]
    summary: AdviseSummary
    written: NotRequired[Written]
    """Only with ``--write-resampled``."""
