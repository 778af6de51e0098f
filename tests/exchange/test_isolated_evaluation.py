"""OCCT's evaluation runs in the reader child (issue 27 item 2): a crash or a hang while verifying advice or
locating a peak costs that face an error entry naming the file and the face, never the run.

The same fault injection as the reader's (tests/exchange/test_reader_guards.py: a child that aborts, a child that
sleeps past the timeout), here in the evaluator the child runs (``exchange.load.EVALUATE``, replaced by the
functions of ``cadartifact/testing/eval_faults.py``, which fail on the hood's face only)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("OCP")

from cadartifact.cli.app import app  # noqa: E402
import importlib  # noqa: E402

from cadartifact.execution import child as isolation  # noqa: E402
from cadartifact.execution.child import ChildFailed  # noqa: E402
from cadartifact.testing.outcomes import no_traceback  # noqa: E402
from cadartifact.testing.paths import SAMPLES  # noqa: E402

HOOD = SAMPLES / "car_hood_coarse.step"
PANEL = SAMPLES / "wavy_panel_diagonal.step"
load = importlib.import_module("cadartifact.exchange.load")  # the module (the package exports a function of its name)


@pytest.fixture
def fault(monkeypatch):
    """``fault("crash" | "hang")``: the reader child's evaluator replaced by a faulty one."""
    isolation.shutdown()  # a fresh child for the faulty evaluator
    monkeypatch.setenv("CADARTIFACT_SHARE_FACES", "0")

    def use(name: str, timeout: float | None = None):
        monkeypatch.setattr(load, "EVALUATE", f"cadartifact.testing.eval_faults:{name}")
        if timeout is not None:
            monkeypatch.setenv("CADARTIFACT_READ_TIMEOUT", str(timeout))  # the CLI's (read at its edge)
            # the library calls': the reader child's settings, as a run configures them
            monkeypatch.setattr(isolation, "_settings", isolation.settings().replace(read_timeout=float(timeout)))

    yield use
    isolation.shutdown()


def _grid(net):
    (ku, kv), (p, q) = net.knots, net.degrees
    return np.linspace(ku[p], ku[-p - 1], 5), np.linspace(kv[q], kv[-q - 1], 4)


def test_a_crash_of_the_evaluation_is_an_error_naming_face_and_file_and_the_next_evaluation_works(fault):
    fault("crash")
    hood, panel = load.load(HOOD)[0], load.load(PANEL)[0]
    with pytest.raises(ChildFailed, match=r"car_hood_coarse\.step: OCCT's evaluation of face 0 crashed \(SIGABRT\)"):
        load.evaluate_grid(hood, *_grid(hood))
    got = load.evaluate_grid(panel, *_grid(panel))  # a new child evaluates the next face
    from cadartifact.exchange.occ import evaluate_grid

    assert np.array_equal(got, evaluate_grid(panel, *_grid(panel)))


def test_a_hang_of_the_evaluation_is_stopped_after_the_timeout(fault):
    hood = load.load(HOOD)[0]
    fault("hang", timeout=2)
    with pytest.raises(ChildFailed, match=r"car_hood_coarse\.step: OCCT's evaluation of face 0 gave no answer in 2 s"):
        load.evaluate_grid(hood, *_grid(hood))


@pytest.mark.parametrize("kind, needle", [("crash", "crashed (SIGABRT)"), ("hang", "gave no answer in 3 s")])
def test_the_gate_locating_a_peak_gives_the_face_an_error_entry_and_gates_the_next_file(fault, kind, needle):
    fault(kind, timeout=3 if kind == "hang" else None)
    # tolerance 0.05: both faces fail, so both peaks are located (OCCT evaluates a point of each)
    r = CliRunner().invoke(app, ["gate", str(HOOD), str(PANEL), "--tol", "0.05", "--format", "json", "--jobs", "1"])
    no_traceback(r)
    doc = json.loads(r.stdout)
    assert r.exit_code == 2
    hood, panel = doc["files"]
    assert hood["verdict"] == "error" and hood["faces"] == []
    assert hood["error"] == f"{HOOD}: OCCT's evaluation of face 0 {needle}" + ("" if kind == "crash" else " and was stopped")
    assert panel["verdict"] == "fail" and panel["faces"][0]["peak_at"]["xyz"]  # located: the run went on


@pytest.mark.parametrize("kind, needle", [("crash", "crashed (SIGABRT)"), ("hang", "gave no answer in 3 s")])
def test_advise_verifying_on_occt_fails_in_one_line_naming_the_face(fault, kind, needle):
    fault(kind, timeout=3 if kind == "hang" else None)
    r = CliRunner().invoke(app, ["advise", str(HOOD), "--tol", "0.05", "--json"])
    assert r.exit_code == 2 and r.stdout == "", r.output
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"{HOOD}: OCCT's evaluation of face 0 {needle}" in lines[0], r.stderr
    # the same command with the real evaluator: advice verified on OCCT's surface
    isolation.shutdown()
    load.EVALUATE = "cadartifact.exchange.occ:evaluate_grid"
    r = CliRunner().invoke(app, ["advise", str(HOOD), "--tol", "0.05", "--json"])
    assert r.exit_code == 1, r.output  # the face exceeds the tolerance: advised, and verified on OCCT's surface
    assert json.loads(r.stdout)["files"][0]["faces"][0]["advice"]["verification"]["method"] == "occt"


def test_evaluation_runs_in_the_child_even_when_this_process_has_ocp(fault):
    import OCP  # noqa: F401  (imported here: the evaluation still goes to the child)

    fault("crash")
    with pytest.raises(ChildFailed):
        load.evaluate_grid(load.load(HOOD)[0], np.array([0.5]), np.array([0.5]))


def test_the_child_knows_it_is_the_child_under_the_module_name_requests_import():
    """The child runs ``python -m cadartifact.execution.child`` (the module is ``__main__`` there); the
    requests import ``cadartifact.execution.child`` again, and that copy must say it serves, or an
    evaluation inside the child (the verification of its share of faces) starts a child of the child: a
    second OCP import per file, 0.8-1.2 s of a 40-face file's advise (found by the issue 24 benchmarks)."""
    if not isolation.enabled():
        pytest.skip("isolation is off in this environment")
    assert not isolation.serving()  # this process is not the child
    assert isolation.call("cadartifact.execution.child:serving", (), path="<test>", what="test") is True
