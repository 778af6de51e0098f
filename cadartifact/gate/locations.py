"""Where a gate finding is, independent of the machine: the run's root, paths relative to it, the record of a
face, and the finding's fingerprint.

A CI service recognises a finding from one run to the next by its fingerprint (GitHub code scanning: SARIF
``partialFingerprints``; GitLab Code Quality: ``fingerprint``; the gate's ``--baseline``). It must not change
when the checkout moves, a line is inserted above the face or the face's numbers change, and two findings of a
run must never share it. So it is a hash of three things only:

- the file's path relative to the run's root (``/``-separated): the working directory when every file lies in
  it (a CI job runs in its checkout), else the deepest folder holding every file;
- the record the finding is about: a STEP face's entity (``#1234``, the ``ADVANCED_FACE`` record; an edge's
  finding names its edge's record the same way), a face without an entity by its index (``face 3``: OBJ
  charts, BREP files), an OBJ cage's extraordinary vertex by its OBJ index (``vertex 12``, 1-based as the
  file's ``f`` statements count; a triangle's or n-gon's centre, which the file does not hold, ``centre of
  polygon 5``: the file's 5th ``f`` statement), the file itself ``""``;
- the criterion: ``ripple`` (CA001 and CA002 alike, so that a face moving from warn to fail stays one alert),
  else the rule's name (``unreadable-file``, ``pdq-waviness``...).

Standard library only.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

__all__ = ["FINGERPRINT_KEY", "ROOT_ID", "run_root", "relative", "face_record", "vertex_record", "fingerprint",
           "Fingerprints"]

#: The key of the fingerprint in SARIF ``partialFingerprints`` (v2: path relative to the root, record, criterion).
FINGERPRINT_KEY = "cadartifactFinding/v2"
#: The SARIF ``uriBaseId`` every location is relative to (``originalUriBaseIds`` gives its absolute URI).
ROOT_ID = "SRCROOT"


def run_root(paths, cwd: str | None = None) -> str:
    """The run's root: ``cwd`` (default: the working directory) when every path lies inside it, else the deepest
    folder holding every path (absolute; ``cwd`` when there is no path or the paths are on several drives)."""
    cwd = os.path.abspath(cwd or os.getcwd())
    absolute = [os.path.abspath(p) for p in paths]
    if all(_inside(p, cwd) for p in absolute):
        return cwd
    try:
        return os.path.commonpath([os.path.dirname(p) for p in absolute])
    except ValueError:  # several drives: no common folder
        return cwd


def _inside(path: str, folder: str) -> bool:
    try:
        return os.path.commonpath([path, folder]) == folder
    except ValueError:
        return False


def relative(path: str, root: str) -> str:
    """``path`` relative to ``root``, ``/``-separated (the absolute path's POSIX form when it is not inside)."""
    absolute = os.path.abspath(path)
    if not _inside(absolute, root):
        return Path(absolute).as_posix()
    return Path(os.path.relpath(absolute, root)).as_posix()


def face_record(face: dict | None) -> str:
    """The record a face's finding is about: ``"#1234"`` (its STEP entity), ``"face 3"`` (no entity), ``""``
    (no face: a finding about the whole file)."""
    if face is None:
        return ""
    return f"#{face['entity']}" if face.get("entity") is not None else f"face {face['face']}"


def vertex_record(vertex: dict) -> str:
    """The record an extraordinary vertex's finding is about (an ``extraordinary`` entry of the document, whose
    ids are 0-based): ``"vertex 12"``, its OBJ index, or ``"centre of polygon 5"``, its face's ordinal in the
    file (1-based both, as a user finds them in the file)."""
    if vertex.get("face") is None:
        return f"vertex {int(vertex['vertex']) + 1}"
    return f"centre of polygon {int(vertex['face']) + 1}"


def fingerprint(path: str, record: str, criterion: str) -> str:
    """32 hex digits of SHA-256 over ``path \\0 record \\0 criterion`` (``path`` relative to the run's root)."""
    return hashlib.sha256("\0".join((path, record, criterion)).encode("utf-8", "backslashreplace")).hexdigest()[:32]


class Fingerprints:
    """The fingerprints of one run's findings, unique: a repeated ``(path, record, criterion)`` (a file given twice)
    gets its occurrence number as a fourth part, so that the first keeps the plain fingerprint."""

    def __init__(self):
        self._seen: dict[tuple, int] = {}

    def __call__(self, path: str, record: str, criterion: str) -> str:
        key = (path, record, criterion)
        n = self._seen.get(key, 0)
        self._seen[key] = n + 1
        return fingerprint(path, record, criterion if n == 0 else f"{criterion}\0{n}")
