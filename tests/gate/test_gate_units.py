"""Gate pieces without CAD files: verdict rules (properties), policy parsing, inputs, atomic writes."""

import json
import os
import re

import pytest
from hypothesis import given, settings, strategies as st

from cadartifact.errors import CadArtifactError, InputError
from cadartifact.runs.verdicts import VERDICTS, face_verdict
from cadartifact.gate.run import build_document, file_verdict
from cadartifact.gate.policy import FileSettings, Policy, PolicyError, expand_paths, find_policy, load_policy, parse_policy
from cadartifact.gate.reports import to_junit, write_atomic
from cadartifact.gate.sarif import to_sarif
from cadartifact.testing.paths import ROOT

REPO = ROOT


def record(value, method="predicted", rms=None, face=0):
    """A face record as report.face_record makes it (only what the gate reads)."""
    stat = {"peak": value, "rms": value / 2 if rms is None else rms}
    budget = {k: dict(stat) for k in ("x1", "x2", "diagonal", "lateral", "total", "signal_error", "deviation")}
    return {"face": face, "name": None, "kind": "bspline", "net": [8, 6], "scheme": "bspline(3,3)",
            "method": method, "budget": budget, "share": {k: None for k in budget}, "meets_tolerance": True,
            "advice": {"net": [9, 6], "points": 54, "meets_tolerance": True, "verification": None}}


positive = st.floats(min_value=1e-9, max_value=1e6, allow_nan=False)
fraction = st.floats(min_value=1e-3, max_value=1.0)


@settings(max_examples=200, deadline=None)
@given(value=st.floats(min_value=0, max_value=1e6), t1=positive, t2=positive, f=fraction)
def test_verdict_never_gets_worse_as_the_tolerance_grows(value, t1, t2, f):
    lo, hi = sorted((t1, t2))
    v_lo = face_verdict(record(value), FileSettings(tolerance=lo, warn_fraction=f))[0]
    v_hi = face_verdict(record(value), FileSettings(tolerance=hi, warn_fraction=f))[0]
    assert VERDICTS.index(v_hi) <= VERDICTS.index(v_lo)


@settings(max_examples=200, deadline=None)
@given(value=st.floats(min_value=0, max_value=1e6), t=positive, f=fraction)
def test_verdict_rule(value, t, f):
    verdict, reason, got = face_verdict(record(value), FileSettings(tolerance=t, warn_fraction=f))
    assert got == value
    assert verdict == ("fail" if value > t else "warn" if value >= f * t else "pass")
    assert f"{t:g}" in reason
    # the cap follows faces outside the uniform theory (non-uniform knots, varying weights), not the road
    outside = dict(record(value, method="measured"), uniform=False)
    assert face_verdict(outside, FileSettings(tolerance=t, warn_fraction=f))[0] == verdict  # default: gated
    capped = face_verdict(outside, FileSettings(tolerance=t, warn_fraction=f, measured="warn"))[0]
    assert capped == ("warn" if verdict == "fail" else verdict)
    assert face_verdict(dict(record(value, method="measured"), uniform=True), FileSettings(tolerance=t))[0] == \
        face_verdict(record(value), FileSettings(tolerance=t))[0]
    strict = face_verdict(outside, FileSettings(tolerance=t, warn_fraction=f, measured="fail"))[0]
    assert strict == verdict


def test_metric_and_signal_error_choose_the_value():
    rec = record(1.0, rms=0.25)
    rec["budget"]["deviation"] = {"peak": 3.0, "rms": 2.0}
    assert face_verdict(rec, FileSettings(tolerance=1, metric="rms"))[2] == 0.25
    assert face_verdict(rec, FileSettings(tolerance=1, include_signal_error=True))[2] == 3.0
    assert face_verdict(rec, FileSettings(tolerance=1, metric="rms", include_signal_error=True))[2] == 2.0


@given(st.lists(st.sampled_from(VERDICTS[:3]), max_size=6), st.booleans())
def test_file_verdict_is_the_worst_and_error_dominates(verdicts, error):
    entry = {"faces": [{"verdict": v} for v in verdicts], "error": "x: broken" if error else None}
    expect = "error" if error else max(verdicts, key=VERDICTS.index, default="pass")
    assert file_verdict(entry) == expect


def entry(path, verdicts, error=None, tol=1.0):
    verdicts = [] if error else verdicts  # an error entry has no faces (gate._error_entry)
    faces = []
    for i, v in enumerate(verdicts):
        value = {"pass": 0.1, "warn": 0.9, "fail": 1.5}[v]
        r = record(value * tol, face=i)
        r.update(verdict=v, verdict_reason=f"ripple peak {value} vs {tol}", value=value * tol)
        faces.append(r)
    pol = FileSettings(tolerance=tol).to_dict()
    e = {"path": path, "units": "mm", "faces_total": len(verdicts), "skipped": {}, "warnings": [], "notes": [],
         "ignored_faces": [], "policy": pol, "faces": faces, "verdict": "error" if error else None}
    if error:
        e["error"] = error
    else:
        e["verdict"] = file_verdict(e)
    return e


