"""A face that repeats another face moved rigidly reuses its analysis (cadartifact.runs.face_instances).

Two roads: the repeated face analysed on its own against the first face's record moved onto it, on
known shapes (several degrees, sizes, directions and frequencies, random motions and parameter shifts)
and on the real files; and the matching itself against faces that differ by a little.
"""

import json

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from cadartifact.testing.known_shapes import family
from typer.testing import CliRunner

from cadartifact.runs.face_instances import congruence, instance_record, instances, rigid_motion
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.testing.paths import REALDATA

IDENTITY = {"face", "name", "entity", "entity_line", "kind"}
NOTE = "the same shape as face"


def _rotation(rng) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _moved(net: ControlNet, rotation, translation, shift=(0.0, 0.0), face=1, points=None) -> ControlNet:
    """``net`` moved rigidly, its parameters shifted (knots and uv bounds alike)."""
    pts = net.points @ np.asarray(rotation).T + translation if points is None else points
    knots = tuple(np.asarray(k) + s for k, s in zip(net.knots, shift))
    bounds = None if net.uv_bounds is None else tuple(b + shift[k // 2] for k, b in enumerate(net.uv_bounds))
    origin = NetOrigin(face=face, name=f"copy{face}", kind=net.origin.kind)
    return ControlNet(points=pts, weights=net.weights, degrees=net.degrees, knots=knots, periodic=net.periodic,
                      uv_bounds=bounds, unit=net.unit, origin=origin)


def _face(seed=0, **kw) -> ControlNet:
    net = family(seed, 1, **kw)[0][0]
    return ControlNet(points=net.points, degrees=net.degrees, knots=net.knots,
                      origin=NetOrigin(face=0, name="first", kind="bspline"))


def _flat(x, path=""):
    if isinstance(x, dict):
        for k, v in x.items():
            if k not in IDENTITY:
                yield from _flat(v, f"{path}.{k}")
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from _flat(v, f"{path}[{i}]")
    else:
        yield path, x


def assert_same_record(own: dict, reused: dict, rtol=1e-6, atol=1e-6):
    """Every number within ``rtol`` of the larger plus ``atol``, everything else equal; the reused record's
    notes end with the reuse note. ``atol`` (shares of the tolerance): two copies of a face, each analysed on its
    own, differ by rounding that the measured road's bridge carries from its fifth derivatives (fitted on one
    span's samples) into the ripple: up to 1e-10 mm on the real files, 4e-7 of a 0.0002 tolerance."""
    reused = dict(reused)
    assert reused["notes"][-1].startswith(NOTE)
    reused["notes"] = reused["notes"][:-1]
    own, reused = dict(own), dict(reused)
    peaks = own.pop("peak_at", None), reused.pop("peak_at", None)
    if peaks[0] is not None:  # tied maxima (a symmetric face) may be located at either: the value is what must agree
        assert peaks[1]["value"] == pytest.approx(peaks[0]["value"], rel=rtol, abs=atol)
        if peaks[0]["index"] == peaks[1]["index"]:
            own["peak_at"], reused["peak_at"] = peaks
    else:
        assert peaks[1] is None
    a, b = dict(_flat(own)), dict(_flat(reused))
    assert a.keys() == b.keys()
    for key, x in a.items():
        y = b[key]
        if isinstance(x, float) and isinstance(y, float):
            assert abs(x - y) <= rtol * max(abs(x), abs(y)) + atol, (key, x, y)
        else:
            assert x == y, (key, x, y)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2 ** 31), n=st.integers(3, 60), scale=st.floats(1e-3, 1e4))
def test_rigid_motion_recovers_a_random_motion(seed, n, scale):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n, 3)) * scale
    rotation, translation = _rotation(rng), rng.normal(size=3) * 10 * scale
    R, t, residual = rigid_motion(p, p @ rotation.T + translation)
    assert residual <= 1e-9 * scale
    assert np.allclose(R, rotation, atol=1e-8) and np.linalg.det(R) > 0


