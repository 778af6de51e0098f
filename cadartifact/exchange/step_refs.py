"""Reference integrity of a STEP text: every ``#N`` exists, and the chain that makes a face holds.

OCCT's STEP transfer drops a face without a word when an entity on the way to it is missing or is not
what the schema says: a shell that lists a deleted face, a pole list naming a deleted point (or the
surface itself), a pole ``CARTESIAN_POINT('')`` with no coordinates, a keyword corrupted to
``ADVANCED_FAC``. This scan (pure Python, no OCP, run beside the reader like :mod:`.step_scan`) makes
such a file an error naming the entity, its line and what is wrong::

    #2446 is referenced by B_SPLINE_SURFACE_WITH_KNOTS #2210 (line 388) as a pole, and is not in the file

Checked:

- every reference ``#N`` anywhere in the DATA section (outside strings and comments) names an entity
  of the file;
- along the chain that makes a face (shell -> face -> bounds -> loop -> oriented edges -> edges, and
  face -> surface -> poles), every entity of the chain has the number of parameters the schema gives
  (:data:`SCHEMA`), each reference stands where the schema allows its type (an unknown or corrupted
  keyword stands nowhere), and a B-spline surface's poles, and the control points of the B-spline curves the
  edges name, are ``CARTESIAN_POINT`` entities with three coordinates;
- the pcurves of the edges' curves on surfaces (:mod:`.step_pcurves`): their curves, and their B-spline
  control points, 2D ``CARTESIAN_POINT`` entities (a broken one crashed OCCT's reader).

The checks run on the records of those types by regular expressions that accept the well-formed
record; only a record they do not accept is parsed (:func:`~.step_scan.parse_parameters`) to say what
is wrong, so the scan costs a few per cent of the read (``benchmarks/bench_load.py``).
"""

from __future__ import annotations

import re
from itertools import compress
from operator import itemgetter

from ..errors import FileFormatError
from .step_scan import clean_data, collapse_grids, data_section, parse_parameters, record_heads
from .step_pcurves import pcurves_problem
from .step_records import (CURVES, POINT3, POINT3_SHAPE, REFERENCES, SURFACES, Records as _Records, point_shapes_ok,
                           reference_problem)

__all__ = ["SCHEMA", "SURFACES", "CURVES", "check_references", "reference_problem"]

FACES = frozenset({"ADVANCED_FACE", "FACE_SURFACE"})
#: Faces a shell may list (an ``ORIENTED_FACE`` wraps one of :data:`FACES`).
SHELL_FACES = FACES | {"ORIENTED_FACE"}
BOUNDS = frozenset({"FACE_BOUND", "FACE_OUTER_BOUND"})
LOOPS = frozenset({"EDGE_LOOP", "VERTEX_LOOP", "POLY_LOOP"})
#: An oriented edge's edge (the schema's rule: not an oriented edge, so a reference cannot loop back).
EDGES = frozenset({"EDGE_CURVE", "SUBEDGE"})
VERTICES = frozenset({"VERTEX_POINT"})
# one parameter slot: None (a value, not a reference), or (role, allowed types, a list of references?)
_FACE_SLOTS = (None, ("a bound", BOUNDS, True), ("its surface", SURFACES, False), None)
_SHELL_SLOTS = (None, ("a face", SHELL_FACES, True))
_BOUND_SLOTS = (None, ("its loop", LOOPS, False), None)
#: The parameters of each entity on the chain that makes a face (simple instances), in schema order.
SCHEMA: dict[str, tuple] = {
    "CLOSED_SHELL": _SHELL_SLOTS,
    "OPEN_SHELL": _SHELL_SLOTS,
    "ORIENTED_FACE": (None, None, ("its face", FACES, False), None),
    "ADVANCED_FACE": _FACE_SLOTS,
    "FACE_SURFACE": _FACE_SLOTS,
    "FACE_BOUND": _BOUND_SLOTS,
    "FACE_OUTER_BOUND": _BOUND_SLOTS,
    "EDGE_LOOP": (None, ("an edge", frozenset({"ORIENTED_EDGE"}), True)),
    "ORIENTED_EDGE": (None, None, None, ("its edge", EDGES, False), None),
    "EDGE_CURVE": (None, ("its start vertex", VERTICES, False), ("its end vertex", VERTICES, False),
                   ("its curve", CURVES, False), None),
}
#: Parameters of a simple B-spline surface entity (its poles are checked one by one).
SURFACE_ARITY = {"B_SPLINE_SURFACE_WITH_KNOTS": 13, "B_SPLINE_SURFACE": 8}

