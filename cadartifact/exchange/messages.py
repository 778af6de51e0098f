"""The warning category of the readers (a file or face that loads but cannot be analysed)."""

from __future__ import annotations

import warnings

__all__ = ["LoadWarning", "warn"]


class LoadWarning(UserWarning):
    """A file with no analysable face, or a face/chart skipped as degenerate."""


def warn(message: str, stacklevel: int = 4) -> None:
    """Issue ``message`` as a :class:`LoadWarning` (pointing at the caller of ``read``/``load``)."""
    warnings.warn(message, LoadWarning, stacklevel=stacklevel)
