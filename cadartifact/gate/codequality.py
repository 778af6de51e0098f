"""The GitLab Code Quality report of a gate run (``cadartifact gate --format gitlab``).

GitLab reads a JSON array of issues (``artifacts: reports: codequality:`` in ``.gitlab-ci.yml``; the format is a
subset of Code Climate's: https://docs.gitlab.com/ci/testing/code_quality/#code-quality-report-format). Each
issue is one SARIF result of :func:`cadartifact.gate.sarif.to_sarif`, so that both reports hold the same
findings with the same fingerprints:

- ``description``: the result's message (the face, its numbers, where it peaks);
- ``check_name``: the rule, ``CA001-ripple-exceeds-tolerance``;
- ``fingerprint``: the SARIF ``partialFingerprints`` (:func:`cadartifact.gate.locations.fingerprint`: the
  path relative to the run's root, the face's record, the criterion; never values or line numbers);
- ``severity``: ``critical`` for a file that could not be read, ``major`` for a failure, ``minor`` for a
  warning, ``info`` for a note;
- ``location.path`` (relative to the run's root, ``/``-separated) and ``location.lines.begin`` (the line of
  the face's STEP record, 1 without one).
"""

from __future__ import annotations

import json

from .locations import FINGERPRINT_KEY
from .reports import RULES
from .sarif import to_sarif

__all__ = ["SEVERITIES", "findings", "baseline_findings", "apply_baseline", "to_gitlab"]

#: GitLab's severity of a SARIF level (CA003, a file that could not be read, is ``critical``).
SEVERITIES = {"error": "major", "warning": "minor", "note": "info"}


def findings(doc, cwd: str | None = None) -> list[dict]:
    """The SARIF results of a gate document (:func:`~cadartifact.gate.sarif.to_sarif`), each with its
    ``properties``: ``path`` (relative to the run's root), ``record``, ``criterion``, and its fingerprint under
    :data:`~cadartifact.gate.locations.FINGERPRINT_KEY`."""
    return json.loads(to_sarif(doc, cwd))["runs"][0]["results"]


def baseline_findings(doc, cwd: str | None = None) -> list[dict]:
    """The findings of a gate document as a baseline lists them (:func:`cadartifact.gate.baseline.finding`)."""
    from .baseline import finding

    return [finding(r) for r in findings(doc, cwd)]


def apply_baseline(doc, previous: list[dict], source: str, cwd: str | None = None) -> dict:
    """Put the comparison with a baseline (:func:`cadartifact.gate.baseline.compare`) in the gate document as
    ``baseline``, and its exit code in ``exit_code``."""
    from .baseline import compare

    doc["baseline"] = compare(baseline_findings(doc, cwd), previous, source, doc["summary"]["errors"])
    doc["exit_code"] = doc["baseline"]["exit_code"]
    return doc


def to_gitlab(doc, cwd: str | None = None) -> str:
    """The GitLab Code Quality report: a JSON array, one issue per finding (passing faces are none)."""
    names = {rid: name for rid, name, *_rest in RULES}
    issues = []
    for r in findings(doc, cwd):
        props = r["properties"]
        line = r["locations"][0]["physicalLocation"]["region"]["startLine"]
        issues.append({"description": r["message"]["text"], "check_name": f"{r['ruleId']}-{names[r['ruleId']]}",
                       "fingerprint": r["partialFingerprints"][FINGERPRINT_KEY],
                       "severity": "critical" if r["ruleId"] == "CA003" else SEVERITIES[r["level"]],
                       "location": {"path": props["path"], "lines": {"begin": line}}})
    return json.dumps(issues, indent=2, allow_nan=False) + "\n"
