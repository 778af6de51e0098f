"""The pcurves of STEP edges (cadartifact/exchange/step_pcurves.py): what crashes OCCT's reader in them is an
error naming the record, before OCCT runs.

Measured on linkrods.step (2026-12-04): a pcurve control point renamed or made a DIRECTION, or the pcurve's
curve keyword corrupted, crashed the reader (SIGSEGV: "the STEP reader crashed on this file"); a control point
with no or malformed coordinates was read without a word. Family: 40 of the file's 216 B-spline pcurves per
way, a control point of each drawn at random and broken four ways; the message is checked against an
independent reading of the mutant's text (the records' lines found by a plain search).
"""

from __future__ import annotations

import random
import re

import pytest

from cadartifact.errors import FileFormatError
from cadartifact.exchange.step_refs import check_references
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REALDATA

LINKRODS = REALDATA / "step" / "linkrods.step"

BREAKS = {
    "renamed": (lambda body: body.replace("CARTESIAN_POINT", "XCARTESIAN_POINT", 1),
                "is XCARTESIAN_POINT (line {line}), which cannot stand there (expected CARTESIAN_POINT)"),
    "a direction": (lambda body: body.replace("CARTESIAN_POINT", "DIRECTION", 1),
                    "is DIRECTION (line {line}), which cannot stand there (expected CARTESIAN_POINT)"),
    "no coordinates": (lambda body: "CARTESIAN_POINT('')",
                       "its record (line {line}) is not a point with two coordinates"),
    "a letter in a number": (lambda body: re.sub(r"(\d)(\d)", r"\1x", body, count=1),
                             "its record (line {line}) is not a point with two coordinates"),
}


@pytest.fixture(scope="module")
def text(realdata) -> str:
    return LINKRODS.read_bytes().decode("latin-1")


def _line(text: str, ident: str) -> int:
    """The 1-based line where ``#ident =`` starts (independent of the scan's own index)."""
    m = re.search(r"(?m)^#" + ident + r"\s*=", text)
    return text.count("\n", 0, m.start()) + 1


def _pcurve_splines(text: str) -> list[tuple[str, str, list[str]]]:
    """``(spline id, its keyword as the message names it, its control point ids)`` of every B-spline curve that
    a DEFINITIONAL_REPRESENTATION names (how linkrods writes pcurves), by a plain reading of the text."""
    records = dict(re.findall(r"(?ms)^#(\d+)\s*=\s*(.*?);\s*$", text))
    out = []
    for body in records.values():
        if not body.startswith("DEFINITIONAL_REPRESENTATION"):
            continue
        for item in re.findall(r"#(\d+)", body)[:-1]:
            spline = records[item]
            if spline.startswith("B_SPLINE_CURVE_WITH_KNOTS"):
                name = "B_SPLINE_CURVE_WITH_KNOTS"
            elif spline.startswith("(") and "B_SPLINE_CURVE" in spline:
                name = "complex instance"
            else:
                continue
            out.append((item, name, list(dict.fromkeys(re.findall(r"#(\d+)", spline)))))
    return out


def test_the_intact_file_passes(text):
    check_references(LINKRODS, text)
    assert len(_pcurve_splines(text)) >= 100  # the family below is not empty


@pytest.mark.slow
@pytest.mark.parametrize("how", sorted(BREAKS))
def test_a_broken_control_point_of_every_b_spline_pcurve_is_named(text, how):
    rng = random.Random(f"pcurves-{how}")
    breaker, said = BREAKS[how]
    splines = _pcurve_splines(text)
    first_owner = {}  # a point shared by two pcurves is named with the first in the scan's order
    for spline, name, points in splines:
        for p in points:
            first_owner.setdefault(p, (spline, name))
    for spline, name, points in rng.sample(splines, min(len(splines), 40)):
        point = rng.choice(points)
        m = re.search(r"(?m)^#" + point + r"\s*=\s*(CARTESIAN_POINT\([^;]*\))\s*;", text)
        mutant = text[:m.start(1)] + breaker(m.group(1)) + text[m.end(1):]
        with pytest.raises(FileFormatError) as caught:
            check_references(LINKRODS, mutant)
        owner, owner_name = first_owner[point]
        want = (f"{LINKRODS}: #{point} is referenced by {owner_name} #{owner} (line {_line(mutant, owner)}) as a "
                f"control point of a pcurve, and " + said.format(line=_line(mutant, point)))
        assert str(caught.value) == want


