"""A fast text pre-scan of STEP files: numbers no real model holds are an error before OCCT sees them.

OCCT's STEP transfer hangs on knots, weights or coordinates of 1e154 and more, crashes or
silently drops faces on absurd degrees and multiplicities. This scan (pure Python, no OCP) rejects:

- any real number anywhere in the DATA section (outside strings) that is not finite or whose
  magnitude exceeds :data:`MAX_ABS` (``1e12`` model units), and ``NaN``/``INF`` words;
- in every B-spline curve or surface entity (simple or complex instance:
  ``B_SPLINE_CURVE_WITH_KNOTS``, ``B_SPLINE_SURFACE_WITH_KNOTS``, their ``RATIONAL_`` parts):
  a degree outside ``1 .. MAX_DEGREE`` (25), a multiplicity outside ``1 .. degree + 1``, knots that
  decrease, as many multiplicities as knots, ``sum(multiplicities) == poles + degree + 1``,
  a control-point grid that is not rectangular, weights not of the grid's shape, or a weight
  that is not positive or outside ``[1/MAX_ABS, MAX_ABS]``.

A repeated entity id (``#3`` defined twice: OCCT would transfer both) is rejected too. It also
counts the faces the file declares (``ADVANCED_FACE`` / ``FACE_SURFACE`` entities), the
reference the reader compares its transferred faces with.
"""

from __future__ import annotations

import math
import operator
import re
from itertools import chain

from ..errors import FileFormatError
from .messages import quote

__all__ = ["MAX_ABS", "MAX_DEGREE", "check_step_text", "clean_data", "data_section", "entity_line_in", "declared_faces", "parse_parameters",
           "record_heads", "record_ids"]

#: Largest magnitude of any real number (model units, knots, weights) a real model holds.
MAX_ABS = 1e12
#: Largest B-spline degree accepted (OCCT's own limit is 25).
MAX_DEGREE = 25
#: Parameters of a simple ``B_SPLINE_SURFACE_WITH_KNOTS`` record (the name, 7 of the surface, 5 of the knots).
SURFACE_WITH_KNOTS_ARITY = 13

_FACE = re.compile(r"#(\d+)\s*=\s*(ADVANCED_FACE|FACE_SURFACE)\s*\(")
# candidates, found on the cleaned text as upper-case bytes (same offsets; a literal first byte: fast): a positive
# exponent of 6 or more; 13 digits in a row after neither a digit nor a point (an integer part of 1e12 or more,
# with a point or without: 9999999999999 where a real stands), found as " " + 13 "0" once digits are "0" and
# every other byte but the point a blank; the NaN/INF words
_EXPONENT = re.compile(rb"E\+?0*(?:[6-9]|[1-9][0-9])")
_DIGITS_ONLY = bytes(0x30 if 0x30 <= i <= 0x39 else 0x2E if i == 0x2E else 0x20 for i in range(256))
_LONG_INTEGER = b" " + b"0" * 13
_HEAD = re.compile(r"\s*#(\d+)\s*=")
# every real (and NaN/INF word) of a record's text, strings removed
# (``1e300``, with no point, is not a STEP real, but OCCT's lexer takes it, and hangs on it: so are huge integers)
_REAL = re.compile(r"(?<![\w#.])[-+]?(?:(?:\d+\.\d*|\.\d+)(?:[eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d{13,})"
                   r"|(?<![\w.])(?:NAN|INF|INFINITY)(?![\w.])", re.IGNORECASE)
_TOKEN = re.compile(r"\s*(?:('(?:[^']|'')*')|(\.[A-Z_0-9]+\.)|(#\d+)|"
                     r"([-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)|([A-Za-z_][A-Za-z_0-9]*)|([(),$*]))")


#: Text made only of characters tokens are made of (then every character belongs to a token).
_PLAIN = re.compile(r"[A-Za-z0-9_#.,()$*+'\-\s]*\Z")


class _Keyword(str):
    """A typed parameter's or a complex instance part's keyword."""


