"""Catmull-Clark subdivision of a polygon mesh as sparse matrices: one step, and the limit stencil.

The rules are Catmull and Clark's (1978) as OpenSubdiv applies them with its default boundary
interpolation (``VTX_BOUNDARY_EDGE_ONLY``): boundary edges (one face) and non-manifold edges (three
or more faces) are infinitely sharp creases.

- face point: the centroid of the face;
- edge point: ``(a + b + F1 + F2) / 4`` for a smooth edge, ``(a + b) / 2`` for a sharp one;
- vertex point of a smooth vertex of valence n (or a dart: one sharp edge): ``(F + 2 R + (n - 3) v) / n``,
  ``F`` the mean of its face points, ``R`` the mean of its edges' midpoints; on exactly two sharp edges
  (a boundary, a boundary corner of one face included): ``(a + 6 v + b) / 8``; on more than two: ``v``.

Crease edges (OpenSubdiv's ``t crease``) are given as a sharpness per edge: 10 or more is infinitely
sharp; a semi-sharp edge of sharpness s is sharp for ``ceil(s)`` steps and smooth after them (its
halves carry ``s - 1``; OpenSubdiv's fractional blending of the last step is not reproduced).

Vertex ids persist: the new mesh's points are ``[vertex points, face points, edge points]``, so
vertex ``i`` of the cage is vertex ``i`` at every level. After one step every face is a quad.

The limit position of a vertex of an all-quad mesh (Halstead, Kass and DeRose 1993, eq. 2):
``(n^2 v + 4 sum e_j + sum d_j) / (n (n + 5))`` for a smooth vertex of valence n (``e_j`` its edge
neighbours, ``d_j`` the corners of its quads opposite to it), ``(a + 4 v + b) / 6`` on a boundary
(the cubic B-spline's limit), ``v`` at a corner.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Topology", "topology", "subdivision_step", "limit_stencil", "one_ring"]


@dataclass(frozen=True, eq=False)
class Topology:
    """Edges of a polygon mesh and what meets at each vertex.

    Attributes
    ----------
    n_vertices : int
    faces : tuple of tuple of int
    edges : (e, 2) int
        Sorted vertex pairs, in order of first appearance.
    edge_faces : tuple of tuple of int
        The faces on each edge.
    edge_index : dict
        ``(a, b)`` with ``a < b`` to the edge's row.
    vertex_faces : tuple of tuple of int
    vertex_edges : tuple of tuple of int
    sharp : (e,) bool
        Edges with one face (boundary) or more than two (non-manifold).
    """

    n_vertices: int
    faces: tuple
    edges: np.ndarray
    edge_faces: tuple
    edge_index: dict
    vertex_faces: tuple
    vertex_edges: tuple
    sharp: np.ndarray


def topology(n_vertices: int, faces, creases=None) -> Topology:
    """The :class:`Topology` of ``faces`` (tuples of 0-based vertex ids) over ``n_vertices`` points;
    ``creases``, optional: ``{(a, b): sharpness}`` (``a < b``), edges with sharpness > 0 are sharp too."""
    faces = tuple(tuple(int(i) for i in f) for f in faces)
    index: dict = {}
    edge_faces: list = []
    vf: list = [[] for _ in range(n_vertices)]
    for k, f in enumerate(faces):
        for a, b in zip(f, f[1:] + f[:1]):
            key = (a, b) if a < b else (b, a)
            if key not in index:
                index[key] = len(edge_faces)
                edge_faces.append([])
            edge_faces[index[key]].append(k)
            vf[a].append(k)
    edges = np.array(list(index), dtype=int).reshape(-1, 2)
    ve: list = [[] for _ in range(n_vertices)]
    for e, (a, b) in enumerate(edges.tolist()):
        ve[a].append(e)
        ve[b].append(e)
    sharp = np.array([len(fs) != 2 for fs in edge_faces], bool)
    for key, s in (creases or {}).items():
        if s > 0 and key in index:
            sharp[index[key]] = True
    return Topology(n_vertices, faces, edges, tuple(map(tuple, edge_faces)), index,
                    tuple(map(tuple, vf)), tuple(map(tuple, ve)), sharp)


def subdivision_step(n_vertices: int, faces, creases=None):
    """One Catmull-Clark step: ``new_points = S @ points`` and the new quads.

    Parameters
    ----------
    n_vertices : int
    faces : sequence of sequence of int
        Polygons (3 or more vertices), consistently oriented.
    creases : dict, optional
        ``{(a, b): sharpness}`` with ``a < b`` (module notes).

    Returns
    -------
    S : (n_vertices + f + e, n_vertices) scipy.sparse.csr_matrix
        Rows: vertex points, face points, edge points (module notes).
    quads : (4 f', 4) int
        Face ``k`` with ``m`` vertices becomes ``m`` quads ``(v_i, e(v_i, v_i+1), F_k, e(v_i-1, v_i))``
        in order, so orientation is kept.
    parent : (4 f',) int
        The face of ``faces`` each quad lies in.
    creases : dict
        The new mesh's crease edges: the halves of each crease of sharpness s, with ``s - 1`` (10 and more
        stays), those still above 0.
    """
    from scipy.sparse import coo_matrix

    top = topology(n_vertices, faces, creases)
    nf, ne = len(top.faces), len(top.edges)
    rows: list = []
    cols: list = []
    vals: list = []

    def put(r, cs, w):
        rows.extend([r] * len(cs))
        cols.extend(cs)
        vals.extend([w] * len(cs))

    face_row = n_vertices
    edge_row = n_vertices + nf
    for k, f in enumerate(top.faces):  # face points: centroids
        put(face_row + k, list(f), 1.0 / len(f))
    for e, (a, b) in enumerate(top.edges.tolist()):
        fs = top.edge_faces[e]
        if top.sharp[e]:
            put(edge_row + e, [a, b], 0.5)
        else:
            put(edge_row + e, [a, b], 0.25)
            for k in fs:
                f = top.faces[k]
                put(edge_row + e, list(f), 0.25 / len(f))
    for v in range(n_vertices):
        es = top.vertex_edges[v]
        if not es:
            put(v, [v], 1.0)
            continue
        sharp = [e for e in es if top.sharp[e]]
        if len(sharp) == 2:
            a, b = (int(top.edges[e].sum() - v) for e in sharp)
            put(v, [v], 0.75)
            put(v, [a, b], 0.125)
        elif len(sharp) > 2:
            put(v, [v], 1.0)
        else:
            n = len(es)
            put(v, [v], (n - 3.0) / n)
            for k in top.vertex_faces[v]:  # F / n: the mean of the face centroids
                f = top.faces[k]
                put(v, list(f), 1.0 / (n * len(top.vertex_faces[v]) * len(f)))
            for e in es:  # 2 R / n: twice the mean of the edge midpoints
                put(v, [int(top.edges[e, 0]), int(top.edges[e, 1])], 1.0 / (n * n))
    quads, parent = [], []
    for k, f in enumerate(top.faces):
        m = len(f)
        for i in range(m):
            a, b, z = f[i], f[(i + 1) % m], f[i - 1]
            quads.append((a, edge_row + top.edge_index[(min(a, b), max(a, b))], face_row + k,
                          edge_row + top.edge_index[(min(z, a), max(z, a))]))
            parent.append(k)
    S = coo_matrix((vals, (rows, cols)), shape=(n_vertices + nf + ne, n_vertices)).tocsr()
    finer = {}
    for (a, b), s in (creases or {}).items():
        e = top.edge_index.get((a, b))
        s = s if s >= 10 else s - 1
        if e is not None and s > 0:
            finer[(a, edge_row + e)] = finer[(b, edge_row + e)] = s
    return S, np.array(quads, dtype=int).reshape(-1, 4), np.array(parent, dtype=int), finer


def one_ring(top: Topology, v: int):
    """The 1-ring of vertex ``v`` of an all-quad mesh, in order around it.

    Returns
    -------
    (edge_neighbours, diagonals, closed) or None
        ``edge_neighbours`` (m,) and ``diagonals`` (k,) vertex ids, ``diagonals[j]`` the corner of the
        ``j``-th quad opposite to ``v``, between ``edge_neighbours[j]`` and ``edge_neighbours[j + 1]``
        (cyclic when ``closed``: m = k; else m = k + 1, the first and last on sharp edges). None when
        the fan is not one chain of quads (non-manifold, or a non-quad face).
    """
    fs = top.vertex_faces[v]
    if not fs or any(len(top.faces[k]) != 4 for k in fs):
        return None
    step = {}  # quad k at v: (neighbour before v, the diagonal, neighbour after v) in the face's orientation
    for k in fs:
        f = top.faces[k]
        i = f.index(v)
        step[f[(i + 1) % 4]] = (k, f[(i + 2) % 4], f[(i + 3) % 4])
    if len(step) != len(fs):
        return None
    starts = set(step) - {s[2] for s in step.values()}
    closed = not starts
    if len(starts) > 1:
        return None
    e = next(iter(starts)) if starts else min(step)
    ring, diag = [e], []
    while e in step and len(diag) < len(fs):
        _, d, e = step[e]
        diag.append(d)
        ring.append(e)
    if closed:
        ring.pop()
        if ring[0] != e:
            return None
    if len(diag) != len(fs):
        return None
    return np.array(ring), np.array(diag), closed


def limit_stencil(n_vertices: int, quads, creases=None, rows=None):
    """The limit positions of an all-quad mesh's vertices: ``limit = L @ points``.

    Parameters
    ----------
    n_vertices : int
    quads : (f, 4) int
    creases : dict, optional
        ``{(a, b): sharpness}`` (a dart, one sharp edge, takes the smooth stencil).
    rows : sequence of int, optional
        Only these vertices (row i of ``L`` is ``rows[i]``'s); default all.

    Returns
    -------
    L : (len(rows), n_vertices) scipy.sparse.csr_matrix
        Rows as in the module notes; a vertex whose fan is not one chain of quads, or on one or more
        than two sharp edges, keeps its position.
    """
    from scipy.sparse import coo_matrix

    top = topology(n_vertices, [tuple(q) for q in np.asarray(quads).tolist()], creases)
    wanted = range(n_vertices) if rows is None else [int(v) for v in rows]
    rows, cols, vals = [], [], []
    for r, v in enumerate(wanted):
        ring = one_ring(top, v) if top.vertex_faces[v] else None
        sharp = [e for e in top.vertex_edges[v] if top.sharp[e]]
        if ring is not None and ring[2] and len(sharp) < 2:
            e, d, _ = ring
            n = len(e)
            w = 1.0 / (n * (n + 5))
            rows += [r] * (1 + 2 * n)
            cols += [v, *e.tolist(), *d.tolist()]
            vals += [n * n * w] + [4 * w] * n + [w] * n
        elif len(sharp) == 2:
            a, b = (int(top.edges[k].sum() - v) for k in sharp)
            rows += [r, r, r]
            cols += [v, a, b]
            vals += [4 / 6, 1 / 6, 1 / 6]
        else:
            rows.append(r)
            cols.append(v)
            vals.append(1.0)
    return coo_matrix((vals, (rows, cols)), shape=(len(wanted), n_vertices)).tocsr()
