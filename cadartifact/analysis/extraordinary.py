"""Extraordinary vertices of a Catmull-Clark cage: the shape defect of the limit surface around each (SPEC §6).

The measure
-----------
Around an extraordinary vertex the limit surface is not a bicubic spline but the scheme's own
construction, and its defects (flat spots at valence 3, curvature diverging at valence 5 and more:
:mod:`cadartifact.theory.vertex_eigen`) are where zebra stripes break. Its *shape defect* at level k is

    d_k = max over the limit points x of the vertex's faces at level k of |h(x) - q(x)|,

``h`` the height of the limit surface over its tangent plane at the vertex (the frame of the principal
axes of the limit points around the vertex's limit point), ``q`` the best quadratic
``a + b x + c y + d x^2 + e x y + f y^2`` in the least-squares sense over those points, in model units.
Level 0 is the cage (its faces after one step when the cage has triangles or n-gons: the caller's
cage); level k is the region k steps finer, half as wide per step. The limit points are the limit
positions (:func:`cadartifact.numerics.catmull_clark.limit_stencil`) of the vertices of the region's
faces three steps finer (8 x 8 quads per face), computed on the vertex's 3-ring of faces only (the
subdivision of the region depends on its 2-ring; one more ring is kept as a margin).

A plane gives 0. On a curved cage d_0 is mostly the design's own shape (a regular vertex of
``samples/cage.obj`` has d_0 = 0.55 model units, more than its extraordinary vertex's 0.38): no
quadratic holds a curved surface over a whole ring of a coarse cage. Finer levels separate the two:
a smooth surface's d_k decays like its cubic terms (8^-k), the vertex's own defect like mu^k (mu the
sub-subdominant eigenvalue: 1/6, 0.34, 0.41, 0.5 for valences 3, 5, 6, 8; the test family measures
it). The vertex's **defect** is therefore d_3 extrapolated back to the cage's scale,

    defect = d_3 / mu^3,

in model units, where the design's share of d_0 has fallen by (8 mu)^3 (20 at valence 5, 64 at 8;
only 2.4 at valence 3, whose mu is close to 1/8). It is what the gate holds against the tolerance.
Its defect at level k is ``defect * mu^k``: the first k where that is within the tolerance is the
subdivision level (or local refinement: edge loops around the vertex) that brings the vertex within
it (:meth:`VertexDefect.level_within`); beyond :data:`MAX_LEVEL` the vertex needs more control.

Reference: Peters and Reif (2008), *Subdivision Surfaces*, ch. 5-7 (the local subdivision matrix and
curvature at extraordinary points); Karčiauskas, Peters and Reif (2004), *Shape characterization of
subdivision surfaces: case studies*.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["VertexDefect", "MAX_LEVEL", "MEASURE_LEVEL", "extraordinary_vertices", "vertex_defects",
           "quadratic_defect", "region_limit_points", "cage_vertex_defects"]

MAX_LEVEL = 6  # the finest subdivision level the advice looks at (64 x finer than the cage)
MEASURE_LEVEL = 3  # the level whose d_k gives the defect (d_3 / mu^3)
_RINGS = 3  # rings of faces kept around a vertex (the region's 2-ring and a margin)
_SAMPLE_STEPS = 3  # the region's faces are sampled 2^3 x 2^3 times


@dataclass(frozen=True)
class VertexDefect:
    """One extraordinary vertex's record.

    Attributes
    ----------
    vertex : int
        Vertex id in the cage given (0-based); ids from the cage's vertex count on are the centres of
        its triangles and n-gons (``face``).
    face : int or None
        The cage's face whose centre the vertex is (a triangle or n-gon after the first step), else None.
    valence : int
    boundary : bool
    crease : bool
        A crease edge (sharpness > 0) ends at the vertex: the eigenvalues are those of the smooth rules
        and do not describe it.
    position : (3,) float
        Its limit position.
    lam, mu : float
        Subdominant and sub-subdominant eigenvalues of its local subdivision matrix.
    curvature : str
        ``"bounded"``, ``"zero"`` or ``"unbounded"`` (:mod:`cadartifact.theory.vertex_eigen`).
    defects : tuple of float
        ``d_0 .. d_3`` in model units (module notes).
    """

    vertex: int
    face: int | None
    valence: int
    boundary: bool
    crease: bool
    position: tuple
    lam: float
    mu: float
    curvature: str
    defects: tuple

    @property
    def defect(self) -> float:
        """``d_3 / mu^3``: the vertex's own shape defect at the cage's scale, in model units."""
        if len(self.defects) <= MEASURE_LEVEL or not self.mu > 0:
            return self.defects[-1]
        return self.defects[MEASURE_LEVEL] / self.mu ** MEASURE_LEVEL

    def level_within(self, tolerance: float) -> int | None:
        """The first level k with ``defect * mu^k <= tolerance``; None beyond :data:`MAX_LEVEL`."""
        d = self.defect
        for k in range(MAX_LEVEL + 1):
            if d <= tolerance:
                return k
            d *= self.mu
        return None


def _vertex_faces(n: int, faces) -> list:
    out: list = [[] for _ in range(n)]
    for k, f in enumerate(faces):
        for v in f:
            out[v].append(k)
    return out


def extraordinary_vertices(n_vertices: int, faces) -> list:
    """Vertex ids of a quad mesh that are extraordinary, with their valence and whether on a boundary.

    Returns
    -------
    list of (int, int, bool)
        ``(vertex, valence, boundary)``: interior with valence != 4, or boundary with 3 or more faces
        (valence >= 4). Vertices whose fan is not one chain of quads are left out.
    """
    from ..numerics.catmull_clark import one_ring, topology

    top = topology(n_vertices, faces)
    out = []
    for v in range(n_vertices):
        if not top.vertex_faces[v]:
            continue
        ring = one_ring(top, v)
        if ring is None:
            continue
        edges, _, closed = ring
        n = len(edges)
        if (closed and n != 4) or (not closed and n >= 4):
            out.append((v, n, not closed))
    return out


def _rings(vf, faces, v: int, rings: int) -> list:
    """Face ids within ``rings`` rings of vertex ``v`` (ring 1: the faces at ``v``)."""
    chosen = set(vf[v])
    front = set(chosen)
    for _ in range(rings - 1):
        verts = {w for k in front for w in faces[k]}
        new = {k for w in verts for k in vf[w]} - chosen
        chosen |= new
        front = new
    return sorted(chosen)


def _local(points: np.ndarray, faces, ids, creases, v: int):
    """The sub-mesh of faces ``ids`` renumbered: (points, faces, creases, v's new id)."""
    used = sorted({w for k in ids for w in faces[k]})
    new = {w: i for i, w in enumerate(used)}
    sub = [tuple(new[w] for w in faces[k]) for k in ids]
    sc = {}
    for (a, b), s in creases.items():
        if a in new and b in new:
            x, y = new[a], new[b]
            sc[(min(x, y), max(x, y))] = s
    return points[used], sub, sc, new[v]


def region_limit_points(points: np.ndarray, faces, v: int, creases=None, steps: int = _SAMPLE_STEPS) -> np.ndarray:
    """Limit points of the faces at vertex ``v``, sampled ``2^steps`` times per face edge.

    Parameters
    ----------
    points : (n, 3) float
    faces : list of tuple of int
        A quad mesh around ``v`` (at least its 3-ring of faces for exact values).
    v : int
    creases : dict, optional
        ``{(a, b): sharpness}``.
    steps : int

    Returns
    -------
    (m, 3) float
        The limit positions of the vertices of the region's faces after ``steps`` steps; the first row is
        ``v``'s.
    """
    from ..numerics.catmull_clark import limit_stencil, subdivision_step

    creases = dict(creases or {})
    P = np.asarray(points, float)
    F = np.asarray(faces, int)
    inside = (F == v).any(axis=1)
    for _ in range(steps):
        S, F, parent, creases = subdivision_step(len(P), F.tolist(), creases)
        P = S @ P
        inside = inside[parent]
        # the region and 2 rings around it: what the next step and the limit stencil read
        keep = inside.copy()
        for _ in range(2):
            keep |= np.isin(F, F[keep]).any(axis=1)
        used, F = np.unique(F[keep], return_inverse=True)
        F = F.reshape(-1, 4)
        P, inside, v = P[used], inside[keep], int(np.searchsorted(used, v))
        new = {int(w): i for i, w in enumerate(used)}
        creases = {(new[a], new[b]): s for (a, b), s in creases.items() if a in new and b in new}
    ids = np.unique(F[inside].ravel())
    ids = np.concatenate([[v], ids[ids != v]])
    return np.asarray(limit_stencil(len(P), F, creases, rows=ids) @ P)


def quadratic_defect(samples: np.ndarray) -> float:
    """``max |h - q|``: the samples' deviation from their best quadratic height over the tangent plane.

    Parameters
    ----------
    samples : (m, 3) float
        Limit points; the first is the vertex's (the frame's origin).

    Returns
    -------
    float
        In the samples' units. The frame's normal is the principal axis of least spread of
        ``samples - samples[0]``; ``q`` is the least-squares fit of ``1, x, y, x^2, x y, y^2``.
    """
    X = np.asarray(samples, float) - samples[0]
    scale = np.abs(X).max()
    if not scale > 0:
        return 0.0
    _, _, Vt = np.linalg.svd(X / scale, full_matrices=False)
    x, y, h = (X @ Vt.T).T
    A = np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=1)
    coef, *_ = np.linalg.lstsq(A, h, rcond=None)
    return float(np.abs(h - A @ coef).max())


