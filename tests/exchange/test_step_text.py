"""The STEP entity-line scan (:mod:`cadartifact.exchange.step_text`) against a character-by-character reference.

The module scans with one regex pass (fast on multi-megabyte files); the reference below is the plain
state machine it replaced, kept here as the second road: both must give the same ``(id, line, keyword)``
list on the real files, the samples and generated text full of quotes, comments and semicolons.
"""

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadartifact.exchange import step_text
from cadartifact.testing.paths import REAL_STEP, ROOT

_RECORD = re.compile(r"#(\d+)\s*=\s*([A-Za-z_][A-Za-z0-9_]*|\()")
REAL = REAL_STEP


def reference(text: str) -> tuple:
    out = []
    line = 1
    i, n = 0, len(text)
    at_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif c == "'":
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


def scan(tmp_path, text: str) -> tuple:
    p = tmp_path / "x.step"
    p.write_bytes(text.encode("latin-1"))
    return tuple(step_text.entity_lines(p))


def files():
    found = sorted((ROOT / "cadartifact" / "samples").glob("*.step"))
    return found + (sorted(REAL.iterdir()) if REAL.is_dir() else [])


@pytest.mark.parametrize("path", files(), ids=lambda p: p.name)
def test_real_and_sample_files_match_the_reference(path):
    text = path.read_bytes().decode("latin-1")
    got = tuple(step_text.entity_lines(path))
    assert got == reference(text) and len(got) > 10
    first = {}
    for ident, line, _ in got:
        first.setdefault(ident, line)
    for ident in list(first)[:: max(1, len(first) // 50)]:
        assert step_text.entity_line(path, ident) == first[ident]
    assert step_text.entity_line(path, None) is None and step_text.entity_line(path, 10 ** 12) is None


PIECES = ["#1=A(", "#22 = B_C(", "#3=(", "#", "=", ";", "'", "''", "/*", "*/", "\n", " ", "x", "(", ")",
          ",", "'a;b'", "/* #9=C(); */", "#7\n=\nD("]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from(PIECES), max_size=40))
def test_generated_text_matches_the_reference(tmp_path_factory, pieces):
    text = "".join(pieces)
    assert scan(tmp_path_factory.mktemp("s"), text) == reference(text)


def test_unreadable_file_is_empty(tmp_path):
    assert step_text.entity_lines(tmp_path / "missing.step") == []
    assert step_text.entity_line(tmp_path / "missing.step", 1) is None
