"""The fixes of issue 14, one test each: faces dropped by the STEP transfer fail the gate, impossible
numbers are errors before OCCT, the reader runs in a child process (crash / hang -> error entry),
the OBJ reader is strict, and messages are one capped line."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.errors import FileFormatError, OptionError
from cadartifact.exchange.load import read
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REALDATA, ROOT, SAMPLES

pytest.importorskip("OCP")
pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")

HOOD = ROOT / "samples" / "car_hood_coarse.step"


def hood_text() -> str:
    return HOOD.read_text(encoding="latin-1")


def write(tmp_path, name, text) -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode("latin-1") if isinstance(text, str) else text)
    return path


def gate(path, *extra):
    r = CliRunner().invoke(app, ["gate", str(path), "--tol", "1e6", "--format", "json", "--jobs", "1", *extra])
    no_traceback(r)
    return r, json.loads(r.stdout)


# ---------------------------------------------------------------- 1. nothing lost without a word
def _without_reference_scan(monkeypatch):
    """The reference scan (issue 27) rejects a renamed pole before OCCT sees it: switched off here to
    test the dropped-face audit behind it, which catches what the scan cannot name."""
    import cadartifact.exchange.step_refs as step_refs

    monkeypatch.setattr(step_refs, "check_references", lambda *args, **kwargs: None)


def test_a_face_the_transfer_drops_is_named_and_fails_the_gate(tmp_path, monkeypatch):
    # a pole's CARTESIAN_POINT renamed: OCCT's parser accepts the file and its transfer drops the face
    text = hood_text().replace("#50 = CARTESIAN_POINT('',(", "#50 = XCARTESIAN_POINT('',(", 1)
    path = write(tmp_path, "hood.step", text)
    with pytest.raises(FileFormatError, match=r"#50 is referenced by B_SPLINE_SURFACE_WITH_KNOTS #\d+ \(line \d+\) "
                                              r"as a pole, and is XCARTESIAN_POINT"):
        read(path)
    _without_reference_scan(monkeypatch)
    res = read(path)
    assert res.skipped == {"dropped": 1} and res.faces_total == 1 and not res.nets
    dropped = [w for w in res.warnings if "was dropped" in w]
    assert len(dropped) == 1 and "#17" in dropped[0] and "ADVANCED_FACE" in dropped[0]
    assert "Surface has not been created" in dropped[0]  # OCCT's own check message
    r, doc = gate(path)
    assert r.exit_code == 2 and doc["files"][0]["verdict"] == "error"
    assert "#17" in doc["files"][0]["error"]
    # advise fails closed too: one line, exit 2, no document
    adv = CliRunner().invoke(app, ["advise", str(path), "--tol", "1", "--json", "--no-verify", "--no-compare"])
    assert adv.exit_code == 2 and adv.stdout == "" and "#17" in adv.stderr


def test_one_dropped_face_among_good_ones_fails_the_folder(tmp_path, monkeypatch):
    from cadartifact.exchange.load import write_step

    _without_reference_scan(monkeypatch)

    good = read(HOOD).nets[0]
    write_step([good, good.replace(origin=good.origin.__class__(name="second", kind="bspline"))],
               tmp_path / "two.step")
    text = (tmp_path / "two.step").read_text(encoding="latin-1")
    first_point = re.search(r"#(\d+) = B_SPLINE_SURFACE_WITH_KNOTS\('',3,3,\(\s*\(#(\d+)", text).group(2)
    text = text.replace(f"#{first_point} = CARTESIAN_POINT(", f"#{first_point} = XCARTESIAN_POINT(", 1)
    folder = tmp_path / "models"
    folder.mkdir()
    write(folder, "two.step", text)
    (folder / "good.step").write_bytes(HOOD.read_bytes())
    res = read(folder / "two.step")
    assert res.faces_total == 2 and len(res.nets) == 1 and res.skipped == {"dropped": 1}
    r, doc = gate(folder)
    verdicts = {Path(f["path"]).name: f["verdict"] for f in doc["files"]}
    assert verdicts == {"good.step": "pass", "two.step": "error"} and r.exit_code == 2


@pytest.mark.realdata
def test_real_files_lose_no_face(tmp_path):
    files = sorted((REALDATA / "step").glob("*.st*p"))
    assert files
    for path in files:
        res = read(path)
        declared = len(re.findall(r"=\s*(?:ADVANCED_FACE|FACE_SURFACE)\s*\(", path.read_text(encoding="latin-1")))
        assert res.faces_total == declared and "dropped" not in res.skipped, path.name


# ---------------------------------------------------------------- 2. bounds before OCCT
def _sub(text, pattern, repl):
    out, n = re.subn(pattern, repl, text, count=1, flags=re.S)
    assert n == 1, pattern
    return out


BOUNDS = {
    # the false pass: a knot multiplicity 1 -> 11 passed the gate (OCCT dropped the face)
    "multiplicity": (lambda t: t.replace("(4,1,1,4)", "(4,1,11,4)", 1), "#27", "multiplicity 11"),
    "degree": (lambda t: _sub(t, r"(#35 = B_SPLINE_SURFACE_WITH_KNOTS\('',)3,", r"\g<1>2147483648,"), "#35",
               "degree 2147483648"),
    "decreasing knots": (lambda t: t.replace("(0.,0.2,0.4,0.6,", "(0.,0.4,0.2,0.6,", 1), "#35", "knots decrease"),
    "multiplicity sum": (lambda t: t.replace("(4,1,1,1,1,4),(4,1,1,4)", "(4,1,1,1,1,4),(4,2,1,4)", 1), "#35",
                         "sum to 11"),
    "huge coordinate": (lambda t: t.replace("#40 = CARTESIAN_POINT('',(", "#40 = CARTESIAN_POINT('',(1.E154+", 1)
                        .replace("(1.E154+", "(1.E154,", 1).replace("(1.E154,0.", "(1.E154,", 1), "#40", "1.E154"),
    "infinite": (lambda t: _sub(t, r"(#41 = CARTESIAN_POINT\('',\()[^,]+", r"\g<1>1.E400"), "#41", "1.E400"),
    "nan": (lambda t: _sub(t, r"(#42 = CARTESIAN_POINT\('',\()[^,]+", r"\g<1>NaN"), "#42", "NaN"),
    # a duplicated record: OCCT transferred the shape twice (2 faces reported, 1 declared)
    "duplicate id": (lambda t: t.replace("#3 = SHAPE_DEFINITION_REPRESENTATION(#4,#10);",
                                         "#3 = SHAPE_DEFINITION_REPRESENTATION(#4,#10);\n"
                                         "#3 = SHAPE_DEFINITION_REPRESENTATION(#4,#10);", 1), "#3", "defined twice"),
    "poles not a grid": (lambda t: t.replace("(#36,#37,#38,#39,#40,#41)", "(#36,#37,#38,#39,#40)", 1), "#35",
                         "rectangular"),
}


@pytest.mark.parametrize("kind", sorted(BOUNDS))
def test_impossible_numbers_are_an_error_before_occt(tmp_path, monkeypatch, kind):
    mutate, ident, needle = BOUNDS[kind]
    path = write(tmp_path, "hood.step", mutate(hood_text()))
    # in this process, with OCCT's reader replaced: the error must come before it is called
    import cadartifact.exchange.step as step

    from cadartifact.execution import child

    monkeypatch.setattr(child, "_settings", child.settings().replace(isolation=False))  # read in this process
    monkeypatch.setattr(step, "read_step_audited", lambda p: pytest.fail("OCCT was called"))
    with pytest.raises(FileFormatError) as err:
        read(path)
    message = str(err.value)
    assert message.startswith(str(path)) and ident in message and needle in message, message
    monkeypatch.undo()
    r, doc = gate(path)
    assert r.exit_code == 2 and ident in doc["files"][0]["error"]


def _rational_step(tmp_path) -> str:
    from cadartifact.exchange.load import write_step
    from cadartifact.net import ControlNet

    i, j = np.meshgrid(np.arange(5), np.arange(4), indexing="ij")
    points = np.stack([10.0 * i, 10.0 * j, np.sin(i) + np.cos(j)], -1)
    weights = 1.0 + 0.3 * ((i + j) % 2)
    net = ControlNet.from_points(points, degrees=(3, 2), weights=weights)
    return write_step([net], tmp_path / "rational.step").read_text(encoding="latin-1")


@pytest.mark.parametrize("weight, needle", [("1.E308", "'1.E308'"), ("0.", "weight 0.0"), ("-1.", "weight -1.0")])
def test_a_weight_out_of_bounds_is_an_error_not_nan_numbers(tmp_path, weight, needle):
    text = _rational_step(tmp_path)
    assert "RATIONAL_B_SPLINE_SURFACE" in text
    text = _sub(text, r"(RATIONAL_B_SPLINE_SURFACE\(\s*\(\s*\()[^,]+", r"\g<1>" + weight)
    path = write(tmp_path, "w.step", text)
    with pytest.raises(FileFormatError, match="weight"):
        read(path)
    adv = CliRunner().invoke(app, ["advise", str(path), "--tol", "1", "--json", "--no-verify", "--no-compare"])
    assert adv.exit_code == 2 and adv.stdout == "" and needle in adv.stderr


def test_weights_of_the_wrong_shape(tmp_path):
    text = _rational_step(tmp_path)
    text = _sub(text, r"(RATIONAL_B_SPLINE_SURFACE\(\s*\(\s*\()([^,]+),", r"\g<1>")
    with pytest.raises(FileFormatError, match="weights are not a 5x4"):
        read(write(tmp_path, "w.step", text))


def test_real_files_and_samples_pass_the_prescan():
    from cadartifact.exchange.step_scan import check_step_text

    files = sorted((ROOT / "samples").glob("*.step"))
    if REALDATA.exists():
        files += sorted((REALDATA / "step").glob("*.st*p"))
    for path in files:
        check_step_text(path, path.read_text(encoding="latin-1"))


def test_parse_parameters_simple_and_complex():
    from cadartifact.exchange.step_scan import parse_parameters

    assert parse_parameters("CARTESIAN_POINT('a''b',(1.,-2.5E-3,3))") == [
        ("CARTESIAN_POINT", ["'a''b'", [1.0, -0.0025, 3]])]
    parts = parse_parameters("( BOUNDED_SURFACE() B_SPLINE_SURFACE(3,2,((#1,#2)),.UNSPECIFIED.,.F.,.F.,.F.) "
                             "RATIONAL_B_SPLINE_SURFACE(((1.,2.))) SURFACE() )")
    assert [p[0] for p in parts] == ["BOUNDED_SURFACE", "B_SPLINE_SURFACE", "RATIONAL_B_SPLINE_SURFACE", "SURFACE"]
    assert parts[1][1][:3] == [3, 2, [["#1", "#2"]]]
    with pytest.raises(ValueError):
        parse_parameters("CARTESIAN_POINT('',(1.,2.)")


# ---------------------------------------------------------------- 3. OCCT cannot take the run down
def test_a_crashing_reader_is_an_error_and_the_next_file_is_read():
    from cadartifact.execution import child

    with pytest.raises(FileFormatError, match=r"x\.step: the STEP reader crashed on this file \(SIGABRT\)"):
        child.call("os:abort", (), path="x.step")
    assert read(HOOD).nets  # a new child serves the next file


def test_a_hanging_reader_is_stopped_after_the_timeout():
    from cadartifact.execution import child

    with pytest.raises(FileFormatError, match=r"y\.step: the STEP reader gave no answer in 0\.5 s"):
        child.call("time:sleep", (30,), path="y.step", timeout=0.5)
    assert read(HOOD).nets


def test_gate_read_timeout_option_and_environment(tmp_path, monkeypatch):
    big = REALDATA / "step" / "nist_ctc_02_asme1_ap242-1.stp"
    path = big if big.exists() else HOOD
    r, doc = gate(path, "--read-timeout", "0.001")
    assert r.exit_code == 2 and "gave no answer in 0.001 s" in doc["files"][0]["error"]
    monkeypatch.setenv("CADARTIFACT_READ_TIMEOUT", "0.001")
    r, doc = gate(path)
    assert r.exit_code == 2 and "gave no answer in 0.001 s" in doc["files"][0]["error"]
    monkeypatch.setenv("CADARTIFACT_READ_TIMEOUT", "soon")
    from cadartifact.cli.environment import execution_settings
    from cadartifact.execution.child import configured

    with configured(execution_settings()):  # read at the CLI's edge, its error raised by the read
        with pytest.raises(OptionError, match="CADARTIFACT_READ_TIMEOUT"):
            read(HOOD)
    r, doc = gate(HOOD)
    assert r.exit_code == 2 and "CADARTIFACT_READ_TIMEOUT" in doc["files"][0]["error"]
    monkeypatch.delenv("CADARTIFACT_READ_TIMEOUT")
    r = CliRunner().invoke(app, ["gate", str(HOOD), "--tol", "1", "--read-timeout", "-1"])
    assert r.exit_code == 2 and "--read-timeout" in r.stderr


def _same(a, b):
    assert a.faces_total == b.faces_total and a.skipped == b.skipped and a.warnings == b.warnings
    assert len(a.nets) == len(b.nets)
    for x, y in zip(a.nets, b.nets):
        assert x.origin == y.origin and x.degrees == y.degrees and x.periodic == y.periodic
        assert x.uv_bounds == y.uv_bounds and x.unit == y.unit
        np.testing.assert_array_equal(x.points, y.points)
        assert (x.weights is None) == (y.weights is None)
        if x.weights is not None:
            np.testing.assert_array_equal(x.weights, y.weights)
        for kx, ky in zip(x.knots, y.knots):
            np.testing.assert_array_equal(kx, ky)


def test_the_child_reads_exactly_what_an_in_process_read_gives(monkeypatch):
    files = sorted((ROOT / "samples").glob("*.step"))
    if REALDATA.exists():
        files += [REALDATA / "step" / "MAINBODY_BACK.stp", REALDATA / "step" / "boxed_sphere.step"]
    isolated = [read(p) for p in files]
    from cadartifact.execution import child

    monkeypatch.setattr(child, "_settings", child.settings().replace(isolation=False))  # read in this process
    for p, a in zip(files, isolated):
        _same(a, read(p))


def test_reading_does_not_import_occt_in_this_process():
    code = ("import sys, warnings; warnings.simplefilter('ignore'); from cadartifact.exchange import read; "
            f"r = read({str(HOOD)!r}); print(len(r.nets), 'OCP' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.stdout.split() == ["1", "False"], out.stderr


def test_a_file_name_that_is_not_utf8(tmp_path):
    if sys.platform == "win32":
        pytest.skip("POSIX byte file names")
    name = os.fsdecode(os.fsencode(str(tmp_path)) + b"/hood\xff.step")
    try:
        Path(name).write_bytes(HOOD.read_bytes())
    except (OSError, UnicodeEncodeError):
        pytest.skip("the file system does not take non-UTF-8 names")
    assert len(read(name).nets) == 1
    out = tmp_path / "gate.txt"
    r = CliRunner().invoke(app, ["gate", name, "--tol", "1e6", "--jobs", "1", "--output", str(out)])
    assert r.exit_code == 0, r.output
    assert "hood\\udcff.step" in out.read_text(encoding="utf-8")
    # on a real terminal too (stdout is strict UTF-8 by default)
    done = subprocess.run([sys.executable, "-m", "cadartifact.cli", "gate", name, "--tol", "1e6", "--jobs", "1"],
                          capture_output=True, timeout=300, env={**os.environ, "PYTHONIOENCODING": "utf-8"})
    assert done.returncode == 0 and b"hood\\udcff.step" in done.stdout, done.stderr


# ---------------------------------------------------------------- 4. OBJ strictness and messages
def obj_grid(n=4) -> str:
    vs = [f"v {i} {j} {0.1 * i * j}" for i in range(n) for j in range(n)]
    fs = [f"f {i * n + j + 1} {i * n + j + n + 1} {i * n + j + n + 2} {i * n + j + 2}"
          for i in range(n - 1) for j in range(n - 1)]
    return "\n".join(vs + fs) + "\n"


@pytest.mark.parametrize("bad, needle", [
    ("t crease 2/1/0 0 99999999999999999999 1.0", "vertex index '99999999999999999999'"),
    ("t crease 2/1/0 0 1 nan", "NaN sharpness"),
    ("f \u0661 2 6 5", "face vertex '\u0661'"),
    ("f 1// 2 6 5", "face vertex '1//'"),
    ("f 1/2/3/4 2 6 5", "face vertex '1/2/3/4'"),
    ("f 1/ 2 6 5", "face vertex '1/'"),
    ("v \u0661 0 0", "not numbers"),
    ("v 1_0 0 0", "not numbers"),
])
def test_obj_reader_is_strict(tmp_path, bad, needle):
    path = write(tmp_path, "m.obj", (obj_grid() + bad + "\n").encode("utf-8"))
    with pytest.raises(FileFormatError) as err:
        read(path)
    assert needle in str(err.value)
    r, doc = gate(path)
    assert r.exit_code == 2 and needle in doc["files"][0]["error"]


def test_a_huge_face_line_is_quoted_briefly(tmp_path):
    path = write(tmp_path, "m.obj", obj_grid() + "f " + " ".join(["1"] * 100_000) + "\n")
    r = CliRunner().invoke(app, ["advise", str(path), "--tol", "1", "--no-verify", "--no-compare"])
    assert r.exit_code == 2 and len(r.stderr.strip().splitlines()) == 1 and len(r.stderr) < 400
    assert "characters)" in r.stderr


def test_skipped_charts_are_told_apart_and_warnings_stay_off_stderr(tmp_path):
    # two separate 2x2 grids whose points coincide: both charts are degenerate
    vs = ["v 0 0 0"] * 18
    fs = []
    for base in (0, 9):
        for i in range(2):
            for j in range(2):
                a = base + i * 3 + j + 1
                fs.append(f"f {a} {a + 3} {a + 4} {a + 1}")
    path = write(tmp_path, "flat.obj", "\n".join(vs + fs) + "\n")
    res = read(path)
    every = [w for w in res.warnings if w.startswith("skipped chart")]
    skipped = [w for w in every if "level 1" not in w]  # (their quads after one step are told apart the same way)
    assert len(skipped) == 2 and "grid 0" in skipped[0] and "grid 1" in skipped[1]
    assert len(every) == 4 and all("level 1 grid" in w for w in every if w not in skipped)
    assert "line 19" in skipped[0] and "line 23" in skipped[1]
    out = subprocess.run([sys.executable, "-m", "cadartifact.cli", "gate", str(path), "--tol", "1", "--jobs", "1"],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert out.returncode == 2 and "LoadWarning" not in out.stderr and "warn(" not in out.stderr, out.stderr


def test_a_subfolder_the_gate_cannot_read_is_an_error(tmp_path, monkeypatch):
    folder = tmp_path / "models"
    (folder / "locked").mkdir(parents=True)
    (folder / "good.step").write_bytes(HOOD.read_bytes())
    real_scandir, real_listdir = os.scandir, os.listdir
    locked = str(folder / "locked")

    def deny(fn):
        def wrapped(path=".", *a):
            if os.fspath(path) == locked:  # root ignores permissions: refuse the listing here
                raise PermissionError(13, "Permission denied", locked)
            return fn(path, *a)
        return wrapped

    monkeypatch.setattr(os, "scandir", deny(real_scandir))
    monkeypatch.setattr(os, "listdir", deny(real_listdir))
    r, doc = gate(folder)
    verdicts = {Path(f["path"]).name: f["verdict"] for f in doc["files"]}
    assert verdicts == {"good.step": "pass", "locked": "error"} and r.exit_code == 2
    assert "cannot read this folder (Permission denied)" in doc["files"][1]["error"]


def test_an_iges_face_the_transfer_skips_fails_the_gate(tmp_path):
    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.occ import make_face

    writer = IGESControl_Writer("MM", 1)
    writer.AddShape(make_face(read(HOOD).nets[0]))
    writer.ComputeModel()
    good = tmp_path / "hood.igs"
    assert writer.Write(str(good))
    assert len(read(good).nets) == 1
    text = good.read_text(encoding="latin-1")
    bad = write(tmp_path, "bad.igs", text.replace("0.,0.,0.,0.,0.2,0.4", "0.,0.,0.,0.,0.4,0.2", 1))  # knots decrease
    res = read(bad)
    assert res.skipped == {"dropped": 1} and not res.nets
    message = next(w for w in res.warnings if "was dropped" in w)
    assert "D1" in message and "Knots are not in ascending order" in message
    r, doc = gate(bad)
    assert r.exit_code == 2 and "D1" in doc["files"][0]["error"]


def test_an_unexpected_exception_is_one_line_and_exit_2(monkeypatch):
    import cadartifact.runs.advising as report

    def boom(*args, **kwargs):
        raise RuntimeError("something\nbroke " + "x" * 2000)

    monkeypatch.setattr(report, "advise_files", boom)
    r = CliRunner().invoke(app, ["advise", str(HOOD), "--tol", "1"])
    assert r.exit_code == 2
    no_traceback(r)
    assert len(r.stderr.strip().splitlines()) == 1 and "RuntimeError: something broke" in r.stderr
    assert len(r.stderr) < 700


def test_collapsed_pole_grids_give_the_same_checks_as_the_full_parse():
    from cadartifact.exchange.step_scan import (_data_section, _grid_shape, _records_with, _spline, clean_data,
                                                collapse_grids, parse_parameters, spline_problem)

    files = sorted((ROOT / "samples").glob("*.step"))
    if REALDATA.exists():
        files += sorted((REALDATA / "step").glob("*.st*p"))
    seen = 0
    for path in files:
        data = clean_data(_data_section(path.read_text(encoding="latin-1")))
        for _, body, _ in _records_with(data, "B_SPLINE"):
            for text in (body, body.replace("(#", "(#1,#", 1)):  # and with one row made ragged
                fast, full = _spline(parse_parameters(collapse_grids(text))), _spline(parse_parameters(text))
                assert fast[0] == full[0] and spline_problem(*fast) == spline_problem(*full)
                dims = 2 if "SURFACE" in full[0] else 1
                assert _grid_shape(fast[1]["poles"], dims) == _grid_shape(full[1]["poles"], dims)
                for key in ("degrees", "mults", "knots", "weights"):
                    assert fast[1].get(key) == full[1].get(key)
            seen += 1
    assert seen >= 20


def test_the_reader_child_ignores_a_cadartifact_folder_in_the_working_directory(tmp_path):
    """``python -m`` puts the working directory first on sys.path: the child is started with ``-P`` so that
    another checkout's (or any) ``cadartifact`` folder there cannot stand in for the installed package."""
    script = Path(sys.executable).with_name("cadartifact")
    if not script.exists():
        pytest.skip("no cadartifact console script beside this interpreter")
    fake = tmp_path / "cadartifact"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('the wrong cadartifact')\n")
    sample = SAMPLES / "clean_panel.step"
    out = subprocess.run([str(script), "gate", str(sample), "--tol", "0.05", "--format", "json"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout[-500:] + out.stderr[-500:]  # the clean panel passes at 0.05
    assert json.loads(out.stdout)["files"][0]["verdict"] != "error"
