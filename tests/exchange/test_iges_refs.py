"""IGES directory-entry integrity (issue 27): a pointer of the chain that makes a face that names no entity,
the entity itself or an entity of the wrong type, and a directory entry whose two lines disagree on the type,
are an error naming the entries and their lines, before OCCT (which read such files as files of no face)."""

from __future__ import annotations

import os
import re
import warnings

import pytest

pytest.importorskip("OCP")

from cadartifact.errors import FileFormatError  # noqa: E402
from cadartifact.exchange.iges_refs import iges_problem  # noqa: E402
from cadartifact.exchange.load import read  # noqa: E402

from pathlib import Path  # noqa: E402

from cadartifact.testing.iges_texts import directory, hood_as_iges, set_parameter  # noqa: E402
from cadartifact.testing.paths import SAMPLES  # noqa: E402


@pytest.fixture(scope="module")
def hood(tmp_path_factory):
    """The hood as an IGES trimmed surface (144 -> 128 surface, 142 boundary): its text."""
    return hood_as_iges(tmp_path_factory.mktemp("iges"), 0)


def _with_surface(text: str, pointer: str) -> str:
    lines = text.split("\n")
    i = next(k for k, ln in enumerate(lines) if ln.startswith("144,") and ln[72] == "P")
    head, rest = lines[i][:64].split(",", 2)[0], lines[i][:64].split(",", 2)[2]
    lines[i] = f"{head},{pointer},{rest}".rstrip().ljust(64) + lines[i][64:]
    return "\n".join(lines)


def test_the_written_file_is_intact(hood):
    assert iges_problem(hood) is None


@pytest.mark.parametrize("pointer, needle", [
    ("99", "D99 is referenced by IGES entity D1 (type 144, line 6) as its surface, and is not in the file"),
    ("4", "D4 is referenced by IGES entity D1 (type 144, line 6) as its surface, and is not in the file"),
    ("1", "D1 is referenced by IGES entity D1 (type 144, line 6) as its surface, and is the entity itself, "
          "which cannot stand there"),
    ("5", "D5 is referenced by IGES entity D1 (type 144, line 6) as its surface, and is type 142 (line 10), "
          "which cannot stand there (expected a surface type)"),
    ("x", "IGES entity D1 (type 144, line 6): parameter 1 (its surface) is not a pointer"),
])
def test_a_broken_surface_pointer_is_an_error_naming_entries_and_lines(hood, tmp_path, monkeypatch, pointer, needle):
    text = _with_surface(hood, pointer)
    assert iges_problem(text) == needle
    path = tmp_path / "m.igs"
    path.write_text(text, encoding="latin-1")
    with pytest.raises(FileFormatError, match=rf"^{path}: ") as err:
        read(path)
    assert str(err.value) == f"{path}: {needle}"
    from cadartifact.execution import child

    monkeypatch.setattr(child, "_settings", child.settings().replace(isolation=False))  # the in-process road
    with pytest.raises(FileFormatError):
        read(path)


def test_a_type_corrupted_on_one_line_of_a_directory_entry(hood):
    text = hood.replace("     144       1", "     145       1", 1)
    assert iges_problem(text) == "IGES entity D1 (line 6): its directory entry gives two entity types (145 and 144)"


def test_without_the_check_occt_reads_a_file_of_no_face(hood, tmp_path, monkeypatch):
    """Why the check exists: OCCT's read of the broken file loses the face and names nothing."""
    import cadartifact.exchange.iges_refs as refs

    monkeypatch.setattr(refs, "check_iges_text", lambda path: (0, "faces"))  # no check, no count
    path = tmp_path / "m.igs"
    path.write_text(_with_surface(hood, "4"), encoding="latin-1")
    from cadartifact.execution import child

    monkeypatch.setattr(child, "_settings", child.settings().replace(isolation=False))  # read in this process
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = read(path)
    assert result.nets == [] and result.skipped == {} and os.path.exists(path)


