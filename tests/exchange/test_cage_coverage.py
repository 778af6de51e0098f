"""Every face of a cage analysed (triangles and n-gons after the first Catmull-Clark step), creases honoured,
coverage in the verdict (SPEC §6). Known answers: planar cages carry no ripple; a sharp-creased cube's flat sides
carry none either, while the same cube without creases is rounded; coverage by hand."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from cadartifact.exchange.obj import read_obj
from cadartifact.gate.keys import FileSettings
from cadartifact.gate.run import gate_file
from cadartifact.runs.records import analysed_share, subdivided_record
from cadartifact.testing.cages import cube_cage
from cadartifact.testing.paths import REALDATA


def write_obj(path, vertices, faces, extra=""):
    lines = [f"v {x:.12g} {y:.12g} {z:.12g}" for x, y, z in vertices]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    path.write_text("\n".join(lines) + "\n" + extra)
    return path


def mixed_grid(n=8, lift=None):
    """An n x n grid of unit quads with a hexagon (two quads merged), a pentagon and a triangle (a quad split in
    two triangles, one merged with its neighbour quad) and two triangles (a quad split), away from the border."""
    vid = lambda i, j: i * (n + 1) + j  # noqa: E731
    v = np.array([[i, j, 0.0] for i in range(n + 1) for j in range(n + 1)], float)
    quads = {(i, j): (vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)) for i in range(n) for j in range(n)}
    faces = [q for k, q in quads.items() if k not in {(2, 2), (3, 2), (5, 5), (5, 4), (2, 5)}]
    faces.append((vid(2, 2), vid(3, 2), vid(4, 2), vid(4, 3), vid(3, 3), vid(2, 3)))   # hexagon
    # (5, 4) split along its diagonal: one triangle merged with quad (5, 5) into a pentagon
    faces.append((vid(5, 4), vid(6, 4), vid(5, 5)))                                    # triangle
    faces.append((vid(6, 4), vid(6, 5), vid(6, 6), vid(5, 6), vid(5, 5)))             # pentagon
    faces.append((vid(2, 5), vid(3, 5), vid(3, 6)))                                    # two triangles
    faces.append((vid(2, 5), vid(3, 6), vid(2, 6)))
    if lift is not None:
        v[:, 2] = lift(v[:, 0], v[:, 1])
    return v, faces


def gate(path, tol=1.0, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gate_file(str(path), FileSettings(tolerance=tol, advise="none", **kw))


@pytest.mark.parametrize("plane", [(0.0, 0.0), (0.3, -0.2), (1.0, 2.0)])
def test_planar_cage_with_polygons_has_no_ripple(tmp_path, plane):
    a, b = plane
    v, faces = mixed_grid(lift=lambda x, y: a * x + b * y)
    path = write_obj(tmp_path / "mixed.obj", v, faces)
    res = read_obj(path)
    sizes = np.array([len(f) for f in faces])
    assert sorted(set(sizes)) == [3, 4, 5, 6]
    assert any(c.level == 1 for c in res.charts)
    rec = subdivided_record(res)
    assert rec["level"] == 1 and rec["charts"] == sum(c.level == 1 for c in res.charts)
    assert rec["quads"] == sum(c.face_ids.size for c in res.charts if c.level == 1)
    entry = gate(path)
    assert entry["faces"] and all(f["value"] <= 1e-9 for f in entry["faces"])
    assert entry["subdivided"] == rec


def test_coverage_by_hand_on_a_planar_cage(tmp_path):
    """Unit quads in the plane: after one step a face's quads have equal areas when it is a square; polygons and
    quads at their corners: count the analysed level-1 quads and weigh them by their own areas (second road:
    shoelace areas of the child quads, not the fan triangulation)."""
    v, faces = mixed_grid()
    res = read_obj(write_obj(tmp_path / "mixed.obj", v, faces))
    parent_area = np.array([0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
                            for p in (v[list(f)] for f in faces)])
    cv = res.refined.mesh.vertices
    child_area = np.array([0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
                           for p in (cv[list(f)] for f in res.refined.mesh.faces)])
    share = np.zeros(len(faces))
    for c in res.charts:
        if c.level == 0:
            share[c.face_ids.ravel()] = 1
    done = np.zeros(len(child_area), bool)
    for c in res.charts:
        if c.level == 1:
            done[c.face_ids.ravel()] = True
    for f in range(len(faces)):
        if share[f] == 0:
            kids = res.refined.parent == f
            share[f] = child_area[kids & done].sum() / child_area[kids].sum()
    assert analysed_share(res) == pytest.approx((share * parent_area).sum() / parent_area.sum(), rel=1e-12)
    # the polygons' own quads all touch their face point (valence 3, 5 or 6): not in charts; the rest is analysed
    assert all(share[f] == 0 for f in range(len(faces)) if len(faces[f]) != 4)
    assert analysed_share(res) < 1
    # counted with the extraordinary vertices' neighbourhoods (what their own measure analyses): everything
    assert analysed_share(res, around=res.refined.mesh.irregular) == pytest.approx(1.0, abs=1e-12)


def creased_cube(creased: bool, n: int = 3):
    """A cube of n x n quads per side (:func:`cadartifact.testing.cages.cube_cage`); ``creased``: every edge on the
    cube's 12 edges has sharpness 10."""
    v, faces = cube_cage(n)
    extra = ""
    if creased:
        edges = {tuple(sorted((f[k], f[(k + 1) % 4]))) for f in faces for k in range(4)}
        sharp = [e for e in edges if (np.isclose(np.abs(v[list(e)]), 1).sum(axis=1) >= 2).all()]
        extra = "".join(f"t crease 2/1/0 {a} {b} 10\n" for a, b in sorted(sharp))
    return v, faces, extra


