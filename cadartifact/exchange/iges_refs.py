"""Directory-entry integrity of an IGES file: the pointers of the chain that makes a face hold.

OCCT's IGES reader makes a pointer it cannot follow a null (a pointer past the directory, to an even
number, to a corrupted type) and its transfer then drops the face, or the whole shape, without naming
it: a trimmed surface (144) whose surface pointer names no entity was read as a file of no face. This
scan (pure Python, no OCP, run in this process while the reader child reads, like :mod:`.step_refs`)
makes such a file an error naming the entities, their lines and what is wrong::

    D999 is referenced by IGES entity D1 (type 144, line 6) as its surface, and is not in the file

Checked, for the entities that make faces (OCCT exposes their pointers after its read; the same pointers
are read here from the text):

- a directory entry's two lines give the same entity type (a corrupted type, e.g. ``144 -> 145`` on one
  line, is a face that would vanish);
- the pointers of a trimmed surface (144: its surface, outer and inner boundaries), a bounded surface
  (143: its surface, boundaries), a face (510: its surface, loops) and a shell (514: its faces) each name a
  directory entry of the file (a positive odd number within the directory), not the entity itself, of a
  type that can stand there;
- the same for what those pointers reach, entity by entity along the chain: a curve on a surface (142: its
  surface, its curves in parameter and model space, either of which may be 0), a boundary (141: its surface,
  its curves), a composite curve (102: its parts), a loop (508: each edge's edge or vertex list and its
  parameter-space curves) and an edge list (504: each edge's curve and vertex lists). OCCT's transfer follows
  these without a check: a loop's edge-list pointer past the directory, or an edge list's curve or vertex-list
  pointer, is a segmentation fault of the reader (an error with no cause named, in the reader child), a wrong
  type there was read without a word. A curve no face reaches (a drawing's wireframe) is not checked;
- every parameter of a numbers-only entity of the chain (:data:`_NUMERIC`) is a number or empty: OCCT's parser
  reads a token that is no number (a byte flipped into ``!``) as whatever its state holds, and the same file
  was refused or read as another surface depending on the files read before it;
- every number of the parameter data is finite and within :data:`~.step_scan.MAX_ABS` (``1.0D300``,
  ``1.0E+400``, an integer part of 13 digits or more, ``NAN``, ``INF``), as the STEP pre-scan does; the message
  names the entity (the directory pointer of the parameter line) and the line::

      IGES entity D7 (type 128, line 52): number '1.0D300' is not finite or exceeds 1e+12 (no real model holds it)

  Candidates are found by one regex pass over the parameter lines' data columns (a positive exponent of two
  digits or more, a run of 13 digits after no point, the words NaN/INF); only an entity that holds one is
  tokenized (Hollerith strings skipped) to confirm it.
"""

from __future__ import annotations

import re

from ..errors import FileFormatError

__all__ = ["SURFACE_TYPES", "check_iges_text", "declared_faces", "iges_problem"]

#: Surface entity types of IGES 5.3 (a face's, trimmed or bounded surface's underlying surface).
SURFACE_TYPES = frozenset({108, 114, 118, 120, 122, 128, 140, 190, 192, 194, 196, 198})
_CURVE_ON_SURFACE = frozenset({142})
_BOUNDARY = frozenset({141})
_LOOP = frozenset({508})
_FACE = frozenset({510})
#: Curve entity types of IGES 5.3 (arc, composite, conic, copious data, line, parametric spline, rational B-spline,
#: offset): what a curve on a surface, a boundary, a loop's or an edge's curve may name.
_CURVE = frozenset({100, 102, 104, 106, 110, 112, 126, 130})
_COMPONENT = _CURVE | {116, 132}  # a composite curve's parts may also be points and connect points (§4.4)
_EDGES = frozenset({504})
_VERTICES = frozenset({502})
#: Entities reached from a face along its chain (its boundaries, loops, edges, curves), whose pointers are checked
#: too: OCCT's IGES transfer dereferences them without a check (a loop's edge list pointer past the directory is
#: a segmentation fault of the reader).
_REACHED = frozenset({142, 141, 508, 504, 102})
_KINDS = {SURFACE_TYPES: "a surface type", _CURVE: "a curve type", _COMPONENT: "a curve or point type"}