def test_faces_the_directory_declares_and_the_transfer_lost_are_counted_dropped(hood, tmp_path, monkeypatch):
    """A byte flipped in a loop's curve made OCCT transfer 24 of the 31 faces of an IGES file, naming none (the
    fuzz campaign): the faces the directory declares are compared with those transferred, and the rest are
    dropped faces with a warning (the gate fails the file)."""
    import json

    from typer.testing import CliRunner

    import cadartifact.exchange.iges_refs as refs
    from cadartifact.cli.app import app
    from cadartifact.exchange.files import LoadResult

    got = refs.faces_missing("m.igs", LoadResult(path=Path("m.igs"), nets=[], faces_total=24, skipped={"plane": 3},
                                                  warnings=[]), (31, "faces (type 510)"))
    assert got.faces_total == 31 and got.skipped == {"plane": 3, "dropped": 7}
    assert got.warnings == ["m.igs: 7 of the 31 faces (type 510) the IGES file declares are not in OCCT's transferred "
                            "shape, and OCCT named none (corrupt parameter data?)"]
    path = tmp_path / "hood.igs"
    path.write_text(hood, encoding="latin-1")
    assert refs.declared_faces(hood) == (1, "trimmed or bounded surfaces (types 144, 143)")
    real = refs.declared_faces
    monkeypatch.setattr(refs, "declared_faces", lambda text: (real(text)[0] + 2, real(text)[1]))  # two faces lost
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = read(path)
    assert result.skipped.get("dropped") == 2 and result.faces_total == 3 and len(result.nets) == 1
    r = CliRunner().invoke(app, ["gate", str(path), "--tol", "1e6", "--format", "json", "--jobs", "1"])
    entry = json.loads(r.stdout)["files"][0]
    assert r.exit_code == 2 and entry["verdict"] == "error" and "2 of the 3" in entry["error"]


def test_a_non_ascii_digit_in_a_directory_entry_is_no_type_and_no_crash(hood):
    """The campaign's one unexpected exception: a flipped byte made a directory field '50²' (``str.isdigit`` is
    true, ``int`` fails); such a field is no entity type, and a pointer field no pointer."""
    text = hood.replace("     144       1", "     14²       1", 1)
    assert "two entity types" in iges_problem(text)
    lines = hood.split("\n")
    i = next(k for k, ln in enumerate(lines) if ln.startswith("     144       1"))
    lines[i] = lines[i][:8] + "       ²" + lines[i][16:]
    assert "no parameter data pointer" in iges_problem("\n".join(lines))


