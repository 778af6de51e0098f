"""Report writers of the quality gate: text (rich), JSON, JUnit XML and SARIF 2.1.0.

Every writer takes the gate document (:func:`cadartifact.gate.build_document`) and returns text;
:func:`write_atomic` puts it in a file so that no partial report is ever left behind (temporary
file in the same folder, then ``os.replace``).

What goes where:

- JUnit: one ``<testsuite>`` per file, one ``<testcase>`` per face named ``"<file>#<face> <name>"``;
  ``fail`` is a ``<failure>`` carrying the numbers, ``warn`` passes with a ``verdict`` property and
  a ``<system-out>`` line, a file that could not be read is a testcase with an ``<error>``, a file
  without analysable face a ``<skipped>`` testcase.
- SARIF: one result per finding (``fail`` CA001 error, ``warn`` CA002 warning, unreadable file
  CA003 error, no analysable face CA004 note); passing faces are not findings. Locations are the
  file (URI relative to the working directory) at line 1, as code scanning needs a line, and the
  face as a logical location; ``partialFingerprints`` keep alerts stable across runs.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import tempfile
from pathlib import Path
from urllib.parse import quote

from .errors import InputError

__all__ = ["FORMATS", "RULES", "SARIF_SCHEMA", "render_text", "to_text", "to_json", "to_junit", "to_sarif",
           "write_atomic", "face_label"]

FORMATS = ("text", "json", "junit", "sarif")

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"

#: SARIF rules: id, name, default level, short description.
RULES = (
    ("CA001", "ripple-exceeds-tolerance", "error",
     "A face's control-net ripple (artifact) exceeds the tolerance"),
    ("CA002", "ripple-near-tolerance", "warning",
     "A face's ripple is within the tolerance but above the warn fraction of it, or is outside the uniform "
     "theory and capped at warn"),
    ("CA003", "unreadable-file", "error",
     "A file could not be read or analysed; the gate fails closed"),
    ("CA004", "no-analysable-face", "note",
     "A file has no B-spline face or quad chart to analyse"),
)

_COLOURS = {"pass": "green", "warn": "yellow", "fail": "red", "error": "bold red"}
_DIRECTIONS = ("x1", "x2", "diagonal", "lateral", "total")


def face_label(path: str, face: dict) -> str:
    """``"<file>#<face> <name>"`` (no trailing name when the face has none)."""
    return f"{path}#{face['face']}" + (f" {face['name']}" if face.get("name") else "")


def _net(shape) -> str:
    return "x".join(str(n) for n in shape)


def _advice_text(face: dict) -> str:
    adv = face["advice"]
    if not adv["meets_tolerance"]:
        return f"no density up to {_net(adv['net'])} meets the tolerance"
    ver = adv.get("verification")
    how = "" if ver is None else " (verified on the real surface)" if ver.get("meets") else " (verification failed)"
    return f"advised net {_net(adv['net'])} ({adv['points']} points){how}"


def _num(x) -> str:
    return "n/a" if x is None else f"{x:.4g}"


def face_numbers(doc: dict, entry: dict, face: dict) -> str:
    """One line with the numbers of a face: value against tolerance, per-direction peaks, advice."""
    pol = entry["policy"]
    units = entry.get("units") or doc["units"]
    peaks = ", ".join(f"{k} {_num(face['budget'][k]['peak'])}" for k in _DIRECTIONS[:4])
    return (f"{face['verdict_reason']} {units}; peaks {peaks} {units}; net {_net(face['net'])}, "
            f"scheme {face['scheme']}, {face['method']}; {_advice_text(face)}; metric {pol['metric']}, "
            f"warn at {pol['warn_fraction']:g} of tolerance")


# ---------------------------------------------------------------- text
def _share(x) -> str:
    return "" if x is None else f"{100 * x:.0f}%"


def render_text(doc: dict, console) -> None:
    """Print one rich table per file (shares of the tolerance per direction, value, verdict) and a summary."""
    from rich.table import Table

    for entry in doc["files"]:
        v = entry["verdict"]
        if v == "error":
            console.print(f"[{_COLOURS[v]}]ERROR[/] {entry['error']}", soft_wrap=True)
            continue
        pol = entry["policy"]
        units = entry.get("units") or doc["units"]
        title = (f"{entry['path']}  [{_COLOURS[v]}]{v.upper()}[/]  (tolerance {pol['tolerance']:g} {units}, "
                 f"{pol['metric']}, warn at {pol['warn_fraction']:g})")
        if entry["faces"]:
            table = Table(title=title, title_justify="left", header_style="bold")
            for col in ("face", "net", "scheme", "method", "X1", "X2", "diag", "lateral", "value", "advised",
                        "verdict"):
                # fold rather than truncate: the numbers must stay readable in narrow CI logs
                table.add_column(col, overflow="fold", min_width=4 if col != "face" else 6)
            for f in entry["faces"]:
                sh = f["share"]
                advised = _net(f["advice"]["net"]) if f["advice"]["meets_tolerance"] else "out of reach"
                label = str(f["face"]) + (f" {f['name']}" if f.get("name") else "")
                table.add_row(label, _net(f["net"]), f["scheme"], f["method"], _share(sh["x1"]), _share(sh["x2"]),
                              _share(sh["diagonal"]), _share(sh["lateral"]), f"{f['value']:.4g}", advised,
                              f"[{_COLOURS[f['verdict']]}]{f['verdict']}[/]")
            console.print(table)
        else:
            console.print(title)
        for f in entry["faces"]:
            if f["verdict"] != "pass":
                console.print(f"  {f['verdict']}: {face_label(entry['path'], f)}: {f['verdict_reason']}",
                              soft_wrap=True)
        for note in entry["notes"] + entry["warnings"]:
            console.print(f"  note: {note}", soft_wrap=True)
    console.print(summary_line(doc))


def summary_line(doc: dict) -> str:
    """``gate FAIL: 3 file(s), 10 face(s): 7 pass, 2 warn, 1 fail; 1 file(s) unreadable (exit 1)``."""
    s = doc["summary"]
    faces = s["verdicts"]["faces"]
    v = doc["verdict"]
    text = (f"[bold]gate [{_COLOURS[v]}]{v.upper()}[/][/]: {s['files']} file(s), {s['faces']} face(s): "
            f"{faces['pass']} pass, {faces['warn']} warn, {faces['fail']} fail")
    if s["errors"]:
        text += f"; {s['errors']} file(s) could not be read or analysed"
    return text + f" (exit {doc['exit_code']})"


def to_text(doc: dict, width: int = 132) -> str:
    """The text report without colours (for ``--output``)."""
    from rich.console import Console

    buf = io.StringIO()
    render_text(doc, Console(file=buf, width=width, color_system=None, force_terminal=False, highlight=False))
    return buf.getvalue()


# ---------------------------------------------------------------- json
def to_json(doc: dict) -> str:
    """The gate document as JSON (strict: no NaN)."""
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"


# ---------------------------------------------------------------- junit
def to_junit(doc: dict) -> str:
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
            for k in ("tolerance", "metric", "warn_fraction", "include_signal_error", "scheme", "measured"):
                ET.SubElement(props, "property", name=k, value="default" if pol[k] is None else str(pol[k]))
            ET.SubElement(props, "property", name="verdict", value=entry["verdict"])
        if entry["verdict"] == "error":
            case = ET.SubElement(suite, "testcase", name=entry["path"], classname="cadartifact.gate")
            err = ET.SubElement(case, "error", message=entry["error"], type="CA003 unreadable-file")
            err.text = entry["error"]
            counts["tests"] += 1
            counts["errors"] += 1
        elif not entry["faces"]:
            case = ET.SubElement(suite, "testcase", name=f"{entry['path']} (no analysable face)",
                                 classname="cadartifact.gate")
            ET.SubElement(case, "skipped", message="; ".join(entry["notes"] + entry["warnings"]))
            counts["tests"] += 1
            counts["skipped"] += 1
        for f in entry["faces"]:
            case = ET.SubElement(suite, "testcase", name=face_label(entry["path"], f), classname="cadartifact.gate")
            props = ET.SubElement(case, "properties")
            for name, value in (("verdict", f["verdict"]), ("value", f"{f['value']:.9g}"),
                                ("tolerance", f"{pol['tolerance']:.9g}"), ("advised_net", _net(f["advice"]["net"]))):
                ET.SubElement(props, "property", name=name, value=value)
            counts["tests"] += 1
            numbers = face_numbers(doc, entry, f)
            if f["verdict"] == "fail":
                fail = ET.SubElement(case, "failure", message=f["verdict_reason"],
                                     type="CA001 ripple-exceeds-tolerance")
                fail.text = numbers
                counts["failures"] += 1
            elif f["verdict"] == "warn":
                ET.SubElement(case, "system-out").text = "warning: " + numbers
        for k, v in counts.items():
            suite.set(k, str(v))
            totals[k] += v
    for k, v in totals.items():
        root.set(k, str(v))
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


# ---------------------------------------------------------------- sarif
def _uri(path: str, cwd: str) -> str:
    absolute = os.path.abspath(path)
    try:
        rel = os.path.relpath(absolute, cwd)
    except ValueError:  # another drive
        return Path(absolute).as_uri()
    return quote(Path(rel).as_posix())


def _fingerprint(*parts) -> str:
    return hashlib.sha256("\0".join(map(str, parts)).encode()).hexdigest()[:32]


def to_sarif(doc: dict, cwd: str | None = None) -> str:
    """SARIF 2.1.0 log: tool.driver ``cadartifact`` with rules CA001-CA004, one result per finding."""
    from . import __version__

    cwd = os.path.abspath(cwd or os.getcwd())
    index = {rule_id: i for i, (rule_id, *_rest) in enumerate(RULES)}
    rules = [{"id": rid, "name": name, "shortDescription": {"text": text}, "fullDescription": {"text": text},
              "defaultConfiguration": {"level": level}, "help": {"text": text}}
             for rid, name, level, text in RULES]
    results = []

    def add(rule_id: str, level: str, text: str, path: str, face: dict | None, props: dict):
        loc = {"physicalLocation": {"artifactLocation": {"uri": _uri(path, cwd)}, "region": {"startLine": 1}}}
        if face is not None:
            loc["logicalLocations"] = [{"name": f"face {face['face']}" + (f" {face['name']}" if face.get("name")
                                                                            else ""),
                                        "fullyQualifiedName": face_label(path, face), "kind": "element"}]
        results.append({"ruleId": rule_id, "ruleIndex": index[rule_id], "level": level, "message": {"text": text},
                        "locations": [loc],
                        "partialFingerprints": {"cadartifactFace/v1": _fingerprint(
                            rule_id, _uri(path, cwd), None if face is None else face["face"])},
                        "properties": props})

    for entry in doc["files"]:
        path = entry["path"]
        if entry["verdict"] == "error":
            add("CA003", "error", entry["error"], path, None, {"verdict": "error"})
            continue
        if not entry["faces"]:
            add("CA004", "note", f"{path}: " + "; ".join(entry["notes"] + entry["warnings"]), path, None,
                {"verdict": entry["verdict"]})
        for f in entry["faces"]:
            if f["verdict"] == "pass":
                continue
            rule_id, level = ("CA001", "error") if f["verdict"] == "fail" else ("CA002", "warning")
            props = {"verdict": f["verdict"], "face": f["face"], "value": f["value"],
                     "tolerance": entry["policy"]["tolerance"], "metric": entry["policy"]["metric"],
                     "peaks": {k: f["budget"][k]["peak"] for k in _DIRECTIONS}, "net": f["net"],
                     "advised_net": f["advice"]["net"]}
            add(rule_id, level, f"{face_label(path, f)}: {face_numbers(doc, entry, f)}", path, f, props)
    log = {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "cadartifact", "version": __version__, "semanticVersion": __version__,
                                "rules": rules}},
            "invocations": [{"executionSuccessful": doc["exit_code"] != 2, "exitCode": doc["exit_code"]}],
            "results": results,
            "properties": {"verdict": doc["verdict"], "summary": doc["summary"]},
        }],
    }
    return json.dumps(log, indent=2, allow_nan=False) + "\n"


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