def test_a_corrupted_pcurve_keyword_is_named(text):
    m = re.search(r"(?m)^#(\d+) = B_SPLINE_CURVE_WITH_KNOTS\(", text)
    ident = m.group(1)
    rep = re.search(r"(?m)^#(\d+) = DEFINITIONAL_REPRESENTATION\('',\(#" + ident + r"\)", text).group(1)
    mutant = text.replace(m.group(0), f"#{ident} = B_SPLINE_CURVE_WITH_KNOTX(", 1)
    with pytest.raises(FileFormatError, match=re.escape(
            f"#{ident} is referenced by DEFINITIONAL_REPRESENTATION #{rep} (line {_line(mutant, rep)}) as its "
            f"curve, and is B_SPLINE_CURVE_WITH_KNOTX (line {_line(mutant, ident)}), which cannot stand there")):
        check_references(LINKRODS, mutant)


@pytest.mark.parametrize("before, after", [
    ("#29 = PCURVE('',#30,#35);", "#29 = XPCURVE('',#30,#35);"),
    ("#35 = DEFINITIONAL_REPRESENTATION(", "#35 = XDEFINITIONAL_REPRESENTATION("),
    ("#29 = PCURVE('',#30,#35);", "#29 = PCURVE('',#30,#37);"),
    ("#38 = CARTESIAN_POINT('',(4.759988869076E-002,4.712388980385));",
     "#38 = CARTESIAN_POINT('',(4.759988869076E-002,4.712388980385,0.));"),
], ids=["pcurve keyword", "representation keyword", "representation a point", "a 3-D control point"])
def test_what_occt_reads_without_harm_is_left_to_it(text, before, after):
    """A pcurve OCCT reads its own way (a corrupted PCURVE or representation keyword, a representation that is
    not one, a third coordinate): the file's faces and report are as the intact file's (checked on linkrods,
    2026-12-04), so the scan does not refuse it."""
    assert text.count(before) == 1
    check_references(LINKRODS, text.replace(before, after))


def test_the_gate_says_it_in_one_line_with_exit_2(text, tmp_path):
    from typer.testing import CliRunner

    from cadartifact.cli.app import app

    path = tmp_path / "rods.step"
    path.write_bytes(text.replace("#38 = CARTESIAN_POINT(", "#38 = XCARTESIAN_POINT(", 1).encode("latin-1"))
    r = CliRunner().invoke(app, ["gate", str(path), "--tol", "0.05"])
    assert r.exit_code == 2 and "crashed" not in r.output
    no_traceback(r)
    assert "#38 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36" in r.output


def test_a_semicolon_inside_a_string_does_not_hide_a_broken_point(text):
    """A ';' inside a name: the cleaned text empties strings, so the statements stay one per record and the
    broken point is named as in the usual file (the one by one reading is forced in the tests above)."""
    shifted = text.replace("#29 = PCURVE('',#30,#35);", "#29 = PCURVE('a;b',#30,#35);", 1)
    assert shifted != text
    check_references(LINKRODS, shifted)
    mutant = shifted.replace("#38 = CARTESIAN_POINT(", "#38 = XCARTESIAN_POINT(", 1)
    with pytest.raises(FileFormatError, match=re.escape(
            f"#38 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36 (line {_line(mutant, '36')}) as a control point of a "
            f"pcurve, and is XCARTESIAN_POINT (line {_line(mutant, '38')})")):
        check_references(LINKRODS, mutant)


# Found by an independent review (2026-12-04); each of these passed the scan and crashed OCCT's reader
# (SIGSEGV), checked on linkrods: a control point that is itself a pcurve spline, a representation whose
# context is '$' and whose item is a point, a PCURVE standing directly as an edge's curve.
@pytest.mark.parametrize("changes, said", [
    ([("#36 = B_SPLINE_CURVE_WITH_KNOTS('',3,(#37,#38,", "#36 = B_SPLINE_CURVE_WITH_KNOTS('',3,(#37,#36,")],
     "#36 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36 (line {36}) as a control point of a pcurve, and is the "
     "B_SPLINE_CURVE_WITH_KNOTS itself"),
    ([("#36 = B_SPLINE_CURVE_WITH_KNOTS('',3,(#37,#38,", "#36 = B_SPLINE_CURVE_WITH_KNOTS('',3,(#37,#263,")],
     "#263 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36 (line {36}) as a control point of a pcurve, and is "
     "B_SPLINE_CURVE_WITH_KNOTS (line {263}), which cannot stand there"),
    ([("#35 = DEFINITIONAL_REPRESENTATION('',(#36),#62)", "#35 = DEFINITIONAL_REPRESENTATION('',(#37),$)")],
     "#37 is referenced by DEFINITIONAL_REPRESENTATION #35 (line {35}) as its curve, and is CARTESIAN_POINT "
     "(line {37}), which cannot stand there"),
    ([("#18 = EDGE_CURVE('',#19,#21,#23,.T.)", "#18 = EDGE_CURVE('',#19,#21,#29,.T.)"),
      ("#23 = SURFACE_CURVE('',#24,(#29,#63),.PCURVE_S2.)", "#23 = SURFACE_CURVE('',#24,(#63),.PCURVE_S2.)"),
      ("#38 = CARTESIAN_POINT(", "#38 = DIRECTION(")],
     "#38 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36 (line {36}) as a control point of a pcurve, and is "
     "DIRECTION (line {38}), which cannot stand there"),
], ids=["itself a control point", "another pcurve a control point", "a point as the item, '$' context",
        "a pcurve as the edge's curve"])
