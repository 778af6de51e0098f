"""``gate --jobs 1`` shares a file's faces with the idle reader child (cadartifact.runs.face_sharing).

The shared run must give the serial run's document byte for byte (records, peak locations, the first
error), must really hand faces to the child, and must survive a child that fails on the way.
"""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.errors import FileFormatError
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.testing.outcomes import no_traceback

pytest.importorskip("OCP")


def _net(nu, nv, amp, name, phase=0.0):
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    x, y = 100.0 * i / (nu - 1), 60.0 * j / (nv - 1)
    z = amp * np.sin(2 * np.pi * x / 37.0 + phase) * np.cos(2 * np.pi * y / 23.0) + 0.02 * x
    return ControlNet.from_points(np.stack([x, y, z], -1), degrees=(3, 3), origin=NetOrigin(name=name, kind="bspline"))


@pytest.fixture(scope="module")
def many(tmp_path_factory):
    """A STEP file of eight faces of several sizes, some rippled enough to fail at 0.01."""
    from cadartifact.exchange.load import write_step

    root = tmp_path_factory.mktemp("split")
    nets = [_net(nu, nv, amp, f"f{k}", phase=k) for k, (nu, nv, amp) in
            enumerate([(20, 16, 2.0), (9, 7, 0.0), (16, 16, 1.0), (7, 6, 0.5), (18, 12, 0.0), (12, 12, 3.0),
                       (8, 8, 0.2), (14, 10, 0.0)])]
    write_step(nets, root / "many.step")
    return root / "many.step"


def _gate(path, *extra, env=None, monkeypatch=None):
    if env is not None:
        for k, v in env.items():
            monkeypatch.setenv(k, v)
    result = CliRunner().invoke(app, ["gate", str(path), "--format", "json", "--jobs", "1", *map(str, extra)])
    no_traceback(result)
    if env is not None:
        for k in env:
            monkeypatch.delenv(k)
    return result


@pytest.fixture
def spy(monkeypatch):
    """The shares sent to the child: function name (``child_gate``, ``child_advise``) -> face counts."""
    from collections import defaultdict

    from cadartifact.execution import child as isolation

    calls = defaultdict(list)
    real = isolation.call

    def call(function, *args, **kwargs):
        name = function.rpartition(":")[2]
        if name.startswith("child_"):
            calls[name].append(len(args[0][0]))
        return real(function, *args, **kwargs)

    monkeypatch.setattr(isolation, "call", call)
    return calls


@pytest.mark.parametrize("tol", ["0.01", "10"])
def test_shared_faces_give_the_serial_document(many, spy, monkeypatch, tol):
    serial = _gate(many, "--tol", tol, env={"CADARTIFACT_SHARE_FACES": "0"}, monkeypatch=monkeypatch)
    assert not spy
    shared = _gate(many, "--tol", tol)
    assert spy["child_gate"] and 0 < spy["child_gate"][0] < 8, spy  # the child took part of the faces, not all
    assert shared.exit_code == serial.exit_code
    assert shared.stdout == serial.stdout
    doc = json.loads(shared.stdout)
    if tol == "0.01":  # failing faces got their advice and their peak location on both sides
        failing = [f for f in doc["files"][0]["faces"] if f["verdict"] == "fail"]
        assert len(failing) >= 3 and all(f["peak_at"] and f["advice"] for f in failing)


def test_a_child_that_fails_its_share_costs_only_time(many, monkeypatch):
    from cadartifact.execution import child as isolation

    serial = _gate(many, "--tol", "0.01", env={"CADARTIFACT_SHARE_FACES": "0"}, monkeypatch=monkeypatch)
    real = isolation.call

    def call(function, *args, **kwargs):
        if function.endswith(":child_gate"):
            kwargs["during"]()  # this process's share runs, then the child "crashes"
            raise FileFormatError("many.step", "the analysis reader crashed on this file (SIGSEGV)")
        return real(function, *args, **kwargs)

    monkeypatch.setattr(isolation, "call", call)
    assert _gate(many, "--tol", "0.01").stdout == serial.stdout


def test_errors_come_back_in_face_order_whichever_side_had_them(monkeypatch):
    """The child's side run in this process (so that one face can be made to fail on both sides): the
    outcomes are the serial loop's, errors included, in face order."""
    import cadartifact.runs.face as pipeline
    import cadartifact.runs.face_sharing as split
    from cadartifact.errors import CadArtifactError
    from cadartifact.execution import child as isolation
    from cadartifact.gate.policy import FileSettings

    real_entry = pipeline.start_face

    def entry(net, settings, options, **kwargs):
        if net.origin.name in ("bad", "worse"):
            raise CadArtifactError(f"{net.origin.name} cannot be analysed")
        if net.origin.name == "odd":
            raise ZeroDivisionError("division by zero")
        return real_entry(net, settings, options, **kwargs)

    def call(function, args, *, during=None, **kwargs):
        during()
        return split.child_gate(*args)

    monkeypatch.setattr(pipeline, "start_face", entry)
    monkeypatch.setattr(isolation, "call", call)
    names = ["a", "bad", "b", "odd", "c", "worse", "d", "e"]
    nets = [_net(10 + k, 8 + k % 3, 1.0, n).replace(origin=NetOrigin(name=n, face=k, kind="bspline"))
            for k, n in enumerate(names)]
    settings = FileSettings(tolerance=0.01)
    serial = [split.face_outcome(n, settings, False) for n in nets]
    from cadartifact.execution.sharing import Sharing

    monkeypatch.setattr(Sharing, "active", lambda self: True)
    shared = split.analyse_faces(nets, settings, False, sharing=Sharing())
    assert [type(o) for o in shared] == [type(o) for o in serial]
    assert [str(o) if isinstance(o, Exception) else json.dumps(o, sort_keys=True) for o in shared] == \
        [str(o) if isinstance(o, Exception) else json.dumps(o, sort_keys=True) for o in serial]
    assert str(shared[1]) == "face 1: bad cannot be analysed"
    assert str(shared[3]) == "analysis failed (ZeroDivisionError: division by zero)"


