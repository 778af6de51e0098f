"""Every bad command-line value is one line on stderr, exit code 2, no traceback and no usage box.

The line names the option, what was expected (the valid choices for a choice option) and what was
received. Choice options are validated by :func:`cadartifact.errors.check_option` (as ``maps`` does);
type and usage errors that typer finds while parsing go through :func:`cadartifact.cli.usage.usage_message`.
"""

from enum import Enum

import pytest
import typer
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.cli.root import _OneLineUsageErrors
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import SAMPLES

pytest.importorskip("OCP")

ONE_FACE = SAMPLES / "clean_panel.step"  # a single analysable face: index 0
SCHEMES = ["'bilinear'", "'bicubic'", "'4-3'", "'4-8'", "'kobbelt'"]


def invoke(args, cli=app):
    return CliRunner().invoke(cli, [str(a) for a in args])


def one_line_error(result) -> str:
    """The single error line; asserts exit 2, nothing on stdout, no traceback, no box."""
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr)
    assert result.stdout == "", result.stdout
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    line = lines[0]
    assert line.startswith("cadartifact: error: "), line
    assert "Traceback" not in line and "╭" not in result.stderr and "Usage:" not in result.stderr
    no_traceback(result, result.stderr)
    return line


def _needs(command):
    if command == "view":
        pytest.importorskip("pyvista")


# (command and its required arguments, option, bad value, the valid choices the line must list)
CHOICES = [
    (["advise", ONE_FACE, "--tol", "0.05"], "--metric", "bogus", ["'peak'", "'rms'"]),
    (["advise", ONE_FACE, "--tol", "0.05"], "--scheme", "bogus", SCHEMES),
    (["gate", ONE_FACE, "--tol", "0.05"], "--format", "bogus", ["'text'", "'json'", "'junit'", "'sarif'"]),
    (["gate", ONE_FACE, "--tol", "0.05"], "--metric", "bogus", ["'peak'", "'rms'"]),
    (["gate", ONE_FACE, "--tol", "0.05"], "--scheme", "bogus", SCHEMES),
    (["view", ONE_FACE], "--direction", "bogus",
     ["'total'", "'x1'", "'x2'", "'diagonal'", "'lateral'", "'signal_error'", "'deviation'"]),
    (["view", ONE_FACE], "--layout", "bogus", ["'auto'", "'model'", "'tiles'"]),
    (["view", ONE_FACE], "--scheme", "bogus", SCHEMES),
    (["maps"], "--stage", "bogus", ["'one-step'", "'limit'", "'continuous'"]),
    (["maps"], "--domain", "bogus", ["'quadrant'", "'square'"]),
    (["maps"], "--scheme", "bogus", SCHEMES),
]


@pytest.mark.parametrize("base, option, bad, choices", CHOICES,
                         ids=[f"{c[0][0]} {c[1]}" for c in CHOICES])
def test_bad_choice_is_one_line_naming_option_choices_and_value(tmp_path, monkeypatch, base, option, bad, choices):
    _needs(base[0])
    monkeypatch.chdir(tmp_path)  # nothing may be written, and no policy file is picked up
    line = one_line_error(invoke([*base, option, bad]))
    assert f"{option}: expected one of " in line, line
    for choice in choices:
        assert choice in line, (choice, line)
    assert line.endswith(f"received {bad!r}"), line
    assert list(tmp_path.iterdir()) == []


