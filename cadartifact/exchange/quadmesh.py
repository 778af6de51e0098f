"""Quad meshes (subdivision cages): topology, regular faces and rectangular grid charts.

Definitions (SPEC §6)
---------------------
- A vertex's *fan* is its incident faces linked through shared edges at the vertex.
  A vertex is *interior* when its fan is closed, *boundary* when it is one open chain.
- **Regular vertex**: all incident faces are quads, one fan, and either interior with
  4 faces (valence 4), boundary with 2 faces (valence 3) or a boundary corner with
  1 face (valence 2). The surface of a Catmull-Clark cage is a uniform bicubic
  B-spline around such vertices.
- **Extraordinary vertex**: interior valence != 4, or boundary with 3 or more faces
  (valence >= 4; OpenSubdiv's irregular boundary vertex).
- **Irregular vertex**: any vertex used by a face that is not regular (extraordinary,
  touching a triangle or n-gon, or non-manifold with several fans).
- **Regular face**: a quad whose 4 vertices are all regular. Only regular faces are
  analysed; triangles, n-gons and quads touching an irregular vertex are reported.

Charts
------
The regular faces form a quad mesh with holes around the irregular vertices. It
is cut along OpenSubdiv crease edges (sharpness > 0) and along the separatrices
of its concave corners: at every vertex where 3 regular faces meet around a
missing quarter (the corners of the holes left by extraordinary vertices and
non-quads, and irregular boundary corners), the shorter of the two grid lines
that continue its border edges is traced straight through regular valence-4
vertices until it meets a border or an earlier trace (a motorcycle graph; one
cut per corner leaves only convex and straight corners). The pieces are then rectangles; each is
collected by growing a rectangle of faces row by row (never across a cut, never
reusing a vertex, which also splits cylinders and tori). Every regular face lies
in exactly one chart; a chart of one quad is 2x2 points.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np

from ..errors import FileFormatError
from ..numerics.arrays import frozen_array
from .messages import quote

__all__ = ["Tag", "QuadMesh", "Chart", "build_quadmesh", "find_charts"]


@dataclass(frozen=True)
class Tag:
    """An OpenSubdiv ``t`` statement: name and its integer, float and string arguments."""

    name: str
    ints: tuple[int, ...] = ()
    floats: tuple[float, ...] = ()
    strings: tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class QuadMesh:
    """A polygon mesh read without triangulation, with its regularity analysis.

    Attributes
    ----------
    vertices : (n, 3) float
    faces : tuple of tuple of int
        0-based vertex ids of every face, in file order (quads stay quads).
    face_sizes : (f,) int
    regular_faces : (f,) bool
        Quads whose four vertices are regular (see the module notes).
    valence : (n,) int
        Edges at each vertex (0 for an unused vertex).
    boundary : (n,) bool
        Vertices on an open edge.
    extraordinary : (k,) int
        Vertex ids: interior valence != 4, or boundary valence >= 4.
    irregular : (k,) int
        Vertex ids that are not regular (includes ``extraordinary``).
    crease_edges : (m, 2) int
        OpenSubdiv ``t crease`` edges (0-based vertex ids, as OpenSubdiv writes them).
    crease_sharpness : (m,) float
    tags : tuple of Tag
        Every ``t`` statement as read (creases included).
    path : str or None
    vertex_lines, face_lines : tuple of int
        The 1-based line of each vertex's ``v`` and each face's ``f`` statement in the file (empty: a mesh not
        read from a file, or a subdivided one).
    """

    vertices: np.ndarray
    faces: tuple
    face_sizes: np.ndarray
    regular_faces: np.ndarray
    valence: np.ndarray
    boundary: np.ndarray
    extraordinary: np.ndarray
    irregular: np.ndarray
    crease_edges: np.ndarray
    crease_sharpness: np.ndarray
    tags: tuple[Tag, ...] = ()
    path: str | None = None
    vertex_lines: tuple[int, ...] = ()
    face_lines: tuple[int, ...] = ()

    @property
    def n_faces(self) -> int:
        return len(self.faces)

    @property
    def n_quads(self) -> int:
        return int(np.count_nonzero(self.face_sizes == 4))

    @property
    def n_triangles(self) -> int:
        return int(np.count_nonzero(self.face_sizes == 3))

    @property
    def n_ngons(self) -> int:
        """Faces with 5 or more vertices."""
        return int(np.count_nonzero(self.face_sizes > 4))

    @property
    def n_regular_faces(self) -> int:
        return int(np.count_nonzero(self.regular_faces))


@dataclass(frozen=True, eq=False)
class Chart:
    """A rectangular grid of mesh vertices: one control net.

    Attributes
    ----------
    index : int
        Chart number (the net's ``origin.face``).
    vertex_ids : (nu, nv) int
        Mesh vertex of each net point.
    face_ids : (nu-1, nv-1) int
        Mesh face (index into ``QuadMesh.faces``) of each grid cell.
    level : int
        Subdivision level of the mesh the ids refer to: 0 the cage as read, 1 the cage after one
        Catmull-Clark step (:class:`~cadartifact.exchange.subdivision.Refined`).
    """

    index: int
    vertex_ids: np.ndarray = field(repr=False)
    face_ids: np.ndarray = field(repr=False)
    level: int = 0

    @property
    def shape(self) -> tuple[int, int]:
        return self.vertex_ids.shape


# ---------------------------------------------------------------- topology
def _edge(a: int, b: int) -> tuple[int, int]:
    return (a, b) if a < b else (b, a)


def _fans(v: int, faces_at_v, faces, linked) -> list[list[int]]:
    """Group the faces at ``v`` into fans: faces linked through an edge at ``v`` when ``linked(edge)``."""
    by_edge = defaultdict(list)
    for f in faces_at_v:
        face = faces[f]
        k = face.index(v)
        for w in (face[k - 1], face[(k + 1) % len(face)]):
            by_edge[_edge(v, w)].append(f)
    parent = {f: f for f in faces_at_v}

    def root(f):
        while parent[f] != f:
            parent[f] = parent[parent[f]]
            f = parent[f]
        return f

    for e, fs in by_edge.items():
        if len(fs) == 2 and linked(e):
            parent[root(fs[0])] = root(fs[1])
    groups = defaultdict(list)
    for f in faces_at_v:
        groups[root(f)].append(f)
    return list(groups.values())


def build_quadmesh(path, vertices: np.ndarray, faces: list[tuple[int, ...]], tags=()) -> tuple[QuadMesh, dict]:
    """Analyse a polygon mesh's topology.

    Returns
    -------
    mesh : QuadMesh
    topology : dict
        ``edge_faces`` (edge -> face ids) and ``faces_at`` (vertex -> face ids), reused by
        :func:`find_charts`.

    Raises
    ------
    FileFormatError
        An edge shared by more than two faces (non-manifold mesh).
    """
    n = len(vertices)
    edge_faces: dict[tuple[int, int], list[int]] = defaultdict(list)
    faces_at: dict[int, list[int]] = defaultdict(list)
    for f, face in enumerate(faces):
        for k, a in enumerate(face):
            faces_at[a].append(f)
            edge_faces[_edge(a, face[(k + 1) % len(face)])].append(f)
    for e, fs in edge_faces.items():
        if len(fs) > 2:
            raise FileFormatError(path, f"non-manifold mesh: edge {e[0] + 1}-{e[1] + 1} is shared by {len(fs)} faces")
    sizes = np.array([len(face) for face in faces], dtype=int)
    valence = np.zeros(n, dtype=int)
    boundary = np.zeros(n, dtype=bool)
    for (a, b), fs in edge_faces.items():
        valence[a] += 1
        valence[b] += 1
        if len(fs) == 1:
            boundary[a] = boundary[b] = True
    regular_vertex = np.zeros(n, dtype=bool)
    extraordinary = []
    for v, fs in faces_at.items():
        nf = len(fs)
        if boundary[v]:
            if nf >= 3:
                extraordinary.append(v)
        elif nf != 4:
            extraordinary.append(v)
        single_fan = len(_fans(v, fs, faces, lambda e: True)) == 1
        all_quads = all(sizes[f] == 4 for f in fs)
        shape_ok = (not boundary[v] and nf == 4) or (boundary[v] and nf <= 2)
        regular_vertex[v] = single_fan and all_quads and shape_ok
    used = np.array(sorted(faces_at), dtype=int)
    irregular = used[~regular_vertex[used]] if len(used) else used
    regular_faces = np.array([len(face) == 4 and all(regular_vertex[a] for a in face) for face in faces], dtype=bool)

    crease_edges, sharpness = [], []
    for tag in tags:
        if tag.name != "crease" or len(tag.ints) < 2:
            continue
        pairs = [tag.ints[i:i + 2] for i in range(0, len(tag.ints) - 1, 2)]
        for i, (a, b) in enumerate(pairs):
            s = tag.floats[i] if i < len(tag.floats) else (tag.floats[0] if tag.floats else 0.0)
            bad = next((k for k in (a, b) if not 0 <= k < n), None)
            if bad is not None:  # also keeps indices >= 2**63 out of numpy's int64
                raise FileFormatError(path, f"crease tag refers to vertex index {quote(str(bad))} (0-based), "
                                      f"but the mesh has {n} vertices")
            if s != s:
                raise FileFormatError(path, f"crease tag on edge {a}-{b} has a NaN sharpness")
            crease_edges.append((a, b))
            sharpness.append(s)
    mesh = QuadMesh(
        vertices=frozen_array(vertices, float), faces=tuple(tuple(f) for f in faces), face_sizes=frozen_array(sizes, int),
        regular_faces=frozen_array(regular_faces, bool), valence=frozen_array(valence, int), boundary=frozen_array(boundary, bool),
        extraordinary=frozen_array(sorted(extraordinary), int), irregular=frozen_array(irregular, int),
        crease_edges=frozen_array(np.array(crease_edges, dtype=int).reshape(-1, 2), int),
        crease_sharpness=frozen_array(sharpness, float), tags=tuple(tags),
        path=None if path is None else str(path))
    return mesh, {"edge_faces": edge_faces, "faces_at": faces_at}


# ---------------------------------------------------------------- charts
class _Region:
    """The regular faces with their cut edges; answers adjacency questions for tracing and growth."""

    def __init__(self, mesh: QuadMesh, topology: dict, analysed=None):
        self.faces = mesh.faces
        self.regular = mesh.regular_faces if analysed is None else mesh.regular_faces & np.asarray(analysed, bool)
        self.edge_faces = topology["edge_faces"]
        self.faces_at = topology["faces_at"]
        self.cut: set[tuple[int, int]] = set()
        for (a, b), s in zip(mesh.crease_edges.tolist(), mesh.crease_sharpness.tolist()):
            if s > 0:
                self.cut.add(_edge(a, b))

    def linked(self, e) -> bool:
        """Whether two regular faces are joined across edge ``e`` inside the region."""
        fs = self.edge_faces.get(e, ())
        return len(fs) == 2 and self.regular[fs[0]] and self.regular[fs[1]] and e not in self.cut

    def regular_fans(self, v: int) -> list[list[int]]:
        fs = [f for f in self.faces_at.get(v, ()) if self.regular[f]]
        return _fans(v, fs, self.faces, self.linked) if fs else []

    def fan_chain(self, v: int, fan: list[int]):
        """Order an open fan: (faces in order, the interior edges between consecutive faces)."""
        if len(fan) == 1:
            return fan, []
        links = defaultdict(list)  # face -> [(edge, other face)]
        for f in fan:
            face = self.faces[f]
            k = face.index(v)
            for w in (face[k - 1], face[(k + 1) % 4]):
                e = _edge(v, w)
                if self.linked(e):
                    g = next(x for x in self.edge_faces[e] if x != f)
                    if g in fan:
                        links[f].append((e, g))
        ends = [f for f in fan if len(links[f]) == 1]
        if not ends:
            return None, None  # closed fan
        order, edges, prev = [min(ends)], [], None
        while True:
            step = [(e, g) for e, g in links[order[-1]] if g != prev]
            if not step:
                break
            e, g = step[0]
            prev = order[-1]
            order.append(g)
            edges.append(e)
        return order, edges

    def through(self, w: int, v: int) -> int | None:
        """The edge opposite ``(v, w)`` at a closed valence-4 fan ``w``, else None (a trace stops)."""
        fans = self.regular_fans(w)
        if len(fans) != 1 or len(fans[0]) != 4 or self.fan_chain(w, fans[0])[0] is not None:
            return None
        neighbours = set()
        for f in fans[0]:
            face = self.faces[f]
            k = face.index(w)
            neighbours.update((face[k - 1], face[(k + 1) % 4]))
        beside = set()
        for f in self.edge_faces[_edge(v, w)]:
            face = self.faces[f]
            k = face.index(w)
            beside.update(x for x in (face[k - 1], face[(k + 1) % 4]) if x != v)
        rest = neighbours - beside - {v}
        return rest.pop() if len(rest) == 1 else None

    def trace(self, v: int, w: int, dry: bool = False) -> int:
        """Cut along the grid line from ``v`` through ``w`` until it meets a border or a cut.

        Returns the number of edges cut (``dry=True``: that would be cut, cutting none).
        """
        seen = set()
        while True:
            e = _edge(v, w)
            if e in self.cut or e in seen:
                return len(seen)
            nxt = self.through(w, v)  # decided before cutting, so the fan at w is still whole
            seen.add(e)
            if not dry:
                self.cut.add(e)
            if nxt is None:
                return len(seen)
            v, w = w, nxt

    def cut_separatrices(self, vertices) -> None:
        """Cut from every concave corner (open fan of 3 faces) and slit end (open fan of 4).

        One cut per corner suffices to leave only convex and straight corners: of the two
        grid lines continuing the corner's border edges, the shorter one is traced (fewer,
        larger charts than tracing both); at a slit end the line continuing the slit.
        """
        for v in vertices:
            for fan in self.regular_fans(v):
                if len(fan) < 3:
                    continue
                order, edges = self.fan_chain(v, fan)
                if order is None:
                    continue
                # open chain f0 e0 f1 e1 f2 (e2 f3): a concave corner or the end of a slit
                candidates = edges if len(fan) == 3 else edges[1:2]
                ends = [e[0] if e[1] == v else e[1] for e in candidates]
                w = min(ends, key=lambda x: (self.trace(v, x, dry=True), x))
                self.trace(v, w)


def _extend(region: _Region, V: np.ndarray, F: np.ndarray, free: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Append one row of faces below the last row of ``V`` (vertices) / ``F`` (faces), or None."""
    last = V[-1]
    used = set(V.ravel().tolist())
    new_row, new_faces = [], []
    for k in range(len(last) - 1):
        a, b = int(last[k]), int(last[k + 1])
        e = _edge(a, b)
        if not region.linked(e):
            return None
        g = next(x for x in region.edge_faces[e] if x != F[-1, k])
        if not free[g]:
            return None
        face = region.faces[g]
        ia, ib = face.index(a), face.index(b)
        # in the quad (..., a, b, ...) the vertex next to a away from b, and next to b away from a
        step = 1 if (ia + 1) % 4 == ib else -1
        x = face[(ia - step) % 4]
        y = face[(ib + step) % 4]
        if k == 0:
            new_row.append(x)
        elif new_row[-1] != x or not region.linked(_edge(a, x)):
            return None
        new_row.append(y)
        new_faces.append(g)
    if len(set(new_row)) != len(new_row) or used.intersection(new_row) or len(set(new_faces)) != len(new_faces):
        return None
    return np.vstack([V, new_row]), np.vstack([F, new_faces])