def test_more_faces_transferred_than_declared_is_said(hood, tmp_path, monkeypatch):
    """The campaign's open case (MAINBODY_BACK's IGES B-rep with a broken pointer gave 33 faces of 31; a
    duplicated directory line gave a one-face file 2): more faces in OCCT's transferred shape than the directory
    declares is a warning naming both counts (the faces are kept: a legitimate file may instance a face twice)."""
    import json

    from typer.testing import CliRunner

    import cadartifact.exchange.iges_refs as refs
    from cadartifact.cli.app import app
    from cadartifact.exchange.files import LoadResult

    from cadartifact.testing import fuzzing

    got = refs.faces_missing("m.igs", LoadResult(path=Path("m.igs"), nets=[], faces_total=33, skipped={"plane": 3},
                                                  warnings=[]), (31, "faces (type 510)"))
    assert got.faces_total == 33 and got.skipped == {"plane": 3}
    assert got.warnings == ["m.igs: OCCT's transferred shape has 33 faces, 2 more than the 31 faces (type 510) the "
                            "IGES file declares (a face instanced more than once, or corrupt directory data?)"]
    same = refs.faces_missing("m.igs", LoadResult(path=Path("m.igs"), nets=[], faces_total=31, warnings=[]),
                              (31, "faces (type 510)"))
    assert same.warnings == []
    none = refs.faces_missing("m.igs", LoadResult(path=Path("m.igs"), nets=[], faces_total=2, warnings=[]),
                              (0, "trimmed or bounded surfaces (types 144, 143)"))
    assert none.warnings == []  # a file of untrimmed surfaces (128) declares no face: nothing to compare
    real = refs.declared_faces
    monkeypatch.setattr(fuzzing, "declared_faces", lambda data, fmt: 1)
    for extra in (1, 2):  # 1 + extra faces written; the directory read as declaring 1 (as the corrupt files were)
        twice = tmp_path / f"copies{extra}.igs"
        _write_hood_copies(twice, 1 + extra)
        assert real(twice.read_text(encoding="latin-1"))[0] == 1 + extra
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            assert not any("more than" in w for w in read(twice).warnings)  # as declared: nothing said
            monkeypatch.setattr(refs, "declared_faces", lambda text: (1, real(text)[1]))
            result = read(twice)
        assert result.faces_total == 1 + extra
        assert any(f"{extra} more than the 1 trimmed" in w for w in result.warnings), result.warnings
        r = CliRunner().invoke(app, ["gate", str(twice), "--tol", "1e6", "--format", "json", "--jobs", "1"])
        entry = json.loads(r.stdout)["files"][0]
        assert entry["verdict"] != "error" and any(f"{extra} more than" in w for w in entry["warnings"])
        case = fuzzing.Case(source="hood.igs", kind="duplicate-line", name=twice.name, data=b"")
        assert fuzzing.check_entry(entry, twice, case) == []  # said: not a contract violation
        monkeypatch.setattr(refs, "declared_faces", real)


def _write_hood_copies(path: Path, copies: int) -> None:
    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.occ import make_face

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        writer = IGESControl_Writer("MM", 0)
        net = read(SAMPLES / "car_hood_coarse.step").nets[0]
        for _ in range(copies):
            writer.AddShape(make_face(net))
        writer.ComputeModel()
        assert writer.Write(str(path))


def _with_number(text: str, value: str, rng) -> tuple[str, int]:
    """``text`` with a random number of a random parameter line of its 128 surface replaced by ``value``; and the
    file line (1-based) of that parameter line."""
    lines = text.split("\n")
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln[64:72].strip().lstrip("0") == "3"]
    while True:  # a number whose replacement still fits the line's 64 data columns
        k = rng.choice(rows)
        data = lines[k][:64].rstrip()
        spans = [m.span() for m in re.finditer(r"(?<![0-9.H])[-+]?[0-9]+\.[0-9]*(?:[ED][-+]?[0-9]+)?", data)]
        a, b = rng.choice(spans)
        new = data[:a] + value + data[b:]
        if len(new) <= 64:
            break
    lines[k] = new.ljust(64) + lines[k][64:]
    return "\n".join(lines), k + 1


@pytest.mark.parametrize("value", ["1.0D300", "1.0E+400", "-1.D99", "NAN", "INF", "-Infinity", "12345678901234",
                                   "2.5E12", "1.E13", "9.99999D+99"])
def test_an_iges_number_that_is_not_finite_or_huge_is_an_error_naming_the_entity_and_line(hood, value, tmp_path):
    """The IGES number pre-scan (as STEP's): the message names the entity (the parameter line's directory pointer),
    its type and the line; the gate gives an error entry, exit 2, one line, no report of faces."""
    import json
    import random

    from typer.testing import CliRunner

    from cadartifact.cli.app import app

    rng = random.Random(value)
    for _ in range(5):
        text, line = _with_number(hood, value, rng)
        assert iges_problem(text) == (f"IGES entity D3 (type 128, line {line}): number {value!r} is not finite or "
                                      "exceeds 1e+12 (no real model holds it)")
    path = tmp_path / "m.igs"
    path.write_text(text, encoding="latin-1")
    r = CliRunner().invoke(app, ["gate", str(path), "--tol", "1", "--format", "json", "--jobs", "1"])
    entry = json.loads(r.stdout)["files"][0]
    assert r.exit_code == 2 and entry["verdict"] == "error" and entry["faces"] == []
    assert entry["error"] == (f"{path}: IGES entity D3 (type 128, line {line}): number {value!r} is not finite or "
                              "exceeds 1e+12 (no real model holds it)")


