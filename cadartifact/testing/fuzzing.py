"""A seeded mutation generator for STEP and OBJ files, and the contract every outcome must meet.

Used by ``tests/integration/test_fuzz.py`` (a few hundred inputs in CI) and ``benchmarks/fuzz_campaign.py``
(10 000 and more). ``mutations(sources, n, seed)`` yields the same inputs for the same arguments.

Mutation kinds (:data:`KINDS`): byte flips, truncation, deleted / duplicated lines, a number
replaced by NaN / inf / 1e308 / 1e154, a broken entity reference, decreasing knots, a changed
multiplicity or degree, a zero weight, an OBJ face index out of range, an odd file name (spaces,
non-ASCII, not UTF-8, a leading dash), an empty file and the other format's extension; and breaks of the
chain that makes a face (:data:`CHAIN_KINDS`, :func:`chain_links`): a referenced entity of each type on
the chain deleted, a reference pointed at an entity of the wrong type or at its owner, a pole emptied to
``CARTESIAN_POINT('')``, a keyword on the chain corrupted (``ADVANCED_FAC``).

The contract (:func:`check_entry`): the gate's entry for the file is either an ``error`` with a
one-line message naming the file, or a complete report whose ``faces_total`` equals the faces the
file declares (an independent count of its text: ``ADVANCED_FACE`` / ``FACE_SURFACE`` records, OBJ
``f`` statements) and whose numbers are all finite; never an exception.
"""

from __future__ import annotations

import json
import os
import random
import re
from dataclasses import dataclass
from pathlib import Path

from .paths import REALDATA, ROOT

KINDS = ("flip", "truncate", "delete-line", "duplicate-line", "nan", "inf", "1e308", "1e154", "broken-ref",
         "decreasing-knots", "multiplicity", "degree", "zero-weight", "obj-index", "odd-name", "empty",
         "wrong-ext", "delete-referenced", "wrong-type-ref", "self-ref", "empty-point", "corrupt-keyword",
         "iges-missing-ref", "iges-wrong-type-ref", "iges-self-ref", "iges-null-entity", "iges-corrupt-type")
#: The kinds that break the chain that makes a face (issue 27): every one is an error naming the entity.
CHAIN_KINDS = ("delete-referenced", "wrong-type-ref", "self-ref", "empty-point", "corrupt-keyword")
#: The same breaks of an IGES file's directory (on the pointers of its 144/143/510/514 entities): a pointer to
#: no entity (past the directory, an even number), to an entity of the wrong type, to the entity itself; the
#: referenced entity made a null entity (type 0: deleted); a chain entity's type corrupted on one of its lines.
IGES_KINDS = ("iges-missing-ref", "iges-wrong-type-ref", "iges-self-ref", "iges-null-entity", "iges-corrupt-type")

#: Faces a STEP text declares (simple instances), counted independently of the reader.
_STEP_FACE = re.compile(rb"#\d+\s*=\s*(?:ADVANCED_FACE|FACE_SURFACE)\s*\(")
_NUMBER = re.compile(rb"(?<![#\w.])[-+]?\d+\.\d*(?:E[-+]?\d+)?")
_REF = re.compile(rb"(?<=[(,])#\d+")
_KNOTS = re.compile(rb"B_SPLINE_(?:SURFACE|CURVE)_WITH_KNOTS\(")
_WEIGHTS = re.compile(rb"RATIONAL_B_SPLINE_(?:SURFACE|CURVE)\(\s*\(+")


@dataclass(frozen=True)
class Case:
    """One mutated input: where it came from, the mutation, and the bytes to write under ``name``."""

    source: str
    kind: str
    name: str
    data: bytes


def default_sources(*, small: bool = True) -> list[Path]:
    """The samples, plus the real files present (``small``: those under 150 KB, for CI)."""
    files = sorted((ROOT / "samples").glob("*.step")) + [ROOT / "samples" / "cage.obj"]
    if REALDATA.exists():
        real = sorted((REALDATA / "step").glob("*.st*p")) + sorted((REALDATA / "obj").glob("*.obj"))
        files += [p for p in real if not small or p.stat().st_size < 150_000]
    return files


