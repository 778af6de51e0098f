"""The three doors to one face pipeline (:mod:`cadartifact.runs.face`) give the same face records.

The CadQuery hook's API (``cadartifact.cq.report`` on the model CadQuery imports), ``advise --json`` and ``gate
--format json`` run on the bundled samples and on a few small real files of ``../shared/realdata``; for every face
the numbers (budget, shares, uncertainty, peak), the decision and the advice must be the same. The doors are asked
the same: every face advised (``gate --advise all``), no scheme comparison and no verification (the hook's and the
gate's defaults: ``advise --no-compare --no-verify``). OBJ cages have no CadQuery model: advise and gate only.
A face that repeats an earlier one moved rigidly takes that face's record, moved, on the command line
(:mod:`cadartifact.runs.face_instances`, a run's work, not a face's): the hook analyses it on its own, so such faces
are compared between advise and gate only.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from typer.testing import CliRunner

pytest.importorskip("OCP")

from cadartifact.cli.app import app  # noqa: E402

from cadartifact.testing.paths import REALDATA, REALDATA_MISSING, ROOT  # noqa: E402

SAMPLES = sorted((ROOT / "cadartifact" / "samples").glob("*.*"))
#: Small real files (a few seconds each); the larger ones are the golden documents' (test_documents_unchanged).
REAL = ["step/MAINBODY_BACK.stp", "obj/blub_control_mesh.obj"]
REAL_SLOW = ["step/nist_ftc_07_asme1_rd.stp"]
TOL = "0.05"
#: What every door must agree on, per face.
SAME = ("face", "net", "degrees", "rational", "units", "scheme", "method", "uniform", "intent", "reason", "notes",
        "budget", "share", "meets_tolerance", "uncertainty", "decision", "outside_trim", "advice")


def _real(name: str) -> Path:
    path = REALDATA / name
    if not path.exists():
        pytest.skip(f"{path} not present ({REALDATA_MISSING})")
    return path


def _cli(*args: str) -> dict:
    result = CliRunner().invoke(app, list(args))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return json.loads(result.stdout)


def _hook(path: Path, intent: str = "surface") -> list[dict]:
    cq = pytest.importorskip("cadquery")
    import cadartifact

    return cadartifact.cq.report(cq.importers.importStep(str(path)), tol=float(TOL), intent=intent)


def _same(a, b, where: str) -> list[str]:
    """Where two records' values differ: exact for strings, flags and counts; numbers to rounding (1e-9 relative:
    the hook's faces are not computed under the one BLAS thread of the command line)."""
    if isinstance(a, bool) or isinstance(b, bool) or a is None or b is None or isinstance(a, str):
        return [] if a == b and type(a) is type(b) else [f"{where}: {a!r} != {b!r}"]
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        # abs 1e-10 (model units, 1e-8 of the smallest tolerance used): an advised net's least-squares fit carries
        # BLAS's summation order into its smallest bands (2e-12 mm seen on a 1e-5 mm diagonal peak)
        return [] if math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-10) else [f"{where}: {a!r} != {b!r}"]
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return [f"{where}: keys {sorted(a.keys() ^ b.keys())}"]
        return [d for k in a for d in _same(a[k], b[k], f"{where}.{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} != {len(b)} items"]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in _same(x, y, f"{where}[{k}]")]
    return [] if a == b else [f"{where}: {a!r} != {b!r}"]


def _doors(path: Path, intent: str = "surface") -> None:
    advise = _cli("advise", str(path), "--tol", TOL, "--json", "--no-compare", "--no-verify", "--intent", intent)
    gate = _cli("gate", str(path), "--tol", TOL, "--format", "json", "--advise", "all", "--jobs", "1",
                "--intent", intent)
    a_faces, g_faces = advise["files"][0]["faces"], gate["files"][0]["faces"]
    assert gate["files"][0]["verdict"] != "error", gate["files"][0].get("error")
    doors = {"gate": g_faces}
    if path.suffix.lower() != ".obj":
        doors["hook"] = _hook(path, intent)
    problems, own = [], 0
    for door, faces in doors.items():
        assert len(faces) == len(a_faces), door
        for a, b in zip(a_faces, faces):
            if door == "hook" and any("its analysis is reused" in n for n in a["notes"]):
                continue  # a face repeating another, moved rigidly: the command line reuses that face's record
            own += door == "hook"
            keys = SAME + (("peak_at", "entity", "entity_line", "name", "kind", "canonical", "exact")
                           if door == "gate" else ())
            problems += _same({k: a[k] for k in keys}, {k: b[k] for k in keys}, f"{door} face {a['face']}")
    assert not problems, "\n".join(problems[:20])
    assert own or "hook" not in doors, "no face of the file was compared with the hook's"
    # the gate's verdicts follow the decisions all three share (under the net reading the decision is the
    # deviation's and the verdict the ripple's: settings.compared)
    for f in g_faces:
        if f["decision"] == "does not conform" and intent == "surface":
            assert f["ripple_verdict"] == "fail"
        assert f["advice_skipped"] is None and f["advice"] is not None
    assert advise["summary"]["faces"] == gate["summary"]["faces"] == len(a_faces)
    for k in ("within", "exceeding", "undecided", "unreachable"):
        assert advise["summary"][k] == gate["summary"][k], k


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_the_samples_through_the_three_doors(path):
    _doors(path)


@pytest.mark.parametrize("name", ["hull_freeform.step", "cage.obj"])
def test_the_net_reading_through_the_three_doors(name):
    _doors(ROOT / "cadartifact" / "samples" / name, intent="net")


@pytest.mark.realdata
@pytest.mark.parametrize("name", REAL)
def test_real_files_through_the_three_doors(name):
    _doors(_real(name))


@pytest.mark.slow
@pytest.mark.realdata
@pytest.mark.parametrize("name", REAL_SLOW)
def test_larger_real_files_through_the_three_doors(name):
    _doors(_real(name))


def test_the_hook_check_decides_as_the_report():
    """``check`` (budget only, the worst face advised) names the faces the report finds out of tolerance, with the
    report's numbers and the worst face's advice."""
    cq = pytest.importorskip("cadquery")
    import cadartifact
    from cadartifact.errors import ArtifactToleranceError

    model = cq.importers.importStep(str(ROOT / "cadartifact" / "samples" / "wavy_panel_diagonal.step"))
    rows = cadartifact.cq.report(model, tol=float(TOL))
    failing = [r for r in rows if r["decision"] == "does not conform"]
    assert failing, "the sample ripples beyond the tolerance"
    with pytest.raises(ArtifactToleranceError) as info:
        cq.Workplane().add(model).invoke(cadartifact.cq.check(tol=float(TOL)))
    worst = info.value.faces[0]
    assert sorted(r["face"] for r in info.value.faces) == sorted(r["face"] for r in failing)
    row = next(r for r in rows if r["face"] == worst["face"])
    assert not _same({k: worst[k] for k in SAME}, {k: row[k] for k in SAME}, "check")