# (arguments, the start of the line after "cadartifact: error: ", the received value it must show)
VALUES = [
    (["advise", ONE_FACE, "--tol", "-1"], "--tol: expected a positive number", "-1.0"),
    (["advise", ONE_FACE, "--tol", "abc"], "--tol: expected a number", "'abc'"),
    (["advise", ONE_FACE, "--tol", "nan"], "--tol: expected a positive number", "nan"),
    (["advise", ONE_FACE, "--tol", "0.05", "--face", "99"],
     "--face: expected an analysable face index of clean_panel.step (0)", "99"),
    (["advise", ONE_FACE, "--tol", "0.05", "--face", "abc"], "--face: expected an integer", "'abc'"),
    (["advise", ONE_FACE], "--tol: expected a value (it is required)", "nothing"),
    (["advise", "--tol", "0.05"], "FILES: expected a value (it is required)", "nothing"),
    (["gate", ONE_FACE, "--tol", "-1"], "--tol: expected a positive number", "-1.0"),
    (["gate", ONE_FACE, "--tol", "abc"], "--tol: expected a number", "'abc'"),
    (["gate", ONE_FACE, "--tol", "0.05", "--jobs", "abc"], "--jobs: expected an integer", "'abc'"),
    (["gate", ONE_FACE, "--tol", "0.05", "--warn-fraction", "2"], "--warn-fraction: expected a number", "2.0"),
    (["view", ONE_FACE, "--tol", "-1"], "--tol: expected a positive number", "-1.0"),
    (["view", ONE_FACE, "--tol", "abc"], "--tol: expected a number", "'abc'"),
    (["view", ONE_FACE, "--face", "99"], "--face: expected an analysable face index of clean_panel.step (0)", "99"),
    (["view", ONE_FACE, "--size", "big"], "--size: expected WIDTHxHEIGHT", "'big'"),
    (["maps", "--resolution", "abc"], "--resolution: expected an integer", "'abc'"),
    (["maps", "--resolution", "4"], "--resolution: expected an integer from 16 to 4096", "4"),
    (["maps", "--out", "maps.txt"], "--out: expected one of '.png'", "'.txt'"),
    (["demo", "--tol", "-1"], "--tol: expected a positive number", "-1.0"),
    (["demo", "--tol", "abc"], "--tol: expected a number", "'abc'"),
]


@pytest.mark.parametrize("args, start, received", VALUES, ids=[" ".join(map(str, v[0][:1] + v[0][2:]))
                                                               for v in VALUES])
def test_bad_value_is_one_line_naming_option_and_value(tmp_path, monkeypatch, args, start, received):
    _needs(args[0])
    monkeypatch.chdir(tmp_path)
    line = one_line_error(invoke(args))
    assert line.startswith("cadartifact: error: " + start), line
    assert line.endswith(f"received {received}"), line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, needle", [
    (["inspect", ONE_FACE, "--bogus"], "No such option: --bogus (see 'cadartifact inspect --help')"),
    (["inspect", ONE_FACE, "--json=yes"], "Option '--json' does not take a value"),
    (["schemes", "--json=yes"], "Option '--json' does not take a value"),
    (["advise", ONE_FACE, "--tol"], "Option '--tol' requires an argument"),
    (["maps", "extra"], "unexpected extra argument"),
    (["advis"], "No such command 'advis'. Did you mean 'advise'?"),
])
def test_other_usage_errors_are_one_line(args, needle):
    assert needle in one_line_error(invoke(args))


def test_help_and_no_arguments_still_print_the_help():
    for args, code in (([], 0), (["--help"], 0), (["-h"], 0), (["advise", "--help"], 0), (["advise", "-h"], 0)):
        result = invoke(args)
        assert result.exit_code == code and "Usage:" in result.stdout and result.stderr == "", args


def test_a_valid_face_is_still_advised():
    result = invoke(["advise", ONE_FACE, "--tol", "10", "--face", "0", "--json", "--no-verify", "--no-compare"])
    assert result.exit_code == 0, result.stderr  # 10 mm: the panel's face is within it
    assert '"face": 0' in result.stdout


class Colour(str, Enum):
    red = "red"
    green = "green"


def test_an_enum_option_would_also_get_one_line():
    """A future Enum / Choice option is covered by the group, not by each command."""
    demo = typer.Typer(cls=_OneLineUsageErrors)

    @demo.command()
    def paint(colour: Colour = typer.Option(Colour.red, "--colour"), times: int = typer.Option(1, "--times")):
        typer.echo(colour.value * times)

    @demo.command()
    def other():  # two commands: typer builds a group
        pass

    assert invoke(["paint", "--colour", "green"], demo).stdout == "green\n"
    line = one_line_error(invoke(["paint", "--colour", "blue"], demo))
    assert line == "cadartifact: error: --colour: expected one of 'red', 'green', received 'blue'"
    line = one_line_error(invoke(["paint", "--times", "2.5"], demo))
    assert line.startswith("cadartifact: error: --times: expected an integer") and line.endswith("received '2.5'")