@pytest.mark.parametrize("value", ["9.9E11", "1.0D-300", "1.0E+11", "-5.D-12", "123456789012", "0.12345678901234567"])
def test_large_but_possible_iges_numbers_pass(hood, value):
    import random

    text, _ = _with_number(hood, value, random.Random(value))
    assert iges_problem(text) is None


def test_an_iges_hollerith_string_is_not_read_as_numbers(hood):
    """A name (Hollerith ``nH...``) may hold INF, NaN or 1E300 as text: not numbers."""
    lines = hood.split("\n")
    k = next(k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln[64:72].strip().lstrip("0") == "3")
    data = lines[k][:64].rstrip()
    if data.endswith(";"):
        return
    extra = "12HINF NAN 1E300"
    # after the last parameter line (the line numbers of the records that follow D3's stay as they are)
    last = max(j for j, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P")
    lines.insert(last + 1, ("," + extra).ljust(64) + lines[k][64:])
    assert iges_problem("\n".join(lines)) is None


@pytest.mark.parametrize("which", range(8))
@pytest.mark.parametrize("change", [(".", ","), (",", ".")])
def test_a_number_split_or_merged_in_a_bspline_surface_record_is_an_error(hood, which, change):
    """A decimal point turned into the delimiter (or a delimiter into a point) inside a type-128 record shifts
    every later parameter, and OCCT reads another surface without a word (a fuzz campaign's false pass: a
    failing face passed): the count its degrees give names the entity."""
    lines = hood.split("\n")
    de = next(ln[64:72].strip() for ln in lines if len(ln) >= 73 and ln[72] == "P" and ln[:64].startswith("128,"))
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln[64:72].strip() == de]
    # the change-th occurrence past the header (K1, K2, M1, M2, PROP1..5 stay intact)
    spots = [(k, i) for k in rows[1:] for i, ch in enumerate(lines[k][:64]) if ch == change[0]]
    k, i = spots[(which * 7919) % len(spots)]
    lines[k] = lines[k][:i] + change[1] + lines[k][i + 1:]
    problem = iges_problem("\n".join(lines))
    assert problem is not None and "type 128" in problem and "parameters where its degrees and counts" in problem


def test_every_bspline_record_the_writer_makes_has_its_count(tmp_path):
    """IGES written by OCCT from every sample, as faces and as B-rep: no count problem (no false alarm)."""
    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.occ import make_face

    for src in sorted(SAMPLES.glob("*.step")):
        nets = read(src).nets
        for mode in (0, 1):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                writer = IGESControl_Writer("MM", mode)
                for net in nets:
                    writer.AddShape(make_face(net))
                writer.ComputeModel()
                path = tmp_path / f"{src.stem}_{mode}.igs"
                assert writer.Write(str(path))
                text = path.read_text(encoding="latin-1")
            assert iges_problem(text) is None, (src.name, mode)


