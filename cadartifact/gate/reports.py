"""Report writers of the quality gate: text (rich), JSON, JUnit XML and SARIF 2.1.0 (GitLab Code Quality:
:mod:`cadartifact.gate.codequality`).

Every writer takes the gate document (:func:`cadartifact.gate.run.build_document`) and returns text;
:func:`write_atomic` puts it in a file so that no partial report is ever left behind (temporary
file in the same folder, then ``os.replace``).

What goes where:

- JUnit: one ``<testsuite>`` per file, one ``<testcase>`` per face named ``"<file>#<face> <name>"``;
  ``fail`` is a ``<failure>`` carrying the numbers, ``warn`` passes with a ``verdict`` property and
  a ``<system-out>`` line, a file that could not be read is a testcase with an ``<error>``, a file
  without analysable face a ``<skipped>`` testcase.
- SARIF: one result per finding (``fail`` CA001 error, ``warn`` CA002 warning, unreadable file
  CA003 error, no analysable face CA004 note, OBJ cage analysed below ``min_analysed_share`` CA005
  error, OBJ cage with an extraordinary vertex's defect beyond the tolerance CA007 error); passing faces are
  not findings. Locations are the file (URI relative to the run's root, its
  ``uriBaseId`` ``SRCROOT``: :mod:`cadartifact.gate.locations`) at the line where the face's STEP entity
  (``#id = ADVANCED_FACE``) is defined (line 1 for OBJ and files without one), and the face (with its ``#id``)
  as a logical location; the properties carry the entity, its line, the peak's ``uv`` and ``xyz``
  (``peak_at``), and the finding's ``path``, ``record`` and ``criterion``; ``partialFingerprints`` (a hash of
  those three: :func:`cadartifact.gate.locations.fingerprint`) keep alerts stable across runs and machines.
  The GitLab Code Quality report (:mod:`cadartifact.gate.codequality`) is these results in GitLab's form.
- PDQ criteria (``--profile``, :mod:`cadartifact.gate.profiles`): every report lists them per face with value,
  threshold and the worst place (text: a ``pdq`` line per face and one per criterion that warns or fails;
  JUnit: a ``pdq.<criterion>`` property each, a failing criterion is the testcase's ``<failure>`` when the
  ripple passes; SARIF: one rule per criterion, CA101-CA109, a result per criterion that warns or fails, and a
  CA110 note per face naming the criteria that could not be evaluated).
- Continuity between faces (with a profile): :mod:`cadartifact.gate.edge_reports` (text lines and a JUnit testcase
  per edge that warns or fails, SARIF results CA131-CA133 at the edge's ``EDGE_CURVE`` line).
"""

from __future__ import annotations

import io
import json
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError
from ..runs.face_instances import NOTE as REPEAT_NOTE
from ..runs.records import estimated_u, plural, unit_name
from .edge_reports import edge_junit, edge_lines
from .rules import CRITERION_RULES, RULES, SARIF_SCHEMA

if TYPE_CHECKING:  # the records the writers read (runs/documents: docs/schema.md)
    from ..runs.documents.face import AdviceRecord
    from ..runs.documents.gate import CriterionAt, CriterionRecord, GateDocument, GateFace, GateFile

__all__ = ["FORMATS", "RULES", "CRITERION_RULES", "SARIF_SCHEMA", "render_text", "to_text", "to_json", "to_junit",
           "write_atomic", "face_label", "criterion_text", "criteria_lines", "profile_line"]

FORMATS = ("text", "json", "junit", "sarif", "gitlab")

#: A file's failures as a whole: its entry's key, the JUnit testcase's name suffix and the failure's type.
_FILE_FAILURES = (("share_failure", "analysed share", "CA005 analysed-share-too-small"),
                  ("extraordinary_failure", "extraordinary vertices", "CA007 extraordinary-vertex-defect"))
_COLOURS = {"pass": "green", "warn": "yellow", "fail": "red", "error": "bold red"}
_DIRECTIONS = ("x1", "x2", "diagonal", "lateral", "total")


