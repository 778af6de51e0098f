"""Catmull-Clark's local subdivision matrix at an extraordinary vertex and what its eigenvalues say.

The 1-ring of a vertex (the vertex ``c``, its edge neighbours ``e_j``, the opposite corners ``f_j`` of
its quads) is mapped onto the 1-ring of the same vertex one step finer by a square matrix ``S``
(Doo and Sabin 1978; Stam 1998 for Catmull-Clark). With its eigenvalues ordered by modulus,
``1 > lambda`` (subdominant, the characteristic map's) ``> mu`` (sub-subdominant), the curvature of
the limit surface at the vertex is, for generic data (Peters and Reif 2004, "Shape characterization
of subdivision surfaces: basic principles"; Karčiauskas, Peters and Reif 2004, case studies):

- ``mu == lambda**2``: **bounded** (the regular case, n = 4: 1/2 and 1/4);
- ``mu < lambda**2``: **zero** (the height decays faster than the quadratic: a flat spot);
- ``mu > lambda**2``: **unbounded** (the height decays slower: curvature diverges).

For an interior vertex of valence n the subdominant eigenvalue has the closed form
``lambda = (5 + cos(2 pi / n) + cos(pi / n) sqrt(2 (9 + cos(2 pi / n)))) / 16``.
The eigenvalues of the larger (2-ring) matrix add only 1/8, 1/16, 1/32 and 1/64 (Stam 1998), never a
larger ``mu``, so the 1-ring decides. Boundary vertices use the crease rules
(:mod:`cadartifact.numerics.catmull_clark`); there ``lambda`` is the larger of the curve's 1/2 and the
interior's.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import cos, pi, sqrt

import numpy as np

__all__ = ["VertexEigen", "one_ring_matrix", "vertex_eigen", "subdominant_closed_form", "CURVATURE_KINDS"]

CURVATURE_KINDS = ("bounded", "zero", "unbounded")
_SAME = 1e-9  # eigenvalues this close are equal (they are computed to ~1e-15)


@dataclass(frozen=True)
class VertexEigen:
    """The leading eigenvalues of a vertex's local subdivision matrix.

    Attributes
    ----------
    valence : int
        Edges at the vertex.
    boundary : bool
    lam : float
        Subdominant eigenvalue.
    mu : float
        Sub-subdominant eigenvalue (the largest below ``lam``).
    curvature : str
        One of :data:`CURVATURE_KINDS`: ``mu`` against ``lam**2``.
    """

    valence: int
    boundary: bool
    lam: float
    mu: float
    curvature: str


def subdominant_closed_form(n: int) -> float:
    """``lambda = (5 + cos(2 pi/n) + cos(pi/n) sqrt(2 (9 + cos(2 pi/n)))) / 16`` (interior valence n)."""
    c = cos(2 * pi / n)
    return (5 + c + cos(pi / n) * sqrt(2 * (9 + c))) / 16


def one_ring_matrix(n_faces: int, boundary: bool = False) -> np.ndarray:
    """The local subdivision matrix of Catmull-Clark on a vertex's 1-ring.

    Parameters
    ----------
    n_faces : int
        Quads at the vertex (the valence when interior; valence - 1 on a boundary).
    boundary : bool
        The fan is open: its first and last edges are sharp (crease rules).

    Returns
    -------
    (m, m) float
        Order ``[c, e_0 .. e_{m_e - 1}, f_0 .. f_{k - 1}]``, ``m_e = k`` (interior) or ``k + 1``
        (boundary), ``f_j`` between ``e_j`` and ``e_{j+1}``.
    """
    k = int(n_faces)
    ne = k if not boundary else k + 1
    m = 1 + ne + k
    E = lambda j: 1 + (j % ne if not boundary else j)  # noqa: E731
    F = lambda j: 1 + ne + (j % k)  # noqa: E731

    def face_point(j):
        row = np.zeros(m)
        for i in (0, E(j), E(j + 1), F(j)):
            row[i] += 0.25
        return row

    S = np.zeros((m, m))
    if boundary:
        S[0, 0], S[0, E(0)], S[0, E(k)] = 0.75, 0.125, 0.125
    else:
        n = k
        S[0, 0] = (n - 1.75) / n
        for j in range(n):
            S[0, E(j)] += 1.5 / (n * n)
            S[0, F(j)] += 0.25 / (n * n)
    for j in range(ne):
        row = np.zeros(m)
        if boundary and j in (0, k):
            row[0] += 0.5
            row[E(j)] += 0.5
        else:
            row[0] += 0.25
            row[E(j)] += 0.25
            row += 0.25 * (face_point(j - 1) + face_point(j))
        S[E(j)] = row
    for j in range(k):
        S[F(j)] = face_point(j)
    return S


def vertex_eigen(valence: int, boundary: bool = False) -> VertexEigen:
    """Subdominant and sub-subdominant eigenvalues of Catmull-Clark at a vertex, and the curvature class.

    Parameters
    ----------
    valence : int
        Edges at the vertex (interior: 3 or more; boundary: 2 or more).
    boundary : bool

    Returns
    -------
    VertexEigen
    """
    k = valence - 1 if boundary else valence
    ev = np.linalg.eigvals(one_ring_matrix(k, boundary))
    mods = np.sort(np.abs(ev))[::-1]
    below_one = mods[mods < 1 - _SAME]
    lam = float(below_one[0])
    rest = below_one[below_one < lam - _SAME]
    mu = float(rest[0]) if len(rest) else 0.0
    if abs(mu - lam * lam) <= _SAME:
        kind = "bounded"
    else:
        kind = "zero" if mu < lam * lam else "unbounded"
    return VertexEigen(int(valence), bool(boundary), lam, mu, kind)