# an integer of at most 15 digits (a longer one is no pointer or count; int() refuses 4300 digits and more)
_NUMBER = re.compile(r"\s*[-+]?[0-9]{1,15}\s*\Z")
# a parameter of a numbers-only record: an integer or a real (E or D exponent), or empty (the default value)
_REAL = re.compile(r"\s*(?:[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[EeDd][-+]?[0-9]+)?)?\s*\Z")
# a number that may exceed MAX_ABS or not be finite: a positive exponent of 2+ digits, 13 digits after no point
# or digit, a NaN or INF word (case-insensitive, as strtod takes them)
_BIG = re.compile(r"[EeDd]\+?0*[1-9][0-9]|(?<![.0-9])[0-9]{13}|(?i:nan|inf)")
# a parameter's token: a Hollerith count (its characters skipped), a number, or a NaN/INF word
_TOKEN = re.compile(r"([0-9]+)H|([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[EeDd][-+]?[0-9]+)?)|([-+]?(?i:nan|inf(?:inity)?))")
_TYPE = re.compile(r"-?[0-9]+")
_HOLLERITH = re.compile(r"(?:^|[,;])\s*[0-9]+H")


def _pointer_slots(kind: int, params: list[str]):
    """``(index in params, role, allowed types, zero allowed)`` of the pointers of an entity on the chain."""
    if kind == 144:  # PTS, N1, N2, PTO, PTI1..PTIn2
        n2 = _int(params, 2)
        slots = [(0, "its surface", SURFACE_TYPES, False), (3, "its outer boundary", _CURVE_ON_SURFACE, True)]
        slots += [(4 + k, "an inner boundary", _CURVE_ON_SURFACE, False) for k in _upto(n2, params)]
        return slots
    if kind == 143:  # TYPE, SPTR, N, BDPT1..BDPTn
        n = _int(params, 2)
        return [(1, "its surface", SURFACE_TYPES, False)] + [
            (3 + k, "a boundary", _BOUNDARY, False) for k in _upto(n, params)]
    if kind == 510:  # SURF, N, OUTER, LOOP1..LOOPn
        n = _int(params, 1)
        return [(0, "its surface", SURFACE_TYPES, False)] + [
            (3 + k, "a loop", _LOOP, False) for k in _upto(n, params)]
    if kind == 514:  # N, FACE1, ORNT1, ...
        n = _int(params, 0)
        return [(1 + 2 * k, "a face", _FACE, False) for k in _upto(n, params)]
    if kind == 142:  # CRTN, SPTR, BPTR, CPTR, PREF (either curve may be absent: 0)
        return [(1, "its surface", SURFACE_TYPES, False), (2, "its curve in the surface's parameters", _CURVE, True),
                (3, "its model-space curve", _CURVE, True)]
    if kind == 102:  # N, DE1..DEN
        n = _int(params, 0)
        return [(1 + k, "a part", _COMPONENT, False) for k in _upto(n, params)]
    if kind == 504:  # N, then per edge: CURV, SVP, SV, TVP, TV
        n = _int(params, 0)
        return [slot for k in _upto(n, params) for slot in (
            (1 + 5 * k, "an edge's curve", _CURVE, False), (2 + 5 * k, "an edge's start vertex list", _VERTICES, False),
            (4 + 5 * k, "an edge's end vertex list", _VERTICES, False))]
    if kind == 508:  # N, then per edge: TYPE, EDGE, NDX, OF, K, K x (ISOP, CURV)
        return _loop_slots(params)
    if kind == 141:  # TYPE, PREF, SPTR, N, then per curve: CRVPT, SENSE, K, PSCPT1..K
        return _boundary_slots(params)
    return []