def vertex_defects(vertices, faces, creases=None, levels: int = MEASURE_LEVEL, first_new: int | None = None) -> list:
    """One :class:`VertexDefect` per extraordinary vertex of a quad cage.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : sequence of sequence of int
        Quads, consistently oriented (a cage with triangles or n-gons after its first step).
    creases : dict, optional
        ``{(a, b): sharpness}``, ``a < b``: OpenSubdiv crease edges.
    levels : int
        ``d_0 .. d_levels`` are measured (the defect needs :data:`MEASURE_LEVEL`).
    first_new : int, optional
        Vertices from this id on are face centres of a first step (see :func:`cage_vertex_defects`).

    Returns
    -------
    list of VertexDefect
        In vertex order.
    """
    from ..numerics.catmull_clark import subdivision_step
    from ..theory.vertex_eigen import vertex_eigen

    P0 = np.asarray(vertices, float)
    F0 = [tuple(int(i) for i in f) for f in faces]
    creases = {(min(a, b), max(a, b)): float(s) for (a, b), s in (creases or {}).items() if s > 0}
    vf0 = _vertex_faces(len(P0), F0)
    out = []
    for v, valence, boundary in extraordinary_vertices(len(P0), F0):
        crease = any(v in e for e in creases)
        eig = vertex_eigen(valence, boundary)
        P, F, C, w = _local(P0, F0, _rings(vf0, F0, v, _RINGS), creases, v)
        defects, position = [], None
        for level in range(levels + 1):
            samples = region_limit_points(P, F, w, C)
            if position is None:
                position = tuple(float(c) for c in samples[0])
            defects.append(quadratic_defect(samples))
            if level == levels:
                break
            S, quads, _, C = subdivision_step(len(P), F, C)
            P1, F1 = S @ P, [tuple(q) for q in quads.tolist()]
            P, F, C, w = _local(P1, F1, _rings(_vertex_faces(len(P1), F1), F1, w, _RINGS), C, w)
        face = None if first_new is None or v < first_new else v - first_new
        out.append(VertexDefect(v, face, valence, boundary, crease, position, eig.lam, eig.mu, eig.curvature,
                                tuple(defects)))
    return out


def cage_vertex_defects(mesh) -> list:
    """:func:`vertex_defects` of a cage read from a file, with its creases; a cage with triangles or n-gons
    is taken after its first step (their centres become extraordinary vertices, ``face`` set).

    Parameters
    ----------
    mesh : cadartifact.exchange.quadmesh.QuadMesh

    Returns
    -------
    list of VertexDefect
        Vertex ids are the cage's (the face centres' ids follow the cage's vertices).
    """
    from ..numerics.catmull_clark import subdivision_step

    creases = {}
    for (a, b), s in zip(np.asarray(mesh.crease_edges).tolist(), np.asarray(mesh.crease_sharpness).tolist()):
        if s > 0:
            creases[(min(a, b), max(a, b))] = float(s)
    V = np.asarray(mesh.vertices, float)
    faces = [tuple(f) for f in mesh.faces]
    if all(len(f) == 4 for f in faces):
        return vertex_defects(V, faces, creases)
    S, quads, _, finer = subdivision_step(len(V), faces, creases)
    recs = vertex_defects(S @ V, quads.tolist(), finer, first_new=len(V))
    # edge points have 4 faces (2 on a boundary): never extraordinary after one step
    return [r for r in recs if r.face is None or r.vertex < len(V) + len(faces)]
