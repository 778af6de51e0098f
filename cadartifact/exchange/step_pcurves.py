"""The pcurves of a STEP file's edges: what OCCT's reader cannot survive in them, named before it runs.

An edge's ``SURFACE_CURVE`` / ``SEAM_CURVE`` names its 3D curve and, for each face it bounds, a ``PCURVE``: the
edge in that face's parameters, a ``DEFINITIONAL_REPRESENTATION`` whose items are 2D curves. Measured on
``linkrods.step`` (2026-12-04): OCCT's STEP reader crashes (SIGSEGV) when a control point of a B-spline pcurve is
not a ``CARTESIAN_POINT`` (a corrupted keyword, a ``DIRECTION``) or when the pcurve's curve keyword is corrupted;
it reads a control point with a missing or malformed list of coordinates without a word. The reader child
turns a crash into an error ("the STEP reader crashed"); this scan names the record instead::

    #38 is referenced by B_SPLINE_CURVE_WITH_KNOTS #36 (line 50) as a control point of a pcurve, and is
    XCARTESIAN_POINT (line 60), which cannot stand there (expected CARTESIAN_POINT)

Checked, for the pcurves the file's edges name: each item of a pcurve's representation is a curve, and each
control point of a B-spline pcurve is a ``CARTESIAN_POINT`` with two coordinates (three are accepted: OCCT reads
them, and some writers give them). A ``PCURVE`` record that is not well formed, or whose representation is not a
``DEFINITIONAL_REPRESENTATION``, is left to OCCT, which reads such files without harm (measured on the same file).
"""

from __future__ import annotations

import re
from operator import itemgetter

from .step_records import CURVES, POINT2, POINT2_SHAPE, REFERENCES, Records, point_shapes_ok, reference_problem
from .step_scan import parse_parameters

__all__ = ["pcurves_problem", "PCURVE_CURVES"]

#: Curve entities an item of a pcurve's representation may be (the 2D offset curve besides the schema's curves).
PCURVE_CURVES = CURVES | {"OFFSET_CURVE_2D"}
_SPLINES = frozenset({"B_SPLINE_CURVE_WITH_KNOTS", "B_SPLINE_CURVE"})
#: A reference that is not a statement's own head ``#N =``.
_BODY_REFS = re.compile(r"#(\d++)(?!\s*+=)")
_HEAD = r"(?:^|(?<=;))\s*+#(\d++)\s*+=\s*+"
_TAIL = r"\s*+(?=;|\Z)"
_NAME = r"(?:'(?:[^']|'')*'|\$)"
_LIST = r"\(\s*+(#\d++(?:\s*+,\s*+#\d++)*+)\s*+\)"
_BATCH_POINT2 = re.compile(_HEAD + POINT2.pattern + _TAIL)
#: ``(id, associated geometry)`` of a well-formed curve on surfaces (its 3D curve, the list, its master).
_ON_SURFACE = re.compile(_HEAD + r"(?:SURFACE_CURVE|SEAM_CURVE|INTERSECTION_CURVE)\s*+\(\s*+" + _NAME
                         + r"\s*+,\s*+#\d++\s*+,\s*+" + _LIST + r"\s*+,\s*+\.[A-Z_0-9]++\.\s*+\)" + _TAIL)
_PCURVE = re.compile(_HEAD + r"PCURVE\s*+\(\s*+" + _NAME + r"\s*+,\s*+#(\d++)\s*+,\s*+#(\d++)\s*+\)" + _TAIL)
#: ``(id, items)`` of a well-formed definitional representation (its context, a reference, not kept).
_DEFREP = re.compile(_HEAD + r"DEFINITIONAL_REPRESENTATION\s*+\(\s*+" + _NAME + r"\s*+,\s*+" + _LIST
                     + r"\s*+,\s*+#\d++\s*+\)" + _TAIL)


