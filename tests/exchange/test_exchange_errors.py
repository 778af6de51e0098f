"""Bad input: the documented error class, a one-line message naming the file, and CLI exit 2."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.errors import FileFormatError, InputError, UnsupportedFormatError
from cadartifact.exchange.load import LoadWarning, read
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REALDATA, ROOT

SAMPLE_STEP = ROOT / "samples" / "wavy_panel_diagonal.step"


def _step_source() -> Path:
    real = REALDATA / "step" / "boxed_sphere.step"
    return real if real.exists() else SAMPLE_STEP


def bad_inputs(tmp: Path) -> dict[str, tuple[Path, type, str]]:
    """name -> (path, error class, text the message must contain)."""
    cases = {}
    cases["missing"] = (tmp / "nope.step", InputError, "file not found")
    (tmp / "empty.step").write_bytes(b"")
    cases["empty"] = (tmp / "empty.step", FileFormatError, "empty file")
    data = _step_source().read_bytes()
    (tmp / "half.step").write_bytes(data[: len(data) // 2])
    cases["truncated"] = (tmp / "half.step", FileFormatError, "not a readable STEP file")
    (tmp / "text.step").write_text("solid cube\n  facet normal 0 0 1\nendsolid\n")
    cases["not step"] = (tmp / "text.step", FileFormatError, "not a readable STEP file")
    (tmp / "garbage.stp").write_bytes(np.random.default_rng(0).integers(0, 256, 4000, dtype=np.uint8).tobytes())
    cases["binary"] = (tmp / "garbage.stp", FileFormatError, "not a readable STEP file")
    (tmp / "noshape.step").write_text(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
        "FILE_SCHEMA(('CONFIG_CONTROL_DESIGN'));\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\n"
        "END-ISO-10303-21;\n")
    cases["no shape"] = (tmp / "noshape.step", FileFormatError, "no shape")
    (tmp / "model.3mf").write_text("x")
    cases["extension"] = (tmp / "model.3mf", UnsupportedFormatError, ".step")
    (tmp / "nan.obj").write_text("v 0 0 0\nv 1 0 nan\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    cases["nan obj"] = (tmp / "nan.obj", FileFormatError, "line 2")
    (tmp / "inf.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 inf\nv 0 1 0\nf 1 2 3 4\n")
    cases["inf obj"] = (tmp / "inf.obj", FileFormatError, "NaN or infinite")
    (tmp / "tris.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    cases["triangles"] = (tmp / "tris.obj", InputError, "no quad faces")
    (tmp / "fin.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 1\nv 0 0 1\nv 1 0 -1\nv 0 0 -1\n"
                                 "f 1 2 3 4\nf 1 2 5 6\nf 1 2 7 8\n")
    cases["non-manifold"] = (tmp / "fin.obj", FileFormatError, "non-manifold")
    (tmp / "range.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 9\n")
    cases["index range"] = (tmp / "range.obj", FileFormatError, "vertex 9")
    (tmp / "repeat.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 2 4\n")
    cases["repeated vertex"] = (tmp / "repeat.obj", FileFormatError, "repeats a vertex")
    (tmp / "binary.obj").write_bytes(b"\x00\x01\x02\xff\xfe" * 50)
    cases["binary obj"] = (tmp / "binary.obj", FileFormatError, "not an OBJ file")
    (tmp / "nofaces.obj").write_text("v 0 0 0\n")
    cases["no faces"] = (tmp / "nofaces.obj", InputError, "no faces")
    (tmp / "garbage.igs").write_text("hello\n")
    cases["iges"] = (tmp / "garbage.igs", FileFormatError, "IGES")
    (tmp / "garbage.brep").write_text("hello\n")
    cases["brep"] = (tmp / "garbage.brep", FileFormatError, "BREP")
    (tmp / "folder.step").mkdir()
    cases["directory"] = (tmp / "folder.step", InputError, "not a file")
    return cases


@pytest.fixture()
def cases(tmp_path):
    return bad_inputs(tmp_path)


CASE_NAMES = ["missing", "empty", "truncated", "not step", "binary",
            "no shape", "extension", "nan obj", "inf obj", "triangles",
            "non-manifold", "index range", "repeated vertex",
            "binary obj", "no faces", "iges", "brep", "directory"]


@pytest.mark.parametrize("name", CASE_NAMES)
def test_bad_input_raises_documented_error(cases, name):
    path, cls, text = cases[name]
    with pytest.raises(cls) as info:
        read(path)
    message = str(info.value)
    assert message.startswith(str(path) + ": ")
    assert text in message and "\n" not in message


@pytest.mark.parametrize("name", CASE_NAMES)
def test_bad_input_cli_exit_2_without_traceback(cases, name):
    path, _, text = cases[name]
    result = CliRunner().invoke(app, ["inspect", str(path), "--json"])
    assert result.exit_code == 2
    no_traceback(result)
    assert str(path.name) in result.output and text in result.output
    assert "{" not in result.output  # no JSON at all


def test_cli_fails_closed_on_one_bad_file_among_good_ones(cases):
    bad, _, _ = cases["truncated"]
    result = CliRunner().invoke(app, ["inspect", str(SAMPLE_STEP), str(bad), "--json"])
    assert result.exit_code == 2 and "{" not in result.output and bad.name in result.output
    # text: the good file's table beside the error (issue 42), exit 2 still
    result = CliRunner().invoke(app, ["inspect", str(SAMPLE_STEP), str(bad)])
    assert result.exit_code == 2 and "wavy_panel_diagonal" in result.stdout.replace(str(SAMPLE_STEP), "")
    assert bad.name in result.stderr and bad.name not in result.stdout
    missing = CliRunner().invoke(app, ["inspect", str(SAMPLE_STEP), str(bad.parent / "missing.step")])
    assert missing.exit_code == 2 and "wavy_panel_diagonal" in missing.stdout.replace(str(SAMPLE_STEP), "")
    assert "missing.step" in missing.stderr


def test_cli_inspect_json_schema_and_tables():
    samples = [ROOT / "samples" / n for n in ("wavy_panel_diagonal.step", "cage.obj")]
    result = CliRunner().invoke(app, ["inspect", *map(str, samples), "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert doc["schema"] == "cadartifact.inspect/1"
    step, obj = doc["files"]
    assert step["format"] == "step" and step["faces_total"] == 1 and step["analysable"] == 1
    face = step["faces"][0]
    assert face == {"face": 0, "name": "wavy_panel_diagonal", "kind": "bspline", "degrees": [3, 3], "size": [12, 12],
                    "rational": False, "weights_vary": False, "periodic": [False, False],
                    "knots_uniform": [True, True], "trimmed_fraction": pytest.approx(1.0)}
    assert obj["format"] == "obj" and obj["mesh"]["quads"] == 40 and obj["mesh"]["extraordinary"]
    # (the cage as read: charts of level 1 hold quads of its first subdivision step)
    assert sum(len(c["faces"]) for c in obj["mesh"]["charts"] if c.get("level", 0) == 0) == obj["mesh"]["regular_faces"]
    table = CliRunner().invoke(app, ["inspect", *map(str, samples)])
    assert table.exit_code == 0 and "wavy_panel_diagonal" in table.output and "1 analysable" in table.output


def test_file_without_analysable_face_is_a_warning(tmp_path):
    cq = pytest.importorskip("cadquery")
    path = tmp_path / "box.step"
    cq.exporters.export(cq.Workplane().box(1, 2, 3), str(path))
    with pytest.warns(LoadWarning, match="no analysable face"):
        result = read(path)
    assert result.nets == [] and result.faces_total == 6 and result.skipped == {"plane": 6}
    cli = CliRunner().invoke(app, ["inspect", str(path)])
    assert cli.exit_code == 0 and "no analysable face" in cli.output


def test_truncated_brep_never_hangs(tmp_path):
    """OCCT's BREP reader can loop forever on truncated input: every cut must fail fast (subprocess + timeout)."""
    code = f"""
import cadquery as cq
from OCP.BRepTools import BRepTools
from cadartifact.exchange import read
from cadartifact.errors import FileFormatError
src = {str(tmp_path / 'part.brep')!r}
BRepTools.Write_s(cq.Workplane().box(1, 2, 3).edges().fillet(0.2).val().wrapped, src)
whole = read(src)  # the uncut file reads: 26 faces, none a B-spline
assert whole.nets == [] and whole.faces_total == 26, (len(whole.nets), whole.faces_total)
assert whole.skipped == {{'plane': 6, 'cylinder': 12, 'sphere': 8}}, whole.skipped
data = open(src).read()
for k in range(1, 12):
    cut = {str(tmp_path / 'cut.brep')!r}
    open(cut, 'w').write(data[: len(data) * k // 12])
    try:
        read(cut)
    except FileFormatError:
        continue
    raise SystemExit('no error for cut ' + str(k))
print('ok')
"""
    pytest.importorskip("cadquery")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip().endswith("ok"), out.stderr[-2000:]


def test_iges_and_brep_read_the_same_nets(tmp_path):
    pytest.importorskip("OCP")
    from OCP.BRepTools import BRepTools
    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.load import load
    from cadartifact.exchange.step import read_step

    shape, _ = read_step(SAMPLE_STEP)
    BRepTools.Write_s(shape, str(tmp_path / "panel.brep"))
    writer = IGESControl_Writer("MM", 1)
    writer.AddShape(shape)
    writer.ComputeModel()
    assert writer.Write(str(tmp_path / "panel.IGS"))
    reference = load(SAMPLE_STEP)[0]
    for name in ("panel.brep", "panel.IGS"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LoadWarning)
            (net,) = load(tmp_path / name)
        np.testing.assert_allclose(net.points, reference.points, atol=1e-9)
        for a, b in zip(net.knots, reference.knots):
            np.testing.assert_allclose(a, b, atol=1e-12)
