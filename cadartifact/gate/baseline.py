"""The gate's baseline (``cadartifact gate --baseline PREVIOUS.json``): adopting the gate on a vault that already
has findings, so that only what gets worse fails.

A baseline is the list of a run's findings (``--update-baseline`` writes it: :func:`to_baseline`), each by its
fingerprint (:func:`cadartifact.gate.locations.fingerprint`: the file's path relative to the run's root, the
face's record, the criterion) with its rule, level and reading. A gate JSON document (``--format json``) serves
as a baseline too. Against it, each finding of this run is

- ``new``: its fingerprint is not in the baseline;
- ``worse``: it is, and its reading got worse beyond its uncertainty: ``value - previous > max(U, U_prev)``
  (``previous - value`` for a criterion where lower is worse, such as the curvature radius; ``U`` is the face's
  intent uncertainty, 0 where a reading has none, plus a relative 1e-6 for rounding across machines);
- ``known``: otherwise (it may have moved from warn to fail within its uncertainty);

and each baseline finding this run no longer has is ``fixed``. The exit code: 2 when a file could not be read
(the gate fails closed, baseline or not); else 1 when a finding at level ``error`` (a face that fails) is new or
worse; else 0. The document's verdicts stay what they are; ``baseline`` in the gate document lists the new,
worse and fixed findings and counts the known ones.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

from ..errors import InputError
from .locations import FINGERPRINT_KEY

__all__ = ["BASELINE_SCHEMA", "STATES", "finding", "to_baseline", "load_baseline", "compare", "baseline_lines",
           "sarif_states"]

BASELINE_SCHEMA = "cadartifact.baseline/1"
#: A finding's state against the baseline, and the SARIF ``baselineState`` of each.
STATES = {"new": "new", "worse": "updated", "known": "unchanged"}
_KEYS = ("fingerprint", "rule", "level", "path", "record", "criterion", "value", "uncertainty", "sense")


def finding(result: dict) -> dict:
    """A SARIF result of :func:`cadartifact.gate.sarif.to_sarif` as a baseline lists it (:data:`_KEYS`)."""
    p = result["properties"]
    value, sense = p.get("value"), (p.get("threshold") or {}).get("sense", "above")
    if result["ruleId"] == "CA005":  # the analysed share: lower is worse
        value, sense = p.get("analysed_share"), "below"
    return {"fingerprint": result["partialFingerprints"][FINGERPRINT_KEY], "rule": result["ruleId"],
            "level": result["level"], "path": p["path"], "record": p["record"], "criterion": p["criterion"],
            "value": value if isinstance(value, (int, float)) and not isinstance(value, bool) else None,
            "uncertainty": p.get("uncertainty"), "sense": sense}


def to_baseline(findings: list[dict]) -> str:
    """The baseline file of a run's findings: ``{"schema": "cadartifact.baseline/1", "findings": [...]}`` sorted
    by path, record and criterion (no absolute path, no time: a vault gives the same bytes on every machine)."""
    found = sorted(({k: f[k] for k in _KEYS} for f in findings),
                   key=lambda f: (f["path"], f["record"], f["criterion"]))
    return json.dumps({"schema": BASELINE_SCHEMA, "findings": found}, indent=2, allow_nan=False) + "\n"


def load_baseline(path, of_document: Callable[[dict], list]) -> list[dict]:
    """The findings of a baseline file, or (through ``of_document``) of a gate JSON document.

    Raises
    ------
    InputError
        The file is missing, not JSON, or neither a baseline nor a gate document.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(path, "no such baseline (--update-baseline writes it)") from None
    except OSError as exc:
        raise InputError(path, f"cannot read the baseline ({exc.strerror or exc})") from None
    except ValueError as exc:
        raise InputError(path, f"not a JSON baseline ({exc})") from None
    if isinstance(data, dict) and data.get("schema") == BASELINE_SCHEMA and isinstance(data.get("findings"), list):
        found = data["findings"]
        if all(isinstance(f, dict) and isinstance(f.get("fingerprint"), str) for f in found):
            return [{k: f.get(k) for k in _KEYS} for f in found]
        raise InputError(path, "a baseline finding without a fingerprint")
    if isinstance(data, dict) and str(data.get("gate", "")).startswith("cadartifact.gate/") and "files" in data:
        return of_document(data)
    raise InputError(path, f"not a baseline ({BASELINE_SCHEMA}) nor a gate JSON document")


def _worse(now: dict, before: dict) -> bool:
    if now["value"] is None or not isinstance(before.get("value"), (int, float)):
        return False
    change = now["value"] - before["value"]
    if now.get("sense") == "below":
        change = -change
    margin = max(now.get("uncertainty") or 0.0, before.get("uncertainty") or 0.0)
    return change > margin + 1e-6 * max(abs(now["value"]), abs(before["value"]))


def compare(findings: list[dict], previous: list[dict], source: str, errors: int) -> dict:
    """The gate document's ``baseline`` record: this run's ``findings`` (:func:`finding`) against ``previous``
    (:func:`load_baseline`); ``errors``: the files that could not be read.

    Returns
    -------
    dict
        ``{"source", "new": [finding], "worse": [finding + "previous"], "known": int, "fixed": [finding],
        "exit_code"}`` (``previous``: the baseline's value).
    """
    before = {f["fingerprint"]: f for f in previous}
    new, worse, known = [], [], 0
    for f in findings:
        old = before.get(f["fingerprint"])
        if old is None:
            new.append(f)
        elif _worse(f, old):
            worse.append({**f, "previous": old["value"]})
        else:
            known += 1
    seen = {f["fingerprint"] for f in findings}
    fixed = [f for f in previous if f["fingerprint"] not in seen]
    exit_code = 2 if errors else 1 if any(f["level"] == "error" for f in new + worse) else 0
    return {"source": str(source), "new": new, "worse": worse, "known": known, "fixed": fixed,
            "exit_code": exit_code}


def baseline_lines(doc: dict) -> list[str]:
    """The text report's lines: ``baseline new fail: pair.step #17 ripple (value 0.12)`` per new or worse
    finding (``was 0.1``) and per fixed one."""
    base = doc.get("baseline")
    if not base:
        return []
    verdicts = {"error": "fail", "warning": "warn", "note": "note"}

    def line(f: dict, state: str) -> str:
        value = "" if f.get("value") is None else f" (value {f['value']:.4g}" + (
            f", was {f['previous']:.4g}" if f.get("previous") is not None else "") + ")"
        return (f"baseline {state} {verdicts.get(f.get('level'), f.get('level'))}: {f['path']} "
                f"{f['record'] or 'file'} {f['criterion']}{value}")

    return ([line(f, "new") for f in base["new"]] + [line(f, "worse") for f in base["worse"]]
            + [line(f, "fixed") for f in base["fixed"]])


def sarif_states(results: list[dict], base: dict) -> None:
    """Set each SARIF result's ``baselineState`` (:data:`STATES`) from the document's ``baseline`` record."""
    states = {f["fingerprint"]: state for state in ("new", "worse") for f in base[state]}
    for r in results:
        r["baselineState"] = STATES[states.get(r["partialFingerprints"][FINGERPRINT_KEY], "known")]
