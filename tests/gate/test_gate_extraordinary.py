"""A cage's extraordinary vertices in the gate and advise documents: one record per vertex, the gate fails a
cage whose vertex defect exceeds the tolerance (CA007 in SARIF, a JUnit failure, a text line) and passes it
within; the cage's advice names the level. Expected numbers come from analysis.extraordinary directly."""

import json

import pytest
from typer.testing import CliRunner

from cadartifact.analysis.extraordinary import vertex_defects
from cadartifact.cli.app import app
from cadartifact.testing.cages import fan_cage, write_obj
from cadartifact.testing.outcomes import no_traceback


def run(*args):
    result = CliRunner().invoke(app, [*map(str, args)])
    no_traceback(result)
    return result


@pytest.fixture(scope="module")
def torus5(tmp_path_factory):
    """A valence-5 fan cage on a torus, and its defect (computed here, not by the gate)."""
    V, F = fan_cage(5, m=3, surface="torus")
    path = tmp_path_factory.mktemp("cage") / "torus5.obj"
    write_obj(path, V, F)
    (rec,) = vertex_defects(V, F)
    return path, rec


@pytest.mark.parametrize("factor, verdict, code", [(2.0, "pass", 0), (0.5, "fail", 1)])
def test_gate_holds_the_defect_against_the_tolerance(torus5, factor, verdict, code):
    path, rec = torus5
    tol = factor * rec.defect
    result = run("gate", path, "--tol", tol, "--format", "json", "--jobs", "1")
    doc = json.loads(result.stdout)
    f = doc["files"][0]
    assert (f["verdict"], result.exit_code) == (verdict, code)
    (v,) = f["extraordinary"]
    assert (v["vertex"], v["valence"], v["boundary"], v["curvature"]) == (0, 5, False, "unbounded")
    assert v["defect"] == pytest.approx(rec.defect, abs=1e-8)  # documents round to 9 significant digits
    assert v["within"] is (factor > 1)
    assert v["level"] == rec.level_within(tol)
    assert ("extraordinary_failure" in f) is (factor < 1)
    advice = f["cage_advice"]
    assert advice["vertices"] == [{"vertex": 0, "face": None, "valence": 5, "level": v["level"]}]
    # at half the defect: mu = 0.34 < 0.5, so level 1 brings it within
    assert v["level"] == (0 if factor > 1 else 1)
    assert rec.mu == pytest.approx(0.3401, abs=1e-4)


def test_failing_cage_in_text_sarif_and_junit(torus5, tmp_path):
    import xml.etree.ElementTree as ET

    path, rec = torus5
    tol = rec.defect / 2
    text = " ".join(run("gate", path, "--tol", tol, "--jobs", "1").stdout.split())  # lines wrap at spaces
    assert "1 extraordinary vertex beyond the tolerance" in text and "advice: vertex 0 (valence 5): level 1 around it" in text
    sarif = json.loads(run("gate", path, "--tol", tol, "--format", "sarif", "--jobs", "1").stdout)
    results = sarif["runs"][0]["results"]
    (ca007,) = [r for r in results if r["ruleId"] == "CA007"]  # one per vertex beyond the tolerance
    assert (ca007["properties"]["vertex"], ca007["properties"]["record"]) == (0, "vertex 1")
    assert ca007["locations"][0]["physicalLocation"]["region"]["startLine"] == 1  # write_obj: vertex 1 first
    run("gate", path, "--tol", tol, "--format", "junit", "--output", tmp_path / "g.xml", "--jobs", "1")
    fails = ET.parse(tmp_path / "g.xml").getroot().findall(".//failure")
    assert [f.get("type") for f in fails] == ["CA007 extraordinary-vertex-defect"]


@pytest.mark.parametrize("n", (3, 5, 6, 8))
def test_planar_cage_passes_any_tolerance(tmp_path, n):
    V, F = fan_cage(n, m=3, surface="plane")
    write_obj(tmp_path / "flat.obj", V, F)
    doc = json.loads(run("advise", tmp_path / "flat.obj", "--tol", 1e-9, "--json").stdout)
    (v,) = doc["files"][0]["extraordinary"]
    assert v["valence"] == n and v["defect"] < 1e-12 and v["within"] and v["level"] == 0
    assert doc["files"][0]["cage_advice"]["level"] == 0


def test_advise_names_levels_not_nets(torus5, capsys):
    path, rec = torus5
    out = run("advise", path, "--tol", rec.defect / 2).stdout
    assert "extraordinary vertices: 1 (curvature 1 unbounded)" in out
    assert "advice: vertex 0 (valence 5): level 1 around it" in out
    assert "level 1" in out.split("advice: subdivide to ")[1]  # the charts need no more: within at level 0


def test_brep_documents_have_no_cage_keys():
    from cadartifact.testing.paths import SAMPLES

    doc = json.loads(run("advise", SAMPLES / "clean_panel.step", "--tol", 0.05, "--json").stdout)
    assert "extraordinary" not in doc["files"][0] and "cage_advice" not in doc["files"][0]
