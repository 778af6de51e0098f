"""The gate's SARIF: one CA007 result per extraordinary vertex beyond the tolerance, at the line of its ``v``
statement (a triangle's or n-gon's centre, which the file does not hold: its ``f`` statement's), recorded by
the vertex's OBJ index so that a baseline matches it when lines move.

The cage is written here as a user's OBJ would be: comments, blank lines, statements the reader skips and
continued statements (a trailing backslash), with the line of every statement noted as it is written; the
results' lines are then read back from the file."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.testing.cages import fan_cage
from cadartifact.testing.outcomes import no_traceback

TOL = 1e-9  # every extraordinary vertex of a curved cage is beyond it


def gate(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args), "--jobs", "1", "--advise", "none"])
    no_traceback(result)
    return result


def hex_cage():
    """A valence-5 fan on a torus with two neighbouring quads of a sector merged into a hexagon: extraordinary
    vertices of valence 5 (the centre), 3 (the merged edge's ends, both interior) and the hexagon's centre."""
    V, F = fan_cage(5, m=4, surface="torus")
    q1, q2 = F[2 * 4 + 1], F[2 * 4 + 2]  # sector 0, quads (2, 1) and (2, 2): they share an interior edge
    assert len(set(q1) & set(q2)) == 2
    hexagon = (q1[0], q1[1], q1[2], q2[2], q2[3], q2[0])  # around both, the shared edge left out
    return V, [f for f in F if f not in (q1, q2)] + [hexagon], hexagon


def write_cage(path, V, F, hexagon):
    """Write the cage with comments, blank lines, skipped statements and continued ``v`` and ``f`` statements;
    returns the 1-based line each vertex's and each face's statement starts on."""
    lines: list[str] = ["# a cage written by hand: comments, blank lines, continued statements", "", "o cage"]
    vertex_lines, face_lines = [], []
    for i, (x, y, z) in enumerate(np.asarray(V, float).tolist()):
        if i % 7 == 3:
            lines += ["", f"# vertices from {i + 1}"]
        vertex_lines.append(len(lines) + 1)
        if i == 0:  # the valence-5 centre, continued over three lines
            lines += [f"v {x!r} \\", f"  {y!r} \\", f"  {z!r}"]
        elif i % 5 == 2:
            lines.append(f"v {x!r} {y!r} {z!r}   # a comment after a vertex")
        else:
            lines.append(f"v {x!r} {y!r} {z!r}")
        if i % 9 == 4:
            lines.append("vt 0.5 0.5")
    lines += ["", "g part", "s off"]
    for j, face in enumerate(F):
        ids = [str(k + 1) for k in face]
        face_lines.append(len(lines) + 1)
        if face == hexagon:  # the n-gon, continued over two lines
            lines += ["f " + " ".join(ids[:3]) + " \\", "  " + " ".join(ids[3:])]
        elif j % 4 == 1:
            lines.append("f " + " ".join(f"{k}/1" for k in ids))
        else:
            lines.append("f " + " ".join(ids))
        if j % 11 == 5:
            lines.append("# a comment between faces")
    path.write_text("\n".join(lines) + "\n")
    return vertex_lines, face_lines


def statement_at(text_lines: list[str], line: int) -> list[str]:
    """The words of the statement starting at 1-based ``line``, continuation lines joined (read back here, not
    by the reader under test)."""
    words, k = [], line - 1
    while True:
        body = text_lines[k].split("#", 1)[0].rstrip()
        words += body.rstrip("\\").split()
        if not body.endswith("\\"):
            return words
        k += 1


@pytest.fixture(scope="module")
def gated(tmp_path_factory):
    V, F, hexagon = hex_cage()
    path = tmp_path_factory.mktemp("cage") / "hex.obj"
    vertex_lines, face_lines = write_cage(path, V, F, hexagon)
    doc = json.loads(gate(path, "--tol", TOL, "--format", "json").stdout)
    result = gate(path, "--tol", TOL, "--format", "sarif")
    assert result.exit_code == 1
    sarif = json.loads(result.stdout)
    return dict(path=path, V=V, F=F, hexagon=hexagon, vertex_lines=vertex_lines, face_lines=face_lines,
                entry=doc["files"][0], results=[r for r in sarif["runs"][0]["results"] if r["ruleId"] == "CA007"])


def test_the_cage_has_the_vertices_the_test_needs(gated):
    found = {(v["valence"], v["face"] is not None) for v in gated["entry"]["extraordinary"]}
    assert {(5, False), (3, False), (6, True)} <= found
    assert all(v["within"] is False for v in gated["entry"]["extraordinary"])


def test_one_result_per_extraordinary_vertex(gated):
    vertices, results = gated["entry"]["extraordinary"], gated["results"]
    beyond = [v for v in vertices if v["within"] is False]
    assert len(results) == len(beyond) == len(vertices) == 4  # centre 5, two ends 3, the hexagon's centre
    records = [r["properties"]["record"] for r in results]
    assert sorted(records) == sorted({r for r in records})  # one each
    assert len({r["partialFingerprints"]["cadartifactFinding/v2"] for r in results}) == len(results)
    assert sorted(r["properties"]["vertex"] for r in results) == sorted(v["vertex"] for v in vertices)


def test_each_result_points_at_its_statement(gated):
    text_lines = gated["path"].read_text().split("\n")
    by_id = {v["vertex"]: v for v in gated["entry"]["extraordinary"]}
    for r in gated["results"]:
        line = r["locations"][0]["physicalLocation"]["region"]["startLine"]
        v = by_id[r["properties"]["vertex"]]
        assert line == v["line"] == r["properties"]["line"]
        words = statement_at(text_lines, line)
        if v["face"] is None:  # a cage vertex: its v statement, holding its coordinates
            assert line == gated["vertex_lines"][v["vertex"]]
            assert words[0] == "v" and [float(w) for w in words[1:4]] == list(gated["V"][v["vertex"]])
            assert r["properties"]["record"] == f"vertex {v['vertex'] + 1}"
            assert f"vertex {v['vertex'] + 1}, line {line} " in r["message"]["text"]
        else:  # a centre: the f statement of its polygon (the hexagon, continued over two lines)
            assert line == gated["face_lines"][v["face"]]
            assert words[0] == "f" and [int(w.split("/")[0]) - 1 for w in words[1:]] == list(gated["hexagon"])
            assert r["properties"]["record"] == f"centre of polygon {v['face'] + 1}"
        assert r["locations"][0]["logicalLocations"][0]["name"] == r["properties"]["record"]
    centre = next(r for r in gated["results"] if r["properties"]["valence"] == 5)
    assert centre["locations"][0]["physicalLocation"]["region"]["startLine"] == gated["vertex_lines"][0] == 4


def test_a_baseline_matches_the_vertices_when_lines_move(gated, tmp_path, monkeypatch):
    """The record is the OBJ index, not the line: comments inserted above leave every finding known."""
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "hex.obj"
    path.write_text(gated["path"].read_text())
    assert gate(path, "--tol", TOL, "--baseline", "base.json", "--update-baseline").exit_code == 0
    base = json.loads((tmp_path / "base.json").read_text())["findings"]
    assert sorted(f["record"] for f in base if f["rule"] == "CA007") == sorted(
        r["properties"]["record"] for r in gated["results"])
    path.write_text("# two lines\n# inserted above\n" + path.read_text())
    result = gate(path, "--tol", TOL, "--baseline", "base.json", "--format", "sarif")
    assert result.exit_code == 0
    moved = [r for r in json.loads(result.stdout)["runs"][0]["results"] if r["ruleId"] == "CA007"]
    assert {r["baselineState"] for r in moved} == {"unchanged"}
    assert sorted(r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in moved) == sorted(
        r["locations"][0]["physicalLocation"]["region"]["startLine"] + 2 for r in gated["results"])