def parse_parameters(text: str):
    """Parse a STEP record body (after ``#id =``) into nested Python values.

    Returns
    -------
    list
        A simple instance ``KEYWORD(a, b, ...)`` gives ``[("KEYWORD", [a, b, ...])]``; a complex
        instance ``(A(...) B(...))`` gives one pair per part. Values: ``int``, ``float``, ``str``
        (strings, enums ``.X.``, references ``#n``, ``$``, ``*``), lists, and ``(keyword, list)``
        pairs for typed parameters.

    Raises
    ------
    ValueError
        Text that is not a STEP record body.
    """
    if not _PLAIN.match(text) or text.count("'") % 2:  # characters no token holds (outside strings): find them the slow way
        rest = _TOKEN.sub("", text)
        if rest.strip():
            raise ValueError(f"unexpected text {quote(rest.strip()[:40])}")
    stack: list[list] = [[]]
    top = stack[0]
    for string, enum, ref, number, word, punct in _TOKEN.findall(text):  # one C pass, then plain tuples
        if punct:
            if punct == "(":
                inner: list = []
                if top and isinstance(top[-1], _Keyword):  # KEYWORD( ... ): a typed value or a part
                    top[-1] = (str(top[-1]), inner)
                else:
                    top.append(inner)
                stack.append(inner)
                top = inner
            elif punct == ")":
                if len(stack) == 1:
                    raise ValueError("unbalanced ')'")
                stack.pop()
                top = stack[-1]
            elif punct in "$*":
                top.append(punct)
        elif ref or string or enum:
            top.append(ref or string or enum)
        elif number:
            top.append(float(number) if ("." in number or "e" in number or "E" in number) else int(number))
        elif word:
            top.append(_Keyword(word.upper()))
    if len(stack) != 1:
        raise ValueError("unbalanced '('")
    out = stack[0]
    if len(out) == 1 and isinstance(out[0], list):  # complex instance: (A(...) B(...))
        out = out[0]
    parts = [p for p in out if isinstance(p, tuple)]
    if not parts or len(parts) != len(out):
        raise ValueError("not an entity instance")
    return parts


def declared_faces(text: str) -> dict[int, str]:
    """``{entity id: "ADVANCED_FACE" | "FACE_SURFACE"}`` of the faces a STEP text declares (simple instances)."""
    return {int(m.group(1)): m.group(2) for m in _FACE.finditer(text)}


# strings, emptied: no backtracking ('' escapes are two strings side by side, both emptied)
_STRINGS_ONLY = re.compile(r"'[^']*'")
# strings and comments, in one pass (only when a comment opens somewhere); an unterminated one runs to the end
_STRINGS_COMMENTS = re.compile(r"'[^']*'|/\*[^*]*(?:\*+[^*/][^*]*)*(?:\*+/|\**\Z)")


def clean_data(data: str) -> str:
    """A DATA section (:func:`data_section`) with its strings emptied (``''``) and its comments removed.

    What is left has a ``;`` only where a statement ends, a ``#`` only in ids and references and digits
    only in numbers, ids and keywords, so the scans split and search it without tracking quotes (one
    regex pass in C, no backtracking; a file's lines are counted on its own text, :func:`entity_line_in`).
    An unterminated string is left as it is (OCCT's parser rejects the file).
    """
    if "/*" not in data:
        return _STRINGS_ONLY.sub("''", data)
    return _STRINGS_COMMENTS.sub(lambda m: "''" if m.group(0)[0] == "'" else " ", data)


def entity_line_in(text: str, ident: str) -> int | None:
    """The 1-based line of the record ``#ident =`` in a STEP text (exact: strings and comments skipped)."""
    from .step_text import text_entity_lines

    want = int(ident)
    return next((line for i, line, _ in text_entity_lines(text) if i == want), None)


def data_section(text: str) -> str:
    """The text from ``DATA;`` on (``DATA ;`` too: Part 21 allows space between tokens; the whole text when
    there is none)."""
    start = text.find("DATA;")
    if start < 0:
        found = _DATA_KEYWORD.search(text)
        start = found.start() if found else -1
    return text[start:] if start >= 0 else text


_DATA_KEYWORD = re.compile(r"(?<![A-Za-z0-9_])DATA\s+;")


_data_section = data_section


