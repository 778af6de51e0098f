"""OBJ cages: faces kept as read, regularity, and grid charts covering every regular face once."""

from __future__ import annotations

import warnings
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadartifact.exchange.load import read
from cadartifact.testing.paths import REALDATA

OBJ_FILES = sorted((REALDATA / "obj").glob("*.obj"))


# ---------------------------------------------------------------- independent checks
def raw_faces(path: Path) -> list[tuple[int, ...]]:
    """Faces straight from the text (positive indices only, as in the test files)."""
    out = []
    for line in path.read_text().splitlines():
        parts = line.split()
        if parts and parts[0] == "f":
            out.append(tuple(int(p.split("/")[0]) - 1 for p in parts[1:]))
    return out


def regular_faces_by_definition(faces) -> np.ndarray:
    """Regular face = quad whose vertices are regular: all incident faces quads, and 4 faces with every
    incident edge shared twice (interior), or <= 2 faces on the boundary, forming one fan."""
    at = defaultdict(list)
    edges = Counter()
    for f, face in enumerate(faces):
        for k, a in enumerate(face):
            at[a].append(f)
            edges[frozenset((a, face[(k + 1) % len(face)]))] += 1

    def regular(v):
        fs = at[v]
        if any(len(faces[f]) != 4 for f in fs):
            return False
        incident = [e for e in edges if v in e]  # slow but obvious; meshes here are small enough
        open_edges = sum(1 for e in incident if edges[e] == 1)
        if open_edges == 0:
            return len(fs) == 4 and len(incident) == 4
        return open_edges == 2 and len(fs) <= 2 and len(incident) == len(fs) + 1

    cache = {}
    out = []
    for face in faces:
        ok = len(face) == 4
        for v in face if ok else ():
            if v not in cache:
                cache[v] = regular(v)
            ok = ok and cache[v]
        out.append(ok)
    return np.array(out, dtype=bool)


def check_charts(result, expected_regular=None):
    """Level-0 charts cover every regular face of the cage once; level-1 charts (after one Catmull-Clark step)
    cover every regular quad of the refined cage whose parent face no level-0 chart holds, once."""
    meshes = {0: result.mesh}
    if result.refined is not None:
        meshes[1] = result.refined.mesh
    covers = {level: np.zeros(m.n_faces, dtype=int) for level, m in meshes.items()}
    assert len(result.charts) == len(result.nets)
    assert [c.level for c in result.charts] == sorted(c.level for c in result.charts)  # level 0 first
    for k, (chart, net) in enumerate(zip(result.charts, result.nets)):
        mesh = meshes[chart.level]
        crease = {frozenset(e) for e, s in zip(mesh.crease_edges.tolist(), mesh.crease_sharpness) if s > 0}
        V, F = chart.vertex_ids, chart.face_ids
        assert chart.index == k == net.origin.face and net.origin.kind == "quad-chart" and net.degrees is None
        assert V.shape == net.shape and F.shape == (V.shape[0] - 1, V.shape[1] - 1)
        assert len(set(V.ravel().tolist())) == V.size  # a chart never reuses a vertex
        np.testing.assert_array_equal(net.points, mesh.vertices[V])
        for i in range(F.shape[0]):
            for j in range(F.shape[1]):
                face = mesh.faces[F[i, j]]
                corners = [V[i, j], V[i + 1, j], V[i + 1, j + 1], V[i, j + 1]]
                # the cell's corners are the face's vertices in cyclic order (either direction)
                start = face.index(corners[0])
                fwd = [face[(start + s) % 4] for s in range(4)]
                bwd = [face[(start - s) % 4] for s in range(4)]
                assert corners in (fwd, bwd)
                covers[chart.level][F[i, j]] += 1
        # no chart crosses a crease: interior grid edges are not crease edges
        for i in range(V.shape[0]):
            for j in range(V.shape[1]):
                if 0 < i < V.shape[0] - 1 and j < V.shape[1] - 1:
                    assert frozenset((V[i, j], V[i, j + 1])) not in crease
                if 0 < j < V.shape[1] - 1 and i < V.shape[0] - 1:
                    assert frozenset((V[i, j], V[i + 1, j])) not in crease
    regular = result.mesh.regular_faces if expected_regular is None else expected_regular
    np.testing.assert_array_equal(covers[0], regular.astype(int))  # every regular face exactly once, nothing else
    if 1 in meshes:
        left = ~np.asarray(regular, bool)[result.refined.parent]
        np.testing.assert_array_equal(covers[1], (meshes[1].regular_faces & left).astype(int))
    else:
        assert np.all(regular)