def iges_sources(folder: Path) -> list[Path]:
    """IGES files written by OCCT from the STEP samples into ``folder``, as faces (mode 0: trimmed surfaces, 144)
    and as B-rep (mode 1: shells of faces, 514/510)."""
    import warnings

    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.load import read
    from cadartifact.exchange.occ import make_face

    folder.mkdir(parents=True, exist_ok=True)
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for src in sorted((ROOT / "samples").glob("*.step")):
            nets = read(src).nets
            for mode in (0, 1):
                writer = IGESControl_Writer("MM", mode)
                for net in nets:
                    writer.AddShape(make_face(net))
                writer.ComputeModel()
                path = folder / f"{src.stem}_{'faces' if mode == 0 else 'brep'}.igs"
                if writer.Write(str(path)):
                    out.append(path)
        # a whole real model (shells of faces of every kind), when present
        real = REALDATA / "step" / "MAINBODY_BACK.stp"
        if real.exists():
            from OCP.STEPControl import STEPControl_Reader

            from cadartifact.exchange.occ import quiet_occt

            reader = STEPControl_Reader()
            with quiet_occt():
                reader.ReadFile(str(real))
                reader.TransferRoots()
                for mode in (0, 1):
                    writer = IGESControl_Writer("MM", mode)
                    writer.AddShape(reader.OneShape())
                    writer.ComputeModel()
                    path = folder / f"{real.stem}_{'faces' if mode == 0 else 'brep'}.igs"
                    if writer.Write(str(path)):
                        out.append(path)
    return out


def _iges_directory(data: bytes) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """Spans (start, end of line) of the D and P section lines of an IGES text."""
    d, p = [], []
    pos = 0
    while pos < len(data):
        end = data.find(b"\n", pos)
        end = len(data) if end < 0 else end
        line = data[pos:end].rstrip(b"\r")
        if len(line) >= 73:
            (d if line[72:73] == b"D" else p if line[72:73] == b"P" else []).append((pos, pos + len(line)))
        pos = end + 1
    return d, p


def _iges_type(data: bytes, span) -> int | None:
    field = data[span[0]:span[0] + 8].strip()
    return int(field) if field.lstrip(b"-").isdigit() else None


def declared_faces(data: bytes, fmt: str) -> int:
    """Faces the text declares: STEP face records, IGES faces (510 entities, else trimmed and bounded surfaces,
    144 and 143) or OBJ ``f`` statements (continuation lines joined)."""
    if fmt == "step":
        return len(_STEP_FACE.findall(data))
    if fmt == "iges":
        d, _ = _iges_directory(data)
        types = [_iges_type(data, d[k]) for k in range(0, len(d) - 1, 2)]
        return types.count(510) or types.count(144) + types.count(143)
    text = data.decode("utf-8", errors="replace").replace("\\\n", " ")
    return sum(1 for line in text.splitlines() if line.split("#", 1)[0].split()[:1] == ["f"])


def _replace_span(data: bytes, start: int, end: int, new: bytes) -> bytes:
    return data[:start] + new + data[end:]


def _random_match(pattern, data: bytes, rng: random.Random, limit: int = 2000):
    matches = []
    for i, m in enumerate(pattern.finditer(data)):
        if i >= limit:
            break
        matches.append(m)
    return rng.choice(matches) if matches else None


def _lines(data: bytes, fmt: str) -> list[int]:
    """Start offsets of the mutable lines (STEP: inside the DATA section)."""
    starts = [0] + [m.end() for m in re.finditer(rb"\n", data)]
    if fmt == "step":
        data_at = data.find(b"DATA;")
        starts = [s for s in starts if s > data_at] or starts
    return [s for s in starts if s < len(data)]