def _spline(parts: list) -> tuple[str, dict] | None:
    """Normalise a B-spline curve/surface entity to its attributes, or None for other entities."""
    names = [name for name, _ in parts]
    surface = any(n.endswith("B_SPLINE_SURFACE_WITH_KNOTS") or n == "B_SPLINE_SURFACE"
                  or n == "RATIONAL_B_SPLINE_SURFACE" for n in names)
    curve = any(n.endswith("B_SPLINE_CURVE_WITH_KNOTS") or n == "B_SPLINE_CURVE"
                or n == "RATIONAL_B_SPLINE_CURVE" for n in names)
    if not (surface or curve):
        return None
    dims = 2 if surface else 1
    base, knots_kw, rational_kw = (("B_SPLINE_SURFACE", "B_SPLINE_SURFACE_WITH_KNOTS", "RATIONAL_B_SPLINE_SURFACE")
                                   if surface else
                                   ("B_SPLINE_CURVE", "B_SPLINE_CURVE_WITH_KNOTS", "RATIONAL_B_SPLINE_CURVE"))
    attrs: dict = {}
    if len(parts) == 1:  # simple instance: name, then the supertype's attributes, then the subtype's
        name, args = parts[0]
        args = args[1:]  # the representation item's name
        head = args[:dims + 1 + 3 + dims - 1] if surface else args[:5]
        rest = args[len(head):]
        attrs["degrees"] = head[:dims]
        attrs["poles"] = head[dims] if len(head) > dims else None
        if name == knots_kw:
            attrs["mults"] = rest[:dims]
            attrs["knots"] = rest[dims:2 * dims]
        elif name == rational_kw:
            attrs["weights"] = rest[0] if rest else None
        return name, attrs
    by_name = dict(parts)
    if base in by_name:
        args = by_name[base]
        attrs["degrees"] = args[:dims]
        attrs["poles"] = args[dims] if len(args) > dims else None
    if knots_kw in by_name:
        args = by_name[knots_kw]
        attrs["mults"] = args[:dims]
        attrs["knots"] = args[dims:2 * dims]
    if rational_kw in by_name:
        args = by_name[rational_kw]
        attrs["weights"] = args[0] if args else None
    return (knots_kw if knots_kw in by_name else base), attrs


_GRID2 = re.compile(r"\(\s*\(\s*#\d+(?:\s*,\s*#\d+)*\s*\)(?:\s*,\s*\(\s*#\d+(?:\s*,\s*#\d+)*\s*\))*\s*\)")
_GRID1 = re.compile(r"\(\s*#\d+(?:\s*,\s*#\d+)*\s*\)")


def _grid_token(m) -> str:
    """A pole list of references as one enum-like token ``.GRID_nu_nv.`` / ``.GRID_n.`` (``.GRID_RAGGED.``)."""
    text = m.group(0)
    if text.count("(") == 1:
        return f".GRID_{text.count('#')}."
    rows = [seg.count("#") for seg in text.split(")") if "#" in seg]
    return f".GRID_{len(rows)}_{rows[0]}." if len(set(rows)) == 1 else ".GRID_RAGGED."


def collapse_grids(body: str) -> str:
    """``body`` with its lists (and lists of lists) of references replaced by :func:`_grid_token` tokens.

    The pole grid is most of a B-spline record's text; its shape is all the checks need, so the
    tokenizer never walks it (4x faster on the real files).
    """
    return _GRID1.sub(_grid_token, _GRID2.sub(_grid_token, body))