# ---------------------------------------------------------------- real cages
@pytest.mark.realdata
@pytest.mark.parametrize("path", OBJ_FILES, ids=lambda p: p.name)
def test_real_obj_keeps_quads_and_charts_cover_regular_faces(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the xord files have no regular face: a warning, checked below
        result = read(path)
    faces = raw_faces(path)
    mesh = result.mesh
    assert [tuple(f) for f in mesh.faces] == faces
    assert mesh.n_quads == sum(len(f) == 4 for f in faces)
    assert result.faces_total == len(faces)
    expected = regular_faces_by_definition(faces)
    np.testing.assert_array_equal(mesh.regular_faces, expected)
    check_charts(result, expected)
    # skipped: the faces of which no part is analysed (on either level), by kind
    analysed = expected.copy()
    for chart in result.charts:
        if chart.level == 1:
            analysed[result.refined.parent[chart.face_ids.ravel()]] = True
    sizes = np.array([len(f) for f in faces])
    skipped = result.skipped
    assert skipped.get("triangle", 0) == np.count_nonzero(~analysed & (sizes == 3))
    assert skipped.get("n-gon", 0) == np.count_nonzero(~analysed & (sizes > 4))
    assert skipped.get("irregular quad", 0) == np.count_nonzero(~analysed & (sizes == 4))


@pytest.mark.realdata
def test_real_obj_facts():
    """Counts from SOURCES.md."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = {p.name: read(p) for p in OBJ_FILES}
    car = results["catmark_car.obj"].mesh
    assert car.n_quads == 1575 and car.n_triangles == 0 and car.n_ngons == 0
    assert len(car.crease_edges) == 314 and np.all(car.crease_sharpness > 0)
    assert len(car.extraordinary) == 346
    blub = results["blub_control_mesh.obj"].mesh
    assert (blub.n_quads, blub.n_triangles, blub.n_ngons) == (100, 8, 4)
    assert len(blub.extraordinary) == 26
    spot = results["spot_quadrangulated.obj"].mesh
    assert spot.n_quads == spot.n_faces and len(spot.extraordinary) == 100
    assert len(results["catmark_xord_interior.obj"].mesh.extraordinary) == 9
    boundary = results["catmark_xord_boundary.obj"]
    assert len(boundary.mesh.extraordinary) == 4 and all(boundary.mesh.boundary[boundary.mesh.extraordinary])
    # no regular face as read; after one Catmull-Clark step the quads away from the extraordinary vertices are
    assert boundary.nets and all(c.level == 1 for c in boundary.charts)
    assert not any("no analysable face" in w for w in boundary.warnings)
    assert [t.name for t in results["catmark_xord_interior.obj"].mesh.tags] == ["interpolateboundary"]


# ---------------------------------------------------------------- synthetic cages (hypothesis)
def grid_obj(nx: int, ny: int, holes=(), wrap: bool = False, creases=(), extra: str = "") -> str:
    """An nx x ny quad grid (optionally wrapped into a cylinder in x) with some faces removed."""
    cols = nx if wrap else nx + 1
    lines = []
    for i in range(cols):
        for j in range(ny + 1):
            angle = 2 * np.pi * i / nx
            x, y = (np.cos(angle), np.sin(angle)) if wrap else (i, 0.3 * np.sin(i))
            lines.append(f"v {x:.6f} {y:.6f} {j + 0.1 * np.cos(i + j):.6f}")
    vid = lambda i, j: (i % cols) * (ny + 1) + j + 1  # noqa: E731
    for i in range(nx):
        for j in range(ny):
            if (i, j) in holes:
                continue
            lines.append(f"f {vid(i, j)} {vid(i + 1, j)} {vid(i + 1, j + 1)} {vid(i, j + 1)}")
    for a, b in creases:
        lines.append(f"t crease 2/1/0 {vid(*a) - 1} {vid(*b) - 1} 3.0")
    return "\n".join(lines) + "\n" + extra


def test_structured_grid_is_one_net(tmp_path):
    path = tmp_path / "grid.obj"
    path.write_text(grid_obj(7, 4))
    result = read(path)
    assert len(result.nets) == 1 and result.nets[0].shape in ((8, 5), (5, 8))
    assert result.skipped == {} and result.mesh.extraordinary.size == 0
    check_charts(result)


def test_crease_splits_charts_and_tags_are_read(tmp_path):
    path = tmp_path / "creased.obj"
    path.write_text(grid_obj(6, 4, creases=[((3, j), (3, j + 1)) for j in range(4)], extra="t corner 1/1/0 0 2.0\n"))
    result = read(path)
    assert len(result.nets) == 2 and sorted(n.size for n in result.nets) == [20, 20]
    assert [t.name for t in result.mesh.tags] == ["crease"] * 4 + ["corner"]
    check_charts(result)


@settings(max_examples=40, deadline=None)
@given(nx=st.integers(1, 9), ny=st.integers(1, 7), wrap=st.booleans(), data=st.data())
def test_random_grids_with_holes_are_covered_exactly_once(tmp_path_factory, nx, ny, wrap, data):
    if wrap:
        nx = max(nx, 3)
    cells = [(i, j) for i in range(nx) for j in range(ny)]
    holes = set(data.draw(st.lists(st.sampled_from(cells), max_size=max(0, len(cells) - 1), unique=True)))
    creases = []
    if data.draw(st.booleans()) and ny >= 1:
        i = data.draw(st.integers(0, nx))
        creases = [((i, j), (i, j + 1)) for j in range(data.draw(st.integers(1, ny)))]
    path = tmp_path_factory.mktemp("obj") / "grid.obj"
    path.write_text(grid_obj(nx, ny, holes, wrap, creases))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = read(path)
    faces = raw_faces(path)
    expected = regular_faces_by_definition(faces)
    np.testing.assert_array_equal(result.mesh.regular_faces, expected)
    check_charts(result, expected)


def test_obj_statements_variants(tmp_path):
    """v/vt/vn forms, negative indices, continuation lines, comments and unknown statements."""
    text = """# comment
mtllib x.mtl
o thing
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0 1.0
vt 0 0
vn 0 0 1
g group
usemtl m
s off
f 1/1/1 2/1/1 3//1 4
f -5 -2 \\
  -1 -4
l 1 2
t unknowntag 0/0/0
x whatever
"""
    path = tmp_path / "variants.OBJ"
    path.write_text(text)
    result = read(path)
    assert result.mesh.faces == ((0, 1, 2, 3), (1, 4, 5, 2))
    assert len(result.nets) == 1 and result.nets[0].size == 6
    assert result.mesh.tags[0].name == "unknowntag"
