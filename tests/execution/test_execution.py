"""The execution wing (cadartifact/execution): its settings, executors and child, and the environment read at the
command line's edge only (cadartifact/cli/environment.py, docs/environment.md)."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from cadartifact.errors import OptionError
from cadartifact.execution.settings import ClusterOptions, ExecutionSettings

from cadartifact.testing.paths import ROOT  # noqa: E402

PACKAGE = ROOT / "cadartifact"
SAMPLES = PACKAGE / "samples"


# ---------------------------------------------------------------- settings
def test_execution_settings_are_validated_once_and_name_the_parameter():
    s = ExecutionSettings()
    assert (s.read_timeout, s.isolation, s.share_faces, s.reuse_faces, s.workers, s.backend) == \
        (120.0, True, True, True, 1, "serial")
    assert s.replace(workers=3).backend == "process"
    assert s.replace(cluster=ClusterOptions("local")).backend == "dask"
    for bad, parameter in (({"read_timeout": -1}, "read_timeout"), ({"read_timeout": float("inf")}, "read_timeout"),
                           ({"workers": 0}, "workers"), ({"cluster": "local"}, "cluster")):
        with pytest.raises(OptionError, match=parameter):
            ExecutionSettings(**bad)


# ---------------------------------------------------------------- the environment, at the edge only
def test_the_environment_table_is_the_documented_one():
    from cadartifact.cli.environment import ENVIRONMENT

    documented = re.findall(r"^\| `(CADARTIFACT_\w+)` \|", (ROOT / "docs" / "environment.md").read_text(), re.M)
    assert documented == [v.name for v in ENVIRONMENT]


def test_no_module_below_the_command_line_reads_the_environment_for_a_setting():
    reads = re.compile(r"environ(?:\.get)?\s*[(\[]\s*[\"']CADARTIFACT_|getenv\(\s*[\"']CADARTIFACT_")
    found = [str(p.relative_to(ROOT)) for p in PACKAGE.rglob("*.py")
             if reads.search(p.read_text()) and p != PACKAGE / "cli" / "environment.py"]
    assert found == []


def test_environment_values_and_options():
    from cadartifact.cli.environment import cluster_options, execution_settings

    env = {"CADARTIFACT_READ_TIMEOUT": "7.5", "CADARTIFACT_READ_ISOLATION": "Off", "CADARTIFACT_SHARE_FACES": "no",
           "CADARTIFACT_REUSE_FACES": " 1 ", "CADARTIFACT_FACE_BATCHES": "3", "CADARTIFACT_TEST_WORKER_EXIT": "a.step"}
    s = execution_settings(env)
    assert (s.read_timeout, s.isolation, s.share_faces, s.reuse_faces) == (7.5, False, False, True)
    assert execution_settings(env, read_timeout=2.0, workers=4).read_timeout == 2.0  # the option wins
    assert execution_settings({"CADARTIFACT_READ_TIMEOUT": "  "}).read_timeout == 120.0  # blank: the default
    c = cluster_options("local", env, workers=2)
    assert (c.face_batches, c.worker_exit, c.workers) == (3, "a.step", 2)
    from cadartifact.execution.child import configured, read_timeout

    for value in ("soon", "0", "-1", "inf"):  # the error of the read that needs the timeout
        with configured(execution_settings({"CADARTIFACT_READ_TIMEOUT": value})):
            with pytest.raises(OptionError, match="CADARTIFACT_READ_TIMEOUT"):
                read_timeout()


def test_prestart_checks_isolation_without_raising():
    from cadartifact.cli.prestart import isolation_on

    assert isolation_on({}) and isolation_on({"CADARTIFACT_READ_ISOLATION": ""})
    assert not isolation_on({"CADARTIFACT_READ_ISOLATION": "0"})
    assert isolation_on({"CADARTIFACT_READ_TIMEOUT": "soon"})  # another variable's bad value: its read's error


def test_the_child_imports_the_cli_names_are_the_gates():
    """cli.prestart names them as strings (it runs before numpy); they must be what gate.run passes down."""
    from cadartifact.cli.prestart import CHILD_IMPORTS
    from cadartifact.gate.run import _child_imports

    assert CHILD_IMPORTS == _child_imports()


# ---------------------------------------------------------------- executors
def _square(x):
    return x * x


def test_executors_map_in_order():
    from cadartifact.execution.executors import ProcessPool, SerialExecutor

    seen = []
    assert SerialExecutor().map(_square, [3, 1, 2], seen.append) == [9, 1, 4] and seen == [9, 1, 4]
    seen = []
    assert ProcessPool(2, cost=lambda x: x).map(_square, [3, 1, 2], seen.append) == [9, 1, 4]
    assert sorted(seen) == [1, 4, 9]


# ---------------------------------------------------------------- the child
def test_the_child_imports_this_very_package():
    """The child's PYTHONPATH starts with the folder holding the package (not the package folder itself)."""
    import cadartifact
    from cadartifact.execution import child
    from cadartifact.execution.start import PACKAGE_PARENT

    assert Path(PACKAGE_PARENT) / "cadartifact" / "__init__.py" == Path(cadartifact.__file__)
    if child.enabled():  # and the child does import it
        there = child.call("builtins:eval", ("__import__('cadartifact').__file__",), path="<test>", what="test")
        assert Path(there) == Path(cadartifact.__file__)


def test_configured_restores_the_previous_settings():
    from cadartifact.execution import child

    before = child.settings()
    with child.configured(ExecutionSettings(read_timeout=5)):
        assert child.read_timeout() == 5.0 and child.read_timeout(2) == 2.0
        with pytest.raises(OptionError, match="timeout"):
            child.read_timeout(-1)
    assert child.settings() is before


def test_sharing_needs_the_callers_leave():
    from cadartifact.execution import child
    from cadartifact.execution.sharing import share

    calls = []
    real = child.call
    try:
        child.call = lambda *a, **k: calls.append(a) or real(*a, **k)
        out = share([1, 2, 3], [100.0] * 3, lambda x: x + 1, lambda x, first: first * 10, "os:getpid", ())
    finally:
        child.call = real
    assert out == [20, 30, 40] and calls == []


# ---------------------------------------------------------------- the run's settings reach the workers
@pytest.mark.parametrize("jobs", [1, 2])
def test_run_gate_passes_the_read_timeout_down_not_through_the_environment(jobs):
    pytest.importorskip("OCP")
    from cadartifact.gate.policy import FileSettings
    from cadartifact.gate.run import run_gate

    from cadartifact.execution import child

    child.shutdown()  # a child left running by an earlier test in this process may hold an early answer
    files = [SAMPLES / "car_hood_coarse.step", SAMPLES / "hull_freeform.step"]
    before = {k: v for k, v in os.environ.items() if k.startswith("CADARTIFACT_")}
    entries = run_gate(files, [FileSettings(tolerance=1.0)] * 2, execution=ExecutionSettings(read_timeout=0.001,
                                                                                              workers=jobs))
    assert {k: v for k, v in os.environ.items() if k.startswith("CADARTIFACT_")} == before
    assert all(e["verdict"] == "error" and "gave no answer in 0.001 s" in e["error"] for e in entries), entries