def _grid_shape(poles, dims: int):
    """``(nu, nv)`` / ``(n,)`` of a rectangular list of references (or its grid token), else None."""
    if isinstance(poles, str) and poles.startswith(".GRID_"):
        sizes = poles[6:-1].split("_")
        if len(sizes) != dims or not all(x.isdigit() for x in sizes):
            return None
        shape = tuple(int(x) for x in sizes)
        return shape if all(shape) else None
    if not isinstance(poles, list) or not poles:
        return None
    if dims == 1:
        return (len(poles),) if all(isinstance(p, str) and p.startswith("#") for p in poles) else None
    if not all(isinstance(row, list) for row in poles):
        return None
    nv = len(poles[0])
    if nv == 0 or any(len(row) != nv for row in poles):
        return None
    if not all(isinstance(p, str) and p.startswith("#") for row in poles for p in row):
        return None
    return len(poles), nv


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _possible(kind: str, attrs: dict) -> bool:
    """True when :func:`spline_problem` would find nothing, decided by C-level loops (``map``, ``min``, ``fsum``)
    instead of a Python test per knot and weight; False when unsure (then :func:`spline_problem` says what)."""
    try:
        dims = 2 if "SURFACE" in kind else 1
        degrees = attrs.get("degrees") or []
        if len(degrees) != dims or set(map(type, degrees)) != {int} or min(degrees) < 1 or max(degrees) > MAX_DEGREE:
            return False
        shape = _grid_shape(attrs.get("poles"), dims)
        if shape is None:
            return False
        if "mults" in attrs:
            mults, knots = attrs["mults"], attrs["knots"]
            if len(mults) != dims or len(knots) != dims:
                return False
            for p, n, m, k in zip(degrees, shape, mults, knots):
                if type(m) is not list or type(k) is not list or len(m) != len(k) or len(k) < 2:
                    return False
                if not set(map(type, m)) <= _INT or not set(map(type, k)) <= _NUMBER_TYPES:
                    return False
                if min(m) < 1 or max(m) > p + 1 or sum(m) != n + p + 1:
                    return False
                # NaN: max may pass it over, fsum does not
                if not max(map(abs, k)) <= MAX_ABS or not math.isfinite(math.fsum(k)):
                    return False
                if not all(map(operator.le, k, k[1:])):
                    return False
        if "weights" in attrs:
            w = attrs["weights"]
            if type(w) is not list or len(w) != shape[0]:
                return False
            if dims == 2:
                if set(map(type, w)) != {list} or set(map(len, w)) != {shape[1]}:
                    return False
                w = list(chain.from_iterable(w))
            if not w or not set(map(type, w)) <= _NUMBER_TYPES:
                return False
            if not (min(w) >= 1 / MAX_ABS and max(w) <= MAX_ABS and math.isfinite(math.fsum(w))):
                return False
        return True
    except (TypeError, ValueError, OverflowError):
        return False


_INT = frozenset({int})
_NUMBER_TYPES = frozenset({int, float})


def spline_problem(kind: str, attrs: dict) -> str | None:
    """What makes a normalised B-spline entity impossible, or None."""
    dims = 2 if "SURFACE" in kind else 1
    dirs = ("u", "v") if dims == 2 else ("",)
    degrees = attrs.get("degrees") or []
    if len(degrees) != dims or not all(isinstance(d, int) for d in degrees):
        return "degrees are not integers"
    for d, p in zip(dirs, degrees):
        if not 1 <= p <= MAX_DEGREE:
            return f"{d + ' ' if d else ''}degree {p} outside 1..{MAX_DEGREE}"
    shape = _grid_shape(attrs.get("poles"), dims)
    if shape is None:
        return "the control points are not a rectangular list of references"
    if "mults" in attrs:
        mults, knots = attrs["mults"], attrs["knots"]
        if len(mults) != dims or len(knots) != dims:
            return "knots or multiplicities missing"
        for d, p, n, m, k in zip(dirs, degrees, shape, mults, knots):
            label = f"{d} " if d else ""
            if not isinstance(m, list) or not isinstance(k, list) or not all(isinstance(x, int) for x in m) \
                    or not all(_number(x) for x in k):
                return f"{label}knots or multiplicities are not numbers"
            if len(m) != len(k) or len(k) < 2:
                return f"{len(m)} {label}multiplicities for {len(k)} knots"
            bad = next((x for x in m if not 1 <= x <= p + 1), None)
            if bad is not None:
                return f"{label}multiplicity {bad} outside 1..degree+1 = {p + 1}"
            if any(not math.isfinite(x) or abs(x) > MAX_ABS for x in k):
                return f"{label}knot {next(x for x in k if not math.isfinite(x) or abs(x) > MAX_ABS)!r} out of bounds"
            i = next((i for i in range(len(k) - 1) if k[i + 1] < k[i]), None)
            if i is not None:
                return f"{label}knots decrease ({k[i]!r} then {k[i + 1]!r})"
            if sum(m) != n + p + 1:
                return f"{label}multiplicities sum to {sum(m)}, expected poles + degree + 1 = {n + p + 1}"
    if "weights" in attrs:
        w = attrs["weights"]
        if dims == 2:
            ok = isinstance(w, list) and len(w) == shape[0] and all(
                isinstance(r, list) and len(r) == shape[1] and all(_number(x) for x in r) for r in w)
            flat = [x for r in w for x in r] if ok else []
        else:
            ok = isinstance(w, list) and len(w) == shape[0] and all(_number(x) for x in w)
            flat = w if ok else []
        if not ok:
            return f"the weights are not a {'x'.join(map(str, shape))} list of numbers"
        bad = next((x for x in flat if not (math.isfinite(x) and 1 / MAX_ABS <= x <= MAX_ABS)), None)
        if bad is not None:
            return f"weight {bad!r} outside [{1 / MAX_ABS:g}, {MAX_ABS:g}]"
    return None


