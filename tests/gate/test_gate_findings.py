"""The gate's findings as CI services see them: GitLab Code Quality, SARIF locations relative to the run's root,
and fingerprints stable across runs and machines (the path relative to the root, the face's record, the
criterion; never values or line numbers), unique per finding and the same in both reports.

Expected fingerprints are recomputed here with hashlib from the file's relative path, the face's STEP entity
(read from the JSON document) and the criterion; expected lines are found by searching the STEP text for the
entity's record.
"""

import hashlib
import json
import os
import shutil
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.gate.codequality import to_gitlab
from cadartifact.gate.locations import FINGERPRINT_KEY, Fingerprints, fingerprint, relative, run_root
from cadartifact.gate.sarif import to_sarif
from cadartifact.testing.outcomes import no_traceback

pytest.importorskip("OCP")

GITLAB_SEVERITIES = ("info", "minor", "major", "critical", "blocker")


def gate(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args), "--jobs", "1"])
    no_traceback(result)
    return result


def vault(models, folder: Path, tolerance: float, blank_lines: int = 0) -> Path:
    """pair.step (pass + fail at ``tolerance`` = ripple / 1.5), sub/ridge.step, broken.step; ``blank_lines``
    empty lines inserted after ``DATA;`` (every record moves down, nothing else changes)."""
    (folder / "sub").mkdir(parents=True)
    for name, target in (("pair.step", "pair.step"), ("ridge.step", "sub/ridge.step"), ("broken.step", "broken.step")):
        text = (models["root"] / name).read_text()
        (folder / target).write_text(text.replace("DATA;\n", "DATA;\n" + "\n" * blank_lines, 1))
    (folder / "cadartifact.toml").write_text(f"tolerance = {tolerance!r}\n")
    return folder


def expected(path: str, record: str, criterion: str) -> str:
    return hashlib.sha256(f"{path}\0{record}\0{criterion}".encode()).hexdigest()[:32]


def record_line(file: Path, entity: int) -> int:
    lines = file.read_text().splitlines()
    return next(k + 1 for k, row in enumerate(lines) if row.replace(" ", "").startswith(f"#{entity}=ADVANCED_FACE"))


@pytest.fixture(scope="module")
def runs(models, tmp_path_factory):
    """The same vault gated from two checkouts (other absolute paths, lines moved, a tighter tolerance in the
    second: warn -> fail), each run's gate JSON document with the working folder it ran in."""
    v = models["value"]
    out = []
    for k, (tol, blanks) in enumerate(((v / 1.5, 0), (v / 3.0, 7))):
        folder = vault(models, tmp_path_factory.mktemp(f"checkout{k}") / "models", tol, blanks)
        cwd = os.getcwd()
        os.chdir(folder)
        try:
            result = gate("pair.step", "sub", "broken.step", "--format", "json")
            doc = json.loads(result.stdout)
            out.append({"folder": folder, "doc": doc, "gitlab": json.loads(to_gitlab(doc)),
                        "sarif": json.loads(to_sarif(doc))})
        finally:
            os.chdir(cwd)
    return out


def test_gitlab_report_has_the_code_quality_fields(runs):
    run = runs[0]
    issues = run["gitlab"]
    assert isinstance(issues, list) and issues
    for issue in issues:
        assert set(issue) >= {"description", "check_name", "fingerprint", "severity", "location"}
        assert isinstance(issue["description"], str) and issue["description"]
        assert issue["severity"] in GITLAB_SEVERITIES
        assert isinstance(issue["location"]["lines"]["begin"], int) and issue["location"]["lines"]["begin"] >= 1
        assert not issue["location"]["path"].startswith(("/", ".")), issue["location"]["path"]
        assert (run["folder"] / issue["location"]["path"]).is_file()
    found = sorted((i["check_name"], i["severity"], i["location"]["path"]) for i in issues)
    assert found == [("CA001-ripple-exceeds-tolerance", "major", "pair.step"),
                     ("CA001-ripple-exceeds-tolerance", "major", "sub/ridge.step"),
                     ("CA003-unreadable-file", "critical", "broken.step")]


def test_gitlab_lines_are_the_face_records(runs):
    for run in runs:
        entities = {(e["path"].replace(os.sep, "/"), f["face"]): f["entity"]
                    for e in run["doc"]["files"] for f in e["faces"]}
        for issue in run["gitlab"]:
            path, line = issue["location"]["path"], issue["location"]["lines"]["begin"]
            if issue["check_name"].startswith("CA003"):
                assert line == 1
                continue
            entity = next(ent for (p, _), ent in entities.items() if p == path and f"#{ent}" in issue["description"])
            assert line == record_line(run["folder"] / path, entity)


def test_fingerprints_are_the_relative_path_the_record_and_the_criterion(runs):
    run = runs[0]
    want = set()
    for e in run["doc"]["files"]:
        path = e["path"].replace(os.sep, "/")
        if e["verdict"] == "error":
            want.add(expected(path, "", "unreadable-file"))
        want.update(expected(path, f"#{f['entity']}", "ripple") for f in e["faces"] if f["verdict"] != "pass")
    assert {i["fingerprint"] for i in run["gitlab"]} == want


