"""The records of a STEP DATA section by id, and what is wrong with a reference among them.

:class:`Records` finds a record's keyword, text and line lazily, exactly when a check needs them (the reference
scans of :mod:`.step_refs` and :mod:`.step_pcurves` run on every read and must cost a few per cent of it);
:func:`reference_problem` words what is wrong with ``#target`` standing where a record names it.
"""

from __future__ import annotations

import re
from operator import itemgetter

from .step_text import text_entity_lines

__all__ = ["CURVES", "SURFACES", "NUMBER", "POINT2", "POINT3", "POINT2_SHAPE", "POINT3_SHAPE", "REFERENCES", "Records",
           "point_shapes_ok", "reference_problem"]

# the point statement's shape (see point_shapes_ok): in bytes, \s as a str pattern's \s over latin-1, 0 for \d+
_ZERO_DIGITS = bytes.maketrans(b"123456789", b"000000000")
_S = rb"[\t\n\x0b\x0c\r\x1c-\x1f \x85\xa0]*+"
_NUM0 = rb"[-+]?+(?:0(?:\.0?+)?+|\.0)(?:[eE][-+]?+0)?+"


def _point_shape(dimensions: tuple[int, ...]) -> re.Pattern:
    """The shape of a ``#N = CARTESIAN_POINT(name, (x, y[, z]))`` statement with ``0`` for each run of digits
    (:func:`point_shapes_ok`), for points of the given numbers of coordinates."""
    coords = rb"|".join(_NUM0 + (_S + rb"," + _S + _NUM0) * (d - 1) for d in dimensions)
    return re.compile(_S + rb"#0" + _S + rb"=" + _S + rb"CARTESIAN_POINT" + _S + rb"\(" + _S + rb"(?:'(?:[^']|'')*'|\$)"
                      + _S + rb"," + _S + rb"\(" + _S + rb"(?:" + coords + rb")" + _S + rb"\)" + _S + rb"\)" + _S)


#: A 3D point's statement shape; a pcurve's control point (2D, or 3D as some writers give).
POINT3_SHAPE = _point_shape((3,))
POINT2_SHAPE = _point_shape((2, 3))

#: A reference ``#N`` in a cleaned text (the id its group).
REFERENCES = re.compile(r"#(\d+)")
#: A STEP number, integer or real (possessive: a run of digits is never followed by a token that starts with one).
NUMBER = r"[-+]?+(?:\d++(?:\.\d*+)?+|\.\d++)(?:[eE][-+]?+\d++)?+"


def _point_body(least: int, most: int) -> re.Pattern:
    """The body of a well-formed ``CARTESIAN_POINT(name, (x, y[, z]))`` record (after ``#N =``) with ``least`` to
    ``most`` coordinates: the text counterpart of :func:`_point_shape`."""
    more = r"\s*+,\s*+" + NUMBER
    optional = r"(?:" + more + r"){0,%d}+" % (most - least) if most > least else ""
    return re.compile(r"\s*+CARTESIAN_POINT\s*+\(\s*+(?:'(?:[^']|'')*'|\$)\s*+,\s*+\(\s*+" + NUMBER
                      + more * (least - 1) + optional + r"\s*+\)\s*+\)\s*+")


#: A 3D point's record body; a pcurve's control point's (2D or 3D).
POINT3 = _point_body(3, 3)
POINT2 = _point_body(2, 3)

#: Surface entities of the STEP geometry schema (a complex instance qualifies with one of them as a part).
SURFACES = frozenset({
    "PLANE", "CYLINDRICAL_SURFACE", "CONICAL_SURFACE", "SPHERICAL_SURFACE", "TOROIDAL_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE", "SURFACE_OF_LINEAR_EXTRUSION", "SURFACE_OF_REVOLUTION", "B_SPLINE_SURFACE",
    "B_SPLINE_SURFACE_WITH_KNOTS", "BEZIER_SURFACE", "UNIFORM_SURFACE", "QUASI_UNIFORM_SURFACE",
    "RATIONAL_B_SPLINE_SURFACE", "RECTANGULAR_TRIMMED_SURFACE", "OFFSET_SURFACE", "CURVE_BOUNDED_SURFACE",
    "RECTANGULAR_COMPOSITE_SURFACE", "SURFACE_REPLICA"})