def _number(data: bytes, fmt: str, rng, value_step: bytes, value_obj: bytes) -> bytes:
    if fmt == "obj":
        lines = [m for m in re.finditer(rb"^v ([^\n]*)", data, re.M)]
        if not lines:
            return data
        m = rng.choice(lines)
        parts = m.group(1).split()
        if parts:
            parts[rng.randrange(min(3, len(parts)))] = value_obj
        return _replace_span(data, m.start(1), m.end(1), b" ".join(parts))
    m = _random_match(_NUMBER, data[data.find(b"DATA;"):], rng)
    if m is None:
        return data
    off = data.find(b"DATA;")
    return _replace_span(data, off + m.start(), off + m.end(), value_step)


def _knot_record(data: bytes, rng):
    """``(start, end)`` of a random B-spline-with-knots record's text, or None."""
    m = _random_match(_KNOTS, data, rng)
    if m is None:
        return None
    end = data.find(b";", m.end())
    return (m.start(), end) if end > 0 else None


def _lists(text: bytes) -> list[tuple[int, int]]:
    """Spans of innermost parenthesised lists of plain numbers in ``text``."""
    return [(m.start(1), m.end(1)) for m in re.finditer(rb"\(([-+0-9.E, \r\n]+)\)", text)]


_RECORD_HEAD = re.compile(rb"(?:^|;)\s*(#(\d+)\s*=\s*([A-Z_0-9]+|\())")
#: The links of the chain that make a face: owner keyword -> (role, the target keywords it may name).
_LINKS = {b"CLOSED_SHELL": b"face", b"OPEN_SHELL": b"face", b"ADVANCED_FACE": None, b"FACE_SURFACE": None,
          b"FACE_BOUND": b"loop", b"FACE_OUTER_BOUND": b"loop", b"EDGE_LOOP": b"oriented edge",
          b"ORIENTED_EDGE": b"edge", b"B_SPLINE_SURFACE_WITH_KNOTS": b"pole"}


def step_records(data: bytes) -> dict[bytes, tuple[int, int, bytes]]:
    """``{id: (start, end, keyword)}`` of a STEP text's records (``start`` at ``#``, ``end`` after ``;``)."""
    out = {}
    for m in _RECORD_HEAD.finditer(data):
        end = data.find(b";", m.end())
        if end > 0:
            out.setdefault(m.group(2), (m.start(1), end + 1, m.group(3)))
    return out


def chain_links(data: bytes) -> list[tuple[str, bytes, bytes, int]]:
    """The references on the chain that makes a face: ``(role, owner id, target id, offset of the reference)``.

    Roles: ``face`` (shell -> face), ``bound`` and ``surface`` (face -> ...), ``loop``, ``oriented edge``,
    ``edge``, ``pole`` (B-spline surface -> point). A face's last reference is its surface, the others
    its bounds.
    """
    records = step_records(data)
    links = []
    for owner, (start, end, keyword) in records.items():
        role = _LINKS.get(keyword, b"-")
        if role == b"-":
            continue
        body = data[start:end]
        refs = [(m.group(1), start + m.start()) for m in re.finditer(rb"#(\d+)", body)][1:]  # [0] is the owner
        if role is None:
            links += [("bound", owner, t, at) for t, at in refs[:-1]] + [("surface", owner, t, at) for t, at in refs[-1:]]
        else:
            links += [(role.decode(), owner, t, at) for t, at in refs]
    return [link for link in links if link[2] in records]


