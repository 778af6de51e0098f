"""``cadartifact advise --json``: the document's ``exit_code`` is the code the command exits with (one source of
truth, :func:`cadartifact.runs.advising.exit_code`), on the bundled samples: a conforming face, a face that
needs another density, and both files in one run."""

import json

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import SAMPLES

CONFORMING = SAMPLES / "clean_panel.step"  # its one face reads within 0.05 mm today
EXCEEDING = SAMPLES / "wavy_panel_diagonal.step"  # its one face's ripple exceeds 0.05 mm


def advise_json(*paths, tol=0.05):
    result = CliRunner().invoke(app, ["advise", *map(str, paths), "--tol", str(tol), "--json"])
    no_traceback(result)
    return json.loads(result.stdout), result.exit_code


@pytest.mark.parametrize("paths, code", [((CONFORMING,), 0), ((EXCEEDING,), 1), ((CONFORMING, EXCEEDING), 1)],
                         ids=["conforming", "exceeding", "both"])
def test_the_document_carries_the_exit_code(paths, code):
    doc, exit_code = advise_json(*paths)
    assert doc["exit_code"] == exit_code == code
    faces = [f for entry in doc["files"] for f in entry["faces"]]
    assert (doc["summary"]["within"] == len(faces)) is (code == 0)  # the code says what the faces say


def test_the_command_exits_with_the_documents_value(monkeypatch):
    """The command does not decide again: the document's value is the process's, whatever it is."""
    import cadartifact.runs.advising as advising

    monkeypatch.setattr(advising, "exit_code", lambda files: 1)
    doc, exit_code = advise_json(CONFORMING)
    assert doc["exit_code"] == exit_code == 1 and doc["summary"]["within"] == 1
