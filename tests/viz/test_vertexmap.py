"""The picture of a cage's extraordinary vertices: each vertex's faces carry its defect, the rest none; the picture
renders; the ripple heatmap of a cage marks its vertices."""

import numpy as np
import pytest

from cadartifact.exchange.quadmesh import build_quadmesh
from cadartifact.testing.cages import fan_cage, write_obj
from cadartifact.viz.vertexmap import defect_values, limit_mesh, render_vertex_defects


def _cage(n=5):
    V, F = fan_cage(n, m=3, surface="sphere")
    mesh, _ = build_quadmesh("fan.obj", V, F)
    return mesh


def test_values_cover_the_vertex_faces_only():
    mesh = _cage()
    pts, quads, ancestor = limit_mesh(mesh, steps=2)
    assert quads.shape == (16 * len(mesh.faces), 4) and len(ancestor) == len(quads)
    records = [{"vertex": 0, "face": None, "defect": 0.25}]
    values = defect_values(mesh, records, ancestor)
    at_vertex = np.array([0 in mesh.faces[k] for k in ancestor])
    assert np.all(values[at_vertex] == 0.25) and np.all(np.isnan(values[~at_vertex]))
    # the limit points lie on the sphere of radius 2 to within the cage's sampling error
    assert np.abs(np.linalg.norm(pts, axis=1) - 2).max() < 0.05


@pytest.mark.parametrize("tol", [None, 1e-4])
def test_picture_renders(tol):
    pytest.importorskip("pyvista")
    from cadartifact.runs.cage_records import vertex_records

    mesh = _cage()
    img = render_vertex_defects(mesh, vertex_records(mesh, tol), tol=tol, title="fan", window_size=(320, 240))
    assert img.shape == (240, 320, 3) and img.dtype == np.uint8 and img.std() > 0


def test_view_of_a_cage_marks_its_vertices(tmp_path):
    pytest.importorskip("pyvista")
    from cadartifact.viz.view import view

    V, F = fan_cage(5, m=3, surface="sphere")
    write_obj(tmp_path / "fan.obj", V, F)
    res = view(tmp_path / "fan.obj", out=tmp_path / "fan.png", window_size=(320, 240))
    assert res.png.exists()
