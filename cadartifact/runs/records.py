"""The advise document's records: one face's budget, advice and peak.

The records and the document they make are typed in :mod:`cadartifact.runs.documents` (the advise document:
:class:`~cadartifact.runs.documents.advise.AdviseDocument`, its faces
:class:`~cadartifact.runs.documents.face.AdviseFace`, its version history in
:mod:`cadartifact.runs.documents.advise`); ``cadartifact schema advise`` prints its JSON Schema (docs/schema.md).
In short: per file and face, ``budget`` (``x1``, ``x2``, ``diagonal``, ``lateral``, ``total``, ``signal_error``,
``deviation``: ``{"peak", "rms"}``), ``share`` of the tolerance, ``uncertainty``, ``decision``,
``meets_tolerance``, ``peak_at`` and the ``advice``; a ``summary`` of counts.

``total`` is the whole ripple (x1 + x2 + diagonal); ``deviation`` is everything the surface differs
from the intent (ripple and signal error); ``lateral`` is the part of the ripple running across
features (SPEC §3 weighting).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .documents.face import PeakAt, UncertaintyRecord

__all__ = ["SCHEMA", "DIRECTIONS", "json_number", "budget_record", "uncertainty_record", "estimated_u", "peak_location", "face_record",
           "analysed_share", "analysed_faces", "polygon_areas", "subdivided_record", "coverage_text", "kind_count",
           "plural", "unit_name"]

SCHEMA = "cadartifact.advise/4"


DIRECTIONS = ("x1", "x2", "diagonal", "lateral", "total", "signal_error", "deviation")


def json_number(x):
    """A finite number rounded to 9 decimals, or None (JSON null) for None, inf and NaN."""
    return None if x is None or not math.isfinite(x) else round(float(x), 9)


def budget_record(net, budget, include_signal_error: bool = False, uncertainty=None) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.budget.Budget` (``advice`` None): the keys of
    :class:`~cadartifact.runs.documents.face.FaceRecord` but ``entity_line`` and ``peak_at``, which the caller adds.

    ``uncertainty`` (:class:`~cadartifact.analysis.uncertainty.Uncertainty`, optional): the intent's ``U``;
    ``decision`` is then the ISO 14253-1 rule on today's value (:func:`cadartifact.advice.decision.decide`)
    and ``meets_tolerance`` is true only for a face that conforms (``value + U <= t``).
    """
    from ..advice.decision import CONFORMS, decide

    t = budget.tolerance
    key = "deviation" if include_signal_error else "total"
    U = 0.0 if uncertainty is None else uncertainty.peak
    decision = None if t is None else decide(budget.stats[key].get(budget.metric), U, t)
    return {
        "face": net.origin.face,
        "name": net.origin.name,
        "kind": net.origin.kind,
        "net": list(net.shape),
        "degrees": list(net.degrees) if net.is_bspline else None,
        "rational": net.rational,
        "units": net.unit,
        "entity": getattr(net.origin, "entity", None),
        "canonical": getattr(net, "canonical", None),
        "exact": list(getattr(net, "exact", (None, None))),
        "scheme": budget.scheme,
        "method": budget.method,
        "uniform": bool(not net.is_bspline or net.uniform),
        "intent": budget.intent,
        "reason": budget.reason,
        "notes": budget.notes,
        "budget": {k: {"peak": json_number(s.peak), "rms": json_number(s.rms)} for k, s in budget.stats.items()},
        "share": None if t is None else {k: json_number(s.get(budget.metric) / t) for k, s in budget.stats.items()},
        "meets_tolerance": None if t is None else decision == CONFORMS,
        "uncertainty": None if uncertainty is None else uncertainty_record(uncertainty),
        "decision": decision,
        "outside_trim": None if getattr(budget, "used", None) is None else {
            k: json_number(v) for k, v in budget.used.to_dict().items()},
        "advice": None,
    }


