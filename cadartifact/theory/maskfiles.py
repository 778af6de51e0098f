"""Mask files: a scheme given as ``file:PATH`` (what ``cadartifact design`` writes), usable wherever a scheme name is.

Two formats: JSON with a ``"mask"`` array of numbers (the design document; other keys are ignored) or a NumPy
``.npy`` array. :func:`cadartifact.theory.catalogue.scheme` resolves such names.
"""

from __future__ import annotations

import json
import os

import numpy as np

from ..errors import SchemeError

__all__ = ["FILE_PREFIX", "is_file_name", "mask_path", "read_mask"]

#: Prefix of a scheme name that is a mask file.
FILE_PREFIX = "file:"

_EXPECTED = "a mask file: JSON with a \"mask\" array of numbers (cadartifact design writes one) or a .npy array"


def is_file_name(name: str) -> bool:
    """Whether ``name`` (a string) is a ``file:PATH`` scheme name (prefix case-insensitive)."""
    return name.strip()[:len(FILE_PREFIX)].lower() == FILE_PREFIX


def mask_path(name: str) -> tuple[str, int, int]:
    """``(absolute path, size, modification time ns)`` of a ``file:PATH`` name (the cache key of its scheme).

    Raises
    ------
    SchemeError
        The file cannot be read.
    """
    path = os.path.expanduser(name.strip()[len(FILE_PREFIX):].strip())
    try:
        st = os.stat(path)
        if not os.path.isfile(path):
            raise IsADirectoryError(21, "not a file")
    except OSError as exc:
        raise SchemeError("scheme", "a readable mask file after 'file:' (JSON with a \"mask\" array, or .npy)",
                          f"{name.strip()} ({exc.strerror or exc})") from None
    return os.path.abspath(path), int(st.st_size), int(st.st_mtime_ns)


def read_mask(name: str, path: str) -> np.ndarray:
    """The mask array in the file ``path`` (``name`` is quoted in errors).

    Raises
    ------
    SchemeError
        Not JSON/.npy, no ``"mask"`` key, or not an array of numbers.
    """
    try:
        if path.lower().endswith(".npy"):
            array = np.load(path, allow_pickle=False)
        else:
            with open(path, encoding="utf-8") as fh:
                doc = json.load(fh)
            array = doc.get("mask") if isinstance(doc, dict) else doc
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise SchemeError("scheme", _EXPECTED, f"{name} ({type(exc).__name__}: {exc})") from None
    if array is None:
        raise SchemeError("scheme", _EXPECTED, f"{name} (no \"mask\" key)")
    try:
        return np.array(array, dtype=float)
    except (TypeError, ValueError):
        raise SchemeError("scheme", _EXPECTED, f"{name} (the mask is not an array of numbers)") from None