@pytest.mark.parametrize("which", range(10))
@pytest.mark.parametrize("char", ["!", "x", "#", "/", "E"])
def test_a_token_that_is_not_a_number_in_a_bspline_surface_record_is_an_error(hood, which, char):
    """A byte of a type-128 record turned into a character that is no part of a number (a blank beside a weight
    flipped into ``!``, a digit into a letter) keeps the parameter count, and OCCT read such a record as whatever
    its state held: the fuzz campaign of seed 2731 saw the same file refused, or read as another surface that
    passed the gate, depending on the files read before it in the same reader child. Refused before OCCT, naming
    the entity and the parameter."""
    lines = hood.split("\n")
    de = next(ln[64:72].strip() for ln in lines if len(ln) >= 73 and ln[72] == "P" and ln[:64].startswith("128,"))
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln[64:72].strip() == de]
    # digits and the blanks right after a delimiter (where a number of the next line may follow), past the header
    spots = [(k, i) for k in rows[1:] for i, ch in enumerate(lines[k][:64].rstrip() + " ")
             if ch.isdigit() or (ch == " " and i and lines[k][i - 1] == ",")]
    k, i = spots[(which * 7919) % len(spots)]
    lines[k] = (lines[k][:i] + char + lines[k][i + 1:])[:80]
    text = "\n".join(lines)
    problem = iges_problem(text)
    if char == "E" and re.search(r"[0-9.]E[0-9]", lines[k][max(0, i - 1):i + 2]):
        return  # a digit turned into an exponent mark between digits is a number still (another value)
    assert problem is not None and "type 128" in problem and "is not a number" in problem, (lines[k], problem)


@pytest.mark.parametrize("kind", ["126", "142", "144", "102"])
@pytest.mark.parametrize("which", range(4))
def test_a_letter_in_a_numbers_only_record_of_the_chain_is_an_error(hood, kind, which):
    """The same for the other numbers-only entities of the chain that makes a face (the boundary's curves and
    curves on the surface, the trimmed surface): a digit turned into a letter is refused, naming the entity."""
    lines = hood.split("\n")
    heads = [ln[64:72].strip() for ln in lines if len(ln) >= 73 and ln[72] == "P" and ln[:64].startswith(kind + ",")]
    if not heads:
        pytest.skip(f"the hood's IGES has no type {kind}")
    de = heads[which % len(heads)]
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln[64:72].strip() == de]
    spots = [(k, i) for k in rows for i, ch in enumerate(lines[k][:64]) if ch.isdigit() and i > len(kind)]
    k, i = spots[(which * 7919) % len(spots)]
    lines[k] = lines[k][:i] + "x" + lines[k][i + 1:]
    problem = iges_problem("\n".join(lines))
    assert problem is not None and f"type {kind}" in problem, problem
    assert "is not a number" in problem or "is not a pointer" in problem, problem  # a pointer's own message


# --- the chain beyond the face: curves on the surface, composite curves, loops, edge lists (a B-rep's faces) ---

@pytest.fixture(scope="module")
def hood_brep(tmp_path_factory):
    """The hood as an IGES B-rep (mode 1: 510 face -> 128 surface, 508 loop -> 504 edge list -> 502 vertices)."""
    return hood_as_iges(tmp_path_factory.mktemp("iges"), 1)


# (entity type, parameter index, role in the message, a type that cannot stand there)
_CHAIN_SLOTS = [
    ("faces", 142, 1, "its surface", 110),
    ("faces", 142, 2, "its curve in the surface's parameters", 128),
    ("faces", 142, 3, "its model-space curve", 128),
    ("faces", 102, 1, "a part", 128),
    ("brep", 508, 2, "an edge's edge list", 126),
    ("brep", 508, 7, "an edge's curve in the surface's parameters", 128),
    ("brep", 504, 1, "an edge's curve", 128),
    ("brep", 504, 2, "an edge's start vertex list", 128),
    ("brep", 504, 4, "an edge's end vertex list", 110),
    # the last slots of a record (a check of the first edge or part only would pass the rows above)
    ("faces", 102, 4, "a part", 128),
    ("brep", 504, 16, "an edge's curve", 128),
    ("brep", 504, 19, "an edge's end vertex list", 110),
    ("brep", 508, 23, "an edge's edge list", 126),
    ("brep", 508, 28, "an edge's curve in the surface's parameters", 128),
]