def test_sharp_creased_cube_keeps_its_edges_and_yields_no_ripple(tmp_path):
    v, faces, extra = creased_cube(creased=True)
    path = write_obj(tmp_path / "sharp.obj", v, faces, extra)
    res = read_obj(path)
    assert len(res.mesh.crease_edges) == 12 * 3
    # the creases stay sharp after the step: the cube's edges and sides are still there
    cv = res.refined.mesh.vertices
    assert np.allclose(np.abs(cv).max(axis=1), 1)  # every point on the cube's surface
    assert len(res.refined.mesh.crease_edges) == 2 * 12 * 3 and set(res.refined.mesh.crease_sharpness) == {9.0}
    entry = gate(path, tol=0.01)
    assert entry["faces"] and all(f["value"] <= 1e-9 and f["verdict"] == "pass" for f in entry["faces"])
    # its corners (valence 3, where creases end) are measured by the extraordinary-vertex measure: the whole area is
    # analysed; a crease's end is reported, not gated, so the cube passes
    assert entry["analysed_share"] == 1.0 and "share_failure" not in entry and entry["verdict"] == "pass"
    assert len(entry["extraordinary"]) == 8 and all(v["crease"] for v in entry["extraordinary"])
    # the same cage without creases rounds off: its charts across the cube's edges carry ripple
    v, faces, extra = creased_cube(creased=False)
    plain = gate(write_obj(tmp_path / "round.obj", v, faces, extra), tol=0.01)
    assert max(f["value"] for f in plain["faces"]) > 5e-4


@pytest.mark.realdata
@pytest.mark.parametrize("name,charts_only", [("blub_control_mesh.obj", 0.6194), ("catmark_car.obj", 0.8467),
                                              ("catmark_xord_boundary.obj", 0.6085),
                                              ("catmark_xord_interior.obj", 0.6267),
                                              ("spot_quadrangulated.obj", 0.9639)])
def test_real_cages_coverage(name, charts_only):
    """The charts alone (level 0 and 1) and with the extraordinary vertices' neighbourhoods after one step, which
    the extraordinary-vertex measure analyses: 100 %."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = read_obj(REALDATA / "obj" / name)
    assert analysed_share(res) == pytest.approx(charts_only, abs=1e-4)
    assert analysed_share(res, around=res.refined.mesh.extraordinary) == pytest.approx(1.0, abs=1e-12)