@pytest.mark.parametrize("reading", ["batch", "one by one"])
def test_what_crashed_occt_past_the_first_scan_is_named(text, monkeypatch, changes, said, reading):
    """Each case by both readings: the batch one (statements one per record, the usual file) and the one by
    one reading (forced: what a section whose statements are not one per record gets)."""
    if reading == "one by one":
        from cadartifact.exchange import step_records

        monkeypatch.setattr(step_records.Records, "aligned", property(lambda self: False))
    mutant = text
    for before, after in changes:
        assert mutant.count(before) == 1
        mutant = mutant.replace(before, after)
    want = re.sub(r"\{(\d+)\}", lambda m: str(_line(mutant, m.group(1))), said)  # {N}: the line of #N
    with pytest.raises(FileFormatError, match=re.escape(want)):
        check_references(LINKRODS, mutant)


@pytest.mark.parametrize("how", ["renamed", "a direction"])
def test_the_one_by_one_reading_names_what_the_batch_names(text, monkeypatch, how):
    """A sample of the break family, read one by one (forced) and in a batch: the same message."""
    from cadartifact.exchange import step_records

    rng = random.Random(f"one-by-one-{how}")
    breaker = BREAKS[how][0]
    for spline, _, points in rng.sample(_pcurve_splines(text), 8):
        m = re.search(r"(?m)^#" + rng.choice(points) + r"\s*=\s*(CARTESIAN_POINT\([^;]*\))\s*;", text)
        mutant = text[:m.start(1)] + breaker(m.group(1)) + text[m.end(1):]
        said = []
        for aligned in (None, False):
            with monkeypatch.context() as patch:
                if aligned is False:
                    patch.setattr(step_records.Records, "aligned", property(lambda self: False))
                with pytest.raises(FileFormatError) as caught:
                    check_references(LINKRODS, mutant)
            said.append(str(caught.value))
        assert said[0] == said[1]


def test_a_space_before_the_data_sections_semicolon_changes_nothing(text):
    """``DATA ;`` (Part 21 allows space between tokens): the section is found, and a broken control point is
    named as in the usual file (the whole text was read as the section before, and nothing was named)."""
    spaced = text.replace("\nDATA;", "\nDATA ;", 1)
    assert spaced != text
    check_references(LINKRODS, spaced)
    with pytest.raises(FileFormatError, match=re.escape("#38 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36")):
        check_references(LINKRODS, spaced.replace("#38 = CARTESIAN_POINT(", "#38 = DIRECTION(", 1))


def test_a_pcurve_spline_without_control_points_does_not_crash_the_scan(tmp_path):
    """A 25-record file whose only pcurve spline lists no control points ('$'): the scan ends without an
    error of its own (the text check before it names such a spline when the file is read)."""
    text = """ISO-10303-21;
HEADER;
FILE_DESCRIPTION((''),'2;1');
FILE_NAME('a','',(''),(''),'','','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));
ENDSEC;
DATA;
#12=MANIFOLD_SOLID_BREP('',#13);
#13=CLOSED_SHELL('',(#14));
#14=ADVANCED_FACE('',(#15),#30,.T.);
#15=FACE_OUTER_BOUND('',#16,.T.);
#16=EDGE_LOOP('',(#17));
#17=ORIENTED_EDGE('',*,*,#18,.T.);
#18=EDGE_CURVE('',#19,#19,#23,.T.);
#19=VERTEX_POINT('',#20);
#20=CARTESIAN_POINT('',(0.,0.,0.));
#23=SURFACE_CURVE('',#24,(#29),.PCURVE_S1.);
#24=LINE('',#20,#25);
#25=VECTOR('',#26,1.);
#26=DIRECTION('',(1.,0.,0.));
#29=PCURVE('',#30,#35);
#30=PLANE('',#31);
#31=AXIS2_PLACEMENT_3D('',#20,#32,#26);
#32=DIRECTION('',(0.,0.,1.));
#35=DEFINITIONAL_REPRESENTATION('',(#36),#62);
#36=B_SPLINE_CURVE_WITH_KNOTS('',1,$,.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);
#37=CARTESIAN_POINT('',(0.,0.));
#38=CARTESIAN_POINT('',(1.,0.));
#62=( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() REPRESENTATION_CONTEXT('2D SPACE','') );
ENDSEC;
END-ISO-10303-21;
"""
    check_references(tmp_path / "mini.step", text)