@pytest.mark.parametrize("fault", ["missing", "even", "itself", "wrong type"])
@pytest.mark.parametrize("mode, kind, index, role, wrong", _CHAIN_SLOTS)
def test_a_broken_pointer_along_the_chain_is_an_error_naming_it(hood, hood_brep, mode, kind, index, role, wrong,
                                                                fault):
    """Every pointer a face reaches through its boundaries (142 curve on surface, 102 composite curve) or its loops
    (508 loop, 504 edge list) names an entity of the file, not itself, of a type that can stand there; OCCT's
    transfer dereferences these without a check."""
    text = hood if mode == "faces" else hood_brep
    types = directory(text)
    d = 2 * types.index(kind) + 1
    value = {"missing": 2 * len(types) + 1, "even": 2, "itself": d,
             "wrong type": 2 * types.index(wrong) + 1}[fault]
    line = next(k for k, ln in enumerate(text.split("\n")) if len(ln) >= 73 and ln[72] == "D" and int(ln[73:80]) == d)
    who = f"IGES entity D{d} (type {kind}, line {line + 1})"
    problem = iges_problem(set_parameter(text, d, index, str(value)))
    expected = {"missing": f"D{value} is referenced by {who} as {role}, and is not in the file",
                "even": f"D{value} is referenced by {who} as {role}, and is not in the file",
                "itself": f"D{value} is referenced by {who} as {role}, and is the entity itself, which cannot stand there"}
    if fault in expected:
        assert problem == expected[fault]
    else:
        assert problem.startswith(f"D{value} is referenced by {who} as {role}, and is type {wrong} (line "), problem
        assert problem.endswith("which cannot stand there (expected " + {
            "its surface": "a surface type)", "a part": "a curve or point type)", "an edge's edge list": "504)",
            "an edge's start vertex list": "502)", "an edge's end vertex list": "502)"}.get(role, "a curve type)"))


def test_the_chain_checks_reach_what_the_faces_reach_and_accept_absent_curves(hood, hood_brep):
    """A curve on a surface may lack either curve (a pointer of 0); a composite curve that no face reaches is not
    the chain's (a wireframe curve of the drawing is not checked); the unbroken files pass."""
    assert iges_problem(hood) is None and iges_problem(hood_brep) is None
    types = directory(hood)
    d142 = 2 * types.index(142) + 1
    assert iges_problem(set_parameter(hood, d142, 2, "0")) is None
    assert iges_problem(set_parameter(hood, d142, 3, "0")) is None
    # cut the face's reach: the 142 keeps no pointer to its composite curves, so a broken part is none of the chain's
    cut = set_parameter(set_parameter(hood, d142, 2, "0"), d142, 3, "0")
    d102 = 2 * types.index(102) + 1
    others = [2 * k + 1 for k, t in enumerate(types) if t == 102]
    for d in others:
        cut = set_parameter(cut, d, 1, str(2 * len(types) + 1))
    assert d102 in others and iges_problem(cut) is None


def test_a_boundary_entity_s_pointers(hood):
    """A boundary (141, IGES 5.3 §4.43; OCCT's writer makes none, other systems do): its surface, each model-space
    curve and its parameter-space curves, read by their counts."""
    from cadartifact.exchange.iges_refs import _CURVE, SURFACE_TYPES, _pointer_slots

    # TYPE, PREF, SPTR, N=2, (CRVPT, SENSE, K=1, PSCPT), (CRVPT, SENSE, K=0)
    slots = _pointer_slots(141, "1,1,3,2,5,1,1,7,9,2,0".split(","))
    assert [(i, role) for i, role, _, _ in slots] == [
        (2, "its surface"), (4, "a model-space curve"), (7, "a curve in the surface's parameters"),
        (8, "a model-space curve")]
    assert slots[0][2] == SURFACE_TYPES and all(s[2] == _CURVE for s in slots[1:])
    assert [i for i, *_ in _pointer_slots(141, "1,1,3,2,5,1,x".split(","))] == [2, 4]  # a count that is none: stop


