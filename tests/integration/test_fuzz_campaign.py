"""benchmarks/fuzz_campaign.py: a batch of mutated files per gate process cannot hide a crash, a hang or a
traceback: such a batch is run again one file per process, and each input gets its own class."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from cadartifact.testing.paths import ROOT


def _campaign():
    spec = importlib.util.spec_from_file_location("fuzz_campaign", ROOT / "benchmarks" / "fuzz_campaign.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_failed_batch_is_rerun_one_file_per_process_and_each_input_classed(monkeypatch, capsys):
    campaign = _campaign()
    calls = []

    def fake_gate(paths, args, folder, timeout, deadline=None):
        calls.append(len(paths))
        if len(paths) > 1 and calls[0] != len(paths):  # the batches (not the sources' baseline): the process died
            return "crash", "exit code -11"
        if len(paths) > 1:  # the baseline of the unmutated sources
            return "ok", [{"path": str(p), "verdict": "pass", "faces": [{}], "faces_total": 1} for p in paths]
        name = str(paths[0])
        index = int(Path(name).parent.name)
        if index == 1:
            return "crash", "exit code -11"
        if index == 2:
            return "hang", "no report in 60 s"
        if index == 3:
            return "traceback", "ZeroDivisionError: division by zero"
        return "ok", [{"path": name, "verdict": "error", "error": f"{name}: something named", "faces": []}]

    monkeypatch.setattr(campaign, "gate_process", fake_gate)
    code = campaign.main(["-n", "6", "--seed", "1", "--batch", "6", "--no-iges", "--progress", "100"])
    out = capsys.readouterr().out
    assert code == 1
    assert "re-run one file per process" in out
    assert calls[1] == 6 and calls[2:] == [1] * 6  # the batch, then each of its files alone
    assert "findings: traceback 1, crash 1, hang 1, false-pass 0, silent-loss 0" in out
    assert "3 error entries, 3 naming their file" in out