def base():
    return {"tolerance": 1.0, "metric": "peak", "include_signal_error": False, "warn_fraction": 0.8,
            "measured": "warn", "scheme": None}


@given(st.lists(st.tuples(st.lists(st.sampled_from(VERDICTS[:3]), max_size=4), st.booleans()), min_size=1,
                max_size=5))
@settings(max_examples=60, deadline=None)
def test_document_exit_code_and_report_counts(files):
    """Exit code 2 if any error, 1 if any fail, else 0; JUnit and SARIF count the same findings."""
    import xml.etree.ElementTree as ET

    entries = [entry(f"m{i}.step", v, error="m.step: broken" if e else None) for i, (v, e) in enumerate(files)]
    doc = build_document(entries, base(), Policy(source=None))
    all_faces = [f["verdict"] for e in entries for f in e["faces"]]
    errors = sum(1 for e in entries if e["verdict"] == "error")
    assert doc["exit_code"] == (2 if errors else 1 if "fail" in all_faces else 0)
    assert doc["summary"]["verdicts"]["faces"]["fail"] == all_faces.count("fail")
    root = ET.fromstring(to_junit(doc))
    empty = sum(1 for e in entries if e["verdict"] != "error" and not e["faces"])
    assert int(root.get("tests")) == len(all_faces) + errors + empty
    assert int(root.get("failures")) == all_faces.count("fail") and int(root.get("errors")) == errors
    results = json.loads(to_sarif(doc))["runs"][0]["results"]
    levels = [r["level"] for r in results]
    assert levels.count("error") == all_faces.count("fail") + errors
    assert levels.count("warning") == all_faces.count("warn") and levels.count("note") == empty


# ---------------------------------------------------------------- policy
def test_parse_policy_and_settings_resolution(tmp_path):
    pol = parse_policy({"tolerance": 0.1, "metric": "rms", "warn_fraction": 1,
                        "override": [{"glob": "legacy/**", "tolerance": 0.5, "ignore_faces": [3, 1, 3]},
                                     {"glob": "*.obj", "metric": "peak", "measured": "fail"},
                                     {"glob": "legacy/old.step", "tolerance": 2}]}, "policy p", tmp_path)
    s = pol.settings_for(tmp_path / "a" / "x.step")
    assert (s.tolerance, s.metric, s.warn_fraction, s.ignore_faces) == (0.1, "rms", 1.0, ())
    s = pol.settings_for(tmp_path / "legacy" / "deep" / "x.step")
    assert (s.tolerance, s.ignore_faces) == (0.5, (1, 3))
    assert pol.settings_for(tmp_path / "legacy" / "old.step").tolerance == 2.0
    s = pol.settings_for(tmp_path / "cage.obj")
    assert (s.metric, s.measured) == ("peak", "fail")
    assert pol.settings_for(tmp_path / "legacy" / "x.step", {"tolerance": 9.0, "metric": None}).tolerance == 9.0
    with pytest.raises(PolicyError, match="no tolerance"):
        Policy(source=None, root=tmp_path).settings_for(tmp_path / "x.step")


@pytest.mark.parametrize("table, key", [({"tolerance": True}, "tolerance"), ({"tolerance": float("nan")}, "tolerance"),
                                        ({"warn_fraction": 0}, "warn_fraction"), ({"scheme": 3}, "scheme"),
                                        ({"override": {"glob": "x"}}, "override"),
                                        ({"override": [{"glob": ""}]}, "override[1].glob"),
                                        ({"override": [{"glob": "x", "ignore_faces": [True]}]},
                                         "override[1].ignore_faces")])
def test_bad_values_name_the_key(table, key, tmp_path):
    with pytest.raises(PolicyError) as exc:
        parse_policy(table, "policy p.toml", tmp_path)
    assert exc.value.key == key and f"key {key!r}" in str(exc.value) and isinstance(exc.value, CadArtifactError)


def test_find_policy_stops_at_the_first_folder_and_load_policy_reads_pyproject(tmp_path):
    (tmp_path / "cadartifact.toml").write_text("tolerance = 1.0\n")
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "pyproject.toml").write_text("[tool.cadartifact]\ntolerance = 2.0\n")
    (tmp_path / "a" / "b").mkdir()
    assert find_policy(tmp_path / "a" / "b").values["tolerance"] == 2.0
    assert find_policy(tmp_path).values["tolerance"] == 1.0
    assert find_policy(tmp_path / "a").root == (tmp_path / "a").resolve()
    assert load_policy(tmp_path / "a" / "pyproject.toml").values == {"tolerance": 2.0}
    (tmp_path / "pyproject.toml").write_text("[project]\nname = 'x'\n")
    with pytest.raises(PolicyError, match=r"no \[tool.cadartifact\] table"):
        load_policy(tmp_path / "pyproject.toml")
    with pytest.raises(InputError, match="policy file not found"):
        load_policy(tmp_path / "missing.toml")