def face_label(path: str, face: GateFace) -> str:
    """``"<file>#<face> <name>"`` (no trailing name when the face has none)."""
    return f"{path}#{face['face']}" + (f" {face['name']}" if face.get("name") else "")


def _net(shape) -> str:
    return "x".join(str(n) for n in shape)


def _advice_text(face: GateFace) -> str:
    adv = face["advice"]
    if adv is None:  # gate --advise: the verdict needs today's budget only
        return f"advice {face.get('advice_skipped') or 'not computed'}"
    if adv.get("verifiable") is False:
        return "no density can be shown to conform (the intent's uncertainty is near the tolerance)"
    if not adv["meets_tolerance"]:
        return f"no density up to {_net(adv['net'])} meets the tolerance"
    ver = adv.get("verification")
    how = "" if ver is None else " (verified on the real surface)" if ver.get("meets") else " (verification failed)"
    return f"advised net {_net(adv['net'])} ({adv['points']} points){how}"


def _num(x) -> str:
    return "n/a" if x is None else f"{x:.4g}"


def where_text(face: GateFace, units: str) -> str:
    """``"STEP #17 (line 28); peak at uv (1, 0.9333), xyz (1000, 11.63, 19.87) mm"``, or ``""``."""
    parts = []
    if face.get("entity") is not None:
        parts.append(f"STEP #{face['entity']}" + (f" (line {face['entity_line']})" if face.get("entity_line") else ""))
    peak = face.get("peak_at")
    if peak:
        at = f"uv ({', '.join(_num(t) for t in peak['uv'])}), " if peak.get("uv") else ""
        parts.append(f"peak at {at}xyz ({', '.join(_num(c) for c in peak['xyz'])}) {units}")
    return "; ".join(parts)


def _at_text(at: CriterionAt | None, units: str) -> str:
    if not at:
        return ""
    xyz = f", xyz ({', '.join(_num(c) for c in at['xyz'])}) {units}" if at.get("xyz") else ""
    return f" at uv ({', '.join(_num(t) for t in at['uv'])}){xyz}"


def criterion_text(c: CriterionRecord, units: str, where: bool = True) -> str:
    """``"waviness 5 inflections (fail: warn > 1, fail > 3) at uv (0.2, 0.5), xyz (1, 2, 3) mm"``, or
    ``"knots not evaluated (a subdivision cage has no knots ...)"``."""
    if not c["evaluated"]:
        return f"{c['criterion']} not evaluated ({c['reason']})"
    th = c["threshold"] or {}
    sign = ">" if th.get("sense") == "above" else "<"
    limits = ", ".join(f"{k} {sign} {th[k]:g}" for k in ("warn", "fail") if th.get(k) is not None) or "no threshold"
    value = "n/a" if c["value"] is None else f"{c['value']:.4g}"
    return (f"{c['criterion']} {value} {c['unit']} ({c['verdict']}: {limits})"
            + (_at_text(c.get("at"), units) if where else ""))


def criteria_summary(face: GateFace) -> str:
    """One line with every criterion's value of a face: ``waviness 2 W, degree 3, ..., knots n/e``."""
    mark = {"warn": " W", "fail": " F", "pass": ""}
    return ", ".join(f"{c['criterion']} " + ("n/e" if not c["evaluated"] else
                                             f"{'n/a' if c['value'] is None else format(c['value'], '.4g')}"
                                             f"{mark[c['verdict']]}") for c in face["criteria"])


def criteria_lines(entry: GateFile, units: str) -> list[str]:
    """The text report's PDQ lines of one file: per face its criteria, then each criterion that warns or fails
    with threshold and place, then what could not be evaluated and why (never silent)."""
    lines = []
    for f in entry["faces"]:
        if not f.get("criteria"):
            continue
        label = face_label(entry["path"], f)
        lines.append(f"pdq: {label}: {criteria_summary(f)}")
        for c in f["criteria"]:
            if c["evaluated"] and c["verdict"] in ("warn", "fail"):
                lines.append(f"pdq {c['verdict']}: {label}: {c['code']}: {criterion_text(c, units)}")
        missing = [c for c in f["criteria"] if not c["evaluated"]]
        for reason in dict.fromkeys(c["reason"] for c in missing):
            names = ", ".join(c["criterion"] for c in missing if c["reason"] == reason)
            lines.append(f"pdq not evaluated: {label}: {names}: {reason}")
    return lines


