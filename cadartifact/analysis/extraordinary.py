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

A plane gives 0; a smooth surface's d_k decays like its cubic terms (8^-k); where the curvature is
unbounded d_k decays like mu^k (mu > lambda^2, the sub-subdominant eigenvalue). The first level with
``d_k <= tolerance`` is the subdivision level that brings the vertex within the tolerance
(:func:`level_within`); none within :data:`MAX_LEVEL` means the vertex needs more control (an edge
loop around it).

Reference: Peters and Reif (2008), *Subdivision Surfaces*, ch. 5-7 (the local subdivision matrix and
curvature at extraordinary points); Karčiauskas, Peters and Reif (2004), *Shape characterization of
subdivision surfaces: case studies*.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["VertexDefect", "MAX_LEVEL", "extraordinary_vertices", "vertex_defects", "quadratic_defect",
           "region_limit_points"]

MAX_LEVEL = 6  # the finest subdivision level the advice looks at (64 x finer than the cage)
_RINGS = 3  # rings of faces kept around a vertex (the region's 2-ring and a margin)
_SAMPLE_STEPS = 3  # the region's faces are sampled 2^3 x 2^3 times


@dataclass(frozen=True)
class VertexDefect:
    """One extraordinary vertex's record.

    Attributes
    ----------
    vertex : int
        Vertex id in the cage given (0-based).
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
        ``d_0, d_1, ...`` in model units, up to the first within the tolerance (or :data:`MAX_LEVEL`).
    """

    vertex: int
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
        """``d_0``: the shape defect over the cage's own faces at the vertex."""
        return self.defects[0]

    def level_within(self, tolerance: float) -> int | None:
        """The first level k with ``d_k <= tolerance``, None if none up to :data:`MAX_LEVEL`."""
        return next((k for k, d in enumerate(self.defects) if d <= tolerance), None)


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


def vertex_defects(vertices, faces, tolerance: float | None = None, creases=None,
                   max_level: int = MAX_LEVEL) -> list:
    """One :class:`VertexDefect` per extraordinary vertex of a quad cage.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : sequence of sequence of int
        Quads, consistently oriented (a cage with triangles or n-gons after its first step).
    tolerance : float, optional
        Stop each vertex's levels at the first ``d_k <= tolerance``; None: ``d_0`` only.
    creases : dict, optional
        ``{(a, b): sharpness}``, ``a < b``: OpenSubdiv crease edges.
    max_level : int

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
        for level in range(max_level + 1):
            samples = region_limit_points(P, F, w, C)
            if position is None:
                position = tuple(float(c) for c in samples[0])
            defects.append(quadratic_defect(samples))
            if tolerance is None or defects[-1] <= tolerance or level == max_level:
                break
            S, quads, _, C = subdivision_step(len(P), F, C)
            P1, F1 = S @ P, [tuple(q) for q in quads.tolist()]
            P, F, C, w = _local(P1, F1, _rings(_vertex_faces(len(P1), F1), F1, w, _RINGS), C, w)
        out.append(VertexDefect(v, valence, boundary, crease, position, eig.lam, eig.mu, eig.curvature,
                                tuple(defects)))
    return out
