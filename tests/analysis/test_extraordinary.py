"""Extraordinary vertices' shape defects: 0 on planes; on spheres, cylinders and tori equal to the defect
computed from COMPAS's Catmull-Clark (a second implementation, subdividing the whole cage) with the limit
stencil and the quadratic fit written again here; the realdata cages: one record per extraordinary vertex."""

import warnings
from collections import deque

import numpy as np
import pytest

from cadartifact.analysis.extraordinary import extraordinary_vertices, vertex_defects
from cadartifact.numerics.catmull_clark import subdivision_step
from cadartifact.testing.cages import fan_cage

compas_mesh = pytest.importorskip("compas.datastructures", reason="compas (test extra) is the second road")

VALENCES = (3, 5, 6, 8)


def _compas_defect(V, F, centre: int, level: int = 0) -> float:
    """d_level of vertex ``centre`` from COMPAS: the whole cage subdivided level + 3 times (boundary edges
    as infinitely sharp creases, OpenSubdiv's default), the region's vertices found as those within king
    distance 8 of the centre (8 x 8 quads per face of the level), their limit positions by the
    Halstead-Kass-DeRose stencil, the fit by the eigenvectors of the covariance."""
    mesh = compas_mesh.Mesh.from_vertices_and_faces([list(map(float, v)) for v in V], [list(f) for f in F])
    steps = level + 3
    mesh.update_default_edge_attributes({"crease": 0})
    for edge in mesh.edges():
        if mesh.is_edge_on_boundary(edge):
            mesh.edge_attribute(edge, "crease", steps + 1)
    sub = mesh.subdivided("catmullclark", k=steps)
    xyz = {k: np.array(sub.vertex_coordinates(k)) for k in sub.vertices()}
    # king distance <= 8: breadth first over the vertices of the faces at a vertex
    dist, todo = {centre: 0}, deque([centre])
    while todo:
        v = todo.popleft()
        if dist[v] == 8:
            continue
        for f in sub.vertex_faces(v):
            for w in sub.face_vertices(f):
                if w not in dist:
                    dist[w] = dist[v] + 1
                    todo.append(w)
    pts = []
    for v in [centre] + [w for w in dist if w != centre]:
        if sub.is_vertex_on_boundary(v):
            nb = [w for w in sub.vertex_neighbors(v) if sub.is_edge_on_boundary((v, w))]
            pts.append((4 * xyz[v] + xyz[nb[0]] + xyz[nb[1]]) / 6 if len(nb) == 2 else xyz[v])
            continue
        e = sub.vertex_neighbors(v)
        n = len(e)
        d = [w for f in sub.vertex_faces(v) for w in sub.face_vertices(f) if w != v and w not in e]
        pts.append((n * n * xyz[v] + 4 * sum(xyz[w] for w in e) + sum(xyz[w] for w in d)) / (n * (n + 5)))
    X = np.array(pts) - pts[0]
    _, vec = np.linalg.eigh(X.T @ X)
    x, y, h = X @ vec[:, 2], X @ vec[:, 1], X @ vec[:, 0]
    A = np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=1)
    return float(np.abs(h - A @ np.linalg.lstsq(A, h, rcond=None)[0]).max())


@pytest.mark.parametrize("boundary", [False, True])
@pytest.mark.parametrize("n", VALENCES)
def test_plane_has_no_defect(n, boundary):
    V, F = fan_cage(n, surface="plane", boundary=boundary)
    recs = vertex_defects(V, F)
    assert [r.vertex for r in recs] == [0]
    assert max(recs[0].defects) < 1e-13 and recs[0].defect < 1e-11
    assert recs[0].level_within(1e-9) == 0


@pytest.mark.parametrize("surface", ["sphere", "cylinder", "torus"])
@pytest.mark.parametrize("n", VALENCES)
def test_curved_defect_is_compas(surface, n):
    V, F = fan_cage(n, m=3, surface=surface)
    (rec,) = vertex_defects(V, F)
    assert (rec.vertex, rec.valence, rec.boundary) == (0, n, False)
    assert rec.defects[0] > 1e-5  # not a plane: something to compare
    assert rec.defects[0] == pytest.approx(_compas_defect(V, F, 0), rel=1e-9, abs=1e-14)


@pytest.mark.parametrize("n", (3, 5))
def test_boundary_defect_is_compas(n):
    V, F = fan_cage(n, m=3, surface="sphere", boundary=True)
    rec = next(r for r in vertex_defects(V, F) if r.vertex == 0)
    assert (rec.valence, rec.boundary) == (n + 1, True)
    assert rec.defects[0] == pytest.approx(_compas_defect(V, F, 0), rel=1e-9, abs=1e-14)


