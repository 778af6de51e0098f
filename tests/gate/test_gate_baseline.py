"""``gate --baseline``: adopting the gate on a vault with findings. Only new findings and faces whose reading got
worse beyond its uncertainty fail; fixed ones are listed; ``--update-baseline`` writes the baseline.

The vault is the ridge models of known ripple (tests/conftest.py ``models``); the readings a baseline compares
are checked against :func:`cadartifact.budget` on the loaded faces (the second road).
"""

import json
import shutil

import pytest
from typer.testing import CliRunner

import cadartifact as ca
from cadartifact.cli.app import app
from cadartifact.gate.baseline import BASELINE_SCHEMA, compare
from cadartifact.testing.gate_models import named, ridge_points
from cadartifact.testing.outcomes import no_traceback

pytest.importorskip("OCP")


def gate(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args), "--jobs", "1"])
    no_traceback(result)
    return result


def ripple(path) -> float:
    return max(ca.budget(net).stats["total"].peak for net in ca.load(path))


@pytest.fixture
def vault(models, tmp_path, monkeypatch):
    """pair.step (dome passes, ridge fails) and sub/ridge.step (fails) at tolerance ripple / 1.5, baselined."""
    (tmp_path / "sub").mkdir()
    shutil.copy(models["root"] / "pair.step", tmp_path / "pair.step")
    shutil.copy(models["root"] / "ridge.step", tmp_path / "sub" / "ridge.step")
    (tmp_path / "cadartifact.toml").write_text(f"tolerance = {models['value'] / 1.5!r}\n")
    monkeypatch.chdir(tmp_path)
    result = gate(".", "--baseline", "baseline.json", "--update-baseline")
    assert result.exit_code == 0, result.output  # two faces fail: accepted into the baseline
    return tmp_path


def test_update_baseline_writes_the_findings(vault):
    base = json.loads((vault / "baseline.json").read_text())
    assert base["schema"] == BASELINE_SCHEMA
    assert [(f["path"], f["rule"], f["criterion"], f["level"]) for f in base["findings"]] == [
        ("pair.step", "CA001", "ripple", "error"), ("sub/ridge.step", "CA001", "ripple", "error")]
    assert all(f["record"].startswith("#") for f in base["findings"])
    assert [f["value"] for f in base["findings"]] == pytest.approx([ripple(vault / "sub" / "ridge.step")] * 2,
                                                                   rel=1e-7)
    assert str(vault) not in (vault / "baseline.json").read_text()  # no machine's path


def test_without_changes_the_known_failures_pass(vault):
    result = gate(".", "--baseline", "baseline.json", "--format", "json")
    doc = json.loads(result.stdout)
    assert result.exit_code == 0 and doc["exit_code"] == 0
    assert doc["verdict"] == "fail"  # the faces still fail; the baseline knows them
    assert doc["baseline"] == {"source": "baseline.json", "new": [], "worse": [], "known": 2, "fixed": [],
                               "exit_code": 0}
    text = gate(".", "--baseline", "baseline.json", "--narrow")
    assert "baseline baseline.json: 0 new, 0 worse, 2 known, 0 fixed (exit 0)" in " ".join(text.stdout.split())


def test_a_new_failing_face_fails_and_the_known_do_not(vault, models):
    shutil.copy(models["root"] / "ridge.step", vault / "sub" / "new.step")
    result = gate(".", "--baseline", "baseline.json", "--format", "json")
    doc = json.loads(result.stdout)
    assert result.exit_code == 1
    assert [(f["path"], f["criterion"]) for f in doc["baseline"]["new"]] == [("sub/new.step", "ripple")]
    assert doc["baseline"]["known"] == 2 and not doc["baseline"]["worse"]
    import jsonschema

    from cadartifact.testing.paths import ROOT

    jsonschema.validate(doc, json.loads((ROOT / "docs" / "schemas" / "gate.schema.json").read_text()))


