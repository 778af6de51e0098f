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

It also counts the faces the file declares (``ADVANCED_FACE`` / ``FACE_SURFACE`` entities), the
reference the reader compares its transferred faces with.
"""

from __future__ import annotations

import math
import re

from ..errors import FileFormatError
from .messages import quote

__all__ = ["MAX_ABS", "MAX_DEGREE", "check_step_text", "declared_faces", "parse_parameters"]

#: Largest magnitude of any real number (model units, knots, weights) a real model holds.
MAX_ABS = 1e12
#: Largest B-spline degree accepted (OCCT's own limit is 25).
MAX_DEGREE = 25

_RECORD = re.compile(r"\s*#(\d+)\s*=\s*((?:[^;']|'(?:[^']|'')*')*);")
_FACE = re.compile(r"#(\d+)\s*=\s*(ADVANCED_FACE|FACE_SURFACE)\s*\(")
# candidates (fast to find): a positive exponent of 6 or more, 7+ digits before a point, NaN/INF words
_CANDIDATE = re.compile(r"[eE]\+?0*(?:[6-9]|\d{2,})|\d{7,}\.|[Nn][Aa][Nn]|[Ii][Nn][Ff]")
# every real (and NaN/INF word) of a record's text, strings removed
_REAL = re.compile(r"(?<![\w#.])[-+]?(?:\d+\.\d*|\.\d+)(?:[eE][-+]?\d+)?|(?<![\w.])(?:NAN|INF|INFINITY)(?![\w.])",
                   re.IGNORECASE)
_STRING = re.compile(r"'(?:[^']|'')*'")
_TOKEN = re.compile(r"\s*(?:('(?:[^']|'')*')|(\.[A-Z_0-9]+\.)|(#\d+)|"
                     r"([-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)|([A-Za-z_][A-Za-z_0-9]*)|([(),$*]))")


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
    pos, end = 0, len(text)
    stack: list[list] = [[]]
    while True:
        m = _TOKEN.match(text, pos)
        if m is None:
            if text[pos:].strip():
                raise ValueError(f"unexpected text at {pos}: {quote(text[pos:pos + 40])}")
            break
        pos = m.end()
        string, enum, ref, number, word, punct = m.groups()
        top = stack[-1]
        if string is not None or enum is not None or ref is not None:
            top.append(string or enum or ref)
        elif number is not None:
            top.append(float(number) if ("." in number or "e" in number.lower()) else int(number))
        elif word is not None:
            top.append(_Keyword(word.upper()))
        elif punct == "(":
            inner: list = []
            if top and isinstance(top[-1], _Keyword):  # KEYWORD( ... ): a typed value or a part
                top[-1] = (str(top[-1]), inner)
            else:
                top.append(inner)
            stack.append(inner)
        elif punct == ")":
            if len(stack) == 1:
                raise ValueError("unbalanced ')'")
            stack.pop()
        elif punct in "$*":
            top.append(punct)
        if pos >= end:
            break
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


def _data_section(text: str) -> str:
    start = text.find("DATA;")
    return text[start:] if start >= 0 else text


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


def _grid_shape(poles, dims: int):
    """``(nu, nv)`` / ``(n,)`` of a rectangular list of references, else None."""
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


def check_step_text(path, text: str) -> None:
    """Raise :class:`FileFormatError` for the first impossible number or B-spline entity.

    Parameters
    ----------
    path : path-like
        For the message.
    text : str
        The STEP file's text (latin-1 decoded).

    Raises
    ------
    FileFormatError
        ``"PATH: #ID: problem"`` (see the module notes).
    """
    data = _data_section(text)
    seen = -1
    for m in _CANDIDATE.finditer(data):
        if m.start() < seen:
            continue
        start = data.rfind(";", 0, m.start()) + 1  # the record's start (a ';' in a string: judged alone)
        rec = _RECORD.match(data, start)
        if rec is None or rec.end() < m.end():
            body, ident, seen = data[max(0, m.start() - 40):m.end() + 40], "?", m.end()
        else:
            body, ident, seen = rec.group(2), rec.group(1), rec.end()
        for tok in _REAL.finditer(_STRING.sub("''", body)):
            value = _real(tok.group(0))
            if value is None or not math.isfinite(value) or abs(value) > MAX_ABS:
                raise FileFormatError(path, f"#{ident}: number {quote(tok.group(0))} is not finite or exceeds "
                                            f"{MAX_ABS:g} (no real model holds it)")
    for m in _records_with(data, "B_SPLINE"):
        body = m.group(2)
        try:
            parts = parse_parameters(body)
        except (ValueError, RecursionError) as exc:
            raise FileFormatError(path, f"#{m.group(1)}: malformed B-spline entity ({exc})") from None
        spline = _spline(parts)
        if spline is None:
            continue
        problem = spline_problem(*spline)
        if problem:
            raise FileFormatError(path, f"#{m.group(1)}: {spline[0]}: {problem}")


def _records_with(data: str, word: str):
    """The records (``_RECORD`` matches) whose text holds ``word``, each once, found from ``word`` (fast)."""
    pos, last = 0, -1
    while True:
        hit = data.find(word, pos)
        if hit < 0:
            return
        start = data.rfind(";", 0, hit) + 1
        rec = _RECORD.match(data, start)
        if rec is None or rec.end() <= hit:  # a ';' inside a string before the word: scan from further back
            rec = next((r for r in _RECORD.finditer(data, max(0, start - 100_000), hit + 1) if r.end() > hit), None)
        if rec is None:
            pos = hit + len(word)
            continue
        if rec.start() != last:
            last = rec.start()
            yield rec
        pos = rec.end()


def _real(token: str) -> float | None:
    try:
        return float(token)
    except ValueError:
        return None