def _upto(count: int | None, params: list[str]) -> range:
    """``range(count)`` for a record's count of pointers, at most one per parameter it has (a corrupted count of
    1e9 would otherwise make a list of 1e9 slots; past the record's end a slot is "not a pointer")."""
    return range(max(0, min(count or 0, len(params) + 1)))


def _loop_slots(params: list[str]):
    """The pointer slots of a loop (508, IGES 5.3 §4.149): each edge's edge or vertex list and parameter curves."""
    slots, i = [], 1
    for _ in _upto(_int(params, 0), params):
        kind, k = _int(params, i), _int(params, i + 4)
        slots.append((i + 1, "an edge's vertex list" if kind == 1 else "an edge's edge list",
                      _VERTICES if kind == 1 else _EDGES, False))
        if k is None or k < 0 or i + 5 + 2 * k > len(params):
            break  # a count that is no count: the slots found so far are checked, OCCT reads the rest
        slots += [(i + 6 + 2 * j, "an edge's curve in the surface's parameters", _CURVE, False) for j in range(k)]
        i += 5 + 2 * k
    return slots


def _boundary_slots(params: list[str]):
    """The pointer slots of a boundary (141, IGES 5.3 §4.43): its surface, each model-space curve and its
    parameter-space curves."""
    slots, i = [(2, "its surface", SURFACE_TYPES, False)], 4
    for _ in _upto(_int(params, 3), params):
        k = _int(params, i + 2)
        slots.append((i, "a model-space curve", _CURVE, False))
        if k is None or k < 0 or i + 3 + k > len(params):
            break
        slots += [(i + 3 + j, "a curve in the surface's parameters", _CURVE, False) for j in range(k)]
        i += 3 + k
    return slots


def _bspline_count_problem(params: list[str]) -> str | None:
    """Whether a rational B-spline surface record (type 128) has the parameters its degrees and counts give.

    IGES 5.3 §4.24: ``K1, K2, M1, M2, PROP1..5``, then ``A + 1`` and ``B + 1`` knots (``A = N1 + 2 M1``,
    ``N1 = 1 + K1 - M1``; ``B`` likewise), ``C = (K1 + 1)(K2 + 1)`` weights, ``3 C`` coordinates and four
    parameter bounds; optionally followed by the two groups of additional pointers (a count, then that many).
    A split or merged number (a decimal point turned into the delimiter) shifts every later parameter: OCCT
    reads such a record without a word, as another surface.
    """
    head = [_int(params, i) for i in range(4)]
    if any(h is None or h < 0 for h in head):
        return "its degrees and counts (K1, K2, M1, M2) are not non-negative integers"
    k1, k2, m1, m2 = head
    if k1 > 1_000_000 or k2 > 1_000_000:
        return None  # left to the reader's own limits
    a, b, c = k1 + m1 + 1, k2 + m2 + 1, (k1 + 1) * (k2 + 1)
    expected = 9 + (a + 1) + (b + 1) + 4 * c + 4
    n = len(params)
    if n == expected:
        return None
    if n > expected:  # the two groups of additional pointers: NB, back pointers, NP, property pointers
        nb = _int(params, expected)
        np_ = _int(params, expected + 1 + nb) if nb is not None and nb >= 0 else None
        if np_ is not None and np_ >= 0 and n == expected + 2 + nb + np_:
            return None
    return (f"its record has {n} parameters where its degrees and counts (K1={k1}, K2={k2}, M1={m1}, M2={m2}) "
            f"give {expected}: a number split or merged in the text")


def _not_a_number(params: list[str]) -> str | None:
    """The first parameter of a numbers-only record (type 128) that is neither a number nor empty (a default).

    OCCT's parser reads such a token (a byte flipped into ``!`` beside a weight) as whatever its state holds:
    in the fuzz campaign the same file was refused ("some weight parameters are not of positive real type") or
    read as another surface that passed the gate, depending on the files the reader child had read before.
    """
    for i, token in enumerate(params):
        if not _REAL.match(token):
            return f"parameter {i + 1} ({token.strip()[:20]!r}) is not a number"
    return None


