"""What is written is what was measured: advised faces written into a shell stay on the old faces and meet.

The family (cadartifact.testing.extended_faces.extended_shell): faces over graded (non-uniform) knots, so the
advice's refit is parametrised otherwise than the old surface, extended 0.5-5 % past their trims on one to four
sides, joined at multiplicity p and p - 1, side by side sharing edges, one cut by a circle (a trim that is no
iso-line), in mm, cm and inches; advised at t = 0.01 and 0.05 and written with the model. Every replaced face lies
within t + the old face's ripple of the old face (the writer's measure, checked by a second road: the faces read
back, evaluated with the numpy B-spline basis, nearest sample by scipy's KD-tree and the distance to its tangent
plane), its edges within the input's tolerance + t of it (read back from the file), BRepCheck no worse, and the
file reads back. On the old writer (old pcurves reused on the refit surface) the edges ended up to the advice's
tangential drift off the new surfaces and the record measured surfaces at equal (u, v).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

pytest.importorskip("OCP")
pytest.importorskip("scipy")

from scipy.spatial import cKDTree  # noqa: E402

from cadartifact.exchange.face_distance import edge_tolerance, face_valid  # noqa: E402
from cadartifact.exchange.load import read  # noqa: E402
from cadartifact.exchange.model_writer import _read_source  # noqa: E402
from cadartifact.exchange.occ import iter_faces  # noqa: E402
from cadartifact.numerics.splines import basis_matrix  # noqa: E402
from cadartifact.runs.advising import advise_files, write_advised  # noqa: E402
from cadartifact.testing.extended_faces import extended_shell  # noqa: E402

FAST = [("two-mm", dict(), 0.05)]
SLOW = [("four-sides-cm", dict(unit="CM", ext=0.05), 0.01),
        ("one-side-p-1-inch", dict(mult=2, unit="INCH", sides=("u0",)), 0.05),
        ("two-sides-p-1", dict(mult=2, sides=("u1", "v0"), ext=0.005), 0.01),
        ("circle-three-cm", dict(circle=True, pieces=3, unit="CM", ext=0.005), 0.05),
        ("circle-three", dict(circle=True, pieces=3, ext=0.03, seed=3), 0.01)]


def quiet_read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read(path)


def faces_of(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return dict(iter_faces(_read_source(path)[0]))


def cloud(net, face, n=300):
    """Points and unit normals of ``net`` (numpy basis) on an ``n x n`` lattice of its uv box, inside ``face``'s
    trim (OCCT's classifier says which lattice points are)."""
    from OCP.BRepTopAdaptor import BRepTopAdaptor_FClass2d
    from OCP.gp import gp_Pnt2d
    from OCP.TopAbs import TopAbs_OUT

    u0, u1, v0, v1 = net.uv_bounds
    u, v = np.linspace(u0, u1, n), np.linspace(v0, v1, n)
    Bu = basis_matrix(np.asarray(net.knots[0]), net.degrees[0], u, net.shape[0])
    Bv = basis_matrix(np.asarray(net.knots[1]), net.degrees[1], v, net.shape[1])
    P = np.einsum("ai,ijk,bj->abk", Bu, np.asarray(net.points), Bv)
    normal = np.cross(np.gradient(P, axis=0), np.gradient(P, axis=1))
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    classifier = BRepTopAdaptor_FClass2d(face, 1e-7)
    mask = np.array([[classifier.Perform(gp_Pnt2d(a, b)) != TopAbs_OUT for b in v] for a in u])
    spacing = max(np.linalg.norm(np.diff(P, axis=0), axis=-1).max(), np.linalg.norm(np.diff(P, axis=1), axis=-1).max())
    return P[mask], normal[mask], float(spacing)


def second_road(new, old) -> float:
    """The largest distance of ``new``'s points to ``old``'s face: nearest sample, then its tangent plane (what
    lies farther along the plane than a lattice cell's diagonal is past the face's trim: that part counts too)."""
    (p, _, _), (q, m, h) = new, old
    _, index = cKDTree(q).query(p)
    gap = p - q[index]
    normal = np.einsum("ij,ij->i", gap, m[index])
    along = np.linalg.norm(gap - normal[:, None] * m[index], axis=1)
    return float(np.sqrt(normal ** 2 + np.maximum(along - np.sqrt(2.0) * h, 0.0) ** 2).max())


def run(tmp_path, shape, tol):
    source = extended_shell(tmp_path / "shell.step", **shape)
    keep = []
    doc = advise_files([source], tol, keep=keep)
    out = tmp_path / "written.step"
    written = write_advised(keep, out)
    return source, out, doc, written["files"][0]


def check(source, out, doc, f, tol):
    assert f["faces"], "the family must replace faces"
    for r in f["refused"]:  # kept on measured grounds: what it measured says why
        m = r["measured"]
        assert m["max_distance"] > m["allowed_distance"] or m["edge_tolerance"] > m["edge_tolerance_before"] + tol \
            or (m["valid_before"] and not m["valid"]) or m.get("edges"), r
    today = {r["face"]: r["advice"]["today"]["peak"] for r in doc["files"][0]["faces"]}
    old_faces, new_faces = faces_of(source), faces_of(out)
    assert sorted(new_faces) == sorted(old_faces)  # the file reads back, every face in its place
    old_nets = {n.origin.face: n for n in quiet_read(source).nets}
    new_nets = {n.origin.face: n for n in quiet_read(out).nets}
    for r in f["faces"]:
        i = r["face"]
        assert r["allowed_distance"] == pytest.approx(tol + today[i] + r["edge_tolerance_before"], rel=1e-12)
        assert r["max_distance"] <= r["allowed_distance"]
        assert r["max_distance"] == max(r["distance_to_old"], r["distance_from_old"])
        # read back: edges within the input's tolerance + t of the new face, BRepCheck no worse
        assert edge_tolerance(new_faces[i]) <= edge_tolerance(old_faces[i]) + tol
        assert r["edge_tolerance"] <= r["edge_tolerance_before"] + tol
        assert face_valid(new_faces[i]) or not face_valid(old_faces[i])
        # the second road, both ways
        a, b = cloud(new_nets[i], new_faces[i]), cloud(old_nets[i], old_faces[i])
        for measured, road, target in ((r["distance_to_old"], second_road(a, b), b),
                                       (r["distance_from_old"], second_road(b, a), a)):
            # the road never finds more than the writer measured; it finds less only by what it cannot resolve:
            # an offset along the face past the target's border within one lattice cell (its diagonal, sqrt(2) h,
            # is allowed for), e.g. a refit's border 0.0106 from a sliver face's border, in the face's plane
            assert road <= measured + 0.1 * tol + 2e-4, (i, measured, road)
            assert measured <= road + 0.1 * tol + 2e-4 + np.sqrt(2.0) * target[2], (i, measured, road)


@pytest.mark.slow
@pytest.mark.parametrize("name, shape, tol", FAST, ids=[c[0] for c in FAST])
def test_written_faces_stay_on_the_old_faces_and_meet(name, shape, tol, tmp_path):
    check(*run(tmp_path, shape, tol), tol)


@pytest.mark.slow
@pytest.mark.parametrize("name, shape, tol", SLOW, ids=[c[0] for c in SLOW])
def test_written_faces_stay_on_the_old_faces_and_meet_family(name, shape, tol, tmp_path):
    check(*run(tmp_path, shape, tol), tol)


@pytest.mark.slow
@pytest.mark.parametrize("tol", [0.01, 0.05])
def test_advising_the_written_shell_again_is_a_fixed_point(tol, tmp_path):
    source, out, doc, f = run(tmp_path, dict(pieces=2, ext=0.02, seed=1), tol)
    written = {r["face"] for r in f["faces"]}
    assert written
    advised = {r["face"]: r["advice"]["net"] for r in doc["files"][0]["faces"]}
    again = {r["face"]: r for r in advise_files([out], tol)["files"][0]["faces"]}
    for i in written:
        assert again[i]["meets_tolerance"], (i, again[i]["advice"])
        assert all(abs(a - b) <= 1 for a, b in zip(again[i]["advice"]["net"], advised[i])), \
            (i, again[i]["advice"]["net"], advised[i])


def check_model(source, tol, tmp_path):
    """Advise ``source`` at ``tol`` and write it: every replaced face within its allowance of the old face, its
    edges (read back) within the input's tolerance + t, BRepCheck no worse; every refused face says what it
    measured. Returns the written record of the file."""
    keep = []
    advise_files([source], tol, keep=keep)
    out = tmp_path / f"written_{tol}.step"
    f = write_advised(keep, out)["files"][0]
    if f["path"] is None:
        return f
    old_faces, new_faces = faces_of(source), faces_of(out)
    assert len(new_faces) == len(old_faces)
    for r in f["faces"]:
        i = r["face"]
        assert r["max_distance"] <= r["allowed_distance"]
        assert edge_tolerance(new_faces[i]) <= edge_tolerance(old_faces[i]) + tol + 1e-9
        assert face_valid(new_faces[i]) or not face_valid(old_faces[i])
    for r in f["refused"]:
        m = r.get("measured")
        if m is not None:
            assert (m["max_distance"] > m["allowed_distance"] or m["edge_tolerance"] > m["edge_tolerance_before"] + tol
                    or (m["valid_before"] and not m["valid"]) or m.get("edges")), r
    return f


@pytest.mark.slow
@pytest.mark.parametrize("tol", [0.01, 0.05])
@pytest.mark.parametrize("name", ["hull_freeform.step", "car_hood_coarse.step", "wavy_panel_diagonal.step"])
def test_samples_written_within_their_allowance(name, tol, tmp_path):
    from cadartifact.testing.paths import ROOT

    f = check_model(ROOT / "samples" / name, tol, tmp_path)
    # every face is written, refused with what it measured, or kept (its advice keeps today's net or is an honest
    # no: car_hood_coarse at 0.01, whose candidates' own U, 0.024, leaves no net verifiable)
    assert f["faces"] or f["refused"] or f["kept"]


@pytest.mark.realdata
@pytest.mark.slow
@pytest.mark.parametrize("name", ["MAINBODY_BACK.stp", "nist_ftc_07_asme1_rd.stp"])
def test_real_models_written_within_their_allowance(name, tmp_path):
    from cadartifact.testing.paths import REAL_STEP, REALDATA_MISSING

    source = REAL_STEP / name
    if not source.exists():
        pytest.skip(REALDATA_MISSING)
    f = check_model(source, 0.05, tmp_path)
    # at t = 0.05 every advised face of both opens an edge beyond the gate's continuity rules: all are kept
    assert f["faces"] or f["refused"]


#: Shells whose first face is sewn with degenerate slivers reaching into its extension (a join lowered to p - 1
#: moves the shared border; the sewing leaves an edge of one vertex 0.005 into the extension, in uv, on each end of
#: it): the fast case, then the family.
SLIVERS = [pytest.param(dict(mult=2, sides=("u1", "v0"), ext=0.005), 0.01, id="u1-v0-0.5%-p-1-0.01"),
           pytest.param(dict(mult=2, sides=("u1", "v0"), ext=0.005), 0.05, id="u1-v0-0.5%-p-1-0.05",
                        marks=pytest.mark.slow),
           pytest.param(dict(mult=2, sides=("u1", "v1"), ext=0.005, pieces=3, seed=2), 0.01,
                        id="three-u1-v1-0.5%-p-1-0.01", marks=pytest.mark.slow),
           pytest.param(dict(mult=2, sides=("u1", "v0"), ext=0.02), 0.01, id="u1-v0-2%-p-1-0.01",
                        marks=pytest.mark.slow)]


@pytest.mark.parametrize("shape, tol", SLIVERS)
def test_the_advice_claim_agrees_with_the_written_distance(shape, tol, tmp_path):
    """Every face advised a new net that conforms is written (or kept for the gate's edge rules only), and lies
    within t + its old ripple (+ its edge
    tolerance) of the old face: the advice's claim and the measure of what is written agree. Before, a degenerate
    edge kept its old pcurve on the new surface, which addressed points 0.235 mm past the old face (face 0, 14x6
    advised within 0.0097 of the intent at t = 0.01), and the face was kept."""
    source, out, doc, f = run(tmp_path, shape, tol)
    advised = {r["face"]: r["advice"] for r in doc["files"][0]["faces"]
               if r["advice"]["meets_tolerance"] and not r["advice"]["kept_today"]}
    written = {r["face"]: r for r in f["faces"]}
    # a face may still be kept for the gate's edge rules (a shared border the refit opens past 0.02 mm), never
    # for its distance to the old face
    edges = {r["face"]: r for r in f["refused"] if "edge continuity" in r["reason"]}
    assert advised and len(edges) == len(f["refused"]), f["refused"]
    assert sorted([*written, *edges]) == sorted(advised)
    for r in edges.values():
        assert r["measured"]["max_distance"] <= r["measured"]["allowed_distance"]
    for i, a in advised.items():
        if i in edges:
            continue
        assert written[i]["max_distance"] <= tol + a["today"]["peak"] + written[i]["edge_tolerance_before"]
        assert written[i]["valid"]
    check(source, out, doc, f, tol)
