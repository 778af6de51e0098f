"""File checks shared by every reader (no OCP)."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import FileFormatError, InputError

__all__ = ["check_file"]


def check_file(path: str | os.PathLike) -> Path:
    """Return ``path`` as a Path if it is a readable, non-empty file, else raise :class:`InputError`."""
    path = Path(path)
    if not path.exists():
        raise InputError(path, "file not found")
    if not path.is_file():
        raise InputError(path, "not a file")
    try:
        size = path.stat().st_size
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise InputError(path, f"cannot be read ({exc.strerror or exc})") from None
    if size == 0:
        raise FileFormatError(path, "empty file")
    return path