@pytest.mark.slow
@pytest.mark.parametrize("n", (3, 8))
def test_finer_level_defect_is_compas(n):
    V, F = fan_cage(n, m=3, surface="torus")
    (rec,) = vertex_defects(V, F, levels=1)
    assert len(rec.defects) == 2
    assert rec.defects[1] == pytest.approx(_compas_defect(V, F, 0, level=1), rel=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("surface", ["sphere", "torus"])
@pytest.mark.parametrize("n", VALENCES)
def test_defect_decays_like_mu(n, surface):
    """Finer levels shrink the region by 2 per level; the part of the limit surface no quadratic holds
    decays like the sub-subdominant eigenvalue mu (0.34, 0.41, 0.5 for n = 5, 6, 8; 1/6 for n = 3, where
    it is mixed with the cubic terms' 1/8): the ratio of the last two levels."""
    V, F = fan_cage(n, surface=surface)
    (rec,) = vertex_defects(V, F, levels=5)
    d = np.array(rec.defects)
    assert len(d) == 6 and d[5] < d[3] < d[0]
    if n == 3:
        assert d[5] / d[4] < 0.26
    else:
        assert d[5] / d[4] == pytest.approx(rec.mu, rel=0.15)
        # the defect extrapolated from level 3 predicts level 5's within the same share
        assert rec.defect * rec.mu ** 5 == pytest.approx(d[5], rel=0.3)
    assert rec.level_within(rec.defect * rec.mu ** 2 * 1.0001) == 2
    assert rec.level_within(0.0) is None


def test_extraordinary_vertices_are_the_readers():
    """The same vertices as the reader's QuadMesh.extraordinary on a cage with interior and boundary ones."""
    from cadartifact.exchange.quadmesh import build_quadmesh

    V, F = fan_cage(5, m=3, surface="sphere")
    W, G = fan_cage(4, m=3, surface="plane", boundary=True)
    F2 = F + [tuple(i + len(V) for i in f) for f in G]
    V2 = np.vstack([V, W + [0, 0, 5]])
    mesh, _ = build_quadmesh("two.obj", V2, F2)
    assert [v for v, _, _ in extraordinary_vertices(len(V2), F2)] == sorted(mesh.extraordinary.tolist())


def test_step_keeps_vertex_ids_and_quads():
    V, F = fan_cage(3, m=1)
    S, quads, parent, _ = subdivision_step(len(V), F)
    assert S.shape == (len(V) + len(F) + 9, len(V)) and quads.shape == (12, 4)
    assert np.allclose(S.sum(axis=1), 1) and list(parent) == [0] * 4 + [1] * 4 + [2] * 4


def _real(name):
    from cadartifact.exchange.obj import read_obj
    from cadartifact.testing.paths import REAL_OBJ

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "no analysable face": the charts are not what is tested here
        return read_obj(REAL_OBJ / name).mesh


@pytest.mark.realdata
@pytest.mark.parametrize("name, valences, boundary", [
    ("catmark_xord_interior.obj", list(range(3, 13)), False),
    ("catmark_xord_boundary.obj", [4, 5, 6, 7], True)])
def test_xord_cages_one_record_per_vertex(name, valences, boundary):
    from cadartifact.analysis.extraordinary import cage_vertex_defects

    mesh = _real(name)
    recs = cage_vertex_defects(mesh)
    assert [r.vertex for r in recs] == sorted(mesh.extraordinary.tolist())
    got = sorted(r.valence for r in recs)
    assert got == (sorted(set(valences) - {4}) if not boundary else valences)
    assert all(r.boundary == boundary and r.face is None and r.defect > 0 for r in recs)
    kinds = {r.valence: r.curvature for r in recs}
    assert all(kinds[n] == ("zero" if n == 3 else "unbounded") for n in kinds)


@pytest.mark.realdata
@pytest.mark.slow
@pytest.mark.parametrize("name", ["blub_control_mesh.obj", "spot_quadrangulated.obj", "catmark_car.obj"])
def test_real_cages_one_record_per_vertex(name):
    """Every extraordinary vertex the reader names, and the centre of every triangle and n-gon (an
    extraordinary vertex of valence 3 or n after the first step)."""
    from cadartifact.analysis.extraordinary import cage_vertex_defects

    mesh = _real(name)
    recs = cage_vertex_defects(mesh)
    assert sorted(r.vertex for r in recs if r.face is None) == sorted(mesh.extraordinary.tolist())
    others = [k for k, f in enumerate(mesh.faces) if len(f) != 4]
    assert sorted(r.face for r in recs if r.face is not None) == others
    assert all(r.valence == len(mesh.faces[r.face]) for r in recs if r.face is not None)
    assert all(np.isfinite(r.defect) and r.defect >= 0 for r in recs)
    if len(mesh.crease_edges):
        assert any(r.crease for r in recs)
