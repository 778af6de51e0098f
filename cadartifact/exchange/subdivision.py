"""One Catmull-Clark step of a polygon cage, with OpenSubdiv's crease rules.

After the step every face is a quad: a face of ``n`` vertices becomes ``n`` quads (face point,
edge point, vertex point, edge point), so triangles and n-gons join the quad analysis
(SPEC §6). The rules are OpenSubdiv's Catmark scheme (``opensubdiv/sdc/catmarkScheme.h``,
``opensubdiv/sdc/crease.h``), uniform crease decrement:

- face point: the centroid of the face's vertices;
- edge point: smooth ``(a + b + f0 + f1) / 4``; sharp (sharpness ``s >= 1``, or a boundary edge)
  the midpoint ``(a + b) / 2``; semi-sharp ``0 < s < 1``: ``s`` sharp + ``(1 - s)`` smooth. The
  child edges keep sharpness ``max(s - 1, 0)``;
- vertex point by the number of sharp incident edges: fewer than 2 (smooth)
  ``(Q + 2 R + (n - 3) S) / n`` (``Q`` the mean face point, ``R`` the mean edge midpoint, ``n``
  the valence); 2 (crease) ``(6 S + a + b) / 8`` with ``a, b`` the far ends of the sharp edges;
  more (corner) ``S``. A boundary vertex with a single face is a corner (OpenSubdiv's
  ``VTX_BOUNDARY_EDGE_AND_CORNER``, the ``interpolateboundary 2`` of its shapes; ``1`` keeps the
  crease rule there). When the parent's rule and the child's rule differ (a semi-sharp crease
  running out) the point blends them by the mean parent sharpness of the edges that turn smooth,
  capped at 1 (``Crease::ComputeFractionalWeightAtVertex``).

Reference: E. Catmull, J. Clark, "Recursively generated B-spline surfaces on arbitrary topological
meshes", CAD 10(6), 1978; T. DeRose, M. Kass, T. Truong, "Subdivision surfaces in character
animation", SIGGRAPH 1998 (semi-sharp creases).
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Subdivided", "catmull_clark_step", "crease_map"]


@dataclass(frozen=True, eq=False)
class Subdivided:
    """A cage after one Catmull-Clark step.

    Attributes
    ----------
    vertices : (n1, 3) float
        Vertex points (ids ``0..n0-1``, the parent vertices' order), then edge points, then face points.
    faces : list of tuple of int
        Quads, ``faces[k]`` = (vertex point, edge point, face point, edge point) in the parent's winding.
    parent : (f1,) int
        The parent face of each quad.
    creases : dict (int, int) -> float
        Child edge (sorted vertex ids) -> sharpness after the step (only edges still sharp).
    """

    vertices: np.ndarray
    faces: list
    parent: np.ndarray
    creases: dict = field(default_factory=dict)


def _edge(a: int, b: int) -> tuple[int, int]:
    return (a, b) if a < b else (b, a)


def crease_map(edges, sharpness) -> dict:
    """``{(a, b): s}`` of crease edges with ``s > 0`` (sorted ids; the largest sharpness of a repeated edge)."""
    out: dict = {}
    for (a, b), s in zip(np.asarray(edges, int).reshape(-1, 2).tolist(), np.asarray(sharpness, float).tolist()):
        if s > 0:
            e = _edge(a, b)
            out[e] = max(out.get(e, 0.0), float(s))
    return out


def _rule(sharp_count: int, corner: bool) -> str:
    if corner or sharp_count > 2:
        return "corner"
    return "crease" if sharp_count == 2 else "smooth"


def catmull_clark_step(vertices, faces, creases: dict | None = None, boundary_corners: bool = True) -> Subdivided:
    """Subdivide a polygon cage once by Catmull-Clark (module notes: OpenSubdiv's Catmark rules).

    Parameters
    ----------
    vertices : (n, 3) float
    faces : sequence of sequence of int
        Polygons of 3 or more vertex ids, manifold (each edge in at most two faces).
    creases : dict (int, int) -> float, optional
        Edge sharpness (:func:`crease_map`); boundary edges are infinitely sharp whatever it says.
    boundary_corners : bool
        A boundary vertex with one face stays where it is (``interpolateboundary 2``).

    Returns
    -------
    Subdivided
    """
    v = np.asarray(vertices, float).reshape(-1, 3)
    faces = [tuple(int(i) for i in f) for f in faces]
    creases = dict(creases or {})
    n0 = len(v)
    edge_faces: dict = defaultdict(list)
    vertex_faces: dict = defaultdict(list)
    vertex_edges: dict = defaultdict(list)
    for k, face in enumerate(faces):
        for i, a in enumerate(face):
            e = _edge(a, face[(i + 1) % len(face)])
            if not edge_faces[e]:
                vertex_edges[e[0]].append(e)
                vertex_edges[e[1]].append(e)
            edge_faces[e].append(k)
            vertex_faces[a].append(k)
    edges = list(edge_faces)
    edge_id = {e: n0 + i for i, e in enumerate(edges)}
    face_id0 = n0 + len(edges)
    fpts = np.array([v[list(f)].mean(axis=0) for f in faces]).reshape(-1, 3)

    def sharp(e) -> float:
        return np.inf if len(edge_faces[e]) == 1 else creases.get(e, 0.0)

    # edge points
    epts = np.empty((len(edges), 3))
    for i, e in enumerate(edges):
        mid = 0.5 * (v[e[0]] + v[e[1]])
        s = sharp(e)
        if s >= 1:
            epts[i] = mid
            continue
        fs = edge_faces[e]
        smooth = 0.5 * mid + 0.5 * fpts[fs].mean(axis=0) if len(fs) == 2 else mid
        epts[i] = s * mid + (1 - s) * smooth if s > 0 else smooth

    # vertex points
    vpts = v.copy()
    for a in range(n0):
        es = vertex_edges.get(a)
        if not es:
            continue
        fs = vertex_faces[a]
        s_parent = [sharp(e) for e in es]
        s_child = [max(s - 1.0, 0.0) for s in s_parent]
        corner = boundary_corners and len(fs) == 1 and any(len(edge_faces[e]) == 1 for e in es)
        parent_rule = _rule(sum(s > 0 for s in s_parent), corner)
        child_rule = _rule(sum(s > 0 for s in s_child), corner)

        def point(rule, sharpness):
            if rule == "corner":
                return v[a]
            if rule == "crease":
                far = [e[0] if e[1] == a else e[1] for e, s in zip(es, sharpness) if s > 0]
                return (6 * v[a] + v[far[0]] + v[far[1]]) / 8
            n = len(es)
            q = fpts[fs].mean(axis=0)
            r = np.mean([0.5 * (v[e[0]] + v[e[1]]) for e in es], axis=0)
            return (q + 2 * r + (n - 3) * v[a]) / n

        if parent_rule == child_rule or parent_rule == "smooth":
            vpts[a] = point(parent_rule, s_parent)
        else:  # a semi-sharp feature running out at this level
            turning = [s for s, c in zip(s_parent, s_child) if s > 0 and c <= 0]
            w = min(float(np.mean(turning)), 1.0) if turning else 0.0
            vpts[a] = w * point(parent_rule, s_parent) + (1 - w) * point(child_rule, s_child)

    child_vertices = np.vstack([vpts, epts, fpts])
    child_faces, parent = [], []
    new_creases: dict = {}
    for k, face in enumerate(faces):
        m = len(face)
        for i, a in enumerate(face):
            e_next = edge_id[_edge(a, face[(i + 1) % m])]
            e_prev = edge_id[_edge(face[i - 1], a)]
            child_faces.append((a, e_next, face_id0 + k, e_prev))
            parent.append(k)
    for e in edges:
        s = creases.get(e, 0.0)
        if s > 1 and len(edge_faces[e]) == 2:
            for end in e:
                new_creases[_edge(end, edge_id[e])] = s - 1.0
    return Subdivided(vertices=child_vertices, faces=child_faces, parent=np.array(parent, dtype=int),
                      creases=new_creases)


@dataclass(frozen=True, eq=False)
class Refined:
    """A cage after its first Catmull-Clark step, where its triangles, n-gons and irregular quads are analysed.

    Attributes
    ----------
    level : int
        1 (one step).
    mesh : QuadMesh
        Every face a quad, with its regularity analysis and the creases still sharp.
    topology : dict
        As :func:`~cadartifact.exchange.quadmesh.build_quadmesh` gives it.
    parent : (f1,) int
        The face of the cage as read that each quad comes from.
    """

    level: int
    mesh: object
    topology: dict = field(repr=False)
    parent: np.ndarray = field(repr=False)


def refine_cage(path, mesh) -> Refined:
    """The cage ``mesh`` (:class:`~cadartifact.exchange.quadmesh.QuadMesh`) after one Catmull-Clark step, its
    crease tags honoured (sharpness decremented by one) and its ``interpolateboundary`` tag read (``1``: edges
    only, boundary corners smooth; otherwise corners kept)."""
    from .quadmesh import Tag, build_quadmesh

    corners = not any(t.name == "interpolateboundary" and t.ints[:1] == (1,) for t in mesh.tags)
    step = catmull_clark_step(mesh.vertices, mesh.faces, crease_map(mesh.crease_edges, mesh.crease_sharpness),
                              boundary_corners=corners)
    tags = [t for t in mesh.tags if t.name != "crease"]
    if step.creases:
        pairs = list(step.creases.items())
        tags.append(Tag("crease", tuple(i for e, _ in pairs for i in e), tuple(s for _, s in pairs)))
    child, topology = build_quadmesh(path, step.vertices, step.faces, tags)
    return Refined(level=1, mesh=child, topology=topology, parent=step.parent)
