"""One Catmull-Clark step with OpenSubdiv's crease rules (cadartifact.exchange.subdivision): known answers.

Second roads: hand-computed points of a cube; the Catmull-Clark limit-position stencil (not used by the step),
which must give the same limit point for a vertex before and after the step, at regular and extraordinary
vertices; creases by OpenSubdiv's documented rules on cubes whose sides stay flat."""

from __future__ import annotations

import numpy as np
import pytest

from cadartifact.exchange.subdivision import catmull_clark_step, crease_map
from cadartifact.testing.cages import cube_cage

CUBE_V = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
CUBE_F = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
CUBE_E = sorted({tuple(sorted((f[k], f[(k + 1) % 4]))) for f in CUBE_F for k in range(4)})


def test_cube_by_hand():
    """Face points at the face centres, edge points (3/4, 3/4, 0), vertex points 5/9 of the corner."""
    s = catmull_clark_step(CUBE_V, CUBE_F)
    n_e = len(CUBE_E)
    assert len(s.vertices) == 8 + n_e + 6 and len(s.faces) == 24
    np.testing.assert_allclose(s.vertices[:8], 5 / 9 * CUBE_V, atol=1e-15)
    edges = s.vertices[8:8 + n_e]
    np.testing.assert_allclose(np.sort(np.abs(edges), axis=1), np.tile([0, 0.75, 0.75], (n_e, 1)), atol=1e-15)
    faces = s.vertices[8 + n_e:]
    np.testing.assert_allclose(np.sort(np.abs(faces), axis=1), np.tile([0, 0, 1], (6, 1)), atol=1e-15)
    assert all(len(f) == 4 for f in s.faces) and np.bincount(s.parent).tolist() == [4] * 6


def limit_point(vertices, faces, a):
    """Catmull-Clark limit position of interior vertex ``a`` of an all-quad mesh of valence n:
    ``(n^2 S + 4 sum e_i + sum f_i) / (n (n + 5))`` (e: edge neighbours, f: the opposite corners of its quads)."""
    ring = [f for f in faces if a in f]
    n = len(ring)
    edge_nb, diag = set(), []
    for f in ring:
        k = f.index(a)
        edge_nb.update((f[k - 1], f[(k + 1) % 4]))
        diag.append(f[(k + 2) % 4])
    assert len(edge_nb) == n
    v = np.asarray(vertices)
    return (n * n * v[a] + 4 * v[sorted(edge_nb)].sum(axis=0) + v[diag].sum(axis=0)) / (n * (n + 5))


def bumpy_closed_cage(seed):
    """A cube of 3x3 quads per side (valences 3 at the corners, 4 elsewhere) pushed onto a bumpy blob."""
    rng = np.random.default_rng(seed)
    v, faces = cube_cage(3)
    v = v / np.linalg.norm(v, axis=1, keepdims=True) * (1 + 0.2 * rng.random((len(v), 1)))
    return v, faces


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_limit_point_is_kept_by_the_step(seed):
    """Valence 3 corners and valence 4 vertices: the limit stencil on the cage and on its first step agree."""
    v, faces = bumpy_closed_cage(seed)
    s = catmull_clark_step(v, faces)
    for a in range(len(v)):
        np.testing.assert_allclose(limit_point(s.vertices, s.faces, a), limit_point(v, faces, a), atol=1e-13)


@pytest.mark.parametrize("valence", [3, 5, 6, 8])
def test_limit_point_at_extraordinary_vertices(valence):
    """A fan of ``valence`` quads around a centre on a paraboloid-like bump: limit point kept (centre and
    face points of the step are new vertices of valence ``valence`` / 4)."""
    rng = np.random.default_rng(valence)
    n = valence
    ang = 2 * np.pi * np.arange(n) / n
    # centre 0, ring 1..n (edge neighbours), n+1..2n (diagonals), outer ring for closing: a disc of quads
    ring = np.c_[np.cos(ang), np.sin(ang), 0.3 + 0.05 * rng.random(n)]
    diag = np.c_[1.6 * np.cos(ang + np.pi / n), 1.6 * np.sin(ang + np.pi / n), 0.8 + 0.05 * rng.random(n)]
    v = np.vstack([[0, 0, 0.05], ring, diag])
    faces = [(0, 1 + k, 1 + n + k, 1 + (k + 1) % n) for k in range(n)]
    s = catmull_clark_step(v, faces)
    np.testing.assert_allclose(limit_point(s.vertices, s.faces, 0), limit_point(v, faces, 0), atol=1e-13)


