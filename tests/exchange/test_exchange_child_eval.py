"""OCCT evaluation through the warm reader child (``exchange.evaluate_grid`` when this process has no OCP).

Two roads to the same numbers: the child's ``occ.evaluate_grid`` and this process's. The gate of a
file with a failing face (its peak location needs one OCCT point) must not import OCP in the
gating process: the reader child has it loaded already.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from cadartifact.testing.paths import ROOT

pytest.importorskip("OCP")

SAMPLES = ROOT / "cadartifact" / "samples"

CODE = """
import json, sys
import numpy as np
from cadartifact.gate.run import gate_file
from cadartifact.gate.policy import FileSettings
from cadartifact.exchange.load import evaluate_grid, load
entry = gate_file(sys.argv[1], FileSettings(tolerance=0.05))
net = load(sys.argv[1])[0]
grid = evaluate_grid(net, np.linspace(0, 1, 7), np.linspace(0, 1, 5))
print(json.dumps({"ocp": "OCP" in sys.modules, "peak_at": entry["faces"][0]["peak_at"],
                  "verdict": entry["faces"][0]["verdict"], "grid": grid.tolist()}))
"""


def test_gate_locates_the_peak_without_importing_ocp_and_the_child_evaluates_the_same():
    from cadartifact.exchange.load import load
    from cadartifact.exchange.occ import evaluate_grid
    from cadartifact.gate.run import gate_file
    from cadartifact.gate.policy import FileSettings

    path = str(SAMPLES / "car_hood_coarse.step")
    out = subprocess.run([sys.executable, "-c", CODE, path], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert got["ocp"] is False and got["verdict"] == "fail" and got["peak_at"]["xyz"]
    # this process has OCP: the in-process road
    here = gate_file(path, FileSettings(tolerance=0.05))["faces"][0]["peak_at"]
    assert got["peak_at"] == here
    grid = evaluate_grid(load(path)[0], np.linspace(0, 1, 7), np.linspace(0, 1, 5))
    assert np.array_equal(np.array(got["grid"]), grid)
