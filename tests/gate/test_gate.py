"""The CI quality gate end to end: verdicts and exit codes, policy lookup and overrides, fail closed.

Models are STEP files written in tmp_path from nets of known ripple; the expected verdicts are
derived from the ripple that :func:`cadartifact.budget` reports for the loaded face (a separate
road from the gate's advise -> face_record -> verdict chain).
"""

import json
import os
import shutil

import numpy as np
import pytest
from typer.testing import CliRunner

import cadartifact as ca
from cadartifact.cli.app import app
from cadartifact.net import ControlNet
from cadartifact.testing.gate_models import named, ridge_points
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REALDATA

pytest.importorskip("OCP")


def run(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args)])
    no_traceback(result)
    return result


def gate_json(*args):
    result = run(*args, "--format", "json", "--jobs", "1")
    return result, (json.loads(result.stdout) if result.stdout.strip() else None)


def copy(models, tmp_path, *names, sub=""):
    folder = tmp_path / sub
    folder.mkdir(parents=True, exist_ok=True)
    for n in names:
        shutil.copy(models["root"] / n, folder / n)
    return folder


# ---------------------------------------------------------------- verdicts and exit codes
@pytest.mark.parametrize("ratio, verdict, code", [(0.5, "pass", 0), (0.9, "warn", 0), (1.5, "fail", 1)])
def test_verdict_and_exit_code_follow_the_ripple(models, ratio, verdict, code):
    """value = ratio * tolerance: below 0.8 pass, within but above 0.8 warn, beyond fail."""
    v = models["value"]
    result, doc = gate_json(models["root"] / "ridge.step", "--tol", v / ratio)
    assert result.exit_code == code, result.output
    face = doc["files"][0]["faces"][0]
    assert face["value"] == pytest.approx(v, rel=1e-6)
    assert face["verdict"] == verdict and doc["files"][0]["verdict"] == verdict
    assert doc["verdict"] == verdict and doc["exit_code"] == code
    assert doc["summary"]["verdicts"]["faces"][verdict] == 1
    assert face["name"] == "ridge"
    # the verdict needs today's budget only: advice for faces that warn or fail (--advise failing)
    assert (face["advice"] is None) == (verdict == "pass")


def test_file_verdict_is_the_worst_face(models):
    v = models["value"]
    _, doc = gate_json(models["root"] / "pair.step", "--tol", v / 0.9)
    assert [f["verdict"] for f in doc["files"][0]["faces"]] == ["pass", "warn"]
    assert doc["files"][0]["verdict"] == "warn" and doc["exit_code"] == 0


def test_warn_fraction_option(models):
    v = models["value"]
    _, doc = gate_json(models["root"] / "ridge.step", "--tol", v / 0.5, "--warn-fraction", 0.4)
    assert doc["files"][0]["faces"][0]["verdict"] == "warn"


def test_unreadable_file_fails_closed_and_the_rest_is_analysed(models, tmp_path):
    folder = copy(models, tmp_path, "clean.step", "broken.step", "ridge.step")
    result, doc = gate_json(folder, "--tol", 1e6)
    assert result.exit_code == 2
    verdicts = {os.path.basename(f["path"]): f["verdict"] for f in doc["files"]}
    assert verdicts == {"broken.step": "error", "clean.step": "pass", "ridge.step": "pass"}
    err = next(f for f in doc["files"] if f["verdict"] == "error")
    assert "broken.step" in err["error"] and err["faces"] == []
    assert doc["verdict"] == "error" and doc["summary"]["errors"] == 1
    text = run(folder, "--tol", 1e6, "--jobs", "1")
    assert text.exit_code == 2 and "ERROR" in text.stdout and "broken.step" in text.stdout


def test_text_report(models):
    v = models["value"]
    result = run(models["root"] / "pair.step", "--tol", v / 1.5, "--jobs", "1")
    assert result.exit_code == 1
    out = result.stdout
    assert "pair.step" in out and "FAIL" in out and "1 fail" in out and "ridge" in out