#: Entity types whose parameters are all numbers (integers, reals, pointers) in IGES 5.3: the geometry and
#: topology a face is made of. A record of one of them that holds a string (Hollerith) is left alone.
_NUMERIC = frozenset({*SURFACE_TYPES, 100, 102, 104, 110, 112, 116, 124, 126, 141, 142, 143, 144, 502, 504, 508, 510,
                      514})


def _token_problem(p_lines: list[str], d_lines: list[str], types: list, delimiter: str, end: str, label) -> str | None:
    """The first parameter of a numbers-only entity (:data:`_NUMERIC`) that is neither a number nor empty.

    Candidates are found by one regex pass over the parameter lines' data columns (a character no number,
    delimiter or blank is made of); only the entities of those lines are split into parameters.
    """
    other = re.compile("[^0-9+\\-.EeDd \n" + re.escape(delimiter + end) + "]")
    data = "\n".join(ln[:64] for ln in p_lines)
    if not other.search(data):
        return None
    seen = set()
    for m in other.finditer(data):
        de = p_lines[data.count("\n", 0, m.start())][64:72].strip()
        if de in seen or not _NUMBER.match(de):
            continue
        seen.add(de)
        d = int(de)
        k = (d - 1) // 2
        if not (d > 0 and d % 2 and k < len(types)) or types[k] not in _NUMERIC:
            continue
        a, b = d_lines[2 * k], d_lines[2 * k + 1]
        if not (_NUMBER.match(a[8:16]) and _NUMBER.match(b[24:32])):
            continue
        start, n_lines = int(a[8:16]), int(b[24:32])
        record = "".join(ln[:64] for ln in p_lines[start - 1:start - 1 + n_lines]) if start > 0 else ""
        if _HOLLERITH.search(record):
            continue
        problem = _not_a_number(record.split(end, 1)[0].split(delimiter)[1:])
        if problem:
            return f"{label(d)}: {problem}"
    return None


def _int(params: list[str], i: int) -> int | None:
    return int(params[i]) if i < len(params) and _NUMBER.match(params[i]) else None


