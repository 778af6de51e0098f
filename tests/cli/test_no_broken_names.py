"""Off a terminal (CI logs, pipes, files) text output never breaks a path or a name (issue item 5).

A path is one token a user copies or greps in a CI log: the real console script runs with stdout piped
(never a TTY), with and without ``COLUMNS=80``, on copies of the samples in a deep folder under file
names of 150+ characters (one with a space and ``[draft]`` in it, which rich would read as markup, and
one face renamed past the 24 characters a terminal's table cell keeps). Wherever a path or a face name
starts in the output, it is there whole, on that line.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from cadartifact.testing.paths import ROOT

pytest.importorskip("OCP")

SAMPLES = ROOT / "cadartifact" / "samples"
LONG_FACE = "wavy_panel_diagonal_renamed_to_a_face_name_longer_than_any_table_cell"
HEAD = 12  # a token's first (last) characters: where they stand, the whole token must


@pytest.fixture(scope="module")
def long_files(tmp_path_factory):
    """Three samples in a deep folder under 150+ character names; the wavy panel's face renamed long."""
    folder = tmp_path_factory.mktemp("names")
    for part in ("a_deep_folder_whose_name_alone_takes_half_a_line", "and_a_second_level_below_it_as_long",
                 "third_level_of_the_tree"):
        folder = folder / part
    folder.mkdir(parents=True)
    tail = ("_copied_under_a_file_name_long_enough_to_cross_the_eighty_columns_of_a_narrow_log_by_itself_alone"
            "_and_then_some_more_to_pass_150")
    files = {
        "hull_freeform": folder / f"hull_freeform{tail}_one.step",
        "car_hood_coarse": folder / f"car hood [draft] coarse{tail}_two.step",
        LONG_FACE: folder / f"wavy_panel_diagonal{tail}_three.step",
    }
    for name, path in files.items():
        sample = SAMPLES / ("wavy_panel_diagonal.step" if name == LONG_FACE else f"{name}.step")
        text = sample.read_text()
        if name == LONG_FACE:
            text = text.replace("ADVANCED_FACE('wavy_panel_diagonal'", f"ADVANCED_FACE('{LONG_FACE}'")
        path.write_text(text)
        assert len(path.name) >= 150
    return files


def cadartifact(*args, columns: str | None):
    """The console script (``cadartifact``), stdout and stderr piped: never a terminal."""
    script = Path(sys.executable).with_name("cadartifact")
    cmd = [str(script)] if script.is_file() else [sys.executable, "-m", "cadartifact.cli"]
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    if columns is not None:
        env["COLUMNS"] = columns
    return subprocess.run([*cmd, *map(str, args)], capture_output=True, text=True, env=env, timeout=600)


def _at(line: str, piece: str):
    at = line.find(piece)
    while at != -1:
        yield at
        at = line.find(piece, at + 1)


def broken(text: str, tokens: list[str]) -> list[tuple[str, str]]:
    """(token, line) wherever a line holds the first or the last characters of a token (half of it, 12 at
    most: a break leaves one piece at least that long) outside every whole token on that line."""
    out = []
    for line in text.splitlines():
        spans = [(at, at + len(t)) for t in tokens for at in _at(line, t)]
        for tok in tokens:
            n = min(HEAD, (len(tok) + 1) // 2)
            for piece in {tok[:n], tok[-n:]}:
                if any(not any(a <= at and at + n <= b for a, b in spans) for at in _at(line, piece)):
                    out.append((tok, line))
    return out


def assert_whole(text: str, tokens: list[str]) -> None:
    lines = text.splitlines()
    missing = [t for t in tokens if not any(t in line for line in lines)]
    assert not missing, f"not whole on any line: {missing}\n{text}"
    cut = broken(text, tokens)
    assert not cut, f"broken: {cut}\n{text}"


def test_the_checker_sees_a_broken_path_or_name():
    path, name = "/tmp/a_deep_folder/hull_freeform.step", "hull_freeform"
    assert broken(f"{path}  PASS\n 0 {name}  16x8", [path, name]) == []
    assert broken("/tmp/a_deep_folder/hu\nll_freeform.step  PASS", [path]) == [
        (path, "/tmp/a_deep_folder/hu"), (path, "ll_freeform.step  PASS")]
    assert broken("/tm\np/a_deep_folder/hull_freeform.step", [path]) == [(path, "p/a_deep_folder/hull_freeform.step")]
    assert broken(" 0 hull_freefo  16x8\n   rm", [path, name]) == [(name, " 0 hull_freefo  16x8")]
    assert broken(" 0 hull_free~  16x8", [path, name]) == [(name, " 0 hull_free~  16x8")]


COLUMNS = pytest.mark.parametrize("columns", [None, "80"], ids=["no-COLUMNS", "COLUMNS=80"])


@pytest.mark.slow
@COLUMNS
def test_gate_text(long_files, columns, tmp_path):
    paths = [str(p) for p in long_files.values()]
    res = cadartifact("gate", *paths, "--tol", "0.05", "--jobs", "1", columns=columns)
    assert res.returncode == 1, res.stderr  # the hull and the panels exceed 0.05 mm
    assert_whole(res.stdout, paths + list(long_files))
    assert_whole(res.stderr, paths)  # one progress line per file
    out = tmp_path / "gate.txt"
    res = cadartifact("gate", *paths, "--tol", "0.05", "--jobs", "1", "--output", out, columns=columns)
    assert res.returncode == 1, res.stderr
    assert_whole(out.read_text(), paths + list(long_files))


@pytest.mark.slow
@COLUMNS
def test_gate_text_with_pdq_criteria(long_files, columns):
    """The PDQ lines (``gate --profile default``, issue 25) name paths and faces whole too."""
    paths = [str(p) for p in long_files.values()]
    res = cadartifact("gate", *paths, "--tol", "0.05", "--jobs", "1", "--profile", "default", columns=columns)
    assert res.returncode == 1, res.stderr
    assert "pdq:" in res.stdout  # (the line may wrap after its label)
    assert_whole(res.stdout, paths + list(long_files))


@pytest.mark.slow
@COLUMNS
def test_advise_tables(long_files, columns):
    paths = [str(p) for p in long_files.values()]
    res = cadartifact("advise", *paths, "--tol", "0.05", "--no-verify", "--no-compare", columns=columns)
    assert res.returncode == 1, res.stderr
    assert_whole(res.stdout, paths + list(long_files))
    assert_whole(res.stderr, paths)


@COLUMNS
def test_inspect(long_files, columns):
    paths = [str(p) for p in long_files.values()]
    res = cadartifact("inspect", *paths, columns=columns)
    assert res.returncode == 0, res.stderr
    assert_whole(res.stdout, paths + list(long_files))


@pytest.mark.slow
@COLUMNS
def test_demo(columns):
    res = cadartifact("demo", columns=columns)
    assert res.returncode == 0, res.stderr
    folder = res.stdout.split(" from ", 1)[1].split(", tolerance", 1)[0]
    paths = [os.path.join(folder, p.name) for p in sorted(SAMPLES.iterdir()) if p.suffix in (".step", ".obj")]
    names = [p.stem for p in SAMPLES.glob("*.step")]  # each sample's face is named after its file
    assert_whole(res.stdout, [folder] + paths + names)
