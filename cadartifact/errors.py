"""Exceptions raised by cadartifact.

Every error a user can cause (a bad file, a bad option, a net the theory cannot
handle) is a :class:`CadArtifactError`. Its message is one line that names the
file or parameter and the problem; the CLI prints it and exits with
:attr:`CadArtifactError.exit_code` (2), never with a traceback.
"""

from __future__ import annotations

import os
from collections.abc import Iterable

__all__ = [
    "CadArtifactError",
    "InputError",
    "FileFormatError",
    "UnsupportedFormatError",
    "InvalidNetError",
    "OptionError",
    "SchemeError",
    "MissingDependencyError",
    "ArtifactToleranceError",
    "check_option",
    "one_line",
]

#: Longest message :func:`one_line` lets through.
MESSAGE_LIMIT = 600


class CadArtifactError(Exception):
    """Base class of every error cadartifact raises on purpose."""

    exit_code: int = 2


class InputError(CadArtifactError):
    """An input file is missing, empty, unreadable or malformed.

    Parameters
    ----------
    path : str or path-like or None
        The file the problem is in.
    problem : str
        What is wrong, in a few words.
    """

    def __init__(self, path: str | os.PathLike | None, problem: str):
        self.path = None if path is None else os.fspath(path)
        self.problem = problem
        super().__init__(problem if path is None else f"{self.path}: {problem}")


class FileFormatError(InputError):
    """A file is not what its extension says, or is truncated or corrupt."""


class UnsupportedFormatError(InputError):
    """A file extension cadartifact does not read."""


class InvalidNetError(CadArtifactError, ValueError):
    """A control net that cannot be analysed (NaN, degenerate, wrong shape)."""


class OptionError(CadArtifactError, ValueError):
    """A bad parameter: the message says which, what was expected and what was received."""

    def __init__(self, parameter: str, expected: str, received: object):
        self.parameter = parameter
        self.expected = expected
        self.received = received
        super().__init__(f"{parameter}: expected {expected}, received {received!r}")


class SchemeError(OptionError):
    """An unknown scheme name or a mask that is not a convergent binary scheme."""


class MissingDependencyError(CadArtifactError, ImportError):
    """An optional package is needed for this feature and is not installed."""


class ArtifactToleranceError(CadArtifactError):
    """Raised by the CadQuery hook when a face's artifact exceeds the tolerance."""

    exit_code = 1


def check_option(parameter: str, value: str, choices: Iterable[str]) -> str:
    """Return ``value`` if it is one of ``choices``, else raise :class:`OptionError` listing them."""
    choices = tuple(choices)
    if value not in choices:
        raise OptionError(parameter, "one of " + ", ".join(repr(c) for c in choices), value)
    return value


def one_line(message: str, limit: int = MESSAGE_LIMIT) -> str:
    """``message`` on one line (whitespace runs collapsed), cut to ``limit`` characters with ``...``."""
    text = " ".join(str(message).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."
