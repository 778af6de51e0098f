"""Huge and non-finite numbers of every spelling are an error of the STEP pre-scan (issue 27), before OCCT
sees them: ``1e300`` (no decimal point: not a STEP real, but OCCT's lexer takes it and then hangs until the
read timeout), ``1E+400``, ``-1e999``, ``1.e309``, integers beyond 1e12, and the NaN/INF words. The message
is one line naming the file, the entity and its line."""

from __future__ import annotations

import re

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.errors import FileFormatError
from cadartifact.exchange.load import read
from cadartifact.exchange.step_scan import check_step_text
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REAL_STEP, ROOT

HOOD = ROOT / "samples" / "car_hood_coarse.step"
POINT = "#23 = CARTESIAN_POINT('',(0.,0.,-14.));"

HUGE = ["1e300", "1E+400", "-1e999", "1.e309", "1e13", "+1E0013", "1.E13", "-.5E400", "9999999999999",
        "123456789012345678901234567890", "inf", "-INF", "+Inf", "Infinity", "-INFINITY", "NaN", "-nan", "1.#INF"]
FINE = ["1e12", "1E12", "-1e12", "1e-400", "999999999999", "1.E-300", "0.", "-.5", "1e6"]


def _hood(number: str, *, split: bool = False) -> str:
    text = HOOD.read_bytes().decode("latin-1")
    assert POINT in text
    record = f"#23 = CARTESIAN_POINT('',\n(0.,\n{number},-14.));" if split else f"#23 = CARTESIAN_POINT('',(0.,{number},-14.));"
    return text.replace(POINT, record)


def _line(text: str, ident: str) -> int:
    return text[:re.search(r"(?:^|;)\s*(" + ident + r"\s*=)", text, re.M).start(1)].count("\n") + 1


@pytest.mark.parametrize("number", HUGE)
def test_a_huge_or_non_finite_number_of_any_spelling_is_an_error_naming_entity_and_line(number):
    text = _hood(number)
    with pytest.raises(FileFormatError) as err:
        check_step_text("m.step", text)
    message = str(err.value)
    assert "\n" not in message and message.startswith("m.step: #23 ")
    assert f"(line {_line(text, '#23')})" in message and "not finite or exceeds" in message
    word = re.search(r"[A-Za-z]+", number)
    assert (word.group(0) if word and not re.fullmatch(r"[\d.eE+-]+", number) else number.lstrip("+")) in message


@pytest.mark.parametrize("number", FINE)
def test_large_finite_numbers_within_bounds_pass(number):
    check_step_text("m.step", _hood(number))


def test_the_line_is_the_entity_s_when_its_record_spans_lines():
    text = _hood("1e300", split=True)
    with pytest.raises(FileFormatError, match=rf"#23 \(line {_line(text, '#23')}\): number '1e300'"):
        check_step_text("m.step", text)


def test_a_number_inside_a_string_is_not_a_number():
    check_step_text("m.step", _hood("0.").replace("CARTESIAN_POINT('',(0.,0.", "CARTESIAN_POINT('1e300 inf',(0.,0.", 1))


@pytest.mark.parametrize("number", ["1e300", "1E+400", "-1e999", "1.e309", "inf"])
def test_the_cli_fails_in_one_line_before_occt_hangs(tmp_path, number, monkeypatch):
    path = tmp_path / "hood.step"
    path.write_text(_hood(number), encoding="latin-1")
    # a read that reached OCCT would hang until this timeout, and the message would say so
    from cadartifact.execution import child

    monkeypatch.setenv("CADARTIFACT_READ_TIMEOUT", "60")  # the CLI's (read at its edge)
    monkeypatch.setattr(child, "_settings", child.settings().replace(read_timeout=60.0))  # the library call's
    with pytest.raises(FileFormatError, match=r"#23 \(line \d+\): number"):
        read(path)
    r = CliRunner().invoke(app, ["advise", str(path), "--tol", "1", "--json"])
    assert r.exit_code == 2 and r.stdout == "", r.output
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and "#23 (line" in lines[0]
    no_traceback(r, r.stderr)


