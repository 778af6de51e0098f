"""A second look at the same STEP file in one process reuses its read (``exchange.step.open_step(reuse=True)``):
the quality gate measures a file's edges after its faces in the same reader child. Only the same unchanged file
is reused; what it measures is what a fresh read measures."""

from __future__ import annotations

import os
import shutil

from cadartifact.analysis.edges import file_edges
from cadartifact.exchange import step
from cadartifact.testing.paths import SAMPLES


def test_the_edges_of_a_file_just_read_reuse_its_read_and_measure_the_same(tmp_path, monkeypatch):
    path = tmp_path / "hull.step"
    shutil.copy(SAMPLES / "hull_freeform.step", path)
    monkeypatch.setattr(step, "_LAST_READ", {})
    fresh = file_edges(path, "step")  # nothing kept: a read of its own
    assert not step._LAST_READ
    step.read_step(path)
    kept = next(iter(step._LAST_READ.values()))
    assert step.open_step(path, reuse=True) is kept
    assert file_edges(path, "step") == fresh
    # the file changed (same size, another modification time): read again, not reused
    stat = path.stat()
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000_000))
    assert step.open_step(path, reuse=True) is not kept
    assert step.open_step(tmp_path / "hull.step", reuse=False) is not kept


def test_a_read_kept_is_replaced_by_the_next_file_s(tmp_path, monkeypatch):
    monkeypatch.setattr(step, "_LAST_READ", {})
    first, second = tmp_path / "a.step", tmp_path / "b.step"
    shutil.copy(SAMPLES / "hull_freeform.step", first)
    shutil.copy(SAMPLES / "clean_panel.step", second)
    step.read_step(first)
    step.read_step(second)
    assert len(step._LAST_READ) == 1 and next(iter(step._LAST_READ))[0] == str(second.resolve())