def profile_line(doc: GateDocument) -> str | None:
    """``"PDQ profile default: waviness warn > 1, fail > 3; ..."`` (None without a profile)."""
    prof = doc.get("profile")
    if not prof:
        return None
    parts = []
    for key in CRITERION_RULES:
        th = prof.get(key)
        if th is None:
            parts.append(f"{key} off")
            continue
        sign = ">" if th["sense"] == "above" else "<"
        parts.append(f"{key} " + (", ".join(f"{k} {sign} {th[k]:g}" for k in ("warn", "fail") if th[k] is not None)
                                  or "no threshold"))
    src = f" ({prof['source']})" if prof.get("source") else ""
    return f"PDQ profile {prof['name']}{src}: " + "; ".join(parts)


def face_numbers(doc: GateDocument, entry: GateFile, face: GateFace) -> str:
    """One line with the numbers of a face: value against tolerance, per-direction peaks, advice."""
    pol = entry["policy"]
    units = file_units(doc, entry)
    peaks = ", ".join(f"{k} {_num(face['budget'][k]['peak'])}" for k in _DIRECTIONS[:4])
    where = where_text(face, units)
    what = f"canonical {face['canonical']}; " if face.get("canonical") else ""
    unc = face.get("uncertainty")
    u = (f"; uncertainty U {_num(unc['peak'])} {units} (u {_num(unc['u'])}, v {_num(unc['v'])}), "
         f"decision: {face.get('decision')}") if estimated_u(face) is not None else ""
    return (f"{what}{face['verdict_reason']}; peaks {peaks} {units}{u}; net {_net(face['net'])}, "
            f"scheme {face['scheme']}, {face['method']}; {_advice_text(face)}; metric {pol['metric']}, "
            f"warn at {pol['warn_fraction']:g} of tolerance" + (f"; {where}" if where else ""))


# ---------------------------------------------------------------- text
def _advised_cell(adv: AdviceRecord | None) -> str:
    if adv is None:  # skipped (gate --advise): the reason is in the JSON's advice_skipped
        return "-"
    if adv.get("verifiable") is False:
        return "unverifiable"
    return _net(adv["net"]) if adv["meets_tolerance"] else "out of reach"


def _u_cell(face: GateFace) -> str:
    """The intent's uncertainty U of a face (``-`` where none is estimated)."""
    u = estimated_u(face)
    return "-" if u is None else f"{u:.2g}"


def _share(x) -> str:
    return "" if x is None else f"{100 * x:.0f}%"


def file_units(doc: GateDocument, entry: GateFile) -> str:
    """The unit of one file (never another file's: an OBJ beside STEP files stays in model units)."""
    return unit_name(entry.get("units") if entry.get("units") else (doc["units"] if entry.get("faces") else None))