_IDS = re.compile(r";\s*#(\d+)\s*=")
_HEADS = re.compile(r";\s*#(\d+)\s*=\s*([A-Za-z_][A-Za-z_0-9]*|\()")


def record_ids(text: str) -> list[str]:
    """The ``#id`` of every record of the DATA section, in file order (OCCT's model keeps that order)."""
    return ["#" + i for i in _IDS.findall(_data_section(text))]


def record_heads(data: str) -> list[tuple[str, str]]:
    """``[(id, KEYWORD)]`` of every record of a DATA section (:func:`data_section`), in file order.

    The keyword is as written (``"("`` for a complex instance); ids are the digits, without ``#``. A
    statement ``#n =`` followed by no keyword is not a record (OCCT's parser rejects it).
    """
    return _HEADS.findall(data)


def check_step_text(path, text: str, heads: list[tuple[str, str]] | None = None, clean: str | None = None,
                    arities: dict | None = None) -> list[str]:
    """Raise :class:`FileFormatError` for a repeated entity id or the first impossible number or B-spline entity.

    Returns
    -------
    list of str
        :func:`record_ids` of the text (for naming entities later).

    Parameters
    ----------
    path : path-like
        For the message.
    text : str
        The STEP file's text (latin-1 decoded).
    heads : list of (str, str), optional
        :func:`record_heads` of ``clean``, if known.
    clean : str, optional
        :func:`clean_data` of the text's DATA section, if known.
    arities : dict, optional
        Filled with ``{id: parameter count}`` of the simple B-spline surface records (parsed here once, for
        :func:`~.step_refs.check_references`).

    Raises
    ------
    FileFormatError
        ``"PATH: #ID (line N): problem"`` (see the module notes).
    """
    if clean is None:
        clean = clean_data(_data_section(text))
    ids = ["#" + i for i, _ in (record_heads(clean) if heads is None else heads)]
    if len(set(ids)) != len(ids):
        seen_ids: set[str] = set()
        twice = next(i for i in ids if i in seen_ids or seen_ids.add(i))
        raise FileFormatError(path, f"{twice} is defined twice (entity ids must be unique)")

    def where(ident: str) -> str:
        line = entity_line_in(text, ident) if ident != "?" else None
        return f"#{ident}" + (f" (line {line})" if line else "")

    hits = sorted(_candidates(clean))
    seen = -1
    for at in hits:
        if at < seen:
            continue
        ident, body, seen = _record_around(clean, at)
        for tok in _REAL.finditer(body):
            value = _real(tok.group(0))
            if value is None or not math.isfinite(value) or abs(value) > MAX_ABS:
                raise FileFormatError(path, f"{where(ident)}: number {quote(tok.group(0))} is not finite or "
                                            f"exceeds {MAX_ABS:g} (no real model holds it)")
    for ident, body, _ in _records_with(clean, "B_SPLINE"):
        collapsed = collapse_grids(body)
        spline = _fast_spline(collapsed)
        if spline is not None and _possible(*spline):  # well-formed and possible: the common case
            if arities is not None and spline[0] == "B_SPLINE_SURFACE_WITH_KNOTS":
                arities[ident] = SURFACE_WITH_KNOTS_ARITY
            continue
        try:  # the full parse: other records, and the message of a problem
            parts = parse_parameters(collapsed)
        except (ValueError, RecursionError) as exc:
            raise FileFormatError(path, f"{where(ident)}: malformed B-spline entity ({exc})") from None
        spline = _spline(parts)
        if spline is None:
            continue
        if arities is not None and len(parts) == 1 and parts[0][0] in ("B_SPLINE_SURFACE_WITH_KNOTS",
                                                                        "B_SPLINE_SURFACE"):
            arities[ident] = len(parts[0][1])
        problem = None if _possible(*spline) else spline_problem(*spline)
        if problem:
            raise FileFormatError(path, f"{where(ident)}: {spline[0]}: {problem}")
    return ids


