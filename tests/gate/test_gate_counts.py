"""The gate's counts add up and its explanation lines read on any width (issue 42's frictions): every face in
exactly one verdict class, file-level failures counted, the HTML report's tiles adding up; explanation lines
wrapped at the console's width without breaking a path or a face label."""

import io
import json
import re
import shutil

import pytest
from rich.console import Console
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.gate.reports import face_label, render_text, to_text
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import SAMPLES

pytest.importorskip("OCP")


def gate(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args), "--jobs", "1"])
    no_traceback(result)
    return result


@pytest.fixture(scope="module")
def doc(tmp_path_factory):
    """Two samples at a tolerance most of their faces exceed, under a long folder name with a space."""
    folder = tmp_path_factory.mktemp("counts") / "a rather long folder name for the vault of body panels"
    folder.mkdir()
    for name in ("wavy_panel_diagonal.step", "clean_panel.step"):
        shutil.copy(SAMPLES / name, folder / name)
    result = gate(folder, "--tol", "0.001", "--format", "json")
    return json.loads(result.stdout)


def test_every_face_is_in_exactly_one_class(doc):
    s = doc["summary"]
    faces = s["verdicts"]["faces"]
    assert faces["pass"] + faces["warn"] + faces["fail"] == s["faces"]
    assert s["within"] + s["undecided"] + s["exceeding"] == s["faces"]
    assert s["unreachable"] <= s["exceeding"] + s["undecided"]


@pytest.mark.parametrize("width", [60, 80, 100])
def test_explanation_lines_wrap_without_breaking_paths_or_labels(doc, width):
    buf = io.StringIO()
    render_text(doc, Console(file=buf, width=width, color_system=None, soft_wrap=True), wide=False)
    text = buf.getvalue()
    labels = [face_label(e["path"], f) for e in doc["files"] for f in e["faces"] if f["verdict"] != "pass"]
    assert labels
    for label in labels:
        assert label in text  # whole, on one line
    table = ("┃", "│", "┏", "┡", "└")
    long = [ln for ln in text.splitlines() if len(ln) > width and not ln.startswith(table)]
    # a line longer than the console holds a single unbreakable token: a path or a label
    for ln in long:
        assert any(label in ln for label in labels) or any(e["path"] in ln for e in doc["files"]), ln


@pytest.mark.parametrize("width", [60, 80, 100])
def test_file_headings_wrap_at_spaces_and_keep_the_path_whole(doc, width):
    """A file's heading (path, verdict, policy) is wrapped at spaces; a line longer than the console holds the
    path alone; the heading's words all come back, in order."""
    buf = io.StringIO()
    render_text(doc, Console(file=buf, width=width, color_system=None, soft_wrap=True), wide=False)
    lines = buf.getvalue().splitlines()
    for entry in doc["files"]:
        start = next(i for i, ln in enumerate(lines) if ln.startswith(entry["path"]))
        heading = []
        for ln in lines[start:]:
            if ln.startswith(("┏", "┃")):
                break
            heading.append(ln)
            assert len(ln) <= width or ln.strip() == entry["path"], ln
        words = " ".join(" ".join(heading).split())
        assert words.startswith(f"{entry['path']} {entry['verdict'].upper()} (tolerance ") and words.endswith(")")


def test_a_report_file_keeps_each_explanation_on_one_line(doc):
    text = to_text(doc)
    fails = [ln for ln in text.splitlines() if ln.startswith("  fail: ")]
    assert fails and all("exceeds tolerance" in ln and "peak at" in ln for ln in fails)


def test_a_file_failing_as_a_whole_is_counted(tmp_path, monkeypatch):
    shutil.copy(SAMPLES / "cage.obj", tmp_path / "cage.obj")
    # without the extraordinary-vertex measure the sample cage's analysed share is 98 %: a policy asking 99 % fails
    # it as a whole
    monkeypatch.setattr("cadartifact.runs.cage_records.measured_around", lambda result, vertices: [])
    (tmp_path / "cadartifact.toml").write_text("tolerance = 100\nmin_analysed_share = 0.99\n")
    result = gate(tmp_path / "cage.obj", "--policy", tmp_path / "cadartifact.toml")
    assert result.exit_code == 1
    text = " ".join(result.stdout.split())  # the summary may wrap at spaces
    line = text[text.rindex("gate FAIL"):]
    assert "0 fail" in line
    assert "1 file(s) fail as a whole (analysed share below min_analysed_share)" in line


def test_html_tiles_add_up(doc, tmp_path):
    pytest.importorskip("matplotlib")
    from cadartifact.viz.html import write_report

    write_report(doc, tmp_path / "r.html")
    html = (tmp_path / "r.html").read_text()
    cards = {label: int(n) for n, label in re.findall(r'<div class="n">(\d+)</div><div class="l">([^<]+)</div>', html)}
    assert cards["within"] + cards.get("undecided", 0) + cards["exceeding"] == cards["faces"]
    assert cards["pass"] + cards["warn"] + cards["fail"] == cards["faces"]
    assert "out of reach" not in cards
    assert cards["of them out of reach"] <= cards["exceeding"] + cards.get("undecided", 0)