def test_a_face_worse_beyond_its_uncertainty_fails(vault):
    before = ripple(vault / "sub" / "ridge.step")
    from cadartifact.exchange.load import write_step

    write_step([named(ridge_points(amp=3.0), "ridge")], vault / "sub" / "ridge.step")  # the same record, more ripple
    after = ripple(vault / "sub" / "ridge.step")
    assert after > 1.2 * before
    result = gate(".", "--baseline", "baseline.json", "--format", "json")
    doc = json.loads(result.stdout)
    assert result.exit_code == 1
    (worse,) = doc["baseline"]["worse"]
    assert worse["path"] == "sub/ridge.step" and worse["value"] == pytest.approx(after, rel=1e-7)
    assert worse["previous"] == pytest.approx(before, rel=1e-7)
    assert worse["value"] - worse["previous"] > (worse["uncertainty"] or 0)
    assert not doc["baseline"]["new"] and doc["baseline"]["known"] == 1


def test_a_fixed_face_is_reported_as_fixed(vault, models):
    shutil.copy(models["root"] / "clean.step", vault / "sub" / "ridge.step")  # the ridge repaired
    result = gate(".", "--baseline", "baseline.json", "--narrow")
    assert result.exit_code == 0
    out = " ".join(result.stdout.split())  # lines wrap at spaces to the console's width
    assert "baseline fixed fail: sub/ridge.step #" in out and " ripple (value " in out
    assert "0 new, 0 worse, 1 known, 1 fixed (exit 0)" in out


def test_a_gate_json_report_serves_as_baseline(vault, models):
    doc = json.loads(gate(".", "--format", "json").stdout)
    (vault / "previous.json").write_text(json.dumps(doc))
    shutil.copy(models["root"] / "ridge.step", vault / "new.step")
    result = gate(".", "--baseline", "previous.json", "--format", "sarif")
    assert result.exit_code == 1
    states = {r["properties"]["path"]: r["baselineState"] for r in json.loads(result.stdout)["runs"][0]["results"]}
    assert states == {"pair.step": "unchanged", "sub/ridge.step": "unchanged", "new.step": "new"}


def test_an_unreadable_file_fails_closed_with_a_baseline(vault, models):
    shutil.copy(models["root"] / "broken.step", vault / "broken.step")
    assert gate(".", "--baseline", "baseline.json").exit_code == 2
    assert gate(".", "--baseline", "baseline.json", "--update-baseline").exit_code == 2
    base = json.loads((vault / "baseline.json").read_text())
    assert "CA003" in {f["rule"] for f in base["findings"]}  # written all the same
    assert gate(".", "--baseline", "baseline.json").exit_code == 2


@pytest.mark.parametrize("args, needle", [
    (("--baseline", "missing.json"), "missing.json: no such baseline"),
    (("--update-baseline",), "--update-baseline"),
    (("--baseline", "cadartifact.toml"), "cadartifact.toml: not a JSON baseline"),
])
def test_baseline_usage_errors(vault, args, needle):
    result = gate(".", *args)
    assert result.exit_code == 2 and needle in result.output
    assert len([ln for ln in result.output.splitlines() if ln.strip()]) <= 3


@pytest.mark.parametrize("sense", ["above", "below"])
@pytest.mark.parametrize("u", [0.0, 0.01, 0.1])
@pytest.mark.parametrize("step", [0.5, 0.99, 1.01, 2.0])
def test_worse_means_beyond_the_uncertainty(sense, u, step):
    """A reading moving by ``step * U`` the bad way is worse when step > 1 (U = 0: any move of ``step * 1e-3``
    beyond rounding); the good way never; the larger of the two runs' U counts."""
    delta = step * u if u else step * 1e-3
    sign = 1 if sense == "above" else -1
    old = {"fingerprint": "f", "rule": "CA001", "level": "error", "path": "a", "record": "#1", "criterion": "r",
           "value": 1.0, "uncertainty": u / 2, "sense": sense}
    for direction, expect_worse in ((1, step > 1 or u == 0), (-1, False)):
        now = dict(old, value=1.0 + sign * direction * delta, uncertainty=u)
        rec = compare([now], [old], "b.json", errors=0)
        assert (len(rec["worse"]) == 1) == expect_worse, (direction, rec)
        assert rec["exit_code"] == (1 if expect_worse else 0) and rec["known"] == (0 if expect_worse else 1)
