"""Where STEP entities are defined in the file's text (for reports that point at a line).

Text only, no OCCT: a STEP (ISO 10303-21) DATA section holds records ``#id = KEYWORD(...);`` (or a
complex ``#id = (A(...) B(...));``), possibly spanning lines, with ``/* comments */`` and quoted
strings that may contain any of ``#=;``.
"""

from __future__ import annotations

import functools
import os
import re

__all__ = ["entity_lines", "entity_line", "face_id_from_model", "remember_face_lines", "text_entity_lines"]

_RECORD = re.compile(r"#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*|\()")


def entity_lines(path) -> list[tuple[int, int, str]]:
    """``[(id, line, keyword)]`` of every entity instance, in file order (lines 1-based; keyword
    upper case, ``"("`` for a complex instance). Empty for a file that cannot be read."""
    try:
        stat = os.stat(path)
    except OSError:
        return []
    return list(_entity_lines(os.fspath(path), stat.st_mtime_ns, stat.st_size))


#: What matters to the scan, in one pass of the regex engine: strings ('' escapes a quote; an
#: unterminated one runs to the end), comments, statement ends and record heads.
_TOKENS = re.compile(r"'(?:[^']|'')*(?:'|\Z)|/\*.*?(?:\*/|\Z)|;|#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*|\()",
                     re.DOTALL)
_BLANK_OR_HASH = re.compile(r"[\s#]*\Z")


@functools.lru_cache(maxsize=32)
def _entity_lines(path: str, mtime: int, size: int) -> tuple:
    try:
        with open(path, encoding="latin-1") as fh:
            text = fh.read()
    except OSError:
        return ()
    return text_entity_lines(text)


def text_entity_lines(text: str) -> tuple:
    """:func:`entity_lines` of a STEP text (one linear pass: the tokens' regex cannot backtrack)."""
    # a record counts only at the start of a statement (nothing but blanks, comments and strings since
    # the last ';'); the regex skips the text between tokens, which is scanned only while at a start
    out = []
    line, counted = 1, 0  # line number at offset ``counted``
    at_start, since = True, 0  # ``since``: end of the last token
    for m in _TOKENS.finditer(text):
        ident = m.group(1)
        if ident is None:
            c = text[m.start()]
            if at_start and not _BLANK_OR_HASH.match(text, since, m.start()):
                at_start = False
            if c == ";":
                at_start = True
        else:
            if at_start and _BLANK_OR_HASH.match(text, since, m.start()):
                line += text.count("\n", counted, m.start())
                counted = m.start()
                out.append((int(ident), line, m.group(2).upper()))
            at_start = False
        since = m.end()
    return tuple(out)


def entity_line(path, entity: int | None) -> int | None:
    """The line where ``#entity`` is defined, None when unknown (a face's from :func:`remember_face_lines` when the
    read left them, else from the index of every record)."""
    if entity is None:
        return None
    try:
        stat = os.stat(path)
        known = _face_lines.get((os.fspath(path), stat.st_mtime_ns, stat.st_size))
    except OSError:
        known = None
    if known is not None and entity in known:
        return known[entity]
    return _lines_by_id(path).get(entity)


_face_lines: dict = {}  # (path, mtime, size) -> {face id: line}, left by the read (a few files)
_FACE_HEAD = re.compile(r";\s*#(\d+)\s*=\s*ADVANCED_FACE\b")


def remember_face_lines(path, text: str, data: str, clean: str) -> None:
    """Index the lines of the ``ADVANCED_FACE`` records of a STEP text for :func:`entity_line` without a full
    tokenizing pass: their heads are found in the file's own DATA section ``data`` and trusted only when they are
    exactly those found in ``clean`` (the same section with strings emptied and comments removed, where a head
    cannot be inside a string); otherwise nothing is remembered and :func:`entity_line` builds the full index.
    """
    found = list(_FACE_HEAD.finditer(data))
    if [m.group(1) for m in found] != _FACE_HEAD.findall(clean):
        return
    try:
        stat = os.stat(path)
    except OSError:
        return
    line, at = text.count("\n", 0, len(text) - len(data)) + 1, 0
    lines = {}
    for m in found:
        line += data.count("\n", at, m.start(1))
        at = m.start(1)
        lines.setdefault(int(m.group(1)), line)
    if len(_face_lines) > 16:
        _face_lines.clear()
    _face_lines[(os.fspath(path), stat.st_mtime_ns, stat.st_size)] = lines


def _lines_by_id(path) -> dict:
    try:
        stat = os.stat(path)
    except OSError:
        return {}
    return _index(os.fspath(path), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=8)
def _index(path: str, mtime: int, size: int) -> dict:
    out = {}
    for ident, line, _ in _entity_lines(path, mtime, size):
        out.setdefault(ident, line)  # the first definition, as a scan in file order finds it
    return out


def face_id_from_model(records, number: int | None) -> int | None:
    """The file's ``#id`` of model entity ``number`` given :func:`entity_lines` ``records``;
    None when unknown or when the file's record there is not an ``ADVANCED_FACE`` (numbering mismatch)."""
    if number is None or not 0 < number <= len(records) or records[number - 1][2] != "ADVANCED_FACE":
        return None
    return records[number - 1][0]
