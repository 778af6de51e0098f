"""Catmull-Clark's local subdivision matrix: eigenvalues against the closed form, and against the matrix
rebuilt from one global subdivision step of a fan cage (a second road to the same rules)."""

from math import cos, pi, sqrt

import numpy as np
import pytest

from cadartifact.numerics.catmull_clark import subdivision_step, topology
from cadartifact.testing.cages import fan_cage
from cadartifact.theory.vertex_eigen import one_ring_matrix, subdominant_closed_form, vertex_eigen


def _ring_from_global_step(n: int, boundary: bool) -> np.ndarray:
    """The 1-ring map read off one global step of a fan cage: rows of the new 1-ring of vertex 0 (its
    vertex point, the edge points of its edges, the face points of its faces) on the old 1-ring."""
    V, F = fan_cage(n, m=2, boundary=boundary)
    top = topology(len(V), F)
    S = subdivision_step(len(V), F)[0].toarray()
    # the old 1-ring in the matrix's order: centre, edge neighbours in fan order, then the diagonals
    step = {}
    for f in (f for f in F if 0 in f):
        i = f.index(0)
        step[f[(i + 1) % 4]] = (f[(i + 2) % 4], f[(i + 3) % 4])
    start = (set(step) - {s[1] for s in step.values()}) or {min(step)}
    e = start.pop()
    ring, diag = [e], []
    for _ in range(n):
        d, e = step[e]
        diag.append(d)
        ring.append(e)
    if not boundary:
        ring.pop()
    old = [0, *ring, *diag]
    nv, nf = len(V), len(F)
    face_of = {frozenset(f): k for k, f in enumerate(F)}
    new = [0] + [nv + nf + top.edge_index[(min(0, w), max(0, w))] for w in ring]
    for j in range(n):  # the face between ring[j] and ring[j + 1] (cyclically when interior)
        k = face_of[frozenset((0, ring[j], diag[j], ring[(j + 1) % len(ring)]))]
        new.append(nv + k)
    M = S[np.ix_(new, old)]
    assert np.allclose(S[new].sum(axis=1), M.sum(axis=1)), "the 1-ring is not closed under a step"
    return M


@pytest.mark.parametrize("n", range(3, 13))
def test_subdominant_is_the_closed_form(n):
    c = cos(2 * pi / n)
    assert vertex_eigen(n).lam == pytest.approx((5 + c + cos(pi / n) * sqrt(2 * (9 + c))) / 16, abs=1e-12)
    assert subdominant_closed_form(n) == pytest.approx(vertex_eigen(n).lam, abs=1e-12)


@pytest.mark.parametrize("n,boundary", [(n, False) for n in (3, 4, 5, 6, 8, 12)] + [(k, True) for k in (1, 2, 3, 4, 6)])
def test_one_ring_matrix_is_the_global_step(n, boundary):
    M = one_ring_matrix(n, boundary)
    assert np.allclose(M.sum(axis=1), 1)
    assert np.allclose(M, _ring_from_global_step(n, boundary), atol=1e-15)


@pytest.mark.parametrize("n,kind", [(3, "zero"), (4, "bounded"), (5, "unbounded"), (6, "unbounded"),
                                    (8, "unbounded"), (12, "unbounded")])
def test_curvature_class_interior(n, kind):
    e = vertex_eigen(n)
    assert e.curvature == kind
    if n == 4:  # the regular bicubic spline: 1/2 and 1/4
        assert (e.lam, e.mu) == pytest.approx((0.5, 0.25), abs=1e-12)
    if n == 3:  # mu = 1/6 < lambda^2 = 0.1682: a flat spot
        assert e.mu == pytest.approx(1 / 6, abs=1e-12)


@pytest.mark.parametrize("valence,kind", [(2, "bounded"), (3, "bounded"), (4, "unbounded"), (5, "unbounded")])
def test_curvature_class_boundary(valence, kind):
    e = vertex_eigen(valence, boundary=True)
    assert e.curvature == kind
    if valence <= 3:  # the regular boundary and corner: the cubic B-spline's 1/2 and 1/4
        assert (e.lam, e.mu) == pytest.approx((0.5, 0.25), abs=1e-12)