def test_fingerprints_are_stable_across_checkouts_lines_and_values_and_shared_with_sarif(runs):
    first, second = runs
    assert first["folder"] != second["folder"]
    # the lines moved and the ridge face went from fail at v/1.5 ... to fail at v/3: other numbers, other lines
    assert ({i["location"]["lines"]["begin"] for i in first["gitlab"]}
            != {i["location"]["lines"]["begin"] for i in second["gitlab"]})
    assert ([i["description"] for i in first["gitlab"]] != [i["description"] for i in second["gitlab"]])
    for run in runs:
        prints = [i["fingerprint"] for i in run["gitlab"]]
        assert len(set(prints)) == len(prints)  # unique per finding
        assert prints == [r["partialFingerprints"][FINGERPRINT_KEY] for r in run["sarif"]["runs"][0]["results"]]
    assert sorted(i["fingerprint"] for i in first["gitlab"]) == sorted(i["fingerprint"] for i in second["gitlab"])


def test_warn_and_fail_of_a_face_share_its_fingerprint(models, runs, tmp_path, monkeypatch):
    """A face moving from warn to fail stays one alert (the criterion is the ripple, not the rule)."""
    folder = vault(models, tmp_path / "models", models["value"] / 0.9)
    monkeypatch.chdir(folder)
    doc = json.loads(gate("sub", "--format", "json").stdout)
    (warned,) = json.loads(to_gitlab(doc))
    assert warned["check_name"].startswith("CA002") and warned["severity"] == "minor"
    failed = next(i for i in runs[0]["gitlab"] if i["location"]["path"] == "sub/ridge.step")
    assert warned["fingerprint"] == failed["fingerprint"]


def test_sarif_locations_are_relative_to_the_run_root(runs, tmp_path, monkeypatch):
    """Files outside the working folder: the root is the deepest folder holding them, no '..' in any URI."""
    run = runs[0]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    doc = json.loads(json.dumps(run["doc"]))
    for e in doc["files"]:
        e["path"] = str(run["folder"] / e["path"])
    log = json.loads(to_sarif(doc))
    base = log["runs"][0]["originalUriBaseIds"]["SRCROOT"]["uri"]
    assert base.startswith("file:///") and base.endswith("/")
    root = Path(unquote(urlparse(base).path))
    assert root == run["folder"]
    for r in log["runs"][0]["results"]:
        loc = r["locations"][0]["physicalLocation"]["artifactLocation"]
        assert loc["uriBaseId"] == "SRCROOT" and ".." not in loc["uri"] and not loc["uri"].startswith("/")
        assert (root / unquote(loc["uri"])).is_file()
    # the same fingerprints as the run from inside the checkout
    assert ([r["partialFingerprints"] for r in log["runs"][0]["results"]]
            == [r["partialFingerprints"] for r in run["sarif"]["runs"][0]["results"]])


def test_sarif_has_the_required_fields(runs):
    """SARIF 2.1.0's required properties (no copy of its schema offline): version, runs, tool.driver.name,
    each result's message.text; artifact locations with a uriBaseId the run defines."""
    log = runs[0]["sarif"]
    assert log["version"] == "2.1.0" and isinstance(log["runs"], list)
    run = log["runs"][0]
    assert run["tool"]["driver"]["name"] == "cadartifact"
    for r in run["results"]:
        assert r["message"]["text"] and r["ruleId"]
        assert r["locations"][0]["physicalLocation"]["artifactLocation"]["uriBaseId"] in run["originalUriBaseIds"]


def test_run_root_and_relative_paths(tmp_path):
    a, b = tmp_path / "x" / "a.step", tmp_path / "y" / "z" / "b.step"
    assert run_root([str(a)], cwd=str(tmp_path)) == str(tmp_path)
    assert run_root([str(a), str(b)], cwd=str(tmp_path / "y")) == str(tmp_path)
    assert run_root([str(b)], cwd=str(tmp_path / "x")) == str(tmp_path / "y" / "z")
    assert relative(str(b), str(tmp_path)) == "y/z/b.step"


def test_fingerprints_of_a_run_are_unique():
    prints = Fingerprints()
    got = [prints("a.step", "#12", "ripple"), prints("a.step", "#12", "ripple"), prints("a.step", "#13", "ripple"),
           prints("a.step", "#12", "pdq-waviness"), prints("b.step", "#12", "ripple")]
    assert got[0] == fingerprint("a.step", "#12", "ripple") == expected("a.step", "#12", "ripple")
    assert len(set(got)) == len(got)


def test_gate_format_gitlab_writes_the_report(runs, tmp_path, monkeypatch):
    folder = tmp_path / "m"
    shutil.copytree(runs[0]["folder"], folder)
    monkeypatch.chdir(folder)
    result = gate("pair.step", "--format", "gitlab", "--output", "gl-code-quality.json")
    assert result.exit_code == 1
    issues = json.loads((folder / "gl-code-quality.json").read_text())
    assert [i["location"]["path"] for i in issues] == ["pair.step"]
    assert issues[0]["fingerprint"] == next(i["fingerprint"] for i in runs[0]["gitlab"]
                                            if i["location"]["path"] == "pair.step")
