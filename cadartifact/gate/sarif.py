"""The gate's SARIF 2.1.0 report: one result per finding (faces, their PDQ criteria, shared edges, files), located
relative to the run's root and fingerprinted as GitLab's report and the baseline are
(:mod:`cadartifact.gate.locations`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import quote

from .edge_reports import edge_results
from .reports import _DIRECTIONS, criterion_text, face_label, face_numbers, file_units
from .rules import CRITERION_RULES, RULES, SARIF_SCHEMA

if TYPE_CHECKING:
    from ..runs.documents.gate import GateDocument, GateFace

__all__ = ["to_sarif"]


def to_sarif(doc: GateDocument, cwd: str | None = None) -> str:
    """SARIF 2.1.0 log: tool.driver ``cadartifact`` with its rules, one result per finding; locations relative
    to the run's root (``uriBaseId``, :mod:`cadartifact.gate.locations`), fingerprints stable across runs and
    machines (``partialFingerprints``, the same as GitLab's and the baseline's)."""
    from .. import __version__
    from .locations import FINGERPRINT_KEY, ROOT_ID, Fingerprints, face_record, relative, run_root

    root = run_root([e["path"] for e in doc["files"]], cwd)
    index = {rule_id: i for i, (rule_id, *_rest) in enumerate(RULES)}
    names = {rule_id: name for rule_id, name, *_rest in RULES}
    rules = [{"id": rid, "name": name, "shortDescription": {"text": text}, "fullDescription": {"text": text},
              "defaultConfiguration": {"level": level}, "help": {"text": text}}
             for rid, name, level, text in RULES]
    results = []
    prints = Fingerprints()

    def add(rule_id: str, level: str, text: str, path: str, face: GateFace | None, props: dict,
            record: str | None = None, line: int | None = None, logical: dict | None = None):
        # the line of the face's STEP entity (#id = ADVANCED_FACE...), or the edge's; line 1 where there is none
        line = line or (face or {}).get("entity_line") or 1
        uri = relative(path, root)
        loc = {"physicalLocation": {"artifactLocation": {"uri": quote(uri), "uriBaseId": ROOT_ID},
                                    "region": {"startLine": line}}}
        if face is not None:
            entity = f" #{face['entity']}" if face.get("entity") is not None else ""
            loc["logicalLocations"] = [{"name": f"face {face['face']}" + (f" {face['name']}" if face.get("name")
                                                                            else "") + entity,
                                        "fullyQualifiedName": face_label(path, face), "kind": "element"}]
        if logical is not None:
            loc["logicalLocations"] = [logical]
        criterion = "ripple" if rule_id in ("CA001", "CA002") else names[rule_id]
        record = face_record(face) if record is None else record
        results.append({"ruleId": rule_id, "ruleIndex": index[rule_id], "level": level, "message": {"text": text},
                        "locations": [loc],
                        "partialFingerprints": {FINGERPRINT_KEY: prints(uri, record, criterion)},
                        "properties": {**props, "path": uri, "record": record, "criterion": criterion}})

    for entry in doc["files"]:
        path = entry["path"]
        if entry["verdict"] == "error":
            add("CA003", "error", entry["error"], path, None, {"verdict": "error"})
            continue
        if entry.get("share_failure"):
            add("CA005", "error", f"{path}: {entry['share_failure']}", path, None,
                {"verdict": "fail", "analysed_share": entry.get("analysed_share")})
        if entry.get("extraordinary_failure"):
            _vertex_results(add, entry, path, file_units(doc, entry))
        if not entry["faces"] and not entry.get("edges"):
            add("CA004", "note", f"{path}: " + "; ".join(entry["notes"] + entry["warnings"]), path, None,
                {"verdict": entry["verdict"]})
        edge_results(add, entry)
        for f in entry["faces"]:
            _criteria_results(add, f, path, file_units(doc, entry))
            ripple = f.get("ripple_verdict", f["verdict"])
            if ripple == "pass":
                continue
            rule_id, level = ("CA001", "error") if ripple == "fail" else ("CA002", "warning")
            props = {"verdict": f["verdict"], "face": f["face"], "value": f["value"],
                     "tolerance": entry["policy"]["tolerance"], "metric": entry["policy"]["metric"],
                     "peaks": {k: f["budget"][k]["peak"] for k in _DIRECTIONS}, "net": f["net"],
                     "advised_net": f["advice"]["net"] if f["advice"] else None, "units": file_units(doc, entry),
                     "entity": None if f.get("entity") is None else f"#{f['entity']}",
                     "entity_line": f.get("entity_line"), "peak_at": f.get("peak_at"),
                     "uncertainty": (f.get("uncertainty") or {}).get("peak")}
            add(rule_id, level, f"{face_label(path, f)}: {face_numbers(doc, entry, f)}", path, f, props)
    if doc.get("baseline") is not None:  # SARIF's own word for each finding's state against the baseline
        from .baseline import sarif_states

        sarif_states(results, doc["baseline"])
    log = {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "cadartifact", "version": __version__, "semanticVersion": __version__,
                                "rules": rules}},
            "originalUriBaseIds": {ROOT_ID: {"uri": Path(root).as_uri().rstrip("/") + "/"}},
            "invocations": [{"executionSuccessful": doc["exit_code"] != 2, "exitCode": doc["exit_code"]}],
            "results": results,
            "properties": {"verdict": doc["verdict"], "summary": doc["summary"]},
        }],
    }
    return json.dumps(log, indent=2, allow_nan=False) + "\n"


def _vertex_results(add, entry, path: str, units: str) -> None:
    """SARIF results of a cage's extraordinary vertices beyond the tolerance: one per vertex, at the line of its
    ``v`` statement (a triangle's or n-gon's centre: its ``f`` statement's), recorded by its OBJ index, not its
    line, so that a baseline still matches it when lines are inserted above it."""
    from .locations import vertex_record

    tolerance = entry["policy"]["tolerance"]
    for v in entry["extraordinary"]:
        if v["within"] is not False:  # within, or a crease ends here (reported, not gated)
            continue
        record = vertex_record(v)
        level = ("needs more control (no level up to 6 brings it within)" if v["level"] is None
                 else f"level {v['level']} around it brings it within")
        line = f", line {v['line']}" if v.get("line") is not None else ""
        defect = "not finite" if v["defect"] is None else f"{v['defect']:.4g} {units}"
        text = (f"{path}: extraordinary {record}{line} (valence {v['valence']}): defect {defect} beyond the "
                f"tolerance {tolerance:g}; {level}")
        # "vertex" and "polygon" are the document's 0-based ids (its "extraordinary" entry), "record" the file's
        add("CA007", "error", text, path, None,
            {"verdict": "fail", "vertex": v["vertex"], "polygon": v["face"], "valence": v["valence"],
             "value": v["defect"], "tolerance": tolerance, "units": units, "level": v["level"], "line": v.get("line")},
            record=record, line=v.get("line"), logical={"name": record, "fullyQualifiedName": f"{path} {record}",
                                                         "kind": "element"})


def _criteria_results(add, f: GateFace, path: str, units: str) -> None:
    """SARIF results of a face's PDQ criteria: one per criterion that warns or fails, one note for those not
    evaluated."""
    crit = f.get("criteria") or []
    for c in crit:
        if c["evaluated"] and c["verdict"] in ("warn", "fail"):
            add(CRITERION_RULES[c["criterion"]], "error" if c["verdict"] == "fail" else "warning",
                f"{face_label(path, f)}: {c['code']}: {criterion_text(c, units)}", path, f,
                {"verdict": c["verdict"], "face": f["face"], "criterion": c["criterion"], "code": c["code"],
                 "value": c["value"], "unit": c["unit"], "threshold": c["threshold"], "at": c.get("at"),
                 "detail": c["detail"], "entity": None if f.get("entity") is None else f"#{f['entity']}"})
    missing = [c for c in crit if not c["evaluated"]]
    if missing:
        add("CA110", "note", f"{face_label(path, f)}: " + "; ".join(criterion_text(c, units) for c in missing),
            path, f, {"face": f["face"], "criteria": {c["criterion"]: c["reason"] for c in missing}})
