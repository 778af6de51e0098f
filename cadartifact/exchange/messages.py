"""The warning category of the readers (a file or face that loads but cannot be analysed)."""

from __future__ import annotations

import warnings

__all__ = ["LoadWarning", "QUOTE_LIMIT", "quote", "warn"]


class LoadWarning(UserWarning):
    """A file with no analysable face, or a face/chart skipped as degenerate."""


def warn(message: str, stacklevel: int = 4) -> None:
    """Issue ``message`` as a :class:`LoadWarning` (pointing at the caller of ``read``/``load``)."""
    warnings.warn(message, LoadWarning, stacklevel=stacklevel)


#: Most characters of user input (a token, a line) quoted in a message.
QUOTE_LIMIT = 200


def quote(text: str, limit: int = QUOTE_LIMIT) -> str:
    """``repr(text)``, cut to ``limit`` characters with the full length said (a 469 KB face line stays one line)."""
    text = str(text)
    if len(text) <= limit:
        return repr(text)
    return repr(text[:limit]) + f"... ({len(text)} characters)"
