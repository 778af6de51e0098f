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

__all__ = ["SCHEMA", "DIRECTIONS", "json_number", "budget_record", "uncertainty_record", "peak_location", "face_record", "analysed_share",
           "kind_count", "plural", "unit_name"]

SCHEMA = "cadartifact.advise/3"


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


def face_record(net, advice) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.advice.advise.Advice` (as
    :func:`budget_record`, with ``advice``: :class:`~cadartifact.runs.documents.face.AdviceRecord`)."""
    rec = budget_record(net, advice.current, advice.include_signal_error, advice.uncertainty)
    rec["advice"] = advice.to_dict()
    return rec


def analysed_share(result) -> float | None:
    """Share of an OBJ cage's surface area that its analysed charts cover; None for B-rep files.

    Parameters
    ----------
    result : LoadResult
        With ``mesh`` (polygons) and ``charts`` (the analysed grid cells, ``face_ids``).

    Returns
    -------
    float or None
        ``sum(area of charted faces) / sum(area of all faces)``, polygon areas by fan triangulation
        of the control polygons (1.0 for a mesh of zero area with every face charted).
    """
    import numpy as np

    mesh = getattr(result, "mesh", None)
    if mesh is None:
        return None
    v = np.asarray(mesh.vertices, float)
    areas = np.zeros(len(mesh.faces))
    for k, ids in enumerate(mesh.faces):
        p = v[list(ids)]
        areas[k] = 0.5 * np.linalg.norm(np.cross(p[1:-1] - p[0], p[2:] - p[0]), axis=-1).sum()
    charted = np.zeros(len(mesh.faces), bool)
    for chart in result.charts:
        charted[np.asarray(chart.face_ids).ravel()] = True
    total = float(areas.sum())
    if not total > 0:
        return float(charted.mean()) if len(charted) else None
    return float(areas[charted].sum() / total)


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