_STRING = r"'(?:[^']|'')*'"
# possessive quantifiers (Python 3.11): what they match is what the plain ones match here (a run of spaces or
# digits is never followed by a token that starts with one), without the backtracking states (2x faster)
_VALUE = r"(?:" + _STRING + r"|\$|\*|\.[A-Za-z_0-9]+\.|[-+]?+\d++(?:\.\d*+)?+(?:[eE][-+]?+\d++)?+)"


def _fast_pattern(keyword: str, slots: tuple) -> re.Pattern:
    """A regex accepting the well-formed record ``keyword(...)``, one group per reference slot."""
    parts = []
    for slot in slots:
        if slot is None:
            parts.append(_VALUE)
        elif slot[2]:
            parts.append(r"\(\s*+(#\d++(?:\s*+,\s*+#\d++)*+)\s*+\)")
        else:
            parts.append(r"#(\d++)")
    return re.compile(r"\s*+" + keyword + r"\s*+\(\s*+" + r"\s*+,\s*+".join(parts) + r"\s*+\)\s*+")


_FAST = {keyword: _fast_pattern(keyword, slots) for keyword, slots in SCHEMA.items()}
# the same, as one statement among statements joined by ';', with its id as the first group
_BATCH = {keyword: re.compile(r"(?:^|(?<=;))\s*+#(\d++)\s*+=" + pattern.pattern + r"(?=;|\Z)")
          for keyword, pattern in _FAST.items()}
_BATCH_POINT = re.compile(r"(?:^|(?<=;))\s*+#(\d++)\s*+=" + POINT3.pattern + r"(?=;|\Z)")
_DIGITS = re.compile(r"\d+")
_ON_CHAIN = frozenset({*SCHEMA, *SURFACE_ARITY, "("})
_END = re.compile(r"ENDSEC\s*;\s*END-ISO-10303-21\s*;\s*\Z")


def _slow_refs(records: _Records, ident: str, slots: tuple) -> list[tuple[str, tuple]] | str:
    """The references of a record the fast pattern did not accept, or what is wrong with it."""
    keyword = records.kind[ident]
    try:
        parts = parse_parameters(records.body(ident))
    except (ValueError, RecursionError) as exc:
        return f"{records.label(ident)} is malformed ({exc})"
    args = parts[0][1]
    if len(args) != len(slots):
        return f"{records.label(ident)} has {len(args)} parameters, the schema gives {keyword} {len(slots)}"
    out = []
    for k, (value, slot) in enumerate(zip(args, slots), start=1):
        if slot is None:
            continue
        role, allowed, many = slot
        values = value if many and isinstance(value, list) else [value]
        if not all(isinstance(v, str) and v.startswith("#") for v in values) or (many and not isinstance(value, list)):
            return (f"{records.label(ident)}: parameter {k} ({role}) is "
                    f"{'not a list of references' if many else 'not a reference'}")
        out.extend((v[1:], slot) for v in values)
    return out


def _chain_problem(records: _Records) -> str | None:
    """The first broken link of the chains that make the faces (by entity type, then file order), or None."""
    by_keyword: dict[str, list[int]] = {}  # keyword -> indices in heads
    keywords = list(map(itemgetter(1), records.heads))
    for i in compress(range(len(keywords)), map(_ON_CHAIN.__contains__, keywords)):  # the chain's records (C loops)
        by_keyword.setdefault(keywords[i], []).append(i)
    for keyword, slots in SCHEMA.items():
        problem = _records_problem(records, keyword, slots, by_keyword.get(keyword, []))
        if problem:
            return problem
    heads = records.heads
    surfaces = [heads[i][0] for keyword, indices in by_keyword.items() if keyword != "(" and keyword not in SCHEMA
                for i in indices]
    surfaces += [heads[i][0] for i in by_keyword.get("(", []) if "B_SPLINE_SURFACE" in records.statement_at(i)]
    return _surfaces_problem(records, surfaces) or _edge_curves_problem(records, by_keyword.get("EDGE_CURVE", []))


#: B-spline curve entities whose references are all control points (a complex instance qualifies by a part).
_SPLINE_CURVES = frozenset({"B_SPLINE_CURVE_WITH_KNOTS", "B_SPLINE_CURVE"})
#: Curves on surfaces: ``(name, curve_3d, (associated pcurves), master)``.
_ON_SURFACES = frozenset({"SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"})


