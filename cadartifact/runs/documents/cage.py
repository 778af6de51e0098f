"""The records of a subdivision cage's extraordinary vertices and of the advice a cage user can act on
(OBJ files of the advise and gate documents; :mod:`cadartifact.analysis.extraordinary`,
:mod:`cadartifact.advice.cage_levels`)."""

from __future__ import annotations

from typing import Annotated, Literal

from .keys import Pair, Triple, TypedDict

__all__ = ["ExtraordinaryVertexRecord", "RegionLevel", "VertexLevel", "CageAdvice"]


class ExtraordinaryVertexRecord(TypedDict, closed=True):
    """One extraordinary vertex of the cage (interior valence other than 4, boundary valence 4 or more, or
    the centre of a triangle or n-gon after the first step) and its limit surface's shape defect."""

    vertex: int
    """Vertex id (0-based): the cage's, or for the centre of a triangle or n-gon the cage's vertex count plus
    the face's index."""
    face: int | None
    """The triangle or n-gon whose centre this is (null: a vertex of the cage)."""
    line: int | None
    """Where it is in the OBJ file: the 1-based line of the vertex's ``v`` statement, or for a centre (which the
    file does not hold) of its face's ``f`` statement (null: a cage not read from a file)."""
    valence: int
    boundary: bool
    crease: bool
    """A crease edge ends here: the eigenvalues are the smooth rules' and do not describe it, and the defect
    measures the crease's kink (a feature): reported, not gated (``within`` and ``level`` null)."""
    position: Annotated[list[float], Triple]
    """Its limit position (model units)."""
    subdominant: float
    """lambda: the subdominant eigenvalue of Catmull-Clark's local subdivision matrix at the vertex."""
    subsubdominant: float
    """mu: the next eigenvalue below lambda."""
    curvature: Literal["bounded", "zero", "unbounded"]
    """The limit surface's curvature at the vertex: mu against lambda^2 (equal: bounded; below: zero;
    above: unbounded)."""
    defects: list[float]
    """d_0 .. d_3: the largest deviation of the limit surface over the vertex's faces at level k from its best
    quadratic over the tangent plane (model units)."""
    defect: float
    """The vertex's own shape defect at the cage's scale, d_3 / mu^3 (model units): gated against the
    tolerance."""
    within: bool | None
    """defect <= tolerance (null: no tolerance, or a crease ends here)."""
    level: int | None
    """The first subdivision level k with defect * mu^k within the tolerance (null: none up to 6, the vertex
    needs more control; or no tolerance, or a crease ends here)."""


class RegionLevel(TypedDict, closed=True):
    """A chart (regular region) of the cage and the level that brings its ripple within the tolerance."""

    face: int
    """The chart's face index in the document."""
    net: Annotated[list[int], Pair]
    share: float | None
    """Its ripple's share of the tolerance."""
    level: int | None
    """ceil(log4 share), 0 when within (null: none up to level 6)."""


class VertexLevel(TypedDict, closed=True):
    """An extraordinary vertex and the level that brings its defect within the tolerance."""

    vertex: int
    face: int | None
    valence: int
    level: int | None
    """Null: none up to level 6, it needs more control."""


class CageAdvice(TypedDict, closed=True):
    """What a cage user can act on: subdivision levels per region and vertex, and the vertices that need more
    control."""

    level: int | None
    """The cage's level: the largest of its regions' and vertices' (null: some need more control)."""
    regions: list[RegionLevel]
    vertices: list[VertexLevel]
    need_control: list[int]
    """Vertex ids not within by level 6: add an edge loop around them."""
    text: list[str]
    """The advice in words, one action per line."""