def test_a_call_from_within_during_is_refused_not_a_hang():
    from cadartifact.execution import child as isolation

    seen = []

    def nested():
        with pytest.raises(RuntimeError, match="busy"):
            isolation.call("os:getpid", (), path="x.step")
        seen.append(True)

    assert isinstance(isolation.call("os:getpid", (), path="x.step", during=nested), int)
    assert seen


def test_advise_shares_faces_and_gives_the_serial_document(many, spy, monkeypatch):
    def advise():
        result = CliRunner().invoke(app, ["advise", str(many), "--tol", "0.01", "--json"])
        assert result.exit_code == 1, result.output  # faces rippled beyond 0.01
        no_traceback(result)
        return result.stdout

    monkeypatch.setenv("CADARTIFACT_SHARE_FACES", "0")
    serial = advise()
    monkeypatch.delenv("CADARTIFACT_SHARE_FACES")
    assert not spy
    shared = advise()
    calls = spy["child_advise"]
    assert calls and 0 < calls[0] < 8, spy
    assert shared == serial
    doc = json.loads(shared)
    verified = [f["advice"]["verification"] for f in doc["files"][0]["faces"]]
    assert all(v and v["method"] in ("occt", "today") for v in verified)  # this process's share was verified too


def test_another_thread_waits_for_the_child_instead_of_failing():
    """Only the thread running ``during`` is refused; another thread's call waits for the lock, as before."""
    import threading
    import time

    from cadartifact.execution import child as isolation

    got = {}

    def other():
        time.sleep(0.2)
        got["b"] = isolation.call("os:getpid", (), path="b.step")

    t = threading.Thread(target=other)
    t.start()
    got["a"] = isolation.call("os:getpid", (), path="a.step", during=lambda: time.sleep(0.8))
    t.join(30)
    assert isinstance(got.get("b"), int) and got["a"] == got["b"]


def test_an_error_in_during_is_raised_as_itself_and_the_next_call_works():
    from cadartifact.execution import child as isolation

    def fails():
        raise TimeoutError("this process's own work timed out")  # must not read as the child's timeout

    with pytest.raises(TimeoutError, match="own work"):
        isolation.call("os:getpid", (), path="a.step", during=fails)
    assert isinstance(isolation.call("os:getpid", (), path="a.step"), int)


def test_records_keep_their_key_order(many):
    doc = json.loads(_gate(many, "--tol", "0.01").stdout)
    for face in doc["files"][0]["faces"]:
        # gate/3 (issue 25): the PDQ keys follow advice_skipped
        assert list(face)[-5:] == ["advice_skipped", "ripple_verdict", "criteria", "entity_line", "peak_at"], \
            list(face)[-6:]


def test_rounds_send_the_child_what_is_left_when_it_answers_first(many, spy, monkeypatch):
    """A child that answers before this process is done with its faces is sent half of what is left (rounds,
    longest first): here it is made to look done after each of this process's faces. Every face is computed
    once, the document is the serial one."""
    from cadartifact.execution import child as isolation

    serial = _gate(many, "--tol", "0.01", env={"CADARTIFACT_SHARE_FACES": "0"}, monkeypatch=monkeypatch)
    checks = []
    real = isolation.answered

    def answered():  # the child's real answer is then read by call() as usual (it waits for it)
        checks.append(real())
        return len(checks) % 2 == 0

    monkeypatch.setattr(isolation, "answered", answered)
    shared = _gate(many, "--tol", "0.01")
    rounds = spy["child_gate"]
    assert len(rounds) >= 2 and sum(rounds) < 8, rounds  # several rounds, and this process kept some faces
    assert shared.exit_code == serial.exit_code
    assert shared.stdout == serial.stdout


def test_answered_is_false_outside_during_and_true_once_the_child_has_replied():
    import time

    from cadartifact.execution import child as isolation

    assert isolation.answered() is False
    isolation.call("os:getpid", (), path="x.step")  # a started child (before its hello, answered() is False)
    seen = []

    def wait():
        deadline = time.monotonic() + 30
        while not isolation.answered() and time.monotonic() < deadline:
            time.sleep(0.01)
        seen.append(isolation.answered())

    assert isinstance(isolation.call("os:getpid", (), path="x.step", during=wait), int)
    assert seen == [True]


def test_an_error_from_the_child_keeps_its_attributes():
    """The CLI names the option from an OptionError's ``parameter``: a face's error computed in the child must
    carry it (``demo --tol -1`` once failed with AttributeError when the first face's error came from there)."""
    from cadartifact.errors import OptionError
    from cadartifact.runs.face_sharing import pack, unpack

    back = unpack(pack(OptionError("tolerance", "a positive number", -1.0)))
    assert isinstance(back, OptionError)
    assert (back.parameter, back.expected, back.received) == ("tolerance", "a positive number", -1.0)
    assert str(back) == "tolerance: expected a positive number, received -1.0"