#: Curve entities of the STEP geometry schema.
CURVES = frozenset({
    "LINE", "CIRCLE", "ELLIPSE", "PARABOLA", "HYPERBOLA", "POLYLINE", "B_SPLINE_CURVE", "B_SPLINE_CURVE_WITH_KNOTS",
    "BEZIER_CURVE", "UNIFORM_CURVE", "QUASI_UNIFORM_CURVE", "RATIONAL_B_SPLINE_CURVE", "TRIMMED_CURVE",
    "COMPOSITE_CURVE", "COMPOSITE_CURVE_ON_SURFACE", "OFFSET_CURVE_3D", "SURFACE_CURVE", "SEAM_CURVE",
    "INTERSECTION_CURVE", "BOUNDED_CURVE", "CURVE_REPLICA", "PCURVE", "CURVE"})

# a string ('' escapes a quote; an unterminated one runs to the end), a comment, or a statement end
_STATEMENT_TOKENS = re.compile(r"'(?:[^']|'')*(?:'|\Z)|/\*.*?(?:\*/|\Z)|;", re.DOTALL)
_STATEMENT_HEAD = re.compile(r"\s*(?:/\*.*?\*/\s*)*#(\d+)\s*=", re.DOTALL)


class Records:
    """The records of a DATA section by id: keyword, text and line (found lazily, exactly when needed).

    Parameters
    ----------
    text : str
        The file's text (latin-1 decoded): lines are counted on it.
    data : str
        The DATA section as :func:`~.step_scan.clean_data` gives it (strings emptied, comments removed: a
        ``;`` ends a statement, always).
    heads : list of (str, str)
        ``(id, keyword)`` of each record in file order (:func:`~.step_scan.record_heads`); ``"("`` for a
        complex instance.
    arities : dict, optional
        ``{id: parameter count}`` of records already parsed.
    """

    def __init__(self, text: str, data: str, heads: list[tuple[str, str]], arities: dict | None = None):
        self.text, self.data, self.heads = text, data, heads
        self.arities = arities or {}
        self._lines: dict[str, int] | None = None
        self.kind = dict(heads)
        # statement i + 1 of the section is record i, unless a ';' inside a string or comment shifts them:
        # each use checks the statement's head and falls back to an exact index once
        self.statements = data.split(";")
        self._position: dict[str, int] | None = None
        #: ``index[id]``: the record's position in ``heads`` (an array, from :func:`_references_defined`), or None
        self.index = None
        self.exact: dict[str, tuple[int, int]] | None = None

    @property
    def aligned(self) -> bool:
        """Whether statement ``i + 1`` of the section is record ``i`` for every record: as many statements as
        records, plus ``DATA`` before them and ``ENDSEC``, ``END-ISO-10303-21`` and the end after them."""
        statements = self.statements
        return (len(statements) == len(self.heads) + 4
                and [s.strip() for s in statements[-3:]] == ["ENDSEC", "END-ISO-10303-21", ""])

    @property
    def position(self) -> dict[str, int]:
        """``{id: index in heads}`` (built on first use)."""
        if self._position is None:
            self._position = dict(zip(map(itemgetter(0), self.heads), range(len(self.heads))))
        return self._position

    def body(self, ident: str) -> str:
        """The record's text after ``#ident =``."""
        i = int(self.index[int(ident)]) if self.index is not None else self.position[ident]
        statement = self.statements[i + 1] if i + 1 < len(self.statements) else ""
        head, sep, body = statement.partition("=")
        if sep and head.strip() == "#" + ident and not body.count("'") % 2 and "/*" not in body:
            return body  # the whole record (a ';' inside a string or comment would have cut it short)
        found = self._exact().get(ident)
        if found is None:  # not a well-formed record (an unbalanced quote): up to the next ';'
            head = re.search(r"(?:^|;)\s*#" + ident + r"\s*=", self.data)
            if head is None:
                return ""
            end = self.data.find(";", head.end())
            found = head.end(), len(self.data) if end < 0 else end
        return self.data[found[0]:found[1]]

    def statement(self, ident: str) -> str:
        """The statement ``#ident = ...`` as split at ``;`` (may be another one: :meth:`body` is exact)."""
        return self.statement_at(self.position[ident])

    def statement_at(self, i: int) -> str:
        """The statement of record ``heads[i]`` as split at ``;`` (see :meth:`statement`)."""
        i += 1
        return self.statements[i] if i < len(self.statements) else ""

    def statements_of(self, idents: list[str]) -> str:
        """The statements of records ``idents`` joined by ``;`` (statement ``i + 1`` is record ``i`` where the
        section is :attr:`aligned`; callers that cannot know check the ids), by C calls: positions from
        :attr:`index` when there is one. "" when ``idents`` is empty or some position is past the section."""
        if not idents:
            return ""
        if self.index is not None:
            import numpy as np

            where = (self.index[np.fromiter(map(int, idents), np.int64, len(idents))] + 1).tolist()
        else:
            where = [self.position[p] + 1 for p in idents]
        if max(where) >= len(self.statements):
            return ""
        picked = itemgetter(*where)(self.statements)
        return picked if len(idents) == 1 else ";".join(picked)

    def _exact(self) -> dict[str, tuple[int, int]]:
        """``{id: (start, end) of the body}`` from the statement ends outside strings and comments (one linear
        pass; a regex that also had to end each record at a ';' could backtrack exponentially on '' runs)."""
        if self.exact is None:
            self.exact = {}
            start = 0
            for m in _STATEMENT_TOKENS.finditer(self.data):
                if m.group(0) != ";":
                    continue
                head = _STATEMENT_HEAD.match(self.data, start, m.start())
                if head is not None:
                    self.exact.setdefault(head.group(1), (head.end(), m.start()))
                start = m.end()
        return self.exact

    def line(self, ident: str) -> int | None:
        """The 1-based line of ``#ident =`` in the file (an index of the text's lines, built on first use)."""
        if self._lines is None:
            self._lines = {}
            for i, line, _ in text_entity_lines(self.text):
                self._lines.setdefault(str(i), line)
        return self._lines.get(ident)

    def names(self, ident: str) -> list[str]:
        """The keyword of a simple instance, the part keywords of a complex one."""
        kind = self.kind[ident]
        if kind != "(":
            return [kind]
        return re.findall(r"([A-Za-z_][A-Za-z_0-9]*)\s*\(", self.body(ident))  # a cleaned text: no strings to skip

    def label(self, ident: str) -> str:
        """``KEYWORD #id (line n)``."""
        kind = self.kind[ident]
        name = "complex instance" if kind == "(" else kind
        line = self.line(ident)
        return f"{name} #{ident}" + (f" (line {line})" if line else "")