def test_no_analysable_face_passes_with_a_note(tmp_path):
    cq = pytest.importorskip("cadquery")
    path = tmp_path / "box.step"
    cq.exporters.export(cq.Workplane().box(10, 10, 10), str(path))
    result, doc = gate_json(path, "--tol", 0.01)
    assert result.exit_code == 0
    entry = doc["files"][0]
    assert entry["verdict"] == "pass" and entry["faces"] == [] and entry["faces_total"] == 6
    assert any("no analysable face" in n for n in entry["notes"])


def test_measured_faces_fail_by_default_and_are_capped_at_warn_only_when_the_policy_says_so(tmp_path):
    """Non-uniform knots: measured on the real surface and gated like any face (issue 10); the policy's
    ``measured = "warn"`` keeps the older, lenient cap."""
    from cadartifact.exchange.load import write_step

    pts = ridge_points(nu=10, nv=6)
    ku = np.array([0, 0, 0, 0, 0.05, 0.1, 0.3, 0.5, 0.6, 0.9, 1, 1, 1, 1.0])
    net = named(pts, "blend", knots=(ku, ControlNet.from_points(pts).knots[1]))
    write_step([net], tmp_path / "blend.step")
    loaded = ca.load(tmp_path / "blend.step")[0]
    assert not loaded.uniform
    v = ca.budget(loaded).stats["total"].peak
    result, doc = gate_json(tmp_path / "blend.step", "--tol", v / 2)
    face = doc["files"][0]["faces"][0]
    assert face["method"] == "measured" and face["verdict"] == "fail" and result.exit_code == 1
    (tmp_path / "lenient.toml").write_text('measured = "warn"\n')
    result, doc = gate_json(tmp_path / "blend.step", "--tol", v / 2, "--policy", tmp_path / "lenient.toml")
    face = doc["files"][0]["faces"][0]
    assert face["verdict"] == "warn" and result.exit_code == 0 and "capped at warn" in face["verdict_reason"]


# ---------------------------------------------------------------- policy
def test_policy_is_found_from_the_working_directory_upward(models, tmp_path, monkeypatch):
    v = models["value"]
    (tmp_path / "cadartifact.toml").write_text(f"tolerance = {v / 1.5!r}\n")
    deep = tmp_path / "a" / "b"
    deep.mkdir(parents=True)
    monkeypatch.chdir(deep)
    result, doc = gate_json(models["root"] / "ridge.step")
    assert result.exit_code == 1
    assert doc["policy"] == os.path.relpath(tmp_path / "cadartifact.toml")
    assert doc["files"][0]["policy"]["tolerance"] == pytest.approx(v / 1.5)


def test_pyproject_tool_table_and_a_pyproject_without_it_is_passed_over(models, tmp_path, monkeypatch):
    v = models["value"]
    (tmp_path / "pyproject.toml").write_text(f"[project]\nname='x'\n\n[tool.cadartifact]\ntolerance = {v / 0.5!r}\n")
    inner = tmp_path / "pkg"
    inner.mkdir()
    (inner / "pyproject.toml").write_text("[project]\nname = 'inner'\n")
    monkeypatch.chdir(inner)
    result, doc = gate_json(models["root"] / "ridge.step")
    assert result.exit_code == 0 and doc["files"][0]["faces"][0]["verdict"] == "pass"
    assert doc["policy"].endswith("pyproject.toml") and os.path.dirname(doc["policy"]) == ".."
    # cadartifact.toml beside it wins over pyproject.toml in the same folder
    (tmp_path / "cadartifact.toml").write_text(f"tolerance = {v / 1.5!r}\n")
    assert gate_json(models["root"] / "ridge.step")[0].exit_code == 1


def test_command_line_overrides_the_policy(models, tmp_path, monkeypatch):
    v = models["value"]
    (tmp_path / "cadartifact.toml").write_text(f'tolerance = {v / 1.5!r}\nmetric = "peak"\nwarn_fraction = 0.8\n')
    monkeypatch.chdir(tmp_path)
    assert gate_json(models["root"] / "ridge.step")[0].exit_code == 1
    result, doc = gate_json(models["root"] / "ridge.step", "--tol", v / 0.5)
    assert result.exit_code == 0 and doc["files"][0]["policy"]["tolerance"] == pytest.approx(v / 0.5)
    _, doc = gate_json(models["root"] / "ridge.step", "--tol", v / 0.5, "--metric", "rms")
    face = doc["files"][0]["faces"][0]
    assert face["value"] == pytest.approx(face["budget"]["total"]["rms"]) and doc["metric"] == "rms"