def test_without_the_check_occt_crashes_on_a_loop_s_edge_list_pointer(hood_brep, tmp_path, monkeypatch):
    """Why the chain is checked past the face: a loop whose edge-list pointer names no entity is a segmentation
    fault of OCCT's IGES transfer; in the reader child that costs the file an error that names no cause, in this
    process it would end the run. The check names the pointer before OCCT reads."""
    import cadartifact.exchange.iges_refs as refs

    types = directory(hood_brep)
    d = 2 * types.index(508) + 1
    path = tmp_path / "m.igs"
    path.write_text(set_parameter(hood_brep, d, 2, str(2 * len(types) + 1)), encoding="latin-1")
    with pytest.raises(FileFormatError, match=rf"^{path}: D{2 * len(types) + 1} is referenced by IGES entity D{d} "
                                              rf"\(type 508, line \d+\) as an edge's edge list, and is not in the file$"):
        read(path)
    monkeypatch.setattr(refs, "check_iges_text", lambda path: (0, "faces"))
    with pytest.raises(FileFormatError, match="crashed"):
        read(path)


@pytest.mark.parametrize("mode, kind, index", [("faces", 102, 0), ("faces", 144, 2), ("brep", 510, 1)])
def test_a_corrupted_pointer_count_is_no_list_of_a_billion_slots(hood, hood_brep, mode, kind, index, monkeypatch):
    """A count of pointers corrupted to 999999999 claims more pointers than the record has parameters: the first
    one past the record's end is "not a pointer", found at once (a list of a slot per counted pointer took 5.5 s
    and 1 GB per ten million). Every record's slots stay within its parameters (its time:
    benchmarks/time_limits.py)."""
    import cadartifact.exchange.iges_refs as refs

    real, counted = refs._pointer_slots, []

    def bounded(kind, params):
        slots = real(kind, params)
        counted.append(len(slots))
        assert len(slots) <= 3 * (len(params) + 1), (kind, len(slots), len(params))
        return slots

    monkeypatch.setattr(refs, "_pointer_slots", bounded)
    text = hood if mode == "faces" else hood_brep
    types = directory(text)
    d = 2 * types.index(kind) + 1
    problem = iges_problem(set_parameter(text, d, index, "999999999"))
    assert counted
    assert problem is not None and f"IGES entity D{d} (type {kind}, line" in problem, problem
    assert "is not a pointer" in problem or "is not in the file" in problem, problem


@pytest.mark.parametrize("kind, params", [
    (514, ["999999999", "3", "1"]), (510, ["3", "999999999", "1", "5"]), (144, ["3", "1", "999999999", "5"]),
    (143, ["1", "3", "999999999", "5"]), (102, ["999999999", "9"]), (504, ["999999999", "9", "11", "1", "11", "2"]),
    (508, ["999999999", "0", "7", "1", "0", "999999999", "0", "19"]), (141, ["1", "1", "3", "999999999", "5", "1",
                                                                          "999999999", "7"])])
def test_the_slots_of_a_corrupted_count_stop_at_the_record_s_end(kind, params):
    """Every entity's pointer slots: at most one per parameter the record has, plus the first one past its end
    (their time: benchmarks/time_limits.py)."""
    from cadartifact.exchange.iges_refs import _pointer_slots

    slots = _pointer_slots(kind, params)
    assert 0 < len(slots) <= 3 * (len(params) + 1)


def _retyped(text: str, d: int, kind: int) -> str:
    """``text`` with entity ``D<d>``'s type made ``kind`` on both its directory lines."""
    lines = text.split("\n")
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "D" and int(ln[73:80]) in (d, d + 1)]
    for k in rows:
        lines[k] = str(kind).rjust(8) + lines[k][8:]
    return "\n".join(lines)


@pytest.mark.parametrize("kind", [100, 104, 106, 112, 126, 130, 116, 132])
def test_every_kind_of_curve_or_point_that_may_stand_as_a_part_passes(hood, kind):
    """No false refusal: a composite curve's part may be any curve, a point or a connect point (IGES 5.3 §4.4),
    and a curve on a surface's curves any curve (the part's own record is not what this check reads)."""
    types = directory(hood)
    part = 2 * types.index(110) + 1
    text = _retyped(hood, part, kind)
    assert iges_problem(text) is None
    if kind not in (116, 132):
        d142 = 2 * types.index(142) + 1
        assert iges_problem(set_parameter(text, d142, 3, str(part))) is None