# views that turn "grow at side s" into "append a row at the bottom", and their inverses
_VIEWS = (
    (lambda a: a, lambda a: a),
    (lambda a: a.T, lambda a: a.T),
    (lambda a: a[::-1], lambda a: a[::-1]),
    (lambda a: a.T[::-1], lambda a: a[::-1].T),
)


def _grow(region: _Region, seed: int, free: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    face = region.faces[seed]
    V = np.array([[face[0], face[3]], [face[1], face[2]]], dtype=int)
    F = np.array([[seed]], dtype=int)
    free[seed] = False
    grown = True
    while grown:
        grown = False
        for view, back in _VIEWS:
            result = _extend(region, view(V), view(F), free)
            if result is not None:
                V, F = back(result[0]), back(result[1])
                free[F.ravel()] = False
                grown = True
    return np.ascontiguousarray(V), np.ascontiguousarray(F)


def find_charts(mesh: QuadMesh, topology: dict, analysed=None) -> list[Chart]:
    """Split the regular faces into rectangular grid charts (see the module notes).

    ``analysed`` ``(f,) bool``: only these faces (and regular) are charted; default every face.

    Returns
    -------
    charts : list of Chart
        Disjoint; together they cover every regular face exactly once. Seeds are
        taken at convex corners first (so a rectangular piece comes out whole and in
        a stable orientation), then in face order.
    """
    region = _Region(mesh, topology, analysed)
    regular_ids = np.flatnonzero(region.regular)
    if len(regular_ids) == 0:
        return []
    touched = sorted({v for f in regular_ids for v in mesh.faces[f]})
    region.cut_separatrices(touched)
    corner_faces = sorted({fan[0] for v in touched for fan in region.regular_fans(v) if len(fan) == 1})
    free = np.array(region.regular, bool)
    charts = []
    for seed in [*corner_faces, *regular_ids.tolist()]:
        if not free[seed]:
            continue
        V, F = _grow(region, seed, free)
        charts.append(Chart(index=len(charts), vertex_ids=frozen_array(V, int), face_ids=frozen_array(F, int)))
    return charts