def _edge_curves_problem(records: _Records, indices: list[int]) -> str | None:
    """The control points of the B-spline curves of the edges (``EDGE_CURVE`` records ``heads[i]``, ``i`` in
    ``indices``), checked as a surface's poles are: OCCT read a malformed control point of an edge's curve
    (``'Control Point'l(``, a digit turned into a letter, a corrupted keyword) without a word, and its repair
    split the face into pieces that are no face of the file (the seed-2732 campaign). Then the pcurves of the
    curves on surfaces (:func:`~.step_pcurves.pcurves_problem`)."""
    if not indices:
        return None
    found = _BATCH["EDGE_CURVE"].findall(_pick(records, indices))  # the well-formed edges, each its own statement
    curves = [m[3] for m in found]
    idents = [records.heads[i][0] for i in indices]
    if [m[0] for m in found] != idents:  # some edge not matched there (statements not one per record): by its body
        matched = set(map(itemgetter(0), found))
        for ident in idents:
            slow = [] if ident in matched else _slow_refs(records, ident, SCHEMA["EDGE_CURVE"])
            curves += [target for target, slot in slow if slot[0] == "its curve"] if isinstance(slow, list) else []
    kind = records.kind
    on_surfaces = []
    for k, c in enumerate(curves):  # a curve on surfaces (OCCT writes these): its 3D curve, its first reference
        if kind.get(c) in _ON_SURFACES:
            on_surfaces.append(c)
            first = REFERENCES.search(records.body(c))
            curves[k] = first.group(1) if first else c
    splines = [c for c in dict.fromkeys(curves) if kind.get(c) in _SPLINE_CURVES
               or (kind.get(c) == "(" and "B_SPLINE_CURVE" in records.names(c))]
    pcurves = [c for c in curves if kind.get(c) == "PCURVE"]  # an edge in a face's parameters only
    return ((_poles_problem(records, splines, "a control point") if splines else None)
            or pcurves_problem(records, on_surfaces, pcurves))


def _pick(records: _Records, indices: list[int]) -> str:
    """The statements of records ``heads[i]`` for ``i`` in ``indices``, joined by ``;`` (by C calls)."""
    statements = records.statements
    picked = itemgetter(*[i + 1 for i in indices if i + 1 < len(statements)])(statements) if indices else ()
    return ";".join(picked) if isinstance(picked, tuple) else picked


def _records_problem(records: _Records, keyword: str, slots: tuple, indices: list[int]) -> str | None:
    """The first problem of the ``keyword`` records (``indices`` in heads): their parameters, then their references.

    All the well-formed records are matched by one regex over their statements joined (one C call);
    the others are parsed one by one.
    """
    if not indices:
        return None
    idents = [records.heads[i][0] for i in indices]
    joined = ";".join(map(records.statement_at, indices)) if len(indices) < 64 else _pick(records, indices)
    matched = _BATCH[keyword].findall(joined)
    groups = [slot for slot in slots if slot is not None]
    if len(groups) == 1:
        matched = [(owner, group) for owner, group in matched]
    owners = [m[0] for m in matched]
    # per reference slot, the targets (a list slot's references joined, split by one findall)
    targets = [_DIGITS.findall(",".join(map(itemgetter(k + 1), matched))) if slot[2]
               else list(map(itemgetter(k + 1), matched)) for k, slot in enumerate(groups)]
    late: list[tuple[str, str, tuple]] = []  # (owner, target, slot) of the records parsed one by one
    if owners != idents:  # some record is not well-formed (or not its own statement: found exactly below)
        well_formed = set(owners)
        for ident in idents:
            if ident not in well_formed:
                slow = _slow_refs(records, ident, slots)
                if isinstance(slow, str):
                    return slow
                late.extend((ident, target, slot) for target, slot in slow)
    kind = records.kind
    for k, (role, allowed, many) in enumerate(groups):
        if set(map(kind.get, targets[k])) <= allowed:
            continue  # every target's type can stand there (C loops): the common case
        for target in dict.fromkeys(targets[k]):
            if kind.get(target) in allowed or _complex_allowed(records, target, allowed):
                continue
            owner = next(m[0] for m in matched if target in (_DIGITS.findall(m[k + 1]) if many else [m[k + 1]]))
            problem = reference_problem(records, target, role, allowed, owner)
            if problem:
                return problem
    for owner, target, (role, allowed, _) in late:
        problem = reference_problem(records, target, role, allowed, owner)
        if problem:
            return problem
    return None


def _complex_allowed(records: _Records, target: str, allowed) -> bool:
    """Whether ``#target`` is a complex instance with a part of an ``allowed`` type (no owner needed to say so)."""
    return records.kind.get(target) == "(" and any(name in allowed for name in records.names(target))