@pytest.mark.parametrize("record", ["142,0,3,7,,3;", "142,0,3,7;", "142,0,3,,17,3;"])
def test_an_empty_or_omitted_curve_pointer_of_a_curve_on_a_surface_is_no_curve(hood, tmp_path, record):
    """An empty or omitted parameter takes its default (0: no entity), which either curve of a curve on a surface
    may be; OCCT reads such a file (one face), and so does the check."""
    lines = hood.split("\n")
    k = next(k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and ln.startswith("142,"))
    lines[k] = record.ljust(64) + lines[k][64:]
    text = "\n".join(lines)
    assert iges_problem(text) is None
    path = tmp_path / "m.igs"
    path.write_text(text, encoding="latin-1")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert len(read(path).nets) == 1


def test_composite_curves_that_contain_each_other_are_refused(hood, tmp_path):
    """Two composite curves each naming the other as a part: OCCT's transfer recursed until the reader crashed
    (an error naming no cause); the check names the cycle."""
    types = directory(hood)
    a, b = (2 * k + 1 for k, t in enumerate(types) if t == 102)
    text = set_parameter(set_parameter(hood, a, 1, str(b)), b, 1, str(a))
    problem = iges_problem(text)
    assert problem is not None and "a composite curve that contains itself through its parts" in problem, problem
    assert f"D{a} -> D{b}" in problem or f"D{b} -> D{a}" in problem
    path = tmp_path / "m.igs"
    path.write_text(text, encoding="latin-1")
    with pytest.raises(FileFormatError, match="contains itself through its parts"):
        read(path)


def test_an_over_long_integer_is_no_pointer_and_no_unexpected_error(hood, tmp_path):
    """A pointer of 5000 digits (Python's int() refuses 4300 and more) behind a Hollerith count that hides it from
    the number scan: "not a pointer", a one-line error naming the entity, no ValueError (it was an unexpected
    failure of the analysis). The record is appended after the last parameter line and D5's entry pointed at it."""
    lines = hood.split("\n")
    p_rows = [i for i, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P"]
    d = 2 * directory(hood).index(142) + 1
    record = "142,99999H," + "3," + "9" * 5000 + ",17,3;"
    chunks = [record[i:i + 64] for i in range(0, len(record), 64)]
    lines[p_rows[-1] + 1:p_rows[-1] + 1] = [c.ljust(64) + "%8d" % d + "P%7d" % (len(p_rows) + 1 + j)
                                             for j, c in enumerate(chunks)]
    for i, ln in enumerate(lines):
        if len(ln) >= 80 and ln[72] == "D" and int(ln[73:80]) == d:
            lines[i] = ln[:8] + "%8d" % (len(p_rows) + 1) + ln[16:]
        if len(ln) >= 80 and ln[72] == "D" and int(ln[73:80]) == d + 1:
            lines[i] = ln[:24] + "%8d" % len(chunks) + ln[32:]
    text = "\n".join(lines)
    assert iges_problem(text) == (f"IGES entity D{d} (type 142, line {_directory_line(text, d)}): parameter 3 (its "
                                  "curve in the surface's parameters) is not a pointer")
    path = tmp_path / "m.igs"
    path.write_text(text, encoding="latin-1")
    with pytest.raises(FileFormatError, match="is not a pointer"):
        read(path)


def _directory_line(text: str, d: int) -> int:
    """The file line of entity ``D<d>``'s first directory line."""
    return next(k for k, ln in enumerate(text.split("\n"), start=1) if len(ln) >= 80 and ln[72] == "D"
                and int(ln[73:80]) == d)