# the well-formed simple B-spline-with-knots records (grids collapsed): their lists converted by C calls, not
# tokenised; anything else (complex instances, odd spellings) takes the full parse
_REAL_ITEM = r"\s*[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?\s*"
_REALS = re.compile(_REAL_ITEM + r"(?:," + _REAL_ITEM + r")*")
_INTS = re.compile(r"\s*\d+\s*(?:,\s*\d+\s*)*")
_FLAG = r"\s*,\s*\.[A-Z_]+\."
_LIST = r"\s*,\s*\(([^()]*)\)"
_FAST_SURFACE = re.compile(r"\s*B_SPLINE_SURFACE_WITH_KNOTS\s*\(\s*''\s*,\s*(\d+)\s*,\s*(\d+)\s*,\s*(\.GRID_\d+_\d+\.)"
                           + _FLAG * 4 + _LIST * 4 + _FLAG + r"\s*\)\s*")
_FAST_CURVE = re.compile(r"\s*B_SPLINE_CURVE_WITH_KNOTS\s*\(\s*''\s*,\s*(\d+)\s*,\s*(\.GRID_\d+\.)"
                         + _FLAG * 3 + _LIST * 2 + _FLAG + r"\s*\)\s*")


def _fast_spline(collapsed: str) -> tuple[str, dict] | None:
    """:func:`_spline` of a well-formed simple ``B_SPLINE_SURFACE_WITH_KNOTS`` / ``B_SPLINE_CURVE_WITH_KNOTS`` record
    (:func:`collapse_grids` applied), without the tokenizer; None for any other record."""
    m = _FAST_SURFACE.fullmatch(collapsed)
    if m is not None:
        name, dims, g = "B_SPLINE_SURFACE_WITH_KNOTS", 2, m.groups()
        degrees, poles, lists = [int(g[0]), int(g[1])], g[2], g[3:]
    else:
        m = _FAST_CURVE.fullmatch(collapsed)
        if m is None:
            return None
        name, dims, g = "B_SPLINE_CURVE_WITH_KNOTS", 1, m.groups()
        degrees, poles, lists = [int(g[0])], g[1], g[2:]
    mults, knots = lists[:dims], lists[dims:]
    if not all(_INTS.fullmatch(x) for x in mults) or not all(_REALS.fullmatch(x) for x in knots):
        return None
    return name, {"degrees": degrees, "poles": poles, "mults": [list(map(int, x.split(","))) for x in mults],
                  "knots": [list(map(float, x.split(","))) for x in knots]}


def _candidates(clean: str) -> set[int]:
    """Offsets in a :func:`clean_data` text where a number out of bounds may be (each checked exactly)."""
    upper = clean.encode("latin-1", "replace").upper()
    hits = {m.start() for m in _EXPONENT.finditer(upper)}
    hits.update(at + 1 for at in _find_all(upper.translate(_DIGITS_ONLY), _LONG_INTEGER))
    for word in (b"NAN", b"INF"):
        hits.update(_find_all(upper, word))
    return hits


def _find_all(text: bytes, word: bytes):
    pos = text.find(word)
    while pos >= 0:
        yield pos
        pos = text.find(word, pos + 1)


def _records_with(clean: str, word: str):
    """``(id, body, end)`` (:func:`_record_around`) of each statement of a :func:`clean_data` text holding ``word``."""
    pos = 0
    while (hit := clean.find(word, pos)) >= 0:
        rec = _record_around(clean, hit)
        yield rec
        pos = rec[2]


def _record_around(clean: str, at: int) -> tuple[str, str, int]:
    """``(id, body, end)`` of the statement of a :func:`clean_data` text holding position ``at``: its id (``"?"``
    when it is not a record ``#id = ...``), its text after ``=`` (the whole statement when not a record) and
    where the next statement starts."""
    start = clean.rfind(";", 0, at) + 1
    end = clean.find(";", at)
    end = len(clean) if end < 0 else end
    head = _HEAD.match(clean, start, end)
    if head is None:
        return "?", clean[start:end], end + 1
    return head.group(1), clean[head.end():end], end + 1


def _real(token: str) -> float | None:
    try:
        return float(token)
    except ValueError:
        return None
