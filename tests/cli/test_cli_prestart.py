"""The CLI starts OCCT's reader child early only for runs that read a B-rep file in this process."""

import pytest

from cadartifact.cli.prestart import will_read_here
from cadartifact.testing.paths import ROOT


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

    from cadartifact.execution import child as isolation
    from cadartifact.exchange.load import read

    from cadartifact.exchange.reader_start import PRELOAD

    isolation.shutdown()
    isolation.prestart(PRELOAD)
    child = isolation._child
    assert child is not None and not child.ready
    sample = ROOT / "cadartifact" / "samples" / "clean_panel.step"
    assert read(sample).nets and isolation._child is child and child.ready  # the same process, now ready
    isolation.shutdown()
    # isolation off: the CLI reads it at its edge, and the run's settings say so to the child
    from cadartifact.cli.prestart import isolation_on

    monkeypatch.setenv("CADARTIFACT_READ_ISOLATION", "0")
    assert not isolation_on()
    monkeypatch.setattr(isolation, "_settings", isolation.settings().replace(isolation=False))
    isolation.prestart(PRELOAD)
    assert isolation._child is None


# ---------------------------------------------------------------- the early read (reader_start)
def _sample():
    from pathlib import Path

    return ROOT / "cadartifact" / "samples" / "clean_panel.step"


def test_first_read_names_the_one_file(tmp_path, monkeypatch):
    from pathlib import Path

    from cadartifact.cli.prestart import first_read
    from cadartifact.exchange.reader_start import READ_FUNCTION

    monkeypatch.chdir(tmp_path)
    for name in ("a.step", "b.IGS", "c.brep", "d.step"):
        (tmp_path / name).write_text("x")
    assert first_read(["cadartifact", "gate", "a.step", "--tol", "0.05"]) == (
        READ_FUNCTION, (Path("a.step"), "step", False, True))
    # IGES, like STEP, is read "prescanned": its directory is checked in this process while the child reads
    assert first_read(["cadartifact", "advise", "b.IGS", "--convert"]) == (READ_FUNCTION, (Path("b.IGS"), "iges", True, True))
    assert first_read(["cadartifact", "gate", "c.brep", "--no-convert"]) == (READ_FUNCTION, (Path("c.brep"), "brep",
                                                                                               False))
    assert first_read(["cadartifact", "gate", "a.step", "d.step", "--jobs", "1"]) is None  # which first: not guessed
    assert first_read(["cadartifact", "gate", "missing.step"]) is None
    assert first_read(["cadartifact", "inspect", "a.step"]) is None
    # an option's file is not the input
    assert first_read(["cadartifact", "advise", "a.step", "--write-resampled", "d.step"]) == (
        READ_FUNCTION, (Path("a.step"), "step", False, True))
    assert first_read(["cadartifact", "advise", "cage.obj", "--write-resampled", "d.step"]) is None
    # a gate policy may set convert: no guess unless the command line says
    (tmp_path / "cadartifact.toml").write_text("tolerance = 0.05\n")
    assert first_read(["cadartifact", "gate", "a.step"]) is None
    assert first_read(["cadartifact", "gate", "a.step", "--no-convert"]) == (
        READ_FUNCTION, (Path("a.step"), "step", False, True))
    assert first_read(["cadartifact", "advise", "a.step"]) is not None  # advise reads no policy
    (tmp_path / "cadartifact.toml").unlink()
    (tmp_path / "pyproject.toml").write_text("[tool.cadartifact]\ntolerance = 0.05\n")
    assert first_read(["cadartifact", "gate", "a.step"]) is None
    (tmp_path / "pyproject.toml").write_text("[project]\nname = 'x'\n")
    assert first_read(["cadartifact", "gate", "a.step"]) is not None
    assert first_read(["cadartifact", "gate", "a.step", "--policy", "p.toml"]) is None


def test_early_read_serves_the_same_request_only(monkeypatch):
    """A child started with an early read answers that read (no second request, same result as a read
    without it); a different first read stops that child and is answered by a new one."""
    pytest.importorskip("OCP")
    from cadartifact.exchange import reader_start
    from cadartifact.execution import child as isolation
    from cadartifact.exchange.load import read

    sample = _sample()
    isolation.shutdown()
    plain = read(sample)
    isolation.shutdown()

    reader_start.start(reader_start.read_request(sample, "step", False))
    isolation.prestart()  # adopts the started child and its early request
    child = isolation._child
    assert child.early is not None
    sent = []
    real_write = isolation._write_frame
    monkeypatch.setattr(isolation, "_write_frame", lambda fd, payload: (sent.append(payload), real_write(fd, payload)))
    early = read(sample)
    assert sent == [] and isolation._child is child and child.early is None  # the early answer was the reply
    assert [n.points.tobytes() for n in early.nets] == [n.points.tobytes() for n in plain.nets]
    assert [n.origin for n in early.nets] == [n.origin for n in plain.nets]
    isolation.shutdown()

    reader_start.start(reader_start.read_request(sample, "step", True))  # guessed --convert, read without
    isolation.prestart()
    guessed = isolation._child
    again = read(sample)
    assert isolation._child is not guessed and guessed.proc.poll() is not None  # stopped, a new child answered
    assert [n.points.tobytes() for n in again.nets] == [n.points.tobytes() for n in plain.nets]
    isolation.shutdown()


def test_an_unused_early_child_is_stopped_at_exit():
    from cadartifact.exchange import reader_start
    from cadartifact.execution import start

    reader_start.start(reader_start.read_request(_sample(), "step", False))
    proc = start._prestarted[0]
    start._stop_unused()
    assert proc.poll() is not None and start._prestarted is None


def test_brep_formats_agree_with_the_exchange():
    from cadartifact.cli.prestart import BREP_SUFFIXES
    from cadartifact.exchange.load import SUPPORTED_EXTENSIONS
    from cadartifact.exchange.reader_start import BREP_FORMATS

    assert BREP_FORMATS == {k: v for k, v in SUPPORTED_EXTENSIONS.items() if v != "obj"}
    assert set(BREP_SUFFIXES) == set(BREP_FORMATS)


def test_an_early_child_that_died_is_replaced():
    pytest.importorskip("OCP")
    from cadartifact.exchange import reader_start
    from cadartifact.execution import child as isolation
    from cadartifact.exchange.load import read

    isolation.shutdown()
    reader_start.start(reader_start.read_request(_sample(), "step", False))
    from cadartifact.execution import start

    proc = start._prestarted[0]
    proc.kill()
    proc.wait()
    assert read(_sample()).nets  # a new child answers; the dead one is reaped
    assert isolation._child.proc is not proc and isolation._child.early is None
    isolation.shutdown()