def _iges_mutation(data: bytes, kind: str, rng: random.Random) -> bytes:
    """One break of an IGES file's chain (see :data:`IGES_KINDS`), keeping the 80-column layout."""
    d, p = _iges_directory(data)
    count = len(d) // 2
    types = [_iges_type(data, d[2 * k]) for k in range(count)]
    # the faces' entities and what they reach (curves on surfaces, composite curves, loops, edge lists)
    chain = [k for k, t in enumerate(types) if t in (144, 143, 510, 514, 142, 102, 508, 504)]
    if not chain:
        return data
    k = rng.choice(chain)
    owner = 2 * k + 1
    if kind == "iges-corrupt-type":
        start = d[2 * k + rng.randrange(2)][0]
        return _replace_span(data, start, start + 8, str(types[k] + rng.choice([1, -1, 1000])).rjust(8).encode())
    try:
        first = int(data[d[2 * k][0] + 8:d[2 * k][0] + 16])
    except ValueError:
        return data
    if not 0 < first <= len(p):
        return data
    a, b = p[first - 1]
    text = data[a:a + 64]
    fields = text.split(b";")[0].split(b",")
    # the surface (144, 143, 510, 142), the first face (514), part (102), edge's curve (504) or edge list (508)
    slot = {144: 1, 143: 2, 510: 1, 514: 2, 142: 2, 102: 2, 504: 2, 508: 3}[types[k]]
    if slot >= len(fields) or not fields[slot].strip().isdigit():
        return data
    target = int(fields[slot])
    if kind == "iges-null-entity":  # the referenced entity deleted: a null entity (type 0) on both lines
        if not 0 < target <= 2 * count or target % 2 == 0:
            return data
        for line in (target - 1, target):
            start = d[line][0]
            data = _replace_span(data, start, start + 8, b"0".rjust(8))
        return data
    if kind == "iges-missing-ref":
        new = rng.choice([2 * count + 1, 2 * count + 101, 2, 0 if types[k] != 514 else 4])
    elif kind == "iges-self-ref":
        new = owner
    else:  # iges-wrong-type-ref: an entity of a type that cannot stand there
        curves = {100, 102, 104, 106, 110, 112, 126, 130}
        allowed = {514: {510}, 102: curves | {116, 132}, 504: curves, 508: {502, 504}}.get(
            types[k], {108, 114, 118, 120, 122, 128, 140, 190, 192, 194, 196, 198})
        others = [2 * j + 1 for j, t in enumerate(types) if t not in allowed and j != k]
        if not others:
            return data
        new = rng.choice(others)
    fields[slot] = str(new).encode()
    record = b",".join(fields) + b";" + (text.split(b";", 1)[1] if b";" in text else b"")
    if len(record.rstrip()) > 64:
        return data
    return _replace_span(data, a, a + 64, record.rstrip().ljust(64))


def _chain_mutation(data: bytes, kind: str, rng: random.Random) -> bytes:
    """One break of the chain that makes a face (see :data:`CHAIN_KINDS`); ``data`` unchanged when none applies."""
    links = chain_links(data)
    if kind == "empty-point":
        links = [link for link in links if link[0] == "pole"]
    if not links:
        return data
    records = step_records(data)
    by_role: dict[str, list] = {}
    for link in links:
        by_role.setdefault(link[0], []).append(link)
    role, owner, target, at = rng.choice(by_role[rng.choice(sorted(by_role))])  # every role alike
    start, end, keyword = records[target]
    if kind == "delete-referenced":
        return data[:start] + data[end:]
    if kind == "empty-point":
        return data[:start] + b"#" + target + b" = CARTESIAN_POINT('');" + data[end:]
    if kind == "corrupt-keyword":
        k = data.index(keyword, start)
        new = keyword[:-1] if rng.random() < 0.5 else keyword[:-1] + bytes([keyword[-1] ^ 1])
        return data[:k] + new + data[k + len(keyword):]
    ref_end = at + 1 + len(target)
    if kind == "self-ref":
        return data[:at] + b"#" + owner + data[ref_end:]
    # wrong-type-ref: an entity of another type than the target's
    others = [i for i, (_, _, kw) in records.items() if kw != keyword]
    if not others:
        return data
    return data[:at] + b"#" + rng.choice(others) + data[ref_end:]


