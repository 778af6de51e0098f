"""The CLI starts OCCT's reader child early only for runs that read a B-rep file in this process."""

import pytest

from cadartifact.cli_prestart import will_read_here


@pytest.mark.parametrize("argv, expected", [
    (["cadartifact", "gate", "a.step", "--tol", "0.05"], True),
    (["cadartifact", "advise", "a.STP", "b.igs", "--tol", "0.05"], True),
    (["cadartifact", "inspect", "a.brep"], True),
    (["cadartifact", "gate", "a.step", "b.step", "--tol", "0.05"], False),  # a pool of workers reads
    (["cadartifact", "gate", "a.step", "b.step", "--jobs", "1"], True),
    (["cadartifact", "gate", "a.step", "b.step", "-j1"], True),
    (["cadartifact", "gate", "a.step", "b.step", "--jobs=2"], False),
    (["cadartifact", "gate", "parts/*.step"], False),  # a glob: maybe many files
    (["cadartifact", "gate", "a.step", "--scheduler", "local"], False),
    (["cadartifact", "advise", "cage.obj", "--tol", "1"], False),  # OBJ is read in this process
    (["cadartifact", "demo"], False),
    (["cadartifact"], False),
])
def test_will_read_here(argv, expected):
    assert will_read_here(argv) is expected


def test_a_folder_argument_means_a_pool(tmp_path):
    (tmp_path / "sub").mkdir()
    assert not will_read_here(["cadartifact", "gate", str(tmp_path / "sub"), "x.step"])


def test_prestarted_child_serves_the_first_read_and_isolation_off_starts_none(monkeypatch):
    pytest.importorskip("OCP")
    from pathlib import Path

    from cadartifact.exchange import isolation, read

    isolation.shutdown()
    isolation.prestart()
    child = isolation._child
    assert child is not None and not child.ready
    sample = Path(__file__).resolve().parents[1] / "cadartifact" / "samples" / "clean_panel.step"
    assert read(sample).nets and isolation._child is child and child.ready  # the same process, now ready
    isolation.shutdown()
    monkeypatch.setenv(isolation.ENV_ISOLATION, "0")
    isolation.prestart()
    assert isolation._child is None
