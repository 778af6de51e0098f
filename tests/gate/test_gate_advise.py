"""``gate --advise all|failing|none``: the verdict needs today's budget only, the advice is added where asked.

Models are the STEP files of :mod:`cadartifact.testing.gate_models` (a rippled ridge and a clean saddle; the
``models`` fixture of tests/conftest.py). The gate's numbers without advice (today's budget,
``report.budget_record``) are checked against the numbers with advice (``advise`` -> ``face_record``, whose budget
is computed inside ``advise``): two roads to the same record.
"""

import json
import xml.etree.ElementTree as ET

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.gate.run import build_document, gate_file
from cadartifact.gate.policy import ADVISE, FileSettings, Policy, PolicyError, check_cli, parse_policy
from cadartifact.testing.outcomes import no_traceback

pytest.importorskip("OCP")


def gate(path, mode, tol, **kw):
    return gate_file(str(path), FileSettings(tolerance=tol, advise=mode, **kw))


def faces_by_name(entry):
    return {f["name"]: f for f in entry["faces"]}


@pytest.fixture(scope="module")
def pair(models):
    """pair.step (clean + ridge) at a tolerance the ridge fails, under each mode."""
    tol = models["value"] / 1.5
    return {mode: gate(models["root"] / "pair.step", mode, tol) for mode in ADVISE}


def test_failing_advises_only_faces_that_warn_or_fail(pair):
    faces = faces_by_name(pair["failing"])
    assert faces["ridge"]["verdict"] == "fail" and faces["dome"]["verdict"] == "pass"
    assert faces["ridge"]["advice"]["net"] and faces["ridge"]["advice_skipped"] is None
    assert faces["dome"]["advice"] is None
    assert faces["dome"]["advice_skipped"] == "face passes (--advise failing)"


def test_all_and_none(pair):
    for f in pair["all"]["faces"]:
        assert f["advice"]["net"] and f["advice_skipped"] is None
    for f in pair["none"]["faces"]:
        assert f["advice"] is None and f["advice_skipped"] == "not computed (--advise none)"


def test_verdicts_and_budgets_do_not_depend_on_the_mode(pair):
    """Today's budget straight from budget() (none) equals the one advise() computes (all)."""
    keys = ("face", "net", "scheme", "method", "uniform", "budget", "share", "meets_tolerance", "verdict",
            "verdict_reason", "value", "entity", "entity_line", "peak_at")
    for mode in ("failing", "none"):
        for a, b in zip(pair["all"]["faces"], pair[mode]["faces"]):
            assert {k: a[k] for k in keys} == {k: b[k] for k in keys}
        assert pair[mode]["verdict"] == pair["all"]["verdict"] == "fail"
    # the advised face's record is the same whichever mode advised it
    assert faces_by_name(pair["failing"])["ridge"] == faces_by_name(pair["all"])["ridge"]


def test_a_warning_face_is_advised(models):
    entry = gate(models["root"] / "ridge.step", "failing", models["value"] / 0.9)
    (f,) = entry["faces"]
    assert f["verdict"] == "warn" and f["advice"]["net"] and f["advice_skipped"] is None


def test_include_signal_error_and_net_intent_agree_with_all(models):
    path = models["root"] / "pair.step"
    for kw in ({"include_signal_error": True}, {"intent": "net"}):
        a, n = gate(path, "all", 0.01, **kw), gate(path, "none", 0.01, **kw)
        for fa, fn in zip(a["faces"], n["faces"]):
            assert (fa["budget"], fa["meets_tolerance"], fa["verdict"], fa["value"]) == \
                   (fn["budget"], fn["meets_tolerance"], fn["verdict"], fn["value"])


