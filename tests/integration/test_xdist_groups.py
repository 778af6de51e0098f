"""The suite's xdist groups hold (``--dist loadgroup``, pyproject's addopts): tests marked with the same
``xdist_group`` run on one worker. The Dask cluster tests and the local rational reading's seed-2 readings rely on
it; pytest 9.2 with pytest-xdist 3.8 ignored every group without a word (the test extra pins pytest below 9.2)."""

from __future__ import annotations

import os
import subprocess
import sys

TESTS = '''
import os
import pytest


def _record(tmp, name):
    with open(os.path.join(tmp, name), "w") as f:
        f.write(os.environ.get("PYTEST_XDIST_WORKER", "none"))


@pytest.mark.xdist_group("together")
@pytest.mark.parametrize("i", range(4))
def test_grouped(i):
    _record(os.environ["GROUPS_OUT"], f"grouped{i}")


@pytest.mark.parametrize("i", range(4))
def test_free(i):
    _record(os.environ["GROUPS_OUT"], f"free{i}")
'''


def test_tests_of_one_xdist_group_run_on_one_worker(tmp_path):
    (tmp_path / "test_groups.py").write_text(TESTS)
    out = tmp_path / "out"
    out.mkdir()
    run = subprocess.run([sys.executable, "-m", "pytest", "-n", "2", "--dist", "loadgroup", "-q", "-p",
                          "no:cacheprovider", "test_groups.py"], cwd=tmp_path,
                         env={**os.environ, "GROUPS_OUT": str(out), "PYTEST_ADDOPTS": ""},
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    workers = {p.name: p.read_text() for p in out.iterdir()}
    assert len(workers) == 8
    grouped = {w for name, w in workers.items() if name.startswith("grouped")}
    assert len(grouped) == 1 and grouped <= {"gw0", "gw1"}, workers