def _surfaces_problem(records: _Records, surfaces: list[str]) -> str | None:
    """B-spline surfaces: the parameter count of a simple instance, and every pole a three-coordinate
    CARTESIAN_POINT (the poles' statements checked by one regex, as :func:`_records_problem` does)."""
    for ident in surfaces:
        keyword = records.kind[ident]
        if keyword not in SURFACE_ARITY:
            continue
        count = records.arities.get(ident)  # what the number scan's parse of the record found, if it ran
        if count is None:
            try:
                count = len(parse_parameters(collapse_grids(records.body(ident)))[0][1])
            except (ValueError, RecursionError) as exc:
                return f"{records.label(ident)} is malformed ({exc})"
        if count != SURFACE_ARITY[keyword]:
            return (f"{records.label(ident)} has {count} parameters, the schema gives {keyword} "
                    f"{SURFACE_ARITY[keyword]}")
    return _poles_problem(records, surfaces, "a pole")


def _poles_problem(records: _Records, owners: list[str], role: str) -> str | None:
    """Every reference of the ``owners`` records (B-spline surfaces or curves: their references are their control
    points) names a ``CARTESIAN_POINT`` with three coordinates, or the first that does not, as ``role``."""
    kind = records.kind
    bodies = [records.body(ident) for ident in owners]  # a cleaned text: no strings or comments
    poles = list(dict.fromkeys(REFERENCES.findall(";".join(bodies))))  # each once, in file order

    def owner(pole: str) -> str:
        """The first owner that names ``pole`` (for the message)."""
        return next(i for i, b in zip(owners, bodies) if re.search("#" + pole + r"(?!\d)", b))

    if set(map(kind.get, poles)) - {"CARTESIAN_POINT"}:  # some pole is not a point (C loops when all are)
        for pole in [p for p in poles if kind.get(p) != "CARTESIAN_POINT"]:
            problem = reference_problem(records, pole, role, {"CARTESIAN_POINT"}, owner(pole))
            if problem:
                return problem
    if not poles:
        return None
    joined = records.statements_of(poles)  # each pole's statement, by C calls only
    if records.aligned and _point_shapes_ok(joined):  # every pole's statement (its own), a well-formed 3D point
        return None
    if _BATCH_POINT.findall(joined) == poles:  # every pole's own statement, a well-formed 3D point
        return None
    for pole in poles:
        if not POINT3.fullmatch(records.body(pole)):
            return (f"#{pole} is referenced by {records.label(owner(pole))} as {role}, and "
                    + _point_problem(records, pole))
    return None


def _point_shapes_ok(joined: str) -> bool:
    """Whether every statement of ``joined`` is a well-formed 3D ``CARTESIAN_POINT``
    (:func:`~.step_records.point_shapes_ok`; ids are not compared: the caller picked each statement by its record's
    position in an aligned section, :attr:`~.step_records.Records.aligned`)."""
    return point_shapes_ok(joined, POINT3_SHAPE)


def _point_problem(records: _Records, ident: str) -> str:
    """Why a CARTESIAN_POINT is not a point with three coordinates."""
    where = f"its record (line {records.line(ident)})"
    try:
        args = parse_parameters(records.body(ident))[0][1]
    except (ValueError, RecursionError) as exc:
        return f"{where} is malformed ({exc})"
    coordinates = args[1] if len(args) == 2 and isinstance(args[1], list) else None
    if coordinates is None:
        return f"{where} has no list of coordinates"
    if len(coordinates) != 3:
        return f"{where} has {len(coordinates)} coordinates, not 3"
    return f"{where} has coordinates that are not numbers"


def _missing_reference(records: _Records) -> str | None:
    """A reference anywhere in the DATA section to an entity that is not in the file, or None."""
    missing = set(REFERENCES.findall(records.data))
    missing.difference_update(records.kind)
    for target in sorted(missing, key=int):
        for m in re.finditer(r"#" + target + r"(?!\d)", records.data):
            statement_start = records.data.rfind(";", 0, m.start()) + 1
            head = re.match(r"\s*#(\d+)\s*=", records.data[statement_start:])
            if head is None or head.group(1) not in records.kind:
                continue
            owner = head.group(1)
            if re.search(r"#" + target + r"(?!\d)", records.body(owner)):
                return f"#{target} is referenced by {records.label(owner)}, and is not in the file"
    return None


