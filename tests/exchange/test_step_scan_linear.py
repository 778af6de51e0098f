"""The STEP text scans cannot backtrack on adversarial input (issue 27): every pattern they run is linear.

The exact record regex of the last round (``(?:[^;']|'(?:[^']|'')*')*;``) nested two repetitions that can
split a run of quotes in exponentially many ways; it is gone: the scans now run on the DATA section with its
strings emptied and comments removed by one non-backtracking pass (``step_scan.clean_data``), where a ``;``
always ends a statement. No timing asserts: each input below is large enough (about a megabyte) that a
quadratic pass would take minutes and an exponential one would never end, and the scans run in a child
process with a generous limit, so a regression fails the test instead of hanging the suite.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from cadartifact.errors import FileFormatError
from cadartifact.exchange.step_refs import check_references
from cadartifact.exchange.step_scan import check_step_text, clean_data, data_section
from cadartifact.testing.paths import ROOT

HOOD = ROOT / "samples" / "car_hood_coarse.step"
POINT = "#23 = CARTESIAN_POINT('',(0.,0.,-14.));"
N = 200_000

#: (name, record put in place of #23) - each about N characters of what makes a backtracking regex explode
PATHOLOGICAL = {
    "a run of quotes, odd": "#23 = CARTESIAN_POINT(" + "'" * (2 * N + 1) + ",(0.,0.,-14.));",
    "a run of quotes, even": "#23 = CARTESIAN_POINT(" + "'" * (2 * N) + ",(0.,0.,-14.));",
    "escaped quotes, unterminated": "#23 = CARTESIAN_POINT('" + "a''" * N + ",(0.,0.,-14.));",
    "semicolons in strings": "#23 = CARTESIAN_POINT(" + "';'," * N + "(0.,0.,-14.));",
    "unterminated comments": "#23 = CARTESIAN_POINT(''," + "/*" * N + "(0.,0.,-14.));",
    "comments and stars": "#23 = CARTESIAN_POINT(''," + "/**" * N + "*/(0.,0.,-14.));",
    "a keyword's word many times": "#23 = CARTESIAN_POINT(''," + "B_SPLINE " * (N // 4) + "(0.,0.,-14.));",
    "candidate numbers many times": "#23 = CARTESIAN_POINT(''," + "1E6," * N + "(0.,0.,-14.));",
    "long digit runs": "#23 = CARTESIAN_POINT('',(0." + "1" * N + ",0.,-14.));",
    "nested parentheses": "#23 = CARTESIAN_POINT(''," + "(" * N + "0." + ")" * N + ");",
    "an unclosed pole row": "#23 = B_SPLINE_SURFACE_WITH_KNOTS('',3,3,((" + "#1," * N + "#2);",
}

CODE = """
import sys
from cadartifact.errors import FileFormatError
from cadartifact.exchange.step_refs import check_references
from cadartifact.exchange.step_scan import check_step_text
from cadartifact.exchange.step_text import text_entity_lines
text = open(sys.argv[1], encoding="latin-1").read()
text_entity_lines(text)
for check in (check_step_text, check_references):
    try:
        check("m.step", text)
    except (FileFormatError, RecursionError) as exc:
        print(type(exc).__name__, str(exc)[:200])
print("done")
"""


@pytest.mark.parametrize("name", sorted(PATHOLOGICAL))
def test_the_scans_end_on_pathological_records(tmp_path, name):
    text = HOOD.read_bytes().decode("latin-1")
    assert POINT in text
    path = tmp_path / "m.step"
    path.write_text(text.replace(POINT, PATHOLOGICAL[name]), encoding="latin-1")
    # a guard, not a timing assert: the linear scans take well under a second here
    out = subprocess.run([sys.executable, "-c", CODE, str(path)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and out.stdout.splitlines()[-1] == "done", out.stderr[-2000:]


def test_clean_data_empties_strings_and_removes_comments_only():
    data = "DATA;\n#1 = A('x;#2=B(1e300)','it''s',/* a 'quote; */ 1.5,'');\n#2 = B(/* open"
    clean = clean_data(data)
    assert clean == "DATA;\n#1 = A('','''',  1.5,'');\n#2 = B( "
    assert clean_data("#1 = A('no end;);") == "#1 = A('no end;);"  # an unterminated string stays (OCCT rejects it)


def test_a_semicolon_in_a_string_does_not_move_the_record_a_number_is_blamed_on():
    text = HOOD.read_bytes().decode("latin-1").replace(
        POINT, "#23 = CARTESIAN_POINT('a;#99 = X(',(0.,\n1e300,-14.));")
    line = text[:text.index("#23 = CARTESIAN_POINT('a;")].count("\n") + 1
    with pytest.raises(FileFormatError, match=rf"m\.step: #23 \(line {line}\): number '1e300'"):
        check_step_text("m.step", text)


def test_a_reference_in_a_comment_or_string_is_not_a_reference():
    text = HOOD.read_bytes().decode("latin-1").replace(POINT, "#23 = CARTESIAN_POINT('#77777',/* #88888 */(0.,0.,-14.));")
    check_references("m.step", text)
    assert "#77777" not in clean_data(data_section(text))
