"""The gate's reports of continuity between faces (:mod:`cadartifact.analysis.edges`): text lines and SARIF results.

Text: one ``edges`` line per file (shared edges measured, sharp by design, warning, failing; the edges not measured
by kind), then one line per edge that warns or fails with its STEP record and line, both faces, the values and
where along the edge. SARIF: per criterion that warns or fails on an edge, a result of that criterion's rule
(``edge_gap`` CA131, ``edge_angle`` CA132, ``edge_curvature`` CA133) located at the edge's ``EDGE_CURVE`` line
(line 1 without one), with the edge as the logical location. JUnit: a testcase per edge that warns (its
``system-out``) or fails (a ``<failure>`` of the first failing criterion's rule).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..runs.documents.gate import EdgeAt, GateEdge, GateFile

__all__ = ["edge_label", "edge_text", "edge_lines", "edge_results", "edge_junit"]


def edge_label(path: str, edge: GateEdge) -> str:
    """``"model.step edge #74 (line 98) between faces 0 #17 and 1 #129"``."""
    ent = f" #{edge['entity']}" if edge.get("entity") is not None else f" {edge['edge']}"
    line = f" (line {edge['line']})" if edge.get("line") else ""
    fe = edge.get("face_entities") or [None, None]
    faces = " and ".join(f"{i}" + (f" #{e}" if e is not None else "") for i, e in zip(edge["faces"], fe))
    return f"{path} edge{ent}{line} between faces {faces}"


def _at(at: EdgeAt | None, units: str) -> str:
    if not at:
        return ""
    return f" at {100 * at['t']:.0f} % of the edge, xyz ({', '.join(f'{c:.6g}' for c in at['xyz'])}) {units}"


def edge_text(c: dict, units: str) -> str:
    """``"edge_angle 2 degrees (fail: warn > 0.5, fail > 1) at 50 % of the edge, xyz (0, 0.5, 0) mm"``."""
    th = c["threshold"] or {}
    limits = ", ".join(f"{k} > {th[k]:g}" for k in ("warn", "fail") if th.get(k) is not None) or "no threshold"
    return f"{c['criterion']} {c['value']:.4g} {c['unit']} ({c['verdict']}: {limits}){_at(c.get('at'), units)}"


def edge_lines(entry: GateFile, units: str) -> list[str]:
    """The text report's lines of one file's shared edges (none without a profile or for a non-B-rep file)."""
    edges = entry.get("edges")
    if edges is None:
        return []
    counted = entry.get("edges_counted") or {}
    bad = [e for e in edges if e["verdict"] in ("warn", "fail")]
    other = ", ".join(f"{n} {k.replace('_', '-')}" for k, n in counted.items() if k != "shared" and n)
    lines = [f"edges: {len(edges)} shared edge(s) measured: {sum(e['sharp'] for e in edges)} sharp by design, "
             f"{sum(e['verdict'] == 'warn' for e in edges)} warn, {sum(e['verdict'] == 'fail' for e in edges)} fail"
             + (f" (not measured: {other})" if other else "")]
    for e in bad:
        for c in e["criteria"]:
            if c["evaluated"] and c["verdict"] in ("warn", "fail"):
                lines.append(f"edge {c['verdict']}: {edge_label(entry['path'], e)}: {c['code']}: {edge_text(c, units)}")
    return lines


def edge_results(add, entry: GateFile) -> None:
    """SARIF results of one file's shared edges that warn or fail, through the report's ``add`` (the edge's line,
    its ``#id`` as the finding's record, so that its fingerprint is the edge's)."""
    from ..analysis.quality import CRITERIA

    for e in entry.get("edges") or []:
        for c in e["criteria"]:
            if not (c["evaluated"] and c["verdict"] in ("warn", "fail")):
                continue
            label = edge_label(entry["path"], e)
            entity = None if e.get("entity") is None else f"#{e['entity']}"
            logical = {"name": f"edge {e['edge']}" + (f" {entity}" if entity else ""), "fullyQualifiedName": label,
                       "kind": "element"}
            add(CRITERIA[c["criterion"]].rule[0], "error" if c["verdict"] == "fail" else "warning",
                f"{label}: {c['code']}: {edge_text(c, 'mm')}", entry["path"], None,
                {"verdict": c["verdict"], "edge": e["edge"], "faces": e["faces"], "code": c["code"],
                 "value": c["value"], "unit": c["unit"], "threshold": c["threshold"], "at": c["at"],
                 "detail": c["detail"], "entity": entity, "entity_line": e.get("line")},
                record=entity or f"edge {e['edge']}", line=e.get("line"), logical=logical)


def edge_junit(suite, entry: GateFile, counts: dict) -> None:
    """Add a JUnit testcase to ``suite`` per shared edge of ``entry`` that warns or fails (``counts`` updated)."""
    import xml.etree.ElementTree as ET

    from ..analysis.quality import CRITERIA

    for e in entry.get("edges") or []:
        if e["verdict"] not in ("warn", "fail"):
            continue
        label = edge_label(entry["path"], e)
        case = ET.SubElement(suite, "testcase", name=label, classname="cadartifact.gate.edges")
        bad = [c for c in e["criteria"] if c["evaluated"] and c["verdict"] in ("warn", "fail")]
        text = "; ".join(f"{c['code']}: {edge_text(c, 'mm')}" for c in bad)
        counts["tests"] += 1
        if e["verdict"] == "fail":
            c = next(c for c in bad if c["verdict"] == "fail")
            rule = CRITERIA[c["criterion"]].rule
            fail = ET.SubElement(case, "failure", message=f"{label}: {text}", type=f"{rule[0]} {rule[1]}")
            fail.text = text
            counts["failures"] += 1
        else:
            ET.SubElement(case, "system-out").text = "warning: " + text
