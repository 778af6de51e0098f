"""The gate's continuity between faces (``--profile``): one record per shared edge with its STEP record and line,
text lines and SARIF results at the edge's line, sharp-by-design edges passing, the profile's settings.

The values themselves are tested against their known sizes and OCCT in tests/analysis/test_edge_continuity.py; here
the independent road for places is the STEP text itself (the record at the reported line).
"""

from __future__ import annotations

import json
import math

import pytest

pytest.importorskip("OCP")

from cadartifact.testing.joined_faces import joined, write_step_shape  # noqa: E402
from cadartifact.testing.outcomes import gate_profile_json as gate_json  # noqa: E402
from cadartifact.testing.outcomes import gate_profile_run as gate  # noqa: E402


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("edges")
    out = {kind: write_step_shape(joined(kind, size), root / f"{kind}.step")
           for kind, size in (("g1", math.radians(2.0)), ("g1_constant", math.radians(3.0)), ("g2", (0.5, 0.2)),
                              ("smooth", 0.0))}
    cq = pytest.importorskip("cadquery")
    cq.exporters.export(cq.Workplane().box(10, 20, 30), str(root / "box.step"))
    out["box"] = str(root / "box.step")
    out["root"] = root
    return out


def test_a_g1_break_fails_the_file_at_the_edges_step_record(files):
    result, doc = gate_json(files["g1"], "--tol", "1", "--profile", "default")
    assert result.exit_code == 1
    entry = doc["files"][0]
    assert all(f["verdict"] == "pass" for f in entry["faces"]) and entry["verdict"] == "fail"
    (edge,) = entry["edges"]
    assert entry["edges_counted"] == {"shared": 1, "free": 6, "seam": 0, "degenerate": 0, "non_manifold": 0, "failed": 0}
    assert edge["verdict"] == "fail" and not edge["sharp"]
    assert edge["angle"]["value"] == pytest.approx(2.0, rel=0.05) and edge["angle"]["at"]["t"] == pytest.approx(0.5)
    text = open(files["g1"], encoding="latin-1").read().splitlines()
    assert text[edge["line"] - 1].startswith(f"#{edge['entity']} = EDGE_CURVE")  # the record at its line
    assert sorted(edge["face_entities"]) == sorted(f["entity"] for f in entry["faces"])  # both faces' records
    assert sorted(edge["faces"]) == sorted(f["face"] for f in entry["faces"])
    assert doc["summary"]["edges"] == {"edges": 1, "sharp": 0, "warn": 0, "fail": 1}

    sarif = json.loads(gate(files["g1"], "--tol", "1", "--profile", "default", "--format", "sarif").stdout)
    (res,) = [r for r in sarif["runs"][0]["results"] if r["ruleId"] == "CA132"]
    assert res["level"] == "error" and res["locations"][0]["physicalLocation"]["region"]["startLine"] == edge["line"]
    assert res["properties"]["value"] == edge["angle"]["value"] and res["properties"]["faces"] == edge["faces"]

    import xml.etree.ElementTree as ET

    junit = ET.fromstring(gate(files["g1"], "--tol", "1", "--profile", "default", "--format", "junit").stdout)
    (case,) = [c for c in junit.iter("testcase") if " edge #" in c.get("name")]
    assert case.find("failure").get("type") == "CA132 pdq-edge-angle" and junit.get("failures") == "1"

    body = " ".join(gate(files["g1"], "--tol", "1", "--profile", "default").stdout.split())  # lines wrap at spaces
    assert "edges: 1 shared edge(s) measured: 0 sharp by design, 0 warn, 1 fail" in body
    assert f"edge #{edge['entity']} (line {edge['line']})" in body
    assert "non-tangent faces (G1): edge_angle 2 degrees" in body


def test_box_edges_are_sharp_by_design_and_pass(files):
    result, doc = gate_json(files["box"], "--tol", "1", "--profile", "default")
    assert result.exit_code == 0 and doc["files"][0]["verdict"] == "pass"
    edges = doc["files"][0]["edges"]
    assert len(edges) == 12 and all(e["sharp"] and e["verdict"] == "pass" for e in edges)
    assert all(e["line"] is not None for e in edges)


def test_smooth_join_passes_and_no_profile_means_no_edges(files):
    result, doc = gate_json(files["smooth"], "--tol", "1", "--profile", "default")
    assert result.exit_code == 0 and doc["files"][0]["edges"][0]["verdict"] == "pass"
    _, plain = gate_json(files["g1"], "--tol", "1")
    assert "edges" not in plain["files"][0] and "edges" not in plain["summary"]  # the ripple alone, as before


def test_profile_settings_sharp_angle_and_g2(files):
    root = files["root"]
    (root / "sharp.toml").write_text("[edge_angle]\nsharp_angle = 2.5\n")
    result, doc = gate_json(files["g1_constant"], "--tol", "1", "--profile", root / "sharp.toml")
    assert result.exit_code == 0 and doc["files"][0]["edges"][0]["sharp"] and doc["profile"]["sharp_angle"] == 2.5
    result, doc = gate_json(files["g1_constant"], "--tol", "1", "--profile", "default")  # a 3-degree crease: fails
    assert result.exit_code == 1 and not doc["files"][0]["edges"][0]["sharp"]

    result, doc = gate_json(files["g2"], "--tol", "1", "--profile", "default")  # G2 off by default
    assert result.exit_code == 0
    (root / "classa.toml").write_text("[edge_curvature]\nwarn = 0.02\nfail = 0.1\n")
    result, doc = gate_json(files["g2"], "--tol", "1", "--profile", root / "classa.toml")
    crit = {c["criterion"]: c for c in doc["files"][0]["edges"][0]["criteria"]}
    assert result.exit_code == 1 and crit["edge_curvature"]["value"] == pytest.approx(0.6, rel=0.05)
    (root / "bad.toml").write_text("[edge_angle]\nsharp_angle = 0\n")
    result = gate(files["g2"], "--tol", "1", "--profile", root / "bad.toml")
    assert result.exit_code == 2 and "edge_angle.sharp_angle" in result.output