def render_text(doc: GateDocument, console, wide: bool | None = None, wrap: bool = True) -> None:
    """Print one rich table per file (shares of the tolerance per direction, value, verdict) and a summary.

    ``wide`` (default: a console of 110 columns or more) shows scheme, method and every direction;
    the narrow layout (80 columns) shows face, net, value, its share, the worst direction, advised net
    and verdict, with scheme and method under the table; no cell is cut or wraps inside a number.
    Paths and face names are never broken: each file's heading is a line of its own, and on a console that
    wraps nothing (:func:`~cadartifact.runs.terminal.wraps_nothing`: a log, a file) face labels are whole
    and a table takes its content's width. Explanation lines are wrapped at spaces to the console's width
    (``wrap``; never inside a path or a face label: :func:`~cadartifact.runs.terminal.say`).
    """
    from rich.markup import escape
    from rich.table import Table

    from ..runs.terminal import (WIDE_COLUMNS, canonical_lines, face_cell, print_table, say, worst_direction,
                                 wraps_nothing)

    if wide is None:
        wide = console.width >= WIDE_COLUMNS
    limit = None if wraps_nothing(console) else 24  # a log shows every face name whole
    for entry in doc["files"]:
        v = entry["verdict"]
        if v == "error":
            console.print(f"[{_COLOURS[v]}]ERROR[/] {escape(entry['error'])}", soft_wrap=True)
            continue
        pol = entry["policy"]
        units = file_units(doc, entry)
        share = entry.get("analysed_share")
        cover = "" if share is None else f", cage area analysed {100 * share:.1f} %"
        keep = [entry["path"]] + [face_label(entry["path"], f) for f in entry["faces"]]
        title = (f"{escape(entry['path'])}  [{_COLOURS[v]}]{v.upper()}[/]  (tolerance {pol['tolerance']:g} "
                 f"{units}, {pol['metric']}, warn at {pol['warn_fraction']:g}{cover})")
        if entry["faces"]:
            table = Table(header_style="bold")
            cols = (("face", "net", "scheme", "method", "X1", "X2", "diag", "lateral", "value", "+/-U", "advised",
                     "verdict") if wide else ("face", "net", "value", "+/-U", "share", "worst", "advised", "verdict"))
            for col in cols:
                # only the face label may fold; numbers never wrap or shrink
                table.add_column(col, no_wrap=col != "face", overflow="fold" if col == "face" else "ellipsis")
            for f in entry["faces"]:
                sh = f["share"]
                advised = _advised_cell(f["advice"])
                verdict = f"[{_COLOURS[f['verdict']]}]{f['verdict']}[/]"
                if wide:
                    table.add_row(face_cell(f, limit), _net(f["net"]), f["scheme"], f["method"], _share(sh["x1"]),
                                  _share(sh["x2"]), _share(sh["diagonal"]), _share(sh["lateral"]),
                                  f"{f['value']:.4g}", _u_cell(f), advised, verdict)
                else:
                    key = "deviation" if pol["include_signal_error"] else "total"
                    table.add_row(face_cell(f, limit), _net(f["net"]), f"{f['value']:.4g}", _u_cell(f), _share(sh[key]),
                                  worst_direction(sh), advised, verdict)
            print_table(console, table, title, keep=[entry["path"]])
            if not wide:
                schemes = ", ".join(sorted({f["scheme"] for f in entry["faces"]}))
                methods = ", ".join(sorted({f["method"] for f in entry["faces"]}))
                console.print(f"  values in {units}; scheme {schemes}; {methods}", soft_wrap=True)
        else:
            console.print(title, soft_wrap=True)
        for line in canonical_lines(entry["faces"]):  # no ripple along their exact directions
            say(console, f"  {line}", keep, wrap)
        for f in entry["faces"]:
            if f["verdict"] != "pass":
                where = where_text(f, units)
                what = f" ({f['canonical']})" if f.get("canonical") else ""
                say(console, f"  {f['verdict']}: {face_label(entry['path'], f)}{what}: {f['verdict_reason']}"
                    + (f"; {where}" if where else ""), keep, wrap)
        for line in criteria_lines(entry, units) + edge_lines(entry, units):
            say(console, f"  {line}", keep, wrap)
        repeats = 0
        for f in entry["faces"]:  # what the analysis could not judge on a face: never silent
            for note in f.get("notes") or []:
                if note.startswith(REPEAT_NOTE):  # not a judgement: counted below
                    repeats += 1
                    continue
                say(console, f"  note: {face_label(entry['path'], f)}: {note}", keep, wrap)
        if repeats:
            verb, whose = ("repeats", "its") if repeats == 1 else ("repeat", "their")
            say(console, f"  note: {plural(repeats, 'face')} {verb} an earlier face moved rigidly: {whose} analysis "
                "is reused (the JSON report names the face)", keep, wrap)
        if entry.get("share_failure"):
            say(console, f"  fail: {entry['path']}: {entry['share_failure']}", keep, wrap)
        if entry.get("extraordinary_failure"):
            say(console, f"  fail: {entry['path']}: {entry['extraordinary_failure']}", keep, wrap)
        if entry.get("cage_advice") and entry["verdict"] != "pass":
            for line in entry["cage_advice"]["text"]:
                say(console, f"  advice: {line}", keep, wrap)
        for note in entry["notes"] + entry["warnings"]:
            say(console, f"  note: {note}", keep, wrap)
    prof = profile_line(doc)
    if prof:
        say(console, prof, (), wrap)
    from .baseline import baseline_lines

    for line in baseline_lines(doc):
        say(console, line, (), wrap)
    console.print(summary_line(doc), soft_wrap=not wrap)  # rich wraps it at spaces


