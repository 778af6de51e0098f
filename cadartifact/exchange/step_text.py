"""Where STEP entities are defined in the file's text (for reports that point at a line).

Text only, no OCCT: a STEP (ISO 10303-21) DATA section holds records ``#id = KEYWORD(...);`` (or a
complex ``#id = (A(...) B(...));``), possibly spanning lines, with ``/* comments */`` and quoted
strings that may contain any of ``#=;``.
"""

from __future__ import annotations

import functools
import os
import re

__all__ = ["entity_lines", "entity_line"]

_RECORD = re.compile(r"#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*|\()")


def entity_lines(path) -> list[tuple[int, int, str]]:
    """``[(id, line, keyword)]`` of every entity instance, in file order (lines 1-based; keyword
    upper case, ``"("`` for a complex instance). Empty for a file that cannot be read."""
    try:
        stat = os.stat(path)
    except OSError:
        return []
    return list(_entity_lines(os.fspath(path), stat.st_mtime_ns, stat.st_size))


@functools.lru_cache(maxsize=32)
def _entity_lines(path: str, mtime: int, size: int) -> tuple:
    try:
        with open(path, encoding="latin-1") as fh:
            text = fh.read()
    except OSError:
        return ()
    out = []
    line = 1
    i, n = 0, len(text)
    at_start = True  # at the start of a statement (after ';' or the DATA keyword)
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif c == "'":  # a string: '' is an escaped quote
            j = i + 1
            while j < n:
                if text[j] == "'":
                    if j + 1 < n and text[j + 1] == "'":
                        j += 2
                        continue
                    break
                j += 1
            line += text.count("\n", i, j)
            i = j + 1
        elif c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            line += text.count("\n", i, j)
            i = j
        elif c == ";":
            at_start = True
            i += 1
        elif c == "#" and at_start:
            m = _RECORD.match(text, i)
            if m:
                out.append((int(m.group(1)), line, m.group(2).upper()))
                at_start = False
            i += 1
        else:
            if not c.isspace():
                at_start = False if c != "#" else at_start
            i += 1
    return tuple(out)


def entity_line(path, entity: int | None) -> int | None:
    """The line where ``#entity`` is defined, None when unknown."""
    if entity is None:
        return None
    for ident, line, _ in entity_lines(path):
        if ident == entity:
            return line
    return None