def test_every_report_format_takes_a_face_without_advice(pair, tmp_path):
    from cadartifact.gate.reports import to_json, to_junit, to_text
    from cadartifact.gate.sarif import to_sarif
    from cadartifact.viz.html import write_report

    policy = Policy(source=None)
    base = {"tolerance": pair["none"]["policy"]["tolerance"], "metric": "peak", "include_signal_error": False,
            "warn_fraction": 0.8, "measured": "warn", "scheme": None}
    doc = build_document([pair["none"], pair["failing"]], base, policy)
    assert doc["summary"]["unreachable"] == 0 and doc["exit_code"] == 1
    assert "fail" in to_text(doc)  # the advised column shows "-"
    assert json.loads(to_json(doc))["files"][0]["faces"][0]["advice"] is None
    ET.fromstring(to_junit(doc))
    sarif = json.loads(to_sarif(doc))
    props = [r["properties"] for r in sarif["runs"][0]["results"] if r["ruleId"] == "CA001"]
    assert [p["advised_net"] is None for p in props] == [True, False]
    messages = [r["message"]["text"] for r in sarif["runs"][0]["results"] if r["ruleId"] == "CA001"]
    assert "advice not computed (--advise none)" in messages[0] and "advised net" in messages[1]
    write_report(doc, tmp_path / "r.html", heatmaps=False, maps=False)
    assert "ridge" in (tmp_path / "r.html").read_text()


def test_cli_option_text_report_and_bad_values(models, tmp_path):
    runner = CliRunner()
    pair = models["root"] / "pair.step"
    tol = str(models["value"] / 1.5)
    out = runner.invoke(app, ["gate", str(pair), "--tol", tol, "--jobs", "1", "--advise", "none"])
    assert out.exit_code == 1
    no_traceback(out)
    bad = runner.invoke(app, ["gate", str(pair), "--tol", tol, "--advise", "some"])
    assert bad.exit_code == 2
    no_traceback(bad)
    assert "--advise" in bad.output and "'all', 'failing', 'none'" in bad.output and "'some'" in bad.output
    (tmp_path / "cadartifact.toml").write_text(f'tolerance = {tol}\nadvise = "all"\n')
    doc = json.loads(runner.invoke(app, ["gate", str(pair), "--policy", str(tmp_path / "cadartifact.toml"),
                                         "--format", "json", "--jobs", "1"]).stdout)
    assert all(f["advice"] for f in doc["files"][0]["faces"]) and doc["files"][0]["policy"]["advise"] == "all"


def test_policy_key_is_validated_top_level_and_in_overrides(tmp_path):
    pol = parse_policy({"tolerance": 1.0, "advise": "none", "override": [{"glob": "a/*", "advise": "all"}]},
                       "policy p.toml", tmp_path)
    assert pol.settings_for(tmp_path / "b.step").advise == "none"
    assert pol.settings_for(tmp_path / "a" / "x.step").advise == "all"
    assert pol.settings_for(tmp_path / "a" / "x.step", check_cli({"advise": "failing"})).advise == "failing"
    assert Policy(source=None).settings_for("x.step", {"tolerance": 1.0}).advise == "failing"  # the default
    with pytest.raises(PolicyError, match=r"key 'advise': expected one of 'all', 'failing', 'none', received 'yes'"):
        parse_policy({"advise": "yes"}, "policy p.toml", tmp_path)
    with pytest.raises(PolicyError, match=r"override\[1\]\.advise"):
        parse_policy({"override": [{"glob": "*", "advise": 1}]}, "policy p.toml", tmp_path)


def test_the_cache_key_follows_the_mode(models):
    from cadartifact.gate.cache import cache_key

    keys = {cache_key("0" * 64, FileSettings(tolerance=1.0, advise=m), False) for m in ADVISE}
    assert len(keys) == 3


def test_the_dask_task_gives_the_same_records(models, pair):
    """gate_cluster.gate_task (what a Dask worker runs), by path and by shipped bytes, in this process."""
    from cadartifact.gate.cluster import gate_task
    from cadartifact.gate.run import gate_file

    path = models["root"] / "pair.step"
    settings = FileSettings(tolerance=pair["failing"]["policy"]["tolerance"], advise="failing")
    assert gate_task(gate_file, str(path), None, settings, False) == pair["failing"]
    assert gate_task(gate_file, str(path), path.read_bytes(), settings, False) == pair["failing"]


def test_peak_at_reuses_todays_budget_and_equals_a_fresh_peak_location(models, pair):
    import cadartifact as ca
    from cadartifact.runs.records import peak_location

    nets = {n.origin.name: n for n in ca.load(models["root"] / "pair.step")}
    for mode in ADVISE:
        ridge = faces_by_name(pair[mode])["ridge"]
        assert ridge["peak_at"] == peak_location(nets["ridge"], ridge["scheme"], "total")
        assert faces_by_name(pair[mode])["dome"]["peak_at"] is None  # passes: no location