def summary_line(doc: GateDocument) -> str:
    """``gate FAIL: 3 file(s), 10 face(s): 7 pass, 2 warn, 1 fail; 1 file(s) unreadable (exit 1)``."""
    s = doc["summary"]
    faces = s["verdicts"]["faces"]
    v = doc["verdict"]
    text = (f"[bold]gate [{_COLOURS[v]}]{v.upper()}[/][/]: {s['files']} file(s), {s['faces']} face(s): "
            f"{faces['pass']} pass, {faces['warn']} warn, {faces['fail']} fail")
    if s.get("undecided"):
        text += f" ({s['undecided']} undecided: value +/- U straddles the tolerance, policy undecided = " \
                f"{doc.get('undecided', 'warn')!r})"
    crit = {k: n for k, n in (s.get("criteria") or {}).items() if n["warn"] or n["fail"]}
    if s.get("edges"):
        e = s["edges"]
        text += f"; {e['edges']} shared edge(s): {e['sharp']} sharp, {e['warn']} warn, {e['fail']} fail"
    if crit:
        text += "; PDQ: " + ", ".join(f"{k} " + " ".join(f"{n[v]} {v}" for v in ("fail", "warn") if n[v])
                                      for k, n in crit.items())
    whole = sum(1 for e in doc["files"] if e.get("share_failure"))
    if whole:  # a file-level failure no face carries: counted, so that the verdict adds up
        text += f"; {whole} file(s) fail as a whole (analysed share below min_analysed_share)"
    if s["errors"]:
        text += f"; {s['errors']} file(s) could not be read or analysed"
    base = doc.get("baseline")
    if base:
        from rich.markup import escape

        text += (f"; baseline {escape(base['source'])}: {len(base['new'])} new, {len(base['worse'])} worse, "
                 f"{base['known']} known, {len(base['fixed'])} fixed")
    return text + f" (exit {doc['exit_code']})"


def to_text(doc: GateDocument, width: int = 132) -> str:
    """The text report without colours (for ``--output``): a file, so nothing wraps (a path or a name is one
    token to grep); ``width`` chooses the layout (``render_text``'s ``wide``) and fits tables that can."""
    from rich.console import Console

    buf = io.StringIO()
    render_text(doc, Console(file=buf, width=width, color_system=None, force_terminal=False, highlight=False,
                             soft_wrap=True), wrap=False)
    return buf.getvalue()


# ---------------------------------------------------------------- json
def to_json(doc: GateDocument) -> str:
    """The gate document as JSON (strict: no NaN)."""
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"


