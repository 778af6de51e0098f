"""How a command ended, under typer's ``CliRunner``.

``CliRunner`` catches what the command raises: an uncaught exception never reaches the output as a traceback,
it sits in ``result.exception`` (and the exit code is 1). "No traceback" is therefore checked on both: the text
and the exception, which may only be the ``SystemExit`` of an exit code.
"""

from __future__ import annotations

import traceback


def no_traceback(result, text: str | None = None) -> None:
    """Assert that a ``CliRunner`` result ended by an exit code, not by an uncaught exception.

    Parameters
    ----------
    result : click.testing.Result
        What ``CliRunner().invoke`` returned.
    text : str, optional
        The text that must hold no traceback; default ``result.output``.
    """
    assert "Traceback" not in (result.output if text is None else text), result.output[-2000:]
    error = result.exception
    assert error is None or isinstance(error, SystemExit), "".join(traceback.format_exception(error))[-3000:]


def gate_profile_run(*args):
    """``cadartifact gate ARGS --jobs 1 --advise none`` under ``CliRunner``, checked for a traceback: the gate's
    verdicts and criteria without the advice's search (the PDQ and edge tests)."""
    from typer.testing import CliRunner

    from cadartifact.cli.app import app

    result = CliRunner().invoke(app, ["gate", *map(str, args), "--jobs", "1", "--advise", "none"])
    no_traceback(result)
    return result


def gate_profile_json(*args):
    """:func:`gate_profile_run` with ``--format json``: ``(result, document)``."""
    import json

    result = gate_profile_run(*args, "--format", "json")
    return result, json.loads(result.stdout)