def peak_location(net, scheme=None, field: str = "total", current=None) -> PeakAt:
    """Where a face's ripple peaks: fine-grid index, surface parameters and position.

    Parameters
    ----------
    net : ControlNet
    scheme : str or Scheme, optional
        As :func:`cadartifact.budget` (the scheme the face was analysed with).
    field : str
        ``"total"`` (ripple) or ``"deviation"``.
    current : Budget, optional
        The face's budget under this scheme and the ``surface`` reading, computed with
        ``keep_fields=True`` (the gate has it already); else it is computed here.

    Returns
    -------
    dict
        ``{"value", "index": [x, y] (analysis coordinates, spans), "uv": [u, v] | None (B-spline faces),
        "xyz": [x, y, z]}``;
        ``value`` is the budget's peak of ``field`` over the region its stats cover, ``xyz`` the point of
        the face at ``uv`` (OCCT) or, for cages, of the limit surface there (model units).
    """
    import numpy as np

    from ..analysis.budget import budget
    from ..numerics.peaks import first_peak

    b = current if current is not None and current.fields is not None else budget(net, scheme, keep_fields=True)
    values = np.where(b.region, np.abs(b.scalar_fields[field]), -np.inf)
    i, j = first_peak(values)  # of two places equal to rounding, the first: the same on every CPU
    top = float(values.max())  # the peak itself (the place is the first within rounding of it)
    x, y = float(b.fields.x[i]), float(b.fields.y[j])
    uv = None
    xyz = np.asarray(b.fields.surface)[i, j]  # cages: the limit surface there
    if net.is_bspline:
        from ..exchange.load import evaluate_grid
        from ..analysis.frames import axis_frames

        fu, fv = axis_frames(b.work if b.work is not None else net)  # the spans the trim uses
        uv = [float(fu.param(x)), float(fv.param(y))]
        # the face's own point at that uv (the fine grid of a predicted face is the uniform model's)
        xyz = evaluate_grid(net, np.array([uv[0]]), np.array([uv[1]]))[0, 0]
    return {"value": json_number(top), "index": [round(x, 9), round(y, 9)],
            "uv": None if uv is None else [round(t, 9) for t in uv], "xyz": [json_number(c) for c in xyz]}


def uncertainty_record(u) -> UncertaintyRecord:
    """``{"peak", "u", "v", "reading", "coverage_factor"}`` of an :class:`~cadartifact.analysis.uncertainty.Uncertainty`
    (numbers rounded as every number of the document)."""
    return {"peak": json_number(u.peak), "u": json_number(u.u), "v": json_number(u.v), "reading": u.reading,
            "coverage_factor": json_number(u.factor), "estimated": bool(u.estimated)}


def estimated_u(record: dict) -> float | None:
    """A face record's estimated ``U`` (``uncertainty.peak``), or None where none is estimated (no uncertainty, or
    ``estimated: false``: a cage's ``surface`` reading): the doors print "-" there, never 0."""
    unc = record.get("uncertainty") or {}
    if unc.get("peak") is None or not unc.get("estimated", True):
        return None
    return float(unc["peak"])