# ---------------------------------------------------------------- junit
def to_junit(doc: GateDocument) -> str:
    """JUnit XML: a testsuite per file, a testcase per face; failures carry the numbers."""
    import xml.etree.ElementTree as ET

    root = ET.Element("testsuites", name="cadartifact gate")
    totals = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    for entry in doc["files"]:
        suite = ET.SubElement(root, "testsuite", name=entry["path"])
        counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
        pol = entry.get("policy")
        if pol:
            props = ET.SubElement(suite, "properties")
            for k in ("tolerance", "metric", "warn_fraction", "include_signal_error", "scheme", "measured", "undecided"):
                ET.SubElement(props, "property", name=k, value="default" if pol.get(k) is None else str(pol[k]))
            ET.SubElement(props, "property", name="units", value=file_units(doc, entry))
            ET.SubElement(props, "property", name="verdict", value=entry["verdict"])
        if entry["verdict"] == "error":
            case = ET.SubElement(suite, "testcase", name=entry["path"], classname="cadartifact.gate.run")
            err = ET.SubElement(case, "error", message=entry["error"], type="CA003 unreadable-file")
            err.text = entry["error"]
            counts["tests"] += 1
            counts["errors"] += 1
        for key, what, rule in _FILE_FAILURES:  # the file fails as a whole: one testcase each
            if entry.get(key):
                case = ET.SubElement(suite, "testcase", name=f"{entry['path']} ({what})",
                                     classname="cadartifact.gate.run")
                fail = ET.SubElement(case, "failure", message=entry[key], type=rule)
                fail.text = entry[key]
                counts["tests"] += 1
                counts["failures"] += 1
        if entry["verdict"] != "error" and not entry["faces"]:
            case = ET.SubElement(suite, "testcase", name=f"{entry['path']} (no analysable face)",
                                 classname="cadartifact.gate.run")
            ET.SubElement(case, "skipped", message="; ".join(entry["notes"] + entry["warnings"]))
            counts["tests"] += 1
            counts["skipped"] += 1
        for f in entry["faces"]:
            case = ET.SubElement(suite, "testcase", name=face_label(entry["path"], f), classname="cadartifact.gate.run")
            props = ET.SubElement(case, "properties")
            unc = estimated_u(f)
            for name, value in (("verdict", f["verdict"]), ("value", f"{f['value']:.9g}"),
                                ("uncertainty", "" if unc is None else f"{unc:.9g}"),
                                ("decision", f.get("decision") or ""),
                                ("tolerance", f"{pol['tolerance']:.9g}"), ("units", file_units(doc, entry)),
                                ("advised_net", _net(f["advice"]["net"]) if f["advice"] else "")):
                ET.SubElement(props, "property", name=name, value=value)
            if f.get("entity") is not None:
                ET.SubElement(props, "property", name="entity", value=f"#{f['entity']}")
                if f.get("entity_line"):
                    ET.SubElement(props, "property", name="entity_line", value=str(f["entity_line"]))
            peak = f.get("peak_at")
            if peak:
                if peak.get("uv"):
                    ET.SubElement(props, "property", name="peak_uv", value=" ".join(f"{t:.9g}" for t in peak["uv"]))
                ET.SubElement(props, "property", name="peak_xyz", value=" ".join(f"{c:.9g}" for c in peak["xyz"]))
            for c in f.get("criteria") or []:
                ET.SubElement(props, "property", name=f"pdq.{c['criterion']}",
                              value=criterion_text(c, file_units(doc, entry)))
            counts["tests"] += 1
            numbers = face_numbers(doc, entry, f)
            if f["verdict"] == "fail":
                kind = "CA001 ripple-exceeds-tolerance"
                if f.get("ripple_verdict", "fail") != "fail":  # a PDQ criterion fails the face
                    c = next(c for c in f["criteria"] if c["verdict"] == "fail")
                    rid = CRITERION_RULES[c["criterion"]]
                    kind = f"{rid} {next(r[1] for r in RULES if r[0] == rid)}"
                fail = ET.SubElement(case, "failure", message=f["verdict_reason"], type=kind)
                fail.text = numbers
                counts["failures"] += 1
            elif f["verdict"] == "warn":
                ET.SubElement(case, "system-out").text = "warning: " + numbers
        edge_junit(suite, entry, counts)
        for k, v in counts.items():
            suite.set(k, str(v))
            totals[k] += v
    for k, v in totals.items():
        root.set(k, str(v))
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


# ---------------------------------------------------------------- sarif
# ---------------------------------------------------------------- files
def write_atomic(path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same folder and ``os.replace``.

    Raises
    ------
    InputError
        The folder does not exist or is not writable (the temporary file is removed).
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(path, "cannot write the report: folder does not exist")
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise InputError(path, f"cannot write the report ({exc.strerror or exc})") from None
    try:
        # backslashreplace: a file name that is not UTF-8 is shown as \udcff, not a crash
        with os.fdopen(fd, "w", encoding="utf-8", errors="backslashreplace", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; a report is an ordinary file
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise InputError(path, f"cannot write the report ({exc.strerror or exc})") from None
        raise
    return path