def mutate(data: bytes, fmt: str, kind: str, rng: random.Random) -> tuple[str, bytes]:
    """One mutation of a good ``fmt`` ("step" or "obj") file: ``(file name, content)``."""
    ext = "." + ("stp" if fmt == "step" and rng.random() < 0.2 else "igs" if fmt == "iges" else fmt)
    name = f"mutant{ext}"
    if fmt == "iges" and kind not in IGES_KINDS and kind not in ("truncate", "delete-line", "duplicate-line",
                                                                 "odd-name", "empty", "wrong-ext"):
        kind = "flip"  # the STEP and OBJ kinds: a byte flip instead
    if kind == "flip":
        buf = bytearray(data)
        for _ in range(rng.randint(1, 4)):
            pos = rng.randrange(len(buf))
            buf[pos] ^= 1 << rng.randrange(8)
        return name, bytes(buf)
    if kind == "truncate":
        return name, data[: rng.randrange(1, len(data))]
    if kind in ("delete-line", "duplicate-line"):
        starts = _lines(data, fmt)
        s = rng.choice(starts)
        e = data.find(b"\n", s)
        e = len(data) if e < 0 else e + 1
        return name, (data[:s] + data[e:]) if kind == "delete-line" else (data[:e] + data[s:e] + data[e:])
    if kind in ("nan", "inf", "1e308", "1e154"):
        step_value = {"nan": b"NaN", "inf": b"1.E400", "1e308": b"1.E308", "1e154": b"1.E154"}[kind]
        obj_value = {"nan": b"nan", "inf": b"inf", "1e308": b"1e308", "1e154": b"1e154"}[kind]
        return name, _number(data, fmt, rng, step_value, obj_value)
    if kind == "broken-ref" and fmt == "step":
        m = _random_match(_REF, data, rng)
        if m is not None:
            new = rng.choice([b"#999999999", b"#0", b"#" + str(rng.randrange(1, 50)).encode()])
            return name, _replace_span(data, m.start(), m.end(), new)
        return name, data
    if kind in ("decreasing-knots", "multiplicity", "degree") and fmt == "step":
        span = _knot_record(data, rng)
        if span is None:
            return name, data
        rec = data[span[0]:span[1]]
        if kind == "degree":
            m = re.search(rb"WITH_KNOTS\('[^']*',(\d+)", rec)
            if m is None:
                return name, data
            new = rng.choice([b"0", b"2", b"4", b"26", b"2147483648"])
            rec = rec[:m.start(1)] + new + rec[m.end(1):]
        else:
            lists = _lists(rec)
            ints = [(a, b) for a, b in lists if b"." not in rec[a:b]]
            reals = [(a, b) for a, b in lists if b"." in rec[a:b]]
            pick = ints if kind == "multiplicity" else reals
            if not pick:
                return name, data
            a, b = rng.choice(pick)
            items = rec[a:b].split(b",")
            if kind == "multiplicity":
                i = rng.randrange(len(items))
                items[i] = rng.choice([b"0", b"11", str(int(items[i].strip() or 1) + 1).encode()])
            elif len(items) >= 2:
                i = rng.randrange(len(items) - 1)
                items[i], items[i + 1] = items[i + 1], items[i]
            rec = rec[:a] + b",".join(items) + rec[b:]
        return name, data[:span[0]] + rec + data[span[1]:]
    if kind == "zero-weight" and fmt == "step":
        m = _random_match(_WEIGHTS, data, rng)
        if m is None:  # no rational entity: a zero coordinate list instead
            return name, _number(data, fmt, rng, b"0.", b"0")
        num = _NUMBER.search(data, m.end())
        if num is None:
            return name, data
        return name, _replace_span(data, num.start(), num.end(), rng.choice([b"0.", b"-1.", b"1.E-300"]))
    if kind == "obj-index" and fmt == "obj":
        faces = list(re.finditer(rb"^f ([^\n]*)", data, re.M))
        if not faces:
            return name, data
        m = rng.choice(faces)
        items = m.group(1).split()
        i = rng.randrange(len(items))
        nv = len(re.findall(rb"^v ", data, re.M))
        items[i] = rng.choice([b"0", str(nv + 1).encode(), str(-nv - 1).encode(), b"99999999999999999999",
                               b"1//", b"1/2/3/4", "\u0663".encode()])
        return name, _replace_span(data, m.start(1), m.end(1), b" ".join(items))
    if kind in CHAIN_KINDS and fmt == "step":
        return name, _chain_mutation(data, kind, rng)
    if kind in IGES_KINDS and fmt == "iges":
        return name, _iges_mutation(data, kind, rng)
    if kind == "odd-name":
        base = rng.choice(["with space", "ünïcödé", "-dash", "quote'\"", "semi;colon", "x" * 200])
        raw = rng.choice([base.encode("utf-8"), b"bad\xff\xfe"])
        return os.fsdecode(raw) + ext, data
    if kind == "empty":
        return name, b""
    if kind == "wrong-ext":
        return "mutant" + (".obj" if fmt in ("step", "iges") else ".step"), data
    # a kind that does not apply to this format: a byte flip instead
    return mutate(data, fmt, "flip", rng)