def _spline_records():
    """The B-spline records (grids collapsed) of the samples and real files, each also mutated the ways the
    bounds tests mutate them (a knot pair swapped, a multiplicity raised, a degree changed, a knot made huge)."""
    from cadartifact.exchange.step_scan import _records_with, clean_data, collapse_grids, data_section

    files = sorted((ROOT / "samples").glob("*.step"))
    real = REAL_STEP
    if real.exists():
        files += sorted(real.glob("*.st*p"))
    for path in files:
        clean = clean_data(data_section(path.read_bytes().decode("latin-1")))
        for _, body, _ in _records_with(clean, "B_SPLINE"):
            rec = collapse_grids(body)
            yield rec
            lists = list(re.finditer(r"\(([^()]*)\)", rec))
            for m in lists[:4]:
                items = m.group(1).split(",")
                if len(items) >= 2:
                    swapped = [items[1], items[0]] + items[2:]
                    yield rec[:m.start(1)] + ",".join(swapped) + rec[m.end(1):]
                    yield rec[:m.start(1)] + ",".join(["9"] + items[1:]) + rec[m.end(1):]
                    yield rec[:m.start(1)] + ",".join(["1.E13"] + items[1:]) + rec[m.end(1):]
                    yield rec[:m.start(1)] + ",".join(["NAN"] + items[1:]) + rec[m.end(1):]
            yield re.sub(r"(WITH_KNOTS\(\s*''\s*,\s*)\d+", r"\g<1>26", rec, count=1)


def test_the_fast_b_spline_checks_agree_with_the_full_parse():
    """The number scan's fast road (simple records converted by C calls, ``_possible``) says "no problem" only
    where the full parse and ``spline_problem`` say so, on every B-spline record of the samples and real files
    and on mutations of each."""
    from cadartifact.exchange.step_scan import _fast_spline, _possible, _spline, parse_parameters, spline_problem

    fast_used = checked = 0
    for rec in _spline_records():
        try:
            full = _spline(parse_parameters(rec))
        except ValueError:
            full = None
        fast = _fast_spline(rec)
        if fast is not None:
            fast_used += 1
            assert full is not None and fast[0] == full[0], rec[:200]
            for key in ("degrees", "mults", "knots"):
                assert fast[1][key] == full[1][key], (key, rec[:200])
        if full is not None:
            checked += 1
            if _possible(*full):
                assert spline_problem(*full) is None, rec[:200]
            if fast is not None and _possible(*fast):
                assert spline_problem(*full) is None, rec[:200]
    assert fast_used >= 20 and checked >= 100


def test_the_faces_lines_a_read_remembers_are_the_full_index_s(tmp_path):
    """The read indexes its faces' lines from the cleaned text (no second tokenizing pass): the same lines as the
    index of every record, also when a string spans lines (then the full index is used)."""
    from cadartifact.exchange import step_text
    from cadartifact.exchange.load import _prescan

    files = sorted((ROOT / "samples").glob("*.step"))
    real = REAL_STEP
    if real.exists():
        files += sorted(real.glob("*.st*p"))
    multiline = tmp_path / "hood.step"  # a string across lines, and one holding a face's head
    multiline.write_text(HOOD.read_bytes().decode("latin-1").replace(
        "CARTESIAN_POINT('',", "CARTESIAN_POINT('a\nb;#999 = ADVANCED_FACE(',", 1), encoding="latin-1")
    for path in files + [multiline]:
        _prescan(path)
        faces = [i for i, _, kind in step_text.entity_lines(path) if kind == "ADVANCED_FACE"]
        full = step_text._lines_by_id(path)
        assert faces and all(step_text.entity_line(path, i) == full[i] for i in faces), path
        remembered = any(key[0] == str(path) for key in step_text._face_lines)
        assert remembered == (path != multiline), path  # a head inside a string: the full index instead
