"""The registries: a file format (:data:`cadartifact.exchange.formats.FORMATS`), a named scheme
(:data:`cadartifact.theory.catalogue.NAMED`) and a gate criterion (:data:`cadartifact.analysis.quality.CRITERIA`)
are each one entry, and everything else reads them.

Each fixture registers a dummy (one entry, through ``monkeypatch``) and the tests follow it to the command line,
the policy and the reports: nothing else is told about it.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cadartifact.analysis import quality
from cadartifact.cli.app import app
from cadartifact.exchange import formats
from cadartifact.exchange.files import LoadResult
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.theory import catalogue

from cadartifact.testing.paths import ROOT as REPO  # noqa: E402


def invoke(*args):
    result = CliRunner().invoke(app, [str(a) for a in args])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result


# ---------------------------------------------------------------- a format
def read_dummy(path) -> LoadResult:
    """The dummy format's reader: one bicubic dome, its height the file's first number."""
    path = Path(path)
    height = float(path.read_text().split()[0])
    i, j = np.meshgrid(np.linspace(0, 1, 8), np.linspace(0, 1, 7), indexing="ij")
    points = np.stack([100 * i, 80 * j, -height * ((i - 0.5) ** 2 + (j - 0.5) ** 2)], -1)
    net = ControlNet.from_points(points, degrees=(3, 3), unit="model",
                                 origin=NetOrigin(file=str(path), face=0, name="dome", kind="bspline"))
    return LoadResult(path=path, nets=[net], faces_total=1)


DUMMY_FORMAT = formats.FileFormat("dummy", (".dmy", ".dummy"), "DMY", read_dummy)


@pytest.fixture
def dummy_format(monkeypatch, tmp_path):
    monkeypatch.setattr(formats, "FORMATS", dict(formats.FORMATS))
    formats.register(DUMMY_FORMAT)
    folder = tmp_path / "models"
    folder.mkdir()
    (folder / "dome.dmy").write_text("20\n")
    (folder / "notes.txt").write_text("not a model\n")
    return folder


def test_the_pre_commit_filter_is_the_registry_s():
    text = (REPO / ".pre-commit-hooks.yaml").read_text()
    fields = dict(re.findall(r"^\s*-?\s*(\w+):\s*(.+?)\s*$", text, re.M))
    assert fields["files"] == formats.hook_pattern()


def test_a_registered_format_reaches_every_table(dummy_format):
    from cadartifact.exchange import SUPPORTED_EXTENSIONS, read
    from cadartifact.exchange.reader_start import BREP_FORMATS
    from cadartifact.gate.policy import CAD_SUFFIXES, expand_paths

    assert SUPPORTED_EXTENSIONS[".dmy"] == SUPPORTED_EXTENSIONS[".dummy"] == "dummy"
    assert ".dmy" in CAD_SUFFIXES and ".dmy" not in BREP_FORMATS  # read here, not by OCCT's child
    assert re.search(formats.hook_pattern(), "a/B.DMY") and formats.labels() == "STEP/IGES/BREP/OBJ/DMY"
    result = read(dummy_format / "dome.dmy")
    assert result.nets[0].origin.name == "dome"
    assert expand_paths([dummy_format]) == [dummy_format / "dome.dmy"]
    with pytest.raises(ValueError, match="suffixes no other format reads"):
        formats.register(formats.FileFormat("other", (".dmy",), "OTHER", read_dummy))


def test_a_registered_format_reaches_the_command_line(dummy_format):
    from cadartifact.cli.prestart import will_read_here

    doc = json.loads(invoke("inspect", dummy_format / "dome.dmy", "--json").stdout)
    assert doc["files"][0]["format"] == "dummy"
    bad = invoke("inspect", dummy_format / "notes.txt")
    assert bad.exit_code == 2 and "supported: .brep, .brp, .dmy, .dummy, .iges" in bad.output
    none = invoke("gate", str(dummy_format / "*.txt"), "--tol", "1")
    assert none.exit_code == 2 and "matches no STEP/IGES/BREP/OBJ/DMY file" in none.output
    gate = invoke("gate", dummy_format, "--tol", "1", "-j", "1", "--advise", "none", "--format", "json")
    doc = json.loads(gate.stdout)
    assert [Path(f["path"]).name for f in doc["files"]] == ["dome.dmy"]
    assert doc["files"][0]["verdict"] == "pass" and doc["files"][0]["units"] == "model"
    assert not will_read_here(["cadartifact", "gate", str(dummy_format / "dome.dmy")])


# ---------------------------------------------------------------- a scheme
@pytest.fixture
def dummy_scheme(monkeypatch):
    from cadartifact.theory import symbols

    monkeypatch.setitem(catalogue.NAMED, "dummy", lambda: catalogue.Scheme("dummy", symbols.box_mask(2, 2, 1, 0),
                                                                           arrows=(2, 2, 1, 0)))
    return "dummy"


def test_a_registered_scheme_reaches_the_catalogue_and_the_policy(dummy_scheme, tmp_path):
    from cadartifact.advice.scheme_comparison import NAMED_SCHEMES
    from cadartifact.gate.policy import PolicyError, check_cli, parse_policy

    assert catalogue.scheme(" Dummy ").name == "dummy"
    assert "dummy" in catalogue.schemes() and "dummy" in catalogue.SCHEME_NAMES and "dummy" in NAMED_SCHEMES
    with pytest.raises(ValueError, match="'kobbelt', 'dummy', 'bspline"):
        catalogue.scheme("nonesuch")
    assert check_cli({"scheme": "dummy"}) == {"scheme": "dummy"}
    assert parse_policy({"tolerance": 1.0, "scheme": "dummy"}, "policy t", tmp_path).values["scheme"] == "dummy"
    with pytest.raises(PolicyError, match="'dummy'"):
        parse_policy({"scheme": "nonesuch"}, "policy t", tmp_path)


def test_a_registered_scheme_reaches_the_command_line_and_the_comparison(dummy_scheme):
    listed = json.loads(invoke("schemes", "--json").stdout)
    assert "dummy" in json.dumps(listed)
    sample = REPO / "samples" / "clean_panel.step"
    doc = json.loads(invoke("advise", sample, "--tol", "0.05", "--compare", "--no-verify", "--json").stdout)
    rows = doc["files"][0]["faces"][0]["advice"]["comparison"]
    assert "dummy" in rows and rows["dummy"]["objective"] == "ripple"


# ---------------------------------------------------------------- a criterion
def _patches(face):
    """The dummy criterion's measure: the face's Bezier patches."""
    nu, nv = face.net.shape
    p, q = face.net.degrees
    return quality.Measured((nu - p) * (nv - q), detail=f"{nu - p} x {nv - q} patches")


DUMMY_CRITERION = quality.CriterionSpec(
    "DUMMY-PA", "Bezier patches of the face", "patches", "above", ("CA199", "pdq-dummy-patches", "Too many patches"),
    quality.Limit(warn=10, fail=100), _patches, needs="knots")


@pytest.fixture
def dummy_criterion(monkeypatch):
    monkeypatch.setitem(quality.CRITERIA, "patches", DUMMY_CRITERION)
    return "patches"


def test_a_registered_criterion_reaches_the_profiles(dummy_criterion, tmp_path):
    from cadartifact.gate.policy import PolicyError
    from cadartifact.gate.profiles import BUILT_IN, load_profile, profile_dict

    net = read_dummy(_dome(tmp_path)).nets[0]
    found = {c.key: c for c in quality.criteria(net)}
    assert list(found) == list(quality.FACE_CRITERIA) and found["patches"].value == 20
    assert found["patches"].verdict == "warn" and found["patches"].to_dict()["code"] == "DUMMY-PA"
    assert BUILT_IN["default"].limit("patches") == quality.Limit(warn=10, fail=100)
    (tmp_path / "p.toml").write_text("[patches]\nwarn = 30\n")
    profile = load_profile(tmp_path / "p.toml")
    assert profile.limit("patches") == quality.Limit(warn=30, fail=100)
    assert profile_dict(profile)["patches"] == {"warn": 30, "fail": 100, "sense": "above"}
    (tmp_path / "q.toml").write_text("[patches]\nwarm = 30\n")
    with pytest.raises(PolicyError, match=r"patches.warm.*valid: warn, fail\)"):
        load_profile(tmp_path / "q.toml")


def _dome(folder: Path) -> Path:
    path = folder / "dome.dmy"
    path.write_text("20\n")
    return path


def test_a_registered_criterion_reaches_the_reports(dummy_format, dummy_criterion):
    from cadartifact.gate.reports import CRITERION_RULES, RULES

    assert CRITERION_RULES["patches"] == "CA199" and ("CA199", "pdq-dummy-patches", "warning",
                                                      "Too many patches") in RULES
    path = dummy_format / "dome.dmy"
    common = ("gate", path, "--tol", "1", "-j", "1", "--advise", "none", "--profile", "default")
    text = invoke(*common, "--format", "text").stdout
    assert "pdq warn:" in text and "DUMMY-PA: patches 20 patches (warn: warn > 10, fail > 100)" in text
    assert "patches warn > 10, fail > 100" in " ".join(text.split())  # the profile's line (it may wrap)
    doc = json.loads(invoke(*common, "--format", "json").stdout)
    face = doc["files"][0]["faces"][0]
    crit = {c["criterion"]: c for c in face["criteria"]}
    assert crit["patches"]["value"] == 20 and crit["patches"]["verdict"] == "warn" and face["verdict"] == "warn"
    assert doc["profile"]["patches"] == {"warn": 10, "fail": 100, "sense": "above"}
    assert doc["summary"]["criteria"]["patches"]["warn"] == 1
    sarif = json.loads(invoke(*common, "--format", "sarif").stdout)
    rules = {r["id"]: r for r in sarif["runs"][0]["tool"]["driver"]["rules"]}
    assert rules["CA199"]["name"] == "pdq-dummy-patches"
    assert any(r["ruleId"] == "CA199" for r in sarif["runs"][0]["results"])
    junit = invoke(*common, "--format", "junit").stdout
    assert 'name="pdq.patches"' in junit
