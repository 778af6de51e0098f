"""The OBJ reader's lines: each ``v`` and ``f`` statement's 1-based line, as an editor (and SARIF) counts them,
through comments, blank lines, skipped statements and continued statements."""

import pytest

from cadartifact.exchange.obj import parse_obj, statement_lines

TEXT = """# header comment

o thing
v 0 0 0
v 1 0 0   # trailing comment
# a comment line
v 1 \\
  1 \\
  0
vt 0 0

v 0 1 0
f 1 2 \\
  3 4
# between
f 4/1 3/1 2/1
"""


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"], ids=["LF", "CRLF", "CR"])
def test_vertex_and_face_lines(tmp_path, end):
    path = tmp_path / "lines.obj"
    path.write_bytes(TEXT.replace("\n", end).encode())
    data = parse_obj(path)
    assert data.vertex_lines == [4, 5, 7, 12]
    assert data.face_lines == [13, 16]
    lines = TEXT.split("\n")
    assert all(lines[k - 1].startswith("v ") for k in data.vertex_lines)
    assert all(lines[k - 1].startswith("f ") for k in data.face_lines)


def test_statement_lines_yields_each_statement_at_its_first_line():
    got = [(line, tokens[0]) for line, tokens in statement_lines(TEXT)]
    assert got == [(3, "o"), (4, "v"), (5, "v"), (7, "v"), (10, "vt"), (12, "v"), (13, "f"), (16, "f")]
    assert dict(statement_lines(TEXT))[7] == ["v", "1", "1", "0"]


def test_only_lf_cr_and_crlf_end_lines():
    """A form feed or U+2028 inside a line is whitespace, not a line end (str.splitlines would count it)."""
    text = "v 0 0 0\x0c\nv 1\u2028 0 0\nf 1 2\x0b 3\n"
    assert [line for line, _ in statement_lines(text)] == [1, 2, 3]


def test_the_mesh_keeps_the_lines(tmp_path):
    from cadartifact.exchange.obj import read_obj

    path = tmp_path / "quad.obj"
    path.write_text("# one quad\nv 0 0 0\nv 1 0 0\n\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    mesh = read_obj(path).mesh
    assert mesh.vertex_lines == (2, 3, 5, 6) and mesh.face_lines == (7,)
