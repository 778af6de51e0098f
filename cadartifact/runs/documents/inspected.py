"""The inspect document (``cadartifact inspect --json``, :func:`cadartifact.exchange.summary.result_summary`):
what each file holds, its control nets and, for an OBJ cage, its mesh and charts."""

from __future__ import annotations

from typing import Annotated, Literal

from .keys import Pair, TypedDict

__all__ = ["INSPECT_SCHEMA", "InspectFace", "Chart", "Mesh", "InspectFile", "InspectDocument"]

#: The ``schema`` key of the inspect document.
INSPECT_SCHEMA = "cadartifact.inspect/1"


class InspectFace(TypedDict, closed=True):
    """One analysable face (or OBJ chart)."""

    face: int
    name: str | None
    kind: str
    """``bspline``, ``bezier``, ``converted``, ``quad-chart``."""
    degrees: Annotated[list[int], Pair] | None
    """Null for a cage."""
    size: Annotated[list[int], Pair]
    """Control points (nu, nv)."""
    rational: bool
    weights_vary: bool
    periodic: Annotated[list[bool], Pair]
    knots_uniform: Annotated[list[bool], Pair]
    trimmed_fraction: float | None
    """The share of the knot range the face's UV bounds keep (1.0: untrimmed; null: a cage or no bounds)."""


class Chart(TypedDict, closed=True):
    """A regular quad region of a cage, analysed as one net."""

    chart: int
    size: Annotated[list[int], Pair]
    faces: list[int]
    """Mesh face ids (level 1: quads of the cage after one Catmull-Clark step)."""
    level: int
    """0: a chart of the cage as read; 1: of its first Catmull-Clark step (triangles, n-gons, irregular quads)."""


class Mesh(TypedDict, closed=True):
    """An OBJ cage's mesh."""

    vertices: int
    quads: int
    triangles: int
    ngons: int
    regular_faces: int
    extraordinary: list[int]
    """Vertex ids (0-based)."""
    crease_edges: int
    charts: list[Chart]


class InspectFile(TypedDict, closed=True):
    """One file."""

    path: str
    format: str
    """The reader: ``step``, ``iges``, ``brep``, ``obj``."""
    faces_total: int
    analysable: int
    skipped: dict[str, int]
    warnings: list[str]
    faces: list[InspectFace]
    mesh: Mesh | None
    """Null for a B-rep file."""


class InspectDocument(TypedDict, closed=True):
    """The inspect document: the control nets in each file."""

    schema: Literal["cadartifact.inspect/1"]
    files: list[InspectFile]