# ---------------------------------------------------------------- inputs
def test_expand_paths_folders_globs_order_and_duplicates(tmp_path, monkeypatch):
    for rel in ("b/z.STEP", "b/a.stp", "b/notes.txt", "b/.hidden/h.step", "b/sub/m.Obj", "b/sub/p.IGS",
                "c/k.brep", "c/l.brp", "c/x.iges", "top.step"):
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text("x")
    monkeypatch.chdir(tmp_path)
    got = [p.as_posix() for p in expand_paths(["top.step", "b", "c/*.br*", "b/a.stp", "**/x.iges"])]
    assert got == ["top.step", "b/a.stp", "b/z.STEP", "b/sub/m.Obj", "b/sub/p.IGS", "c/k.brep", "c/l.brp",
                   "c/x.iges"]
    assert [p.as_posix() for p in expand_paths(["b/notes.txt"])] == ["b/notes.txt"]  # explicit file: kept
    for bad, needle in (("nope.step", "no such file"), ("*.obj", "matches no"), ("b/.hidden/*.txt", "matches no")):
        with pytest.raises(PolicyError, match=needle):
            expand_paths([bad])
    with pytest.raises(PolicyError, match="at least one"):
        expand_paths([])


# ---------------------------------------------------------------- files
def test_write_atomic_replaces_whole_and_leaves_nothing_on_failure(tmp_path, monkeypatch):
    target = tmp_path / "r.json"
    write_atomic(target, "one")
    write_atomic(target, "two")
    assert target.read_text() == "two" and os.listdir(tmp_path) == ["r.json"]
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask  # an ordinary file, not mkstemp's private one
    with pytest.raises(InputError, match="folder does not exist"):
        write_atomic(tmp_path / "missing" / "r.json", "x")

    def boom(*a):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(InputError, match="No space left"):
        write_atomic(target, "three")
    assert target.read_text() == "two" and os.listdir(tmp_path) == ["r.json"]


def test_pre_commit_hook_definition():
    text = (REPO / ".pre-commit-hooks.yaml").read_text()
    fields = dict(re.findall(r"^\s*-?\s*(\w+):\s*(.+?)\s*$", text, re.M))
    assert fields["id"] == "cadartifact-gate" and fields["entry"] == "cadartifact gate"
    assert fields["language"] == "python" and fields["pass_filenames"] == "true"
    files = re.compile(fields["files"])
    for name in ("a/b.step", "B.STEP", "x.stp", "m.Obj", "p.igs", "q.IGES", "r.brep", "s.BRP"):
        assert files.search(name), name
    for name in ("a.step.txt", "readme.md", "stp", "x.objx"):
        assert not files.search(name), name


def crash_on_bad(task):
    """A stand-in worker: dies like a native crash for paths containing 'bad', else a pass entry."""
    path = task[0]
    if "bad" in path:
        os._exit(139)
    return {"path": path, "verdict": "pass", "faces": []}


def test_a_crashing_worker_blames_only_its_file():
    from cadartifact.gate.run import _run_isolated

    tasks = [(p, FileSettings(tolerance=1.0), False) for p in ("a.step", "bad.step", "c.step", "d.step")]
    seen = []
    out = _run_isolated(tasks, 2, seen.append, worker=crash_on_bad)
    assert [e["verdict"] for e in out] == ["pass", "error", "pass", "pass"]
    assert "crashed" in out[1]["error"] and "bad.step" in out[1]["error"]
    assert sorted(e["path"] for e in seen) == sorted(t[0] for t in tasks)


def test_document_top_level_tolerance_falls_back_to_the_first_file():
    b = base()
    b["tolerance"] = None  # tolerance only in [[override]] tables
    doc = build_document([entry("a.step", ["pass"], tol=0.3)], b, Policy(source="policy p.toml"))
    assert doc["tolerance"] == 0.3 and doc["policy"] == "p.toml"


def test_programs_from_stdin_are_served_in_process(monkeypatch):
    """Spawned workers re-import __main__ by path; '<stdin>' cannot be, so the pool is not used."""
    import sys
    import types

    from cadartifact.execution.executors import workers_can_start as _workers_can_start

    assert _workers_can_start()
    fake = types.ModuleType("__main__")
    fake.__file__ = "<stdin>"
    monkeypatch.setitem(sys.modules, "__main__", fake)
    assert not _workers_can_start()
    del fake.__file__  # interactive interpreter: nothing to re-import
    assert _workers_can_start()