def pcurves_problem(records: Records, on_surfaces: list[str], pcurves: list[str] = ()) -> str | None:
    """The first broken link of the pcurves of the curves on surfaces ``on_surfaces`` (ids of ``SURFACE_CURVE``,
    ``SEAM_CURVE`` or ``INTERSECTION_CURVE`` records that edges name) and of the ``pcurves`` edges name
    directly, or None.

    Parameters
    ----------
    records : Records
        The file's records (:class:`~.step_records.Records`).
    on_surfaces : list of str
        Record ids; the ``PCURVE`` records among their references are their associated geometry.
    pcurves : list of str, optional
        Ids of ``PCURVE`` records that edges name as their curve.

    Returns
    -------
    str or None
        ``"#ID is referenced by KEYWORD #OWNER (line N) as ROLE, and ..."``.
    """
    kind = records.kind
    on_surfaces = list(dict.fromkeys(on_surfaces))
    if not on_surfaces and not pcurves:
        return None
    # each step reads the well-formed records by one regex over their statements joined (C loops); a record it
    # does not accept (or a section whose statements are not one per record) is read one by one
    found = _batch(records, on_surfaces, _ON_SURFACE) if on_surfaces else []
    if found is None:  # every reference: the PCURVEs among them are the associated geometry (a '$' 3D curve too)
        refs = [r for c in on_surfaces for r in REFERENCES.findall(records.body(c))]
    else:
        refs = REFERENCES.findall(",".join(m[1] for m in found))
    pcurves = [r for r in dict.fromkeys([*pcurves, *refs]) if kind.get(r) == "PCURVE"]
    if not pcurves:
        return None
    found = _batch(records, pcurves, _PCURVE)
    pairs = ([REFERENCES.findall(records.body(pc)) for pc in pcurves] if found is None
             else [[m[1], m[2]] for m in found])
    reps = [r[1] for r in pairs if len(r) == 2 and kind.get(r[1]) == "DEFINITIONAL_REPRESENTATION"]
    reps = list(dict.fromkeys(reps))
    if not reps:
        return None
    found = _batch(records, reps, _DEFREP)
    every = (list(dict.fromkeys(REFERENCES.findall(",".join(map(itemgetter(1), found))))) if found is not None
             else None)
    # the common case: every item a curve, simple (C loops) or complex with a curve part (rational B-splines)
    parts = ({i: records.names(i) for i in every if kind[i] == "("}
             if every is not None and set(map(kind.get, every)) <= PCURVE_CURVES | {"("} else None)
    if parts is not None and all(not PCURVE_CURVES.isdisjoint(names) for names in parts.values()):
        splines = [i for i in every if kind[i] in _SPLINES or "B_SPLINE_CURVE" in parts.get(i, ())]
    else:
        splines = []
        for rep in reps:
            its = _items(records.body(rep))
            for item in its:
                problem = reference_problem(records, item, "its curve", PCURVE_CURVES, rep)
                if problem:
                    return problem
                if kind[item] in _SPLINES or (kind[item] == "(" and "B_SPLINE_CURVE" in records.names(item)):
                    splines.append(item)
    return _control_points_problem(records, list(dict.fromkeys(splines)))


def _items(body: str) -> list[str]:
    """The references of a ``DEFINITIONAL_REPRESENTATION``'s items (its second parameter), or every reference
    but the last (its context) when the record does not parse."""
    try:
        args = parse_parameters(body)[0][1]
    except (ValueError, RecursionError, IndexError):
        return REFERENCES.findall(body)[:-1]
    items = args[1] if len(args) > 1 else []
    return REFERENCES.findall(repr(items))


def _batch(records: Records, idents: list[str], pattern: re.Pattern) -> list[tuple] | None:
    """``pattern``'s matches over the statements of ``idents`` (its first group the id), or None unless every
    record matched, in order (then the caller reads them one by one)."""
    found = pattern.findall(records.statements_of(idents))
    return found if [m[0] for m in found] == idents else None


def _control_points_problem(records: Records, splines: list[str]) -> str | None:
    """Every reference of the B-spline pcurves ``splines`` names a 2D (or 3D) ``CARTESIAN_POINT``, or the first
    that does not. The common case (all well formed) is one regex over the points' statements joined."""
    if not splines:
        return None
    kind = records.kind
    if records.aligned:  # each statement its record's: every reference but the statements' own heads
        points = list(dict.fromkeys(_BODY_REFS.findall(records.statements_of(splines))))
    else:
        points = list(dict.fromkeys(REFERENCES.findall(";".join(map(records.body, splines)))))
    if set(map(kind.get, points)) <= {"CARTESIAN_POINT"} and _all_points(records, points):
        return None
    role = "a control point of a pcurve"
    for spline in splines:
        for point in dict.fromkeys(REFERENCES.findall(records.body(spline))):
            problem = reference_problem(records, point, role, {"CARTESIAN_POINT"}, spline)
            if problem:
                return problem
            if not POINT2.fullmatch(records.body(point)):
                line = records.line(point)
                return (f"#{point} is referenced by {records.label(spline)} as {role}, and its record"
                        f"{f' (line {line})' if line else ''} is not a point with two coordinates")
    return None


def _all_points(records: Records, points: list[str]) -> bool:
    """Whether each of ``points`` has its own statement, a well-formed 2D or 3D point (by the statements' shapes
    where the section is aligned, else by a regex that also reads their ids)."""
    joined = records.statements_of(points)
    if records.aligned and point_shapes_ok(joined, POINT2_SHAPE):
        return True
    return _BATCH_POINT2.findall(joined) == points