@pytest.mark.parametrize("text, needle", [
    ("tolerence = 0.1\n", "key 'tolerence' is unknown (valid: tolerance, metric"),
    ("tolerance = -1\n", "key 'tolerance': expected a positive number"),
    ("tolerance = 0.1\nwarn_fraction = 1.5\n", "key 'warn_fraction'"),
    ("tolerance = 0.1\nmetric = 'max'\n", "key 'metric': expected one of 'peak', 'rms'"),
    ("tolerance = 0.1\nmeasured = 'ignore'\n", "key 'measured'"),
    ("tolerance = 0.1\nscheme = 'bicubik'\n", "key 'scheme'"),
    ("tolerance = 0.1\ninclude_signal_error = 'yes'\n", "key 'include_signal_error'"),
    ("tolerance = 0.1\nignore_faces = [1]\n", "key 'ignore_faces' is unknown"),
    ("tolerance = 0.1\n[[override]]\ntolerance = 1\n", "key 'override[1].glob' is missing"),
    ("tolerance = 0.1\n[[override]]\nglob = '*'\ntol = 1\n", "key 'override[1].tol' is unknown"),
    ("tolerance = 0.1\n[[override]]\nglob = '*'\nignore_faces = [-1]\n", "key 'override[1].ignore_faces'"),
    ("tolerance = [0.1\n", "not valid TOML"),
])
def test_bad_policy_is_a_usage_error_naming_the_key(models, tmp_path, monkeypatch, text, needle):
    (tmp_path / "cadartifact.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    result = run(models["root"] / "ridge.step", "--output", tmp_path / "out.json", "--format", "json")
    assert result.exit_code == 2
    assert needle in result.stderr and "cadartifact.toml" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and result.stdout == ""
    assert not (tmp_path / "out.json").exists()


def test_no_tolerance_anywhere_is_a_usage_error(models, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = run(models["root"] / "ridge.step")
    assert result.exit_code == 2 and "no tolerance" in result.stderr


def test_bad_options_are_usage_errors(models):
    path = models["root"] / "ridge.step"
    for args, needle in ((["--tol", "0"], "--tol"), (["--tol", "1", "--format", "xml"], "--format"),
                         (["--tol", "1", "--jobs", "0"], "--jobs"), (["--tol", "1", "--metric", "max"], "--metric"),
                         (["--tol", "1", "--warn-fraction", "0"], "--warn-fraction"),
                         (["--tol", "1", "--output", "/nonexistent/dir/r.json"], "--output")):
        result = run(path, *args)
        assert result.exit_code == 2 and needle in result.stderr, (args, result.output)
    assert run(models["root"] / "nothing_here.step", "--tol", 1).exit_code == 2
    assert "matches no" in run(str(models["root"] / "*.iges"), "--tol", 1).stderr


def test_override_by_glob_later_wins_and_cli_wins_over_all(models, tmp_path, monkeypatch):
    v = models["value"]
    copy(models, tmp_path, "ridge.step", sub="strict")
    copy(models, tmp_path, "ridge.step", sub="legacy")
    (tmp_path / "cadartifact.toml").write_text(
        f"tolerance = {v / 1.5!r}\n"
        f"[[override]]\nglob = 'legacy/*'\ntolerance = {v / 0.9!r}\n"
        f"[[override]]\nglob = 'legacy/ridge.step'\ntolerance = {v / 0.5!r}\n")
    monkeypatch.chdir(tmp_path / "strict")  # globs are relative to the policy's folder, not the cwd
    result, doc = gate_json(tmp_path)
    verdicts = {os.path.basename(os.path.dirname(f["path"])): f["verdict"] for f in doc["files"]}
    assert verdicts == {"legacy": "pass", "strict": "fail"} and result.exit_code == 1
    _, doc = gate_json(tmp_path, "--tol", v / 0.5)
    assert {f["verdict"] for f in doc["files"]} == {"pass"}


def test_ignore_faces(models, tmp_path, monkeypatch):
    v = models["value"]
    folder = copy(models, tmp_path, "pair.step")
    (tmp_path / "cadartifact.toml").write_text(
        f"tolerance = {v / 1.5!r}\n[[override]]\nglob = 'pair.step'\nignore_faces = [1, 7]\n")
    monkeypatch.chdir(tmp_path)
    result, doc = gate_json(folder / "pair.step")
    entry = doc["files"][0]
    assert result.exit_code == 0 and [f["face"] for f in entry["faces"]] == [0]
    assert entry["ignored_faces"] == [1] and any("[7]" in n for n in entry["notes"])


# ---------------------------------------------------------------- formats
@pytest.fixture(scope="module")
def mixed(models, tmp_path_factory):
    """pair.step (pass + fail), warn/ridge.step (warn), broken.step (error), with a policy."""
    v = models["value"]
    root = tmp_path_factory.mktemp("mixed")
    for n in ("pair.step", "broken.step"):
        shutil.copy(models["root"] / n, root / n)
    (root / "warn").mkdir()
    shutil.copy(models["root"] / "ridge.step", root / "warn" / "ridge.step")
    (root / "cadartifact.toml").write_text(f"tolerance = {v / 1.5!r}\n[[override]]\nglob = 'warn/*'\n"
                                           f"tolerance = {v / 0.9!r}\n")
    return root


def test_junit_report(mixed, monkeypatch):
    import xml.etree.ElementTree as ET

    monkeypatch.chdir(mixed)
    result = run("pair.step", "warn", "broken.step", "--format", "junit", "--output", "gate.xml", "--jobs", "1")
    assert result.exit_code == 2
    root = ET.parse(mixed / "gate.xml").getroot()
    suites = root.findall("testsuite")
    assert [s.get("name") for s in suites] == ["pair.step", os.path.join("warn", "ridge.step"), "broken.step"]
    cases = root.findall(".//testcase")
    assert [c.get("name") for c in cases] == ["pair.step#0 dome", "pair.step#1 ridge",
                                              os.path.join("warn", "ridge.step") + "#0 ridge", "broken.step"]
    failures = root.findall(".//failure")
    assert len(failures) == 1 and "advised net" in failures[0].text and "x1" in failures[0].text
    assert len(root.findall(".//error")) == 1 and "broken.step" in root.find(".//error").get("message")
    assert "warning" in cases[2].find("system-out").text
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("4", "1", "1")
    assert [s.get("failures") for s in suites] == ["1", "0", "0"]


def test_sarif_report(mixed, monkeypatch):
    monkeypatch.chdir(mixed)
    result = run("pair.step", "warn", "broken.step", "--format", "sarif", "--jobs", "1")
    assert result.exit_code == 2
    log = json.loads(result.stdout)
    assert log["version"] == "2.1.0" and "sarif" in log["$schema"]
    run0 = log["runs"][0]
    driver = run0["tool"]["driver"]
    assert driver["name"] == "cadartifact"
    rules = {r["id"]: r for r in driver["rules"]}
    assert rules["CA001"]["name"] == "ripple-exceeds-tolerance"
    assert rules["CA001"]["defaultConfiguration"]["level"] == "error"
    assert rules["CA002"]["defaultConfiguration"]["level"] == "warning"
    assert rules["CA003"]["name"] == "unreadable-file"
    found = sorted((r["ruleId"], r["level"], r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"])
                   for r in run0["results"])
    assert found == [("CA001", "error", "pair.step"), ("CA002", "warning", "warn/ridge.step"),
                     ("CA003", "error", "broken.step")]
    for r in run0["results"]:
        assert r["message"]["text"] and driver["rules"][r["ruleIndex"]]["id"] == r["ruleId"]
        assert r["locations"][0]["physicalLocation"]["region"]["startLine"] >= 1
    fail = next(r for r in run0["results"] if r["ruleId"] == "CA001")
    assert "exceeds tolerance" in fail["message"]["text"] and fail["properties"]["advised_net"]
    assert run0["invocations"][0]["exitCode"] == 2


def test_jobs_2_equals_jobs_1(models, mixed, monkeypatch):
    monkeypatch.chdir(mixed)
    args = ["gate", "pair.step", "warn", "broken.step", str(models["root"] / "clean.step"), "--format", "json"]
    one = CliRunner().invoke(app, [*args, "--jobs", "1"])
    two = CliRunner().invoke(app, [*args, "--jobs", "2"])
    assert one.exit_code == two.exit_code == 2
    assert one.stdout == two.stdout


def test_output_is_written_whole(models, tmp_path):
    out = tmp_path / "reports" / "gate.json"
    out.parent.mkdir()
    out.write_text("stale")
    result = run(models["root"] / "ridge.step", "--tol", models["value"] / 1.5, "--format", "json",
                 "--output", out, "--jobs", "1")
    assert result.exit_code == 1 and "gate FAIL" in result.stdout
    doc = json.loads(out.read_text())
    assert doc["verdict"] == "fail" and doc["exit_code"] == 1
    assert os.listdir(out.parent) == ["gate.json"]  # no temporary file left
    text = tmp_path / "gate.txt"
    run(models["root"] / "ridge.step", "--tol", 1, "--output", text, "--jobs", "1")
    assert "gate PASS" in text.read_text() and "\x1b[" not in text.read_text()


def test_report_option(models, tmp_path):
    import importlib.util

    out = tmp_path / "report.html"
    result = run(models["root"] / "ridge.step", "--tol", 1, "--report", out, "--jobs", "1")
    if importlib.util.find_spec("cadartifact.viz.html") is None:
        assert result.exit_code == 2 and "not available" in result.stderr and not out.exists()
    else:
        assert result.exit_code == 0 and out.read_text().lstrip().lower().startswith("<!doctype html")


# ---------------------------------------------------------------- real files


@pytest.mark.realdata
def test_real_files_verdicts_follow_their_budgets():
    """NIST FTC-07 (non-uniform bicubic faces: gated like any face) and the Blub Catmull-Clark cage (its charts,
    and its extraordinary vertices against the tolerance)."""
    tol = 0.05
    paths = [REALDATA / "step" / "nist_ftc_07_asme1_rd.stp", REALDATA / "obj" / "blub_control_mesh.obj"]
    result, doc = gate_json(*paths, "--tol", tol)
    seen = set()
    for entry, path in zip(doc["files"], paths):
        nets = {n.origin.face: n for n in ca.load(path)}
        assert [f["face"] for f in entry["faces"]] == sorted(nets) and nets
        for f in entry["faces"]:
            b = ca.budget(nets[f["face"]], tolerance=tol)
            value = b.stats["total"].peak
            expect = "fail" if value > tol else "warn" if value >= 0.8 * tol else "pass"
            assert f["value"] == pytest.approx(value, rel=1e-6, abs=1e-9)  # the document keeps 9 decimals
            assert (f["verdict"], f["method"]) == (expect, b.method)
            seen.add(f["verdict"])
    assert seen
    # the Blub cage: its triangles and pentagons after one step touch their face points (extraordinary vertices of
    # valence 3 and 5), so its charts cover 61.9 % of its area, below the default min_analysed_share 0.95
    (blub,) = [e for e in doc["files"] if e["path"].endswith(".obj")]
    # with the quads around them measured by the extraordinary-vertex measure, the whole area is analysed
    assert blub["analysed_share"] == 1.0 and "share_failure" not in blub
    # it also fails on its extraordinary vertices beyond the tolerance (4 of Blub's 38 at 0.05)
    beyond = [v for e in doc["files"] for v in e.get("extraordinary", []) if v["defect"] > tol and not v["crease"]]
    assert len(beyond) == 4 and "extraordinary_failure" in blub
    assert blub["verdict"] == "fail" and result.exit_code == 1 == doc["exit_code"]