def test_congruence_matches_moved_copies_and_nothing_else():
    rng = np.random.default_rng(3)
    face = _face(1)
    size = float(np.ptp(face.points.reshape(-1, 3), axis=0).max())
    rotation, translation = _rotation(rng), rng.normal(size=3) * 50
    copy = _moved(face, rotation, translation, shift=(2.5, -1.0))
    motion = congruence(face, copy)
    assert motion is not None and motion.residual < 1e-12
    assert motion.shift == pytest.approx((2.5, -1.0))
    assert np.allclose(motion.apply(face.points), copy.points, atol=1e-9 * size)

    nudged = copy.points.copy()
    nudged[3, 4, 2] += 1e-6 * size  # a real edit, far above the reader's last bits
    assert congruence(face, _moved(face, rotation, translation, points=nudged)) is None
    mirror = face.points * np.array([1.0, 1.0, -1.0])
    assert congruence(face, _moved(face, np.eye(3), 0.0, points=mirror)) is None
    knots = (np.asarray(face.knots[0]) ** 1.01, face.knots[1])  # same count, not a shift
    assert congruence(face, ControlNet(points=face.points, degrees=face.degrees, knots=knots)) is None
    trimmed = ControlNet(points=face.points, degrees=face.degrees, knots=face.knots, uv_bounds=(0.0, 0.5, 0.0, 1.0))
    assert congruence(trimmed, _moved(trimmed, np.eye(3), 0.0, shift=(0.1, 0.0))) is not None
    other_trim = ControlNet(points=face.points, degrees=face.degrees, knots=face.knots, uv_bounds=(0.0, 0.6, 0.0, 1.0))
    assert congruence(trimmed, other_trim) is None
    heavy = np.ones(face.shape)
    heavy[2, 2] = 1.5
    rational = ControlNet(points=face.points, weights=np.ones(face.shape), degrees=face.degrees, knots=face.knots)
    assert congruence(rational, ControlNet(points=face.points, weights=heavy, degrees=face.degrees,
                                           knots=face.knots)) is None
    assert congruence(ControlNet(points=face.points), ControlNet(points=face.points)) is None  # cages: never


def test_instances_plan_points_each_repeat_at_its_first_face():
    rng = np.random.default_rng(5)
    a, b = _face(1), _face(2)
    nets = [a, _moved(a, _rotation(rng), [1.0, 2.0, 3.0], face=1), b, _moved(b, np.eye(3), [0.0, 0.0, 9.0], face=3),
            _moved(a, _rotation(rng), [-4.0, 0.0, 0.0], (1.0, 1.0), face=4), ControlNet(points=a.points)]
    plan = instances(nets)
    assert [rep for rep, _ in plan] == [0, 0, 2, 2, 0, 5]
    assert all((m is None) == (rep == i) for i, (rep, m) in enumerate(plan))


@pytest.mark.parametrize("seed", [11, 12, 13, 14])
def test_reused_advice_equals_the_repeated_face_own(seed):
    """Known shapes (random degrees 2-5, sizes, directions, frequencies), each moved by a random rigid
    motion with shifted parameters: the copy's own advice and budget against the first face's moved."""
    pytest.importorskip("OCP")
    import cadartifact as ca
    from cadartifact.runs.records import face_record

    rng = np.random.default_rng(seed)
    net, _, what = family(seed, 1, nmin=8, nmax=20)[0]
    scale = float(rng.choice([0.1, 1.0, 30.0]))
    face = ControlNet(points=net.points * scale, degrees=net.degrees, knots=net.knots,
                      origin=NetOrigin(face=0, name="first", kind="bspline"))
    copy = _moved(face, _rotation(rng), rng.normal(size=3) * 100 * scale, tuple(rng.uniform(-3, 3, 2)))
    motion = congruence(face, copy)
    assert motion is not None, what
    tol = 0.05 * scale
    own = face_record(copy, ca.advise(copy, tol))
    reused = instance_record(face_record(face, ca.advise(face, tol)), face, copy, motion)
    assert reused["face"] == 1 and reused["name"] == "copy1"
    assert_same_record(own, reused)


def test_peak_location_moves_with_the_face():
    pytest.importorskip("OCP")
    from cadartifact.runs.records import json_number, peak_location

    rng = np.random.default_rng(8)
    face = _face(4, nmin=10, nmax=16)
    copy = _moved(face, _rotation(rng), [10.0, -20.0, 5.0], (0.75, -2.0))
    motion = congruence(face, copy)
    rec = {"notes": [], "peak_at": peak_location(face, None, "total")}
    moved = instance_record(rec, face, copy, motion)["peak_at"]
    own = peak_location(copy, None, "total")
    size = float(np.ptp(face.points.reshape(-1, 3), axis=0).max())
    assert moved["index"] == own["index"]
    assert moved["uv"] == pytest.approx(own["uv"], abs=1e-8)
    assert moved["xyz"] == pytest.approx(own["xyz"], abs=1e-8 * size)
    assert moved["value"] == pytest.approx(json_number(own["value"]), rel=1e-6, abs=1e-9)


def _documents(monkeypatch, args, exit_code):
    from cadartifact.cli.app import app

    out = []
    for on in ("0", "1"):
        monkeypatch.setenv("CADARTIFACT_REUSE_FACES", on)
        result = CliRunner().invoke(app, args)
        assert result.exit_code == exit_code, result.output
        out.append(json.loads(result.stdout))
    return out


def assert_same_documents(own: dict, reused: dict) -> int:
    """Two documents of the same files, without and with reuse, face by face: a reused record as
    :func:`assert_same_record` says, every other one equal. Returns how many were reused."""
    notes = 0
    for fa, fb in zip(own["files"], reused["files"]):
        assert len(fa["faces"]) == len(fb["faces"])
        for x, y in zip(fa["faces"], fb["faces"]):
            if y["notes"] and y["notes"][-1].startswith(NOTE):
                notes += 1
                assert_same_record(x, y)
            else:
                assert x == y
    return notes


