"""``advise --write-resampled`` onto an input file is bad input: one line naming the file, exit 2, nothing written.

The same file under its own name, another spelling of its path (``./``, ``..``), a symbolic link to it, a hard
link, and with several inputs the ``OUT_<stem>`` name one of them would get; the input stays byte for byte as it
was. ``write_model`` refuses the same on its own.
"""

from __future__ import annotations

import os
import shutil

import pytest

pytest.importorskip("OCP")

from typer.testing import CliRunner  # noqa: E402

from cadartifact.cli.app import app  # noqa: E402
from cadartifact.errors import InputError  # noqa: E402
from cadartifact.testing.paths import SAMPLES  # noqa: E402

SAMPLE = SAMPLES / "wavy_panel_diagonal.step"


def invoke(args):
    return CliRunner().invoke(app, [str(a) for a in args])


def spellings(tmp_path, source):
    link = tmp_path / "link.step"
    link.symlink_to(source)
    hard = tmp_path / "hard.step"
    os.link(source, hard)
    (tmp_path / "sub").mkdir()
    return {"same": source, "dotted": tmp_path / "sub" / ".." / "./model.step", "symlink": link, "hardlink": hard}


@pytest.mark.parametrize("spelling", ["same", "dotted", "symlink", "hardlink"])
def test_writing_onto_the_input_is_refused_before_any_work(spelling, tmp_path):
    source = tmp_path / "model.step"
    shutil.copy(SAMPLE, source)
    content = source.read_bytes()
    out = spellings(tmp_path, source)[spelling]
    result = invoke(["advise", source, "--tol", "0.01", "--no-verify", "--write-resampled", out])
    assert result.exit_code == 2, result.output
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "model.step" in lines[0] and "overwrite" in lines[0] and "Traceback" not in result.output
    assert source.read_bytes() == content
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hard.step", "link.step", "model.step", "sub"]


def test_several_inputs_the_per_file_name_of_one_is_refused(tmp_path):
    a, b = tmp_path / "a.step", tmp_path / "out_a.step"  # a's output would be OUT_a.step: b itself
    shutil.copy(SAMPLE, a)
    shutil.copy(SAMPLE, b)
    content = b.read_bytes()
    result = invoke(["advise", a, b, "--tol", "0.01", "--no-verify", "--write-resampled", tmp_path / "out.step"])
    assert result.exit_code == 2 and "out_a.step" in result.output and "overwrite" in result.output
    assert b.read_bytes() == content and sorted(p.name for p in tmp_path.iterdir()) == ["a.step", "out_a.step"]


def test_write_model_refuses_its_own_source(tmp_path):
    from cadartifact.exchange.model_writer import write_model

    source = tmp_path / "model.step"
    shutil.copy(SAMPLE, source)
    link = tmp_path / "link.step"
    link.symlink_to(source)
    with pytest.raises(InputError, match="overwrite"):
        write_model(source, {}, link)
