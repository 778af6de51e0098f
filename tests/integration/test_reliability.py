"""Reliability: mutated inputs through load, ``advise`` and ``gate`` end in documented outcomes.

Each good file (a STEP written from a net, a small OBJ grid) is truncated, byte-flipped (seeded),
emptied, given huge (1e300) or NaN coordinates, or given the other format's extension. For every
mutation:

- ``cadartifact.load`` returns nets or raises a :class:`CadArtifactError` subclass, nothing else;
- ``cadartifact advise`` exits 0, 1 or 2 with no traceback; when the file does not load it exits 2
  with one line on stderr and prints no (partial) document;
- ``cadartifact gate --output FILE`` exits 0, 1 or 2 with no traceback; the report file is always
  complete (the documented choice: an unreadable file is an ``error`` entry inside a whole report,
  exit 2); a file that does not load is never reported as passing. Usage errors write no report.

Some byte flips leave a valid file (e.g. a changed digit): then only the first two rules apply.
"""

import json
import os
import random
import re

import numpy as np
import pytest
from typer.testing import CliRunner

import cadartifact as ca
from cadartifact.cli.app import app
from cadartifact.errors import CadArtifactError
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.testing.outcomes import no_traceback

pytest.importorskip("OCP")
# mutated inputs are expected to warn (overflow in advise, skipped faces in load): only outcomes are checked
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning", "ignore::UserWarning")

SEED = 20240605
MUTATIONS = ("trunc10", "trunc50", "trunc90", "flip0", "flip1", "flip2", "empty", "huge", "nan", "wrong-ext")
TOL = 0.05


def obj_grid(n=6, m=5) -> str:
    """A small OBJ quad grid with a bump (one structured grid: one cage net)."""
    lines = ["# cadartifact reliability grid"]
    for i in range(n):
        for j in range(m):
            z = 2.0 * np.exp(-((i - 2.5) ** 2 + (j - 2) ** 2) / 2.0)
            lines.append(f"v {10.0 * i:.6f} {10.0 * j:.6f} {z:.6f}")
    for i in range(n - 1):
        for j in range(m - 1):
            a = i * m + j + 1
            lines.append(f"f {a} {a + m} {a + m + 1} {a + 1}")
    return "\n".join(lines) + "\n"


def step_bytes(tmp) -> bytes:
    from cadartifact.exchange.load import write_step

    i, j = np.meshgrid(np.arange(8), np.arange(6), indexing="ij")
    x, y = 10.0 * i, 10.0 * j
    z = 3.0 * np.exp(-((x - 35) ** 2) / 40.0)
    net = ControlNet.from_points(np.stack([x, y, z], -1), degrees=(3, 3), origin=NetOrigin(name="bump",
                                                                                              kind="bspline"))
    path = write_step([net], tmp / "good.step")
    return path.read_bytes()


