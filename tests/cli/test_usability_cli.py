"""A first day with the command line (issue 12): help, version, options, samples, warnings, wording."""

import filecmp
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

import cadartifact
from cadartifact import errors
from cadartifact.cli.advise_cmds import demo_hint
from cadartifact.cli.app import app
from cadartifact.testing.paths import ROOT

SAMPLES = ROOT / "samples"
ONE_FACE = SAMPLES / "clean_panel.step"


def invoke(args, **extra):
    return CliRunner().invoke(app, [str(a) for a in args], **extra)


# ---------------------------------------------------------------- help and version
@pytest.mark.parametrize("args", [[], ["-h"], ["--help"]])
def test_a_bare_call_and_dash_h_print_the_help(args):
    result = invoke(args)
    assert result.exit_code == 0, result.stderr
    assert "Usage: cadartifact" in result.stdout and "advise" in result.stdout and "demo" in result.stdout
    commands = result.stdout[result.stdout.index("Commands:"):]
    assert "..." not in commands  # command summaries are not cut


@pytest.mark.parametrize("flag", ["--version", "-V"])
def test_version(flag):
    result = invoke([flag])
    assert result.exit_code == 0
    assert result.stdout.strip() == f"cadartifact {cadartifact.__version__}"


def test_inspect_help_shows_the_json_schema_as_written():
    out = invoke(["inspect", "-h"], terminal_width=80).stdout
    for text in ('"warnings": [str]', '"degrees": [int, int]|null', '"size": [nu, nv]',
                 '"periodic": [bool, bool]', '"extraordinary": [vertex ids, 0-based]'):
        assert text in out, text


def test_help_paragraphs_are_reflowed_and_options_not_cut_at_80_columns():
    out = invoke(["inspect", "-h"], terminal_width=80).stdout
    para = out[out.index("Columns:"):out.index("JSON schema")].strip().splitlines()
    assert len(para) >= 3
    assert all(len(line) <= 80 for line in para)
    assert all(len(line.strip()) > 55 for line in para[:-1]), para  # filled, not ragged
    adv = invoke(["advise", "-h"], terminal_width=80).stdout
    assert "--include-signal-error" in adv and "…" not in adv
    assert "[tool.cadartifact]" in invoke(["gate", "-h"], terminal_width=80).stdout


# ---------------------------------------------------------------- options
pytest.importorskip("OCP")


def test_advise_and_gate_have_the_convert_option_their_hint_names(tmp_path):
    result = invoke(["advise", ONE_FACE, "--tol", "10", "--convert", "--no-verify", "--no-compare", "--json"])
    assert result.exit_code == 0, result.stderr
    result = invoke(["gate", ONE_FACE, "--tol", "10", "--convert", "-j", "1", "-f", "json"])
    assert result.exit_code == 0, result.stderr
    assert '"convert": true' in result.stdout


def test_advise_accepts_a_folder(tmp_path):
    folder = tmp_path / "models"
    (folder / "sub").mkdir(parents=True)
    shutil.copy(ONE_FACE, folder / "sub" / "a.step")
    (folder / "notes.txt").write_text("not a model")
    result = invoke(["advise", folder, "--tol", "10", "--no-verify", "--no-compare", "--json"])
    assert result.exit_code == 0, result.stderr
    assert "a.step" in result.stdout and "notes.txt" not in result.stdout
    empty = tmp_path / "empty"
    empty.mkdir()
    result = invoke(["advise", empty, "--tol", "10"])
    assert result.exit_code == 2
    assert "folder holds no STEP/IGES/BREP/OBJ file" in result.stderr and "(none)" not in result.stderr


# ---------------------------------------------------------------- demo and its samples
def test_bundled_samples_are_package_data_identical_to_samples():
    bundled = ROOT / "cadartifact" / "samples"
    names = sorted(p.name for p in SAMPLES.iterdir() if p.suffix in (".step", ".obj"))
    assert sorted(p.name for p in bundled.iterdir()) == names
    assert all(filecmp.cmp(SAMPLES / n, bundled / n, shallow=False) for n in names)
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    globs = data["tool"]["setuptools"]["package-data"]["cadartifact"]
    assert {p.name for g in globs for p in (ROOT / "cadartifact").glob(g)} == set(names)


def test_demo_finds_the_samples_in_an_installed_copy_not_in_the_users_folder(tmp_path):
    site = tmp_path / "site"
    shutil.copytree(ROOT / "cadartifact", site / "cadartifact",
                    ignore=shutil.ignore_patterns("__pycache__"))  # as a wheel installs it: no samples/ beside
    work = tmp_path / "work"
    (work / "samples").mkdir(parents=True)
    (work / "samples" / "mine.step").write_text("not the bundled samples")
    code = "import cadartifact.cli.advise_cmds as c; print(c._samples_dir())"
    env = {**os.environ, "PYTHONPATH": str(site)}
    out = subprocess.run([sys.executable, "-c", code], cwd=work, env=env, capture_output=True, text=True, check=True)
    assert Path(out.stdout.strip()) == site / "cadartifact" / "samples"


def test_demo_hint_echoes_the_tolerance_and_the_verification_road():
    def doc(method):
        face = {"advice": {"verification": {"method": method}}}
        return {"files": [{"path": "x", "faces": [face]}]}

    assert "--tol 0.2 " in demo_hint(doc("occt"), 0.2)
    assert "OCCT" in demo_hint(doc("occt"), 0.05)
    obj = demo_hint(doc("subdivision"), 0.05)
    assert "OCCT" not in obj and "subdivision" in obj


# ---------------------------------------------------------------- warnings and errors
def test_no_raw_python_warning_on_stderr(tmp_path):
    n = 4
    lines = [f"v {i * 1e300} {j * 1e300} 0" for i in range(n) for j in range(n)]
    lines += [f"f {i * n + j + 1} {i * n + j + 1 + n} {i * n + j + 2 + n} {i * n + j + 2}"
              for i in range(n - 1) for j in range(n - 1)]
    huge = tmp_path / "huge.obj"
    huge.write_text("\n".join(lines) + "\n")
    res = subprocess.run([sys.executable, "-m", "cadartifact.cli", "advise", str(huge), "--tol", "0.1"],
                         capture_output=True, text=True, cwd=tmp_path)
    assert res.returncode == 2
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("cadartifact: error: "), res.stderr
    assert "Warning" not in res.stderr and ".py:" not in res.stderr


def test_the_error_hierarchy_is_exported_and_documented():
    page = (ROOT / "docs" / "errors.md").read_text()
    assert "docs/errors.md" in (ROOT / "README.md").read_text()
    for name in [n for n in errors.__all__ if n[0].isupper()]:
        assert getattr(cadartifact, name) is getattr(errors, name), name
        assert name in cadartifact.__all__
        assert f"`{name}`" in page, name
    assert issubclass(cadartifact.ArtifactToleranceError, cadartifact.CadArtifactError)


# ---------------------------------------------------------------- wording
def test_counts_are_worded_for_one_and_many(tmp_path):
    out = invoke(["inspect", ONE_FACE]).stdout
    assert "1 face," in out and "1 faces" not in out
    assert "kept area" in out and "trimmed" not in out
    cage = invoke(["inspect", SAMPLES / "cage.obj"]).stdout
    assert "1 extraordinary vertex," in cage
    from cadartifact.runs.records import kind_count, plural

    assert [kind_count("irregular quad", 3), kind_count("triangle", 1), kind_count("n-gon", 4)] == \
        ["3 irregular quads", "1 triangle", "4 n-gons"]
    assert plural(1, "face") == "1 face" and plural(0, "file") == "0 files"