def face_record(net, advice) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.advice.advise.Advice` (as
    :func:`budget_record`, with ``advice``: :class:`~cadartifact.runs.documents.face.AdviceRecord`)."""
    rec = budget_record(net, advice.current, advice.include_signal_error, advice.uncertainty)
    rec["advice"] = advice.to_dict()
    return rec


def polygon_areas(vertices, faces):
    """Area of each polygon by fan triangulation: ``(f,) float``, ``sum_k |(p_k - p_0) x (p_{k+1} - p_0)| / 2``."""
    import numpy as np

    v = np.asarray(vertices, float)
    areas = np.zeros(len(faces))
    for k, ids in enumerate(faces):
        p = v[list(ids)]
        areas[k] = 0.5 * np.linalg.norm(np.cross(p[1:-1] - p[0], p[2:] - p[0]), axis=-1).sum()
    return areas


def analysed_faces(result, around=()):
    """Share of each polygon of an OBJ cage that its charts analyse: ``(f,) float`` in [0, 1], or None for B-rep files.

    A face in a level-0 chart counts whole; a face outside them counts by the area share of its quads
    (after one Catmull-Clark step, :attr:`LoadResult.refined`) that lie in level-1 charts or touch one of the
    vertices ``around`` (ids of the level-1 mesh whose neighbourhood another measure analyses, e.g. an
    extraordinary vertex's).
    """
    import numpy as np

    mesh = getattr(result, "mesh", None)
    if mesh is None:
        return None
    share = np.zeros(len(mesh.faces))
    refined = getattr(result, "refined", None)
    if refined is not None:
        child = polygon_areas(refined.mesh.vertices, refined.mesh.faces)
        in_chart = np.zeros(len(child), bool)
        for chart in result.charts:
            if chart.level == 1:
                in_chart[np.asarray(chart.face_ids).ravel()] = True
        around = set(int(a) for a in around)
        if around:
            in_chart |= np.array([not around.isdisjoint(face) for face in refined.mesh.faces], bool)
        total = np.bincount(refined.parent, weights=child, minlength=len(share))
        done = np.bincount(refined.parent, weights=np.where(in_chart, child, 0.0), minlength=len(share))
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(total > 0, done / np.where(total > 0, total, 1), 0.0)
    for chart in result.charts:
        if chart.level == 0:
            share[np.asarray(chart.face_ids).ravel()] = 1.0
    return share


def analysed_share(result, around=()) -> float | None:
    """Share of an OBJ cage's surface area that its analysed charts cover; None for B-rep files.

    Parameters
    ----------
    result : LoadResult
        With ``mesh`` (polygons), ``charts`` (the analysed grid cells, ``face_ids`` on the mesh of their
        ``level``) and ``refined`` (the cage after one Catmull-Clark step).
    around : iterable of int
        Level-1 vertices whose neighbouring quads another measure analyses (:func:`analysed_faces`).

    Returns
    -------
    float or None
        ``sum_f area_f * a_f / sum_f area_f`` with ``a_f`` the analysed share of face ``f``
        (:func:`analysed_faces`), polygon areas by fan triangulation of the control polygons (the share of
        faces for a mesh of zero area).
    """
    share = analysed_faces(result, around)
    if share is None:
        return None
    areas = polygon_areas(result.mesh.vertices, result.mesh.faces)
    total = float(areas.sum())
    if not total > 0:
        return float(share.mean()) if len(share) else None
    return float((areas * share).sum() / total)


def subdivided_record(result) -> dict | None:
    """What an OBJ cage's first Catmull-Clark step brought into the analysis
    (:class:`~cadartifact.runs.documents.advise.SubdividedRecord`), or None (a B-rep file, or every face charted
    as read)."""
    import numpy as np

    refined = getattr(result, "refined", None)
    if refined is None:
        return None
    charts = [c for c in result.charts if c.level == refined.level]
    quads = np.unique(np.concatenate([np.asarray(c.face_ids).ravel() for c in charts])) if charts else np.zeros(0, int)
    parents = np.unique(refined.parent[quads])
    sizes = np.asarray(result.mesh.face_sizes)[parents]
    kinds = {"triangle": int(np.count_nonzero(sizes == 3)), "n-gon": int(np.count_nonzero(sizes > 4)),
             "quad": int(np.count_nonzero(sizes == 4))}
    return {"level": int(refined.level), "charts": len(charts), "quads": int(len(quads)),
            "from_faces": {k: n for k, n in kinds.items() if n}}


def coverage_text(share: float, subdivided: dict | None) -> str:
    """``"analysed 97.3 % of the cage's area (level 1: 12 triangles, 4 n-gons)"``: the coverage a verdict line gives."""
    text = f"analysed {100 * share:.1f} % of the cage's area"
    if subdivided and subdivided.get("from_faces"):
        kinds = ", ".join(kind_count(k, n) for k, n in subdivided["from_faces"].items())
        text += f" (at subdivision level {subdivided['level']}, parts of {kinds})"
    return text


def kind_count(kind: str, n: int) -> str:
    """``"3 irregular quads"``, ``"1 triangle"``, ``"2 planes"``: a count of skipped faces of one kind."""
    if n == 1 or kind.endswith("s") or kind in ("degenerate", "conversion failed"):
        return f"{n} {kind}"
    return f"{n} {kind}es" if kind.endswith(("sh", "ch", "x")) else f"{n} {kind}s"


def plural(n: int, word: str) -> str:
    """``"1 face"``, ``"2 faces"``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def unit_name(units: str | None) -> str:
    """How a unit is written in every report: ``"mm"``, or ``"model units"`` (OBJ, unknown)."""
    return "model units" if units in (None, "model") else units