def mutate(kind: str, data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    """``(file name, content)`` of one mutation of a good ``fmt`` ("step" or "obj") file."""
    ext = "." + fmt
    if kind.startswith("trunc"):
        return "cut" + ext, data[: len(data) * int(kind[5:]) // 100]
    if kind.startswith("flip"):
        buf = bytearray(data)
        for _ in range(6):
            pos = rng.randrange(len(buf))
            buf[pos] ^= 1 << rng.randrange(8)
        return "flipped" + ext, bytes(buf)
    if kind == "empty":
        return "empty" + ext, b""
    if kind in ("huge", "nan"):
        text = data.decode("latin-1")
        value = "1.E300" if kind == "huge" else "NaN"
        if fmt == "obj":
            text = re.sub(r"^v (\S+)", f"v {value.lower() if kind == 'nan' else '1e300'}", text, count=3, flags=re.M)
        else:  # the first coordinate of a few control points
            text = re.sub(r"(CARTESIAN_POINT\('[^']*',\()([^,]+)", lambda m: m.group(1) + value, text, count=3)
        return f"{kind}{ext}", text.encode("latin-1")
    if kind == "wrong-ext":
        return "swapped" + (".obj" if fmt == "step" else ".step"), data
    raise AssertionError(kind)


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("good")
    return {"step": step_bytes(tmp), "obj": obj_grid().encode()}


def load_outcome(path):
    """``None`` when the file loads, else the CadArtifactError it raised (anything else fails the test)."""
    try:
        ca.load(path)
    except CadArtifactError as exc:
        assert str(exc) and "\n" not in str(exc).strip()
        return exc
    return None


def invoke(*args):
    result = CliRunner().invoke(app, [str(a) for a in args])
    no_traceback(result)
    assert not isinstance(result.exception, Exception) or isinstance(result.exception, SystemExit), \
        repr(result.exception)
    return result


@pytest.mark.parametrize("fmt", ["step", "obj"])
@pytest.mark.parametrize("kind", MUTATIONS)
def test_mutated_input_ends_in_a_documented_outcome(good, tmp_path, fmt, kind):
    rng = random.Random(f"{SEED}-{fmt}-{kind}")
    name, data = mutate(kind, good[fmt], fmt, rng)
    path = tmp_path / name
    path.write_bytes(data)
    error = load_outcome(path)
    if kind in ("empty", "trunc10") or (kind == "wrong-ext"):
        assert error is not None, f"{kind} {fmt} loaded"

    adv = invoke("advise", path, "--tol", TOL, "--json", "--no-compare", "--no-verify")
    assert adv.exit_code in (0, 1, 2)
    if error is not None:
        assert adv.exit_code == 2 and adv.stdout == "" and len(adv.stderr.strip().splitlines()) == 1
        assert path.name in adv.stderr
    elif adv.exit_code != 2:
        json.loads(adv.stdout)  # a whole document

    out = tmp_path / "reports" / "gate.json"
    out.parent.mkdir()
    gate = invoke("gate", path, "--tol", TOL, "--format", "json", "--output", out, "--jobs", "1")
    assert gate.exit_code in (0, 1, 2)
    doc = json.loads(out.read_text())  # complete whatever happened
    assert os.listdir(out.parent) == ["gate.json"]
    entry = doc["files"][0]
    assert doc["exit_code"] == gate.exit_code
    if error is not None or kind in ("huge", "nan"):  # invalid coordinates are errors for the gate
        assert gate.exit_code == 2 and entry["verdict"] == "error" and doc["verdict"] == "error"
        assert path.name in entry["error"]
    if entry["verdict"] == "error":
        assert gate.exit_code == 2


def test_a_folder_of_good_and_bad_files_never_passes(good, tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    (folder / "good.step").write_bytes(good["step"])
    (folder / "good.obj").write_bytes(good["obj"])
    (folder / "empty.STP").write_bytes(b"")
    (folder / "half.step").write_bytes(good["step"][: len(good["step"]) // 2])
    (folder / "mesh.step").write_bytes(good["obj"])
    out = tmp_path / "gate.xml"
    results = {}
    for jobs in ("1", "2"):
        r = invoke("gate", folder, "--tol", 1e6, "--format", "json", "--jobs", jobs)
        assert r.exit_code == 2
        results[jobs] = r.stdout
        doc = json.loads(r.stdout)
        verdicts = {os.path.basename(f["path"]): f["verdict"] for f in doc["files"]}
        assert verdicts == {"empty.STP": "error", "good.obj": "pass", "good.step": "pass", "half.step": "error",
                            "mesh.step": "error"}
        assert doc["verdict"] == "error"
    assert results["1"] == results["2"]
    r = invoke("gate", folder, "--tol", 1e6, "--format", "junit", "--output", out, "--jobs", "1")
    assert r.exit_code == 2 and out.read_text().count("<error") == 3
    # advise fails closed on the folder's first bad file: exit 2, no partial document
    adv = invoke("advise", *sorted(folder.iterdir()), "--tol", 1, "--json", "--no-compare", "--no-verify")
    assert adv.exit_code == 2 and adv.stdout == ""


def test_usage_errors_write_no_report(good, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no policy: the tolerance must come from --tol
    (tmp_path / "good.step").write_bytes(good["step"])
    out = tmp_path / "r.sarif"
    for args in (["--tol", "-1"], ["--tol", "nan"], ["--tol", "1", "--format", "pdf"], []):
        r = invoke("gate", tmp_path / "good.step", "--format", "sarif", "--output", out, *args)
        assert r.exit_code == 2 and not out.exists(), args
    r = invoke("gate", tmp_path / "missing.step", "--tol", 1, "--output", out)
    assert r.exit_code == 2 and not out.exists()