#: ``#N`` ids longer than this (digits), spaces between ``#N`` and ``=`` beyond this: the exact scan decides.
_ID_DIGITS = 12
_SPACES_BEFORE_EQUALS = 16
#: The characters ``\s`` matches in a latin-1 text (str patterns: the ASCII ones, the separators, NEL and NBSP).
_SPACE_CODES = (9, 10, 11, 12, 13, 28, 29, 30, 31, 32, 133, 160)


def _space_table():
    import numpy as np

    table = np.zeros(256, bool)
    table[list(_SPACE_CODES)] = True
    return table


_SPACE = None


def _references_defined(data: str, heads: list, records: _Records | None = None) -> bool:
    """Whether every ``#N`` of ``data`` (a cleaned DATA section) names a record of ``heads``, decided by array
    operations on the bytes around each ``#`` (no string per reference); False also when it cannot tell (an id
    of more than :data:`_ID_DIGITS` digits or with a leading zero, more than :data:`_SPACES_BEFORE_EQUALS` spaces
    before ``=``, a ``#N =`` that is not a record's head): the exact scan (:func:`_missing_reference`) then
    decides, and names the reference. ``records``: given, its ``index`` is set (an id's position in ``heads``)
    when the heads are exactly the ``#N =`` of the text."""
    import numpy as np

    global _SPACE
    if _SPACE is None:
        _SPACE = _space_table()
    a = np.frombuffer((data + " " * 32).encode("latin-1", "replace"), np.uint8)
    start = np.flatnonzero(a == 35) + 1  # after each '#'
    if not len(start):
        return True
    value = np.zeros(len(start), np.int64)
    length = np.zeros(len(start), np.int64)
    code = a[start] - 48  # uint8 arithmetic: only '0'..'9' fall below 10
    active = code < 10
    if (active & (code == 0) & ((a[start + 1] - 48) < 10)).any():
        return False  # '#007': a leading zero (the exact scan compares the digits as written)
    for k in range(1, _ID_DIGITS + 2):  # one digit of every id at a time (ids have a few digits)
        if not active.any():
            break
        if k > _ID_DIGITS:
            return False  # an id of more digits than that: the exact scan
        value[active] = value[active] * 10 + code[active]
        length += active
        code = a[start + k] - 48
        active &= code < 10
    value, after = value[length > 0], (start + length)[length > 0]  # '#' followed by no digit: not a reference
    for k in range(_SPACES_BEFORE_EQUALS + 1):
        more = _SPACE[a[after]]
        if not more.any():
            break
        if k == _SPACES_BEFORE_EQUALS:
            return False
        after += more
    defined = value[a[after] == 61]  # '#N =': a record's head
    if len(defined) != len(heads):
        return False  # a '#N =' that is not a record's head (a corrupted record): the exact scan
    top = int(defined.max()) + 1
    if top > 16 * len(a) + 1_000_000:  # sparse ids: a sorted search instead of a table by id
        return bool(np.isin(value, defined).all())
    index = np.full(top + 1, -1, np.int64)
    index[defined] = np.arange(len(defined))  # the heads in file order are the '#N =' in file order
    if records is not None and (index[defined] == np.arange(len(defined))).all():  # an id defined twice: no index
        records.index = index
    return bool((index[np.minimum(value, top)] >= 0).all())


def check_references(path, text: str, heads: list[tuple[str, str]] | None = None, clean: str | None = None,
                     arities: dict | None = None) -> None:
    """Raise :class:`FileFormatError` for the first broken reference of a STEP text (see the module notes).

    Parameters
    ----------
    path : path-like
        For the message.
    text : str
        The STEP file's text (latin-1 decoded).
    heads : list of (str, str), optional
        :func:`~.step_scan.record_heads` of ``clean``, if known.
    clean : str, optional
        :func:`~.step_scan.clean_data` of its DATA section, if known.
    arities : dict, optional
        ``{id: parameter count}`` of the simple B-spline surface records, as
        :func:`~.step_scan.check_step_text` found them (they are parsed once).

    Raises
    ------
    FileFormatError
        ``"PATH: #ID is referenced by KEYWORD #OWNER (line N) as ROLE, and ..."``.
    """
    if not _END.search(text, max(0, len(text) - 4096)):
        return  # a truncated file: OCCT's parser says so (every reference past the cut would be "missing")
    if clean is None:
        clean = clean_data(data_section(text))
    records = _Records(text, clean, record_heads(clean) if heads is None else heads, arities)
    defined = _references_defined(clean, records.heads, records)  # first: its index serves the chain's scan
    problem = _chain_problem(records)
    if problem is None and not defined:
        problem = _missing_reference(records)
    if problem:
        raise FileFormatError(path, problem)