def reference_problem(records: Records, target: str, role: str, allowed, owner: str) -> str | None:
    """What is wrong with ``#target`` standing as ``role`` in ``#owner``, or None.

    Parameters
    ----------
    records : Records
    target, owner : str
        Record ids: the reference and the record that makes it.
    role : str
        What the reference stands as, for the message ("a pole", "its curve").
    allowed : set of str
        Keywords that may stand there (a complex instance qualifies by one of its parts).

    Returns
    -------
    str or None
        ``"#TARGET is referenced by KEYWORD #OWNER (line N) as ROLE, and ..."``.
    """
    kind = records.kind.get(target)
    if kind is None:
        return f"#{target} is referenced by {records.label(owner)} as {role}, and is not in the file"
    if kind in allowed:
        return None
    names = records.names(target)
    if not any(name in allowed for name in names):
        where = f"#{target} is referenced by {records.label(owner)} as {role}, and"
        what = " ".join(names) if kind == "(" else kind
        line = records.line(target)
        what = f"the {what} itself" if target == owner else what + (f" (line {line})" if line else "")
        expected = " or ".join(sorted(allowed)) if len(allowed) <= 4 else f"one of {len(allowed)} {_family(role)}"
        return f"{where} is {what}, which cannot stand there (expected {expected})"
    return None


def _family(role: str) -> str:
    return {"its surface": "surface types", "its curve": "curve types"}.get(role, "types")


def point_shapes_ok(joined: str, shape: re.Pattern) -> bool:
    """Whether every statement of ``joined`` (``;``-separated) is a well-formed ``CARTESIAN_POINT`` of ``shape``.

    Its digits are made ``0`` and each run of them one ``0`` (a C-level translate and one array pass); the few
    distinct shapes left are matched by ``shape`` (:data:`POINT3_SHAPE`, :data:`POINT2_SHAPE`: the point regex
    with ``0`` for a run of digits, so a text matches :data:`POINT3` exactly when its shape matches
    :data:`POINT3_SHAPE`). Ids are not compared: the caller picked each statement by its record's position in an
    aligned section (:attr:`Records.aligned`)."""
    import numpy as np

    raw = np.frombuffer(joined.encode("latin-1", "replace").translate(_ZERO_DIGITS), np.uint8)
    zero = raw == 48
    keep = np.ones(len(raw), bool)
    keep[1:] = ~(zero[1:] & zero[:-1])
    return all(map(shape.fullmatch, set(raw[keep].tobytes().split(b";"))))