def mutations(sources, n: int, seed: int = 14, kinds=KINDS):
    """``n`` :class:`Case` objects, round-robin over ``kinds`` and random over ``sources`` (seeded)."""
    rng = random.Random(seed)
    cache = {}
    for i in range(n):
        kind = kinds[i % len(kinds)]
        src = Path(rng.choice(list(sources)))
        if src not in cache:
            cache[src] = src.read_bytes()
        fmt = {".obj": "obj", ".igs": "iges", ".iges": "iges"}.get(src.suffix.lower(), "step")
        name, data = mutate(cache[src], fmt, kind, random.Random(rng.getrandbits(64)))
        yield Case(source=src.name, kind=kind, name=name, data=data)


def write_case(case: Case, folder: Path) -> Path:
    """Write a case under ``folder`` and return its path."""
    folder.mkdir(parents=True, exist_ok=True)
    path = Path(os.fsdecode(os.fsencode(str(folder)) + b"/" + os.fsencode(case.name)))
    path.write_bytes(case.data)
    return path


def classify(entry: dict, case: Case) -> str:
    """The outcome class of one gate entry: ``pass/warn/fail``, ``error:<why>``, or a violation."""
    if entry["verdict"] != "error":
        return entry["verdict"]
    text = entry["error"]
    for needle, label in (("crashed", "error:crash"), ("gave no answer", "error:timeout"),
                          ("analysis failed (", "error:unexpected-exception"), ("was dropped", "error:dropped"),
                          ("is referenced by", "error:reference"), ("the schema gives", "error:reference"),
                          ("its directory entry", "error:reference"),
                          ("not finite or exceeds", "error:bounds"), ("B_SPLINE", "error:bounds"),
                          ("OCCT's parser rejected", "error:parse"), ("line ", "error:obj-syntax")):
        if needle in text:
            return label
    return "error:other"


def faces_analysed(entry: dict) -> int:
    """Faces the gate analysed in a file (0 for an error entry)."""
    return len(entry.get("faces") or [])


def silent_loss(entry: dict, baseline: int | None) -> bool:
    """A mutant that lost faces without a word: fewer faces analysed than the unmutated file (``baseline``),
    a verdict that exits 0 (pass or warn), and no warning, note or skipped face in the entry."""
    return (baseline is not None and entry["verdict"] in ("pass", "warn") and faces_analysed(entry) < baseline
            and not entry.get("warnings") and not entry.get("notes") and not entry.get("skipped"))


def check_entry(entry: dict, path: Path, case: Case) -> list[str]:
    """Contract violations of one gate entry (empty when the outcome is documented)."""
    problems = []
    fmt = {".obj": "obj", ".step": "step", ".stp": "step", ".igs": "iges", ".iges": "iges"}.get(path.suffix.lower())
    try:
        json.dumps(entry, allow_nan=False)
    except ValueError:
        problems.append("non-finite number in the report")
    if entry["verdict"] == "error":
        msg = entry["error"]
        if "\n" in msg.strip() or "Traceback" in msg:
            problems.append("error message is not one line")
        if len(msg) > 1000:
            problems.append(f"error message of {len(msg)} characters")
        if "analysis failed (" in msg:
            problems.append(f"unexpected exception: {msg[:300]}")
        return problems
    if fmt is None:
        problems.append("a file of unknown format was gated")
        return problems
    declared = declared_faces(case.data, fmt)
    # more faces than declared is allowed when the report says so (IGES: a face instanced twice, or corrupt data)
    said = entry["faces_total"] > declared and any("more than the" in w for w in entry.get("warnings") or [])
    if entry["faces_total"] != declared and not said:
        problems.append(f"{entry['faces_total']} faces reported, {declared} declared")
    return problems
