"""The records of a cage's extraordinary vertices and of its advice in the advise and gate documents
(:mod:`cadartifact.runs.documents.cage`)."""

from __future__ import annotations

from .records import analysed_share, json_number

__all__ = ["vertex_records", "cage_advice_record", "vertex_failure"]


def vertex_records(mesh, tolerance: float | None) -> list:
    """One :class:`~cadartifact.runs.documents.cage.ExtraordinaryVertexRecord` per extraordinary vertex.

    Parameters
    ----------
    mesh : QuadMesh
    tolerance : float or None
        ``within`` and ``level`` are null without one, and at a vertex where a crease ends (its kink is a
        feature, not a defect: such vertices are reported, never gated).
    """
    from ..analysis.extraordinary import cage_vertex_defects

    out = []
    for v in cage_vertex_defects(mesh):
        out.append({"vertex": v.vertex, "face": v.face, "line": _line(mesh, v.vertex, v.face),
                    "valence": v.valence, "boundary": v.boundary,
                    "crease": v.crease, "position": [json_number(c) for c in v.position],
                    "subdominant": json_number(v.lam), "subsubdominant": json_number(v.mu),
                    "curvature": v.curvature, "defects": [json_number(d) for d in v.defects],
                    "defect": json_number(v.defect),
                    # a crease ending at the vertex is a feature the quadratic cannot hold: not gated
                    "within": None if tolerance is None or v.crease else bool(v.defect <= tolerance),
                    "level": None if tolerance is None or v.crease else v.level_within(tolerance)})
    return out


def _line(mesh, vertex: int, face: int | None) -> int | None:
    """The line of a vertex's ``v`` statement, or for a triangle's or n-gon's centre (not in the file) its face's
    ``f`` statement; None for a mesh not read from a file."""
    lines, index = (mesh.vertex_lines, vertex) if face is None else (mesh.face_lines, face)
    return int(lines[index]) if 0 <= index < len(lines) else None


def cage_advice_record(face_records: list, vertices: list) -> dict:
    """:func:`cadartifact.advice.cage_levels.cage_advice` of a file's face records and vertex records."""
    from ..advice.cage_levels import cage_advice

    return cage_advice(face_records, vertices)


def vertex_failure(vertices: list, tolerance: float) -> str | None:
    """The gate's line for extraordinary vertices beyond the tolerance (None: all within)."""
    bad = [v for v in vertices if v["within"] is False]
    if not bad:
        return None
    worst = max(bad, key=lambda v: v["defect"])
    n = len(bad)
    return (f"{n} extraordinary {'vertices' if n > 1 else 'vertex'} beyond the tolerance {tolerance:g} (worst: vertex "
            f"{worst['vertex']}, valence {worst['valence']}, defect {worst['defect']:.3g})")


def measured_around(result, vertices: list) -> list:
    """Level-1 vertex ids (:attr:`LoadResult.refined`'s mesh) of the extraordinary vertices the vertex measure
    analyses, for :func:`cadartifact.runs.records.analysed_share`: a cage vertex keeps its id after a
    Catmull-Clark step (vertex points come first, in the cage's order); a triangle's or n-gon's centre is its face
    point, the third corner of each of its child quads."""
    refined = getattr(result, "refined", None)
    if refined is None:
        return []
    first_child = {}
    for k, f in enumerate(refined.parent):
        first_child.setdefault(int(f), k)
    out = []
    for v in vertices:
        if v.get("defect") is None:
            continue
        if v.get("face") is None:
            out.append(int(v["vertex"]))
        elif int(v["face"]) in first_child:
            out.append(int(refined.mesh.faces[first_child[int(v["face"])]][2]))
    return out


def vertices_and_coverage(result, tolerance: float | None) -> tuple[list | None, float | None]:
    """A file's extraordinary-vertex records (None: not a cage) and its analysed share of area
    (:func:`cadartifact.runs.records.analysed_share`, the measured vertices' quads counted), as every door
    reports them."""
    if getattr(result, "mesh", None) is None:
        return None, analysed_share(result)
    vertices = vertex_records(result.mesh, tolerance)
    return vertices, analysed_share(result, measured_around(result, vertices))