def test_planar_polygons_stay_planar_and_are_all_quads():
    """A triangle, a pentagon and a hexagon in the plane z = 0: every point of the step lies in it."""
    v = np.array([[0, 0, 0], [2, 0, 0], [1, 1.5, 0], [3, 1, 0], [2.5, 2.5, 0], [4, 2, 0], [5, 3, 0], [4, 4, 0],
                  [3, 4, 0]], float)
    faces = [(0, 1, 2), (1, 3, 4, 2, 8)[::1], (3, 5, 6, 7, 8, 4)]
    s = catmull_clark_step(v, faces)
    assert np.abs(s.vertices[:, 2]).max() == 0
    assert [len(f) for f in s.faces] == [4] * (3 + 5 + 6)
    assert np.bincount(s.parent).tolist() == [3, 5, 6]


def test_triangle_face_point_and_boundary_rules():
    """One triangle: face point its centroid, edge points the midpoints (boundary edges are sharp), vertices kept
    (boundary corners of one face)."""
    v = np.array([[0, 0, 0], [3, 0, 1], [0, 3, 2]], float)
    s = catmull_clark_step(v, [(0, 1, 2)])
    np.testing.assert_allclose(s.vertices[:3], v)
    np.testing.assert_allclose(s.vertices[-1], v.mean(axis=0))
    mids = {tuple(0.5 * (v[a] + v[b])) for a, b in ((0, 1), (1, 2), (0, 2))}
    assert {tuple(p) for p in s.vertices[3:6]} == mids
    # interpolateboundary 1 (edges only): a corner of one face follows the crease rule (6 S + a + b) / 8
    s1 = catmull_clark_step(v, [(0, 1, 2)], boundary_corners=False)
    np.testing.assert_allclose(s1.vertices[0], (6 * v[0] + v[1] + v[2]) / 8)


# ---------------------------------------------------------------- creases
def test_sharp_cube_stays_a_cube():
    """Every edge infinitely sharp (OpenSubdiv writes 10): corners kept (3 sharp edges), edge points the midpoints,
    faces flat; the children of the creased edges are creased with sharpness s - 1."""
    creases = crease_map(CUBE_E, [10.0] * len(CUBE_E))
    s = catmull_clark_step(CUBE_V, CUBE_F, creases)
    np.testing.assert_allclose(s.vertices[:8], CUBE_V)
    edge_points = s.vertices[8:8 + len(CUBE_E)]
    assert np.all(np.isclose(np.abs(edge_points), 1).sum(axis=1) == 2)  # every edge point on a cube edge
    face_points = s.vertices[8 + len(CUBE_E):]
    assert np.all(np.isclose(np.abs(face_points), 1).sum(axis=1) == 1)  # ... every face point on its side
    assert len(s.creases) == 2 * len(CUBE_E) and set(s.creases.values()) == {9.0}
    for a, b in s.creases:  # each child crease runs from a corner to the midpoint of its parent edge
        assert (a < 8) != (b < 8)


@pytest.mark.parametrize("sharpness", [0.25, 0.5, 0.75])
def test_semi_sharp_edge_blends_its_edge_point(sharpness):
    """OpenSubdiv: an edge of sharpness 0 < s < 1 gets s * midpoint + (1 - s) * smooth point; its children are
    smooth; its end vertices (one semi-sharp edge each: a dart) follow the smooth rule."""
    e = CUBE_E[0]
    smooth = catmull_clark_step(CUBE_V, CUBE_F)
    sharp = catmull_clark_step(CUBE_V, CUBE_F, crease_map([e], [1.0]))
    semi = catmull_clark_step(CUBE_V, CUBE_F, crease_map([e], [sharpness]))
    k = 8  # the first edge point
    np.testing.assert_allclose(semi.vertices[k], sharpness * sharp.vertices[k] + (1 - sharpness) * smooth.vertices[k])
    np.testing.assert_allclose(sharp.vertices[k], CUBE_V[list(e)].mean(axis=0))
    np.testing.assert_allclose(semi.vertices[:8], smooth.vertices[:8])
    assert semi.creases == {}


def test_semi_sharp_crease_runs_out_with_a_blended_vertex():
    """Sharpness 1.5 on every cube edge: step 1 keeps the corners (children 0.5, still sharp); step 2 blends the
    corner rule and the smooth rule by the mean parent sharpness of the edges turning smooth, 0.5
    (Crease::ComputeFractionalWeightAtVertex); step 3 is smooth Catmull-Clark."""
    s1 = catmull_clark_step(CUBE_V, CUBE_F, crease_map(CUBE_E, [1.5] * len(CUBE_E)))
    np.testing.assert_allclose(s1.vertices[:8], CUBE_V)
    assert set(s1.creases.values()) == {0.5}
    s2 = catmull_clark_step(s1.vertices, s1.faces, s1.creases)
    plain = catmull_clark_step(s1.vertices, s1.faces)
    np.testing.assert_allclose(s2.vertices[:8], 0.5 * s1.vertices[:8] + 0.5 * plain.vertices[:8])
    # the edge points of the parent's crease children: 0.5 * midpoint + 0.5 * smooth
    assert s2.creases == {}
