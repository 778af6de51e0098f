"""The environment variables the command line reads, in one table, read here only (the CLI's edge).

Below the command line nothing reads the environment: what these variables set travels in the run's
:class:`~cadartifact.execution.settings.ExecutionSettings` (and its
:class:`~cadartifact.execution.settings.ClusterOptions`). docs/environment.md lists the same table for users.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable

from ..errors import OptionError
from ..execution.settings import ClusterOptions, ExecutionSettings, InvalidValue

__all__ = ["ENVIRONMENT", "Variable", "cluster_options", "execution_settings", "read"]

_OFF = ("0", "false", "no", "off")


@dataclass(frozen=True)
class Variable:
    """One environment variable: its name, the setting it fills, how its text is read, and what it does."""

    name: str
    field: str  #: an ExecutionSettings field, or ``cluster.<ClusterOptions field>``
    parse: Callable
    default: str
    meaning: str


def _flag(name: str, raw: str) -> bool:
    return raw.strip().lower() not in _OFF


def _seconds(name: str, raw: str) -> float | InvalidValue:
    # a bad value is the error of the read that needs it (a gate file's error entry), as when the variable was
    # read there: a run that reads no B-rep file, or is given --read-timeout, goes on
    try:
        value = float(raw)
    except ValueError:
        return InvalidValue(name, "a positive number of seconds", raw)
    if not (0 < value < float("inf")):
        return InvalidValue(name, "a positive number of seconds", value)
    return value


def _whole(name: str, raw: str) -> int:
    try:
        return int(raw.strip())
    except ValueError:
        raise OptionError(name, "a whole number of face batches", raw.strip()) from None


def _text(name: str, raw: str) -> str:
    return raw


#: Every variable the command line reads.
ENVIRONMENT = (
    Variable("CADARTIFACT_READ_TIMEOUT", "read_timeout", _seconds, "120",
             "Seconds OCCT's reader (or one evaluation) may take on a file before it is stopped; "
             "`gate --read-timeout` wins."),
    Variable("CADARTIFACT_READ_ISOLATION", "isolation", _flag, "1",
             "`0`: OCCT reads and evaluates in the command's own process (debugging; a crash then ends the run)."),
    Variable("CADARTIFACT_SHARE_FACES", "share_faces", _flag, "1",
             "`0`: `gate --jobs 1` and `advise` do not share a file's faces with the idle reader child."),
    Variable("CADARTIFACT_REUSE_FACES", "reuse_faces", _flag, "1",
             "`0`: every face is analysed on its own (no reuse of a repeated face's analysis)."),
    Variable("CADARTIFACT_FACE_BATCHES", "cluster.face_batches", _whole, "",
             "`gate --scheduler`: face batches per big file (default: as many as leave no thread idle); "
             "tests and benchmarks."),
    Variable("CADARTIFACT_TEST_WORKER_EXIT", "cluster.worker_exit", _text, "",
             "Test hook, `gate --scheduler`: `NAME` makes the Dask worker gating the file NAME exit, every time; "
             "`NAME:MARKER` once (while the file MARKER does not exist); comma-separated."),
)


def read(environ=None, fields=None) -> dict:
    """The settings the environment sets: ``{field: value}`` for each variable set and not blank (only those of
    ``fields`` when given: a variable is read only where its setting is used).

    A read timeout it cannot take is an :class:`~cadartifact.execution.settings.InvalidValue`: its error is raised
    by the read that needs the timeout.

    Raises
    ------
    OptionError
        Naming the variable, for a value it cannot take.
    """
    environ = os.environ if environ is None else environ
    out = {}
    for var in ENVIRONMENT:
        if fields is not None and var.field not in fields:
            continue
        raw = environ.get(var.name)
        if raw is None or not raw.strip():
            continue
        out[var.field] = var.parse(var.name, raw)
    return out


def execution_settings(environ=None, **options) -> ExecutionSettings:
    """The run's :class:`ExecutionSettings`: the environment's, then ``options`` (the command line's, not None).

    Raises
    ------
    OptionError
        A variable's or an option's value is invalid.
    """
    options = {k: v for k, v in options.items() if v is not None}
    # an option replaces its variable, which is then not read at all (its bad value stops nothing)
    fields = [v.field for v in ENVIRONMENT if not v.field.startswith("cluster.") and v.field not in options]
    return ExecutionSettings(**read(environ, fields), **options)


def cluster_options(address: str, environ=None, **options) -> ClusterOptions:
    """:class:`ClusterOptions` for ``--scheduler ADDRESS``: the command line's ``options`` and the environment's
    cluster fields (face batches, the worker-exit test hook)."""
    fields = [v.field for v in ENVIRONMENT if v.field.startswith("cluster.")]
    values = {k.partition(".")[2]: v for k, v in read(environ, fields).items()}
    return ClusterOptions(address, **options, **values)