def _number_problem(lines: list[str], p_lines: list[str], types: list, first_d: int) -> str | None:
    """The first number of the parameter data that is not finite or exceeds MAX_ABS, or None."""
    from .step_scan import MAX_ABS

    data = "\n".join(ln[:64] for ln in p_lines)  # the data columns only (not the pointers and sequence numbers)
    if not _BIG.search(data):
        return None
    first_p = next(i for i, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P") + 1
    seen = set()
    for m in _BIG.finditer(data):
        k = data.count("\n", 0, m.start())  # the parameter line of the candidate
        de = p_lines[k][64:72].strip()
        if de in seen:
            continue
        seen.add(de)
        # the entity's record: its parameter lines (those that point back to its directory entry), tokenized
        rows = [i for i, ln in enumerate(p_lines) if ln[64:72].strip() == de]
        record = "".join(p_lines[i][:64] for i in rows)
        pos = 0
        while True:
            t = _TOKEN.search(record, pos)
            if t is None:
                break
            if t.group(1) is not None:  # a Hollerith string: its characters are not numbers
                pos = t.end() + int(t.group(1))
                continue
            pos = t.end()
            token = t.group(2) or t.group(3)
            try:
                value = float(token.replace("D", "E").replace("d", "e"))
            except ValueError:
                continue
            if not (abs(value) <= MAX_ABS):
                line = first_p + rows[min(t.start() // 64, len(rows) - 1)]
                try:
                    d = int(de)
                    kind = types[(d - 1) // 2] if d > 0 and (d - 1) // 2 < len(types) else None
                    who = f"IGES entity D{d} (type {kind}, line {line})"
                except ValueError:
                    who = f"IGES parameter data (line {line})"
                return f"{who}: number {token!r} is not finite or exceeds {MAX_ABS:g} (no real model holds it)"
    return None


def iges_problem(text: str) -> str | None:
    """The first broken pointer of the chain that makes a face in an IGES text, or None (see the module notes)."""
    lines = text.splitlines()
    d_lines = [ln for ln in lines if len(ln) >= 73 and ln[72] == "D"]
    p_lines = [ln for ln in lines if len(ln) >= 73 and ln[72] == "P"]
    if not d_lines or len(d_lines) % 2:
        return None  # not a well-formed directory: OCCT's parser says so
    first_d = next(i for i, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "D") + 1  # its file line
    delimiter, end = _delimiters(lines)
    count = len(d_lines) // 2
    types: list[int | None] = []
    for k in range(count):
        a, b = d_lines[2 * k], d_lines[2 * k + 1]
        t1, t2 = a[:8].strip(), b[:8].strip()
        types.append(int(t1) if _TYPE.fullmatch(t1) else None)  # ASCII digits only ('50²' is not a type)
        if t1 != t2 and (t1 in _CHAIN or t2 in _CHAIN):
            return (f"IGES entity D{2 * k + 1} (line {first_d + 2 * k}): its directory entry gives two entity types "
                    f"({t1 or 'none'} and {t2 or 'none'})")

    problem = _number_problem(lines, p_lines, types, first_d)
    if problem:
        return problem

    def label(d: int) -> str:
        return f"IGES entity D{d} (type {types[(d - 1) // 2]}, line {first_d + d - 1})"


    # the faces' roots, then what their pointers reach (boundaries, loops, edges, curves), each entity once
    work = [2 * k + 1 for k, kind in enumerate(types) if kind in (128, 144, 143, 510, 514)][::-1]
    seen = set(work)
    parts: dict[int, list[int]] = {}  # composite curve -> its composite-curve parts (a cycle crashes OCCT)
    while work:
        d = work.pop()
        k, kind = (d - 1) // 2, types[(d - 1) // 2]
        a, b = d_lines[2 * k], d_lines[2 * k + 1]
        if not (_NUMBER.match(a[8:16]) and _NUMBER.match(b[24:32])):
            return f"{label(d)}: its directory entry has no parameter data pointer"
        start, n_lines = int(a[8:16]), int(b[24:32])
        record = "".join(ln[:64] for ln in p_lines[start - 1:start - 1 + n_lines]) if start > 0 else ""
        params = record.split(end, 1)[0].split(delimiter)[1:]  # after the entity type
        if kind == 128:
            # a 128 record holds numbers only; one with a string (Hollerith) in it is not a shifted number
            problem = None if _HOLLERITH.search(record) else (_bspline_count_problem(params)
                                                              or _not_a_number(params))
            if problem:
                return f"{label(d)}: {problem}"
            continue
        for i, role, allowed, zero in _pointer_slots(kind, params):
            value = _int(params, i)
            if value is None and zero and (i >= len(params) or not params[i].strip()):
                value = 0  # an empty or omitted parameter takes its default: no entity, where none may stand
            if value is None:
                return f"{label(d)}: parameter {i + 1} ({role}) is not a pointer"
            if value == 0 and zero:
                continue
            if value <= 0 or value % 2 == 0 or value > 2 * count:
                return f"D{value} is referenced by {label(d)} as {role}, and is not in the file"
            if value == d:
                return f"D{value} is referenced by {label(d)} as {role}, and is the entity itself, which cannot stand there"
            target = types[(value - 1) // 2]
            if target not in allowed:
                expected = _KINDS.get(allowed) or " or ".join(str(x) for x in sorted(allowed))
                return (f"D{value} is referenced by {label(d)} as {role}, and is type {target} (line "
                        f"{first_d + value - 1}), which cannot stand there (expected {expected})")
            if kind == 102 and target == 102:
                parts.setdefault(d, []).append(value)
            if target in _REACHED and value not in seen:
                seen.add(value)
                work.append(value)
    return _cycle_problem(parts, label) or _token_problem(p_lines, d_lines, types, delimiter, end, label)


def _cycle_problem(parts: dict[int, list[int]], label) -> str | None:
    """A composite curve (102) that contains itself through others (``D7 -> D17 -> D7``), or None: OCCT's transfer
    follows a composite curve's parts recursively, and such a cycle was a segmentation fault of the reader.
    ``parts``: each composite curve's composite-curve parts."""
    state: dict[int, int] = {}  # 1: on the current path, 2: done
    for root in parts:
        if state.get(root):
            continue
        path, stack = [root], [iter(parts.get(root, ()))]
        state[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                loop = path[path.index(nxt):] + [nxt]
                return (f"{label(nxt)}: a composite curve that contains itself through its parts "
                        f"({' -> '.join(f'D{x}' for x in loop)})")
            elif not state.get(nxt):
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(parts.get(nxt, ())))
    return None


_CHAIN = {str(t) for t in (*SURFACE_TYPES, 102, 141, 142, 143, 144, 502, 504, 508, 510, 514)}


def _delimiters(lines: list[str]) -> tuple[str, str]:
    """The parameter and record delimiters the Global section declares (``,`` and ``;`` by default)."""
    glob = "".join(ln[:72] for ln in lines if len(ln) >= 73 and ln[72] == "G")
    delimiter = "," if not glob.startswith("1H") else glob[2]
    rest = glob[1:] if delimiter == "," and glob.startswith(",") else glob[4:] if glob.startswith("1H") else glob
    end = ";"
    if rest.startswith("1H") and len(rest) > 2:
        end = rest[2]
    return delimiter, end


def declared_faces(text: str) -> tuple[int, str]:
    """``(count, what)``: the faces an IGES text declares in its directory: its faces (510), else its trimmed and
    bounded surfaces (144, 143); ``what`` names them for a message."""
    types = [ln[:8].strip() for ln in text.splitlines() if len(ln) >= 73 and ln[72] == "D"][::2]
    faces = types.count("510")
    if faces:
        return faces, "faces (type 510)"
    return types.count("144") + types.count("143"), "trimmed or bounded surfaces (types 144, 143)"


def check_iges_text(path) -> tuple[int, str]:
    """Raise :class:`FileFormatError` for the first broken pointer of an IGES file (see the module notes); else
    return :func:`declared_faces` (the reader compares the faces OCCT transferred with them)."""
    with open(path, "rb") as fh:
        text = fh.read().decode("latin-1")
    problem = iges_problem(text)
    if problem:
        raise FileFormatError(path, problem)
    return declared_faces(text)


def faces_missing(path, result, declared: tuple[int, str]):
    """``result`` (a :class:`~cadartifact.exchange.files.LoadResult`) with the faces an IGES file declares that are
    neither in OCCT's transferred shape nor named as dropped counted as ``skipped["dropped"]``, and a warning
    saying so (the gate fails such a file): OCCT loses faces without a word on some corrupt parameter data (a
    byte flipped in a curve of a loop).

    More faces transferred than declared is said too (a warning, the faces are kept): a face instanced more than
    once by a legitimate file, or corrupt directory data (a duplicated directory line made OCCT transfer 2 faces
    of a file that declares 1, the fuzz campaign)."""
    from dataclasses import replace

    count, what = declared
    missing = count - result.faces_total
    if missing < 0 and count:
        warning = (f"{path}: OCCT's transferred shape has {result.faces_total} faces, {-missing} more than the "
                   f"{count} {what} the IGES file declares (a face instanced more than once, or corrupt directory "
                   "data?)")
        return replace(result, warnings=[*result.warnings, warning])
    if missing <= 0:
        return result
    skipped = dict(result.skipped)
    skipped["dropped"] = skipped.get("dropped", 0) + missing
    warning = (f"{path}: {missing} of the {count} {what} the IGES file declares are not in OCCT's transferred "
               "shape, and OCCT named none (corrupt parameter data?)")
    return replace(result, faces_total=result.faces_total + missing, skipped=skipped,
                   warnings=[*result.warnings, warning])
