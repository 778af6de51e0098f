"""A bad environment variable stops only what needs its setting, as when the variables were read where used.

``CADARTIFACT_READ_TIMEOUT`` is the read's: a command reading no B-rep file, or given ``--read-timeout``, goes on;
``gate`` reports the file it could not read. ``CADARTIFACT_FACE_BATCHES`` is ``gate --scheduler``'s only.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.errors import OptionError

from cadartifact.testing.paths import ROOT  # noqa: E402

SAMPLES = ROOT / "cadartifact" / "samples"
PANEL = SAMPLES / "clean_panel.step"
CAGE = SAMPLES / "cage.obj"


def invoke(env: dict, *args):
    result = CliRunner().invoke(app, [str(a) for a in args], env=env)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result


@pytest.mark.parametrize("env", [{"CADARTIFACT_READ_TIMEOUT": "soon"}, {"CADARTIFACT_READ_TIMEOUT": "-3"},
                                 {"CADARTIFACT_FACE_BATCHES": "two"}])
def test_a_command_that_does_not_need_the_setting_goes_on(env):
    assert invoke(env, "schemes").exit_code == 0
    assert invoke(env, "inspect", CAGE, "--json").exit_code == 0  # an OBJ cage is read here, with no timeout


def test_the_read_timeout_option_wins_over_a_bad_variable():
    r = invoke({"CADARTIFACT_READ_TIMEOUT": "soon"}, "gate", PANEL, "--tol", "1", "-j", "1", "--read-timeout", "60",
               "--format", "json")
    assert r.exit_code == 0 and json.loads(r.stdout)["files"][0]["verdict"] == "pass"


def test_a_bad_read_timeout_is_the_error_of_the_read_that_needs_it():
    env = {"CADARTIFACT_READ_TIMEOUT": "soon"}
    message = "CADARTIFACT_READ_TIMEOUT: expected a positive number of seconds, received 'soon'"
    r = invoke(env, "gate", PANEL, CAGE, "--tol", "1", "-j", "1", "--format", "json")
    files = {Path(f["path"]).name: f for f in json.loads(r.stdout)["files"]}
    assert r.exit_code == 2 and message in files["clean_panel.step"]["error"]  # that file's error entry
    assert files["cage.obj"]["verdict"] == "pass"  # the others are still gated
    r = invoke(env, "inspect", PANEL)
    assert r.exit_code == 2 and message in r.stderr


def test_face_batches_are_read_for_a_cluster_only():
    from cadartifact.cli.environment import cluster_options, execution_settings

    env = {"CADARTIFACT_FACE_BATCHES": "two"}
    assert execution_settings(env).cluster is None
    with pytest.raises(OptionError, match="CADARTIFACT_FACE_BATCHES.*whole number"):
        cluster_options("local", env)