def test_a_step_file_of_repeated_faces_reads_the_same_with_and_without_reuse(tmp_path, monkeypatch):
    pytest.importorskip("OCP")
    from cadartifact.exchange.load import write_step

    rng = np.random.default_rng(2)
    a, b = _face(6, nmin=8, nmax=14), _face(7, nmin=8, nmax=14)
    nets = [a, _moved(a, _rotation(rng), [40.0, 0.0, 0.0], face=1), b, _moved(a, _rotation(rng), [0.0, 80.0, 0.0],
                                                                               (0.5, 0.0), face=3)]
    write_step(nets, tmp_path / "pattern.step")
    for args, exit_code in ((["advise", str(tmp_path / "pattern.step"), "--tol", "0.01", "--json"], 0),
                            (["gate", str(tmp_path / "pattern.step"), "--tol", "0.001", "--format", "json"], 1)):
        assert assert_same_documents(*_documents(monkeypatch, args, exit_code)) == 2, args[0]


@pytest.mark.slow
@pytest.mark.realdata
@pytest.mark.parametrize("name, exit_code", [("boxed_sphere.step", 0), ("nist_ftc_07_asme1_rd.stp", 1),
                                             ("nist_ctc_02_asme1_ap242-1.stp", 1)])
def test_real_repeated_faces_read_the_same_with_and_without_reuse(name, exit_code, monkeypatch):
    """The real models' repeated faces (35 of boxed_sphere's 42, 9 of NIST FTC-07's 20, 12 of CTC-02's 22):
    the gate at a tight tolerance (every face advised, peaks located) with and without reuse."""
    pytest.importorskip("OCP")
    docs = _documents(monkeypatch, ["gate", str(REALDATA / "step" / name), "--tol", "0.0002", "--format", "json"],
                      exit_code)
    assert assert_same_documents(*docs) > 0


def test_a_repeat_the_analysis_would_read_otherwise_is_not_matched():
    """Within RTOL, but across one of the analysis's own finer decisions: analysed on its own."""
    face = _face(9, nmin=10, nmax=14)
    ones = ControlNet(points=face.points, weights=np.ones(face.shape), degrees=face.degrees, knots=face.knots)
    w = np.ones(face.shape)
    w[3, 3] += 1e-11  # weights_vary reads 1e-12: homogeneous coordinates for this one only
    noisy = ControlNet(points=face.points, weights=w, degrees=face.degrees, knots=face.knots)
    assert congruence(ones, noisy) is None
    p, ku = face.degrees[0], np.asarray(face.knots[0], float)
    k = p + 2  # an interior knot: two of them 5e-13 of the range apart count as one double knot (C1 less)
    double = ku.copy()
    double[k + 1] = double[k] + 5e-13 * (ku[-1] - ku[0])
    single = ku.copy()
    single[k + 1] = single[k] + 5e-10 * (ku[-1] - ku[0])
    a = ControlNet(points=face.points, degrees=face.degrees, knots=(double, face.knots[1]))
    b = ControlNet(points=face.points, degrees=face.degrees, knots=(single, face.knots[1]))
    assert congruence(a, b) is None
    assert congruence(a, ControlNet(points=face.points + 0.0, degrees=face.degrees, knots=a.knots)) is not None


def test_face_batches_give_the_whole_files_records(tmp_path, monkeypatch):
    """A cluster's face batches find repeats over the whole file: their merged entry is the whole file's."""
    pytest.importorskip("OCP")
    from cadartifact.exchange.load import write_step
    from cadartifact.gate.run import gate_file, merge_parts
    from cadartifact.gate.policy import FileSettings

    rng = np.random.default_rng(4)
    a, b = _face(6, nmin=8, nmax=12), _face(7, nmin=8, nmax=12)
    nets = [a, b, _moved(a, _rotation(rng), [40.0, 0.0, 0.0], face=2), _moved(b, _rotation(rng), [0.0, 60.0, 0.0],
                                                                             (1.0, 0.0), face=3),
            _moved(a, np.eye(3), [0.0, 0.0, 90.0], face=4)]
    path = str(tmp_path / "pattern.step")
    write_step(nets, path)
    settings = FileSettings(tolerance=0.001)
    whole = gate_file(path, settings)
    assert sum(NOTE in n for f in whole["faces"] for n in f["notes"]) == 3
    for k in (2, 3):
        merged = merge_parts([gate_file(path, settings, part=(r, k)) for r in range(k)], settings)
        assert json.dumps(merged, sort_keys=True) == json.dumps(whole, sort_keys=True)


def test_an_unexpected_failure_reads_the_same_from_the_child():
    from cadartifact.runs.face_sharing import pack, unpack

    back = unpack(pack(ValueError("shapes (3,) and (4,) not aligned")))
    assert type(back) is ValueError and str(back) == "shapes (3,) and (4,) not aligned"
