"""The advise document's records: one face's budget, advice and peak, and the schema they make.

The document (``cadartifact advise --json``) has this schema (version 2: issue 22 added ``uncertainty`` and
``decision``, and ``meets_tolerance`` is true only for what conforms, ``value + U <= t``; version 3: issue 23
analyses and advises the spans the trimmed face uses, so ``advice.reasons.*.today`` counts those spans' points,
and adds ``outside_trim``, ``advice.joins``, ``advice.no_density``, ``advice.outside_trim`` and the comparison's
``advice`` flag)::

    {
      "schema": "cadartifact.advise/3",
      "tolerance": float, "units": "mm", "metric": "peak" | "rms",
      "intent": "surface" | "net", "include_signal_error": bool,
      "files": [{
        "path": str, "units": "mm" | "model" | null,
        "faces_total": int, "skipped": {kind: count}, "warnings": [str],
        "analysed_share": float | null (OBJ: share of the cage's area in analysed charts),
        "faces": [{
          "face": int, "name": str | null, "kind": "bspline" | "bezier" | "converted" | "quad-chart",
          "net": [nu, nv], "degrees": [p, q] | null, "units": "mm" | "model", "scheme": str,
          "entity": int | null (STEP: the face's #id in the file), "entity_line": int | null (its line),
          "canonical": str | null (what the face exactly is: "sphere r=12.5", "revolved: circular in u"),
          "exact": [u, v] each null | "line" | "circle" | "surface" (directions without artifact),
          "peak_at": null | {"value", "index": [x, y], "uv": [u, v] | null, "xyz": [x, y, z]}
                     (faces beyond the tolerance: where the ripple peaks),
          "method": "predicted" | "measured", "reason": str, "intent": "surface" | "net",
          "uniform": bool (uniform knots and constant weights, or a cage), "notes": [str],
          "budget": {"x1" | "x2" | "diagonal" | "lateral" | "total" | "signal_error" | "deviation":
                     {"peak": float, "rms": float}},
          "share": {same keys: value / tolerance under the metric},
          "meets_tolerance": bool (conforms: value + U <= t),
          "uncertainty": {"peak", "u", "v" (the intent's expanded uncertainty U, model units), "reading",
                          "coverage_factor", "estimated" (false: the surface reading, U = 0)} | null,
          "decision": "conforms" | "undecided" | "does not conform" (ISO 14253-1, today's net) | null,
          "outside_trim": {"u", "v", "share"} (shares of the surface's parameter range outside the trimmed
                          face: those spans are not analysed or advised) | null (untrimmed),
          "advice": {"net": [n'u, n'v], "points": int, "intent": str, "objective": "deviation" | "ripple",
                     "budget": {"deviation" (the advised net against the intent), "boundary" (its borders
                                against today's), its own "x1" ... "total": {"peak", "rms"}},
                     "share": {...}, "today": {"peak", "rms", "boundary"} (today's net, scored the same way),
                     "meets_tolerance": bool (the advised net conforms), "uncertainty": {...} (as above),
                     "decision": str (the advised net's), "today_decision": str, "verifiable": bool (false:
                     U alone is near t, no net can conform; a note says so),
                     "binding": "u" | "v" | null, "kept_today": bool,
                     "reasons": {"u" | "v": {"today", "advised", "change", "coarser_value", "binding", "reason"}},
                     "verification": {"method": "occt" | "today", "levels", "region": "face", "value", "rms",
                                      "meets", "coarser": {"shape", "value", "meets"},
                                      "samples" (net reading: distance to today's points)} | null,
                     "comparison": {scheme: {"net", "points", "meets_tolerance", "objective",
                                             "advice" (true: this row is the advice itself)}},
                     "joins": {"u" | "v": {"joins": [float], "multiplicity", "today_spans": [int],
                                           "plan": "per piece" | "proportional" | "today's",
                                           "advised_spans": [int],
                                           "pieces": [{"range", "today_spans", "advised_spans", "points",
                                                       "deviation", "meets_tolerance"}] | null}} (directions whose joins the advice keeps),
                     "outside_trim": {"u", "v", "share"} | null,
                     "no_density": {"why": ["crease" | "uncertainty" | "stops improving" | "growth limit"],
                                    "best": {"net", "value", "uncertainty"}, "reason": str} | null
                                   (no density within the limits conforms: the best found, and why),
                     "notes": [str]}
        }]
      }],
      "summary": {"files": int, "faces": int, "within": int (conform), "exceeding": int (do not conform),
                  "undecided": int, "unreachable": int},
      "written": {...}  (only with --write-resampled: see :func:`write_advised`)
    }

``total`` is the whole ripple (x1 + x2 + diagonal); ``deviation`` is everything the surface differs
from the intent (ripple and signal error); ``lateral`` is the part of the ripple running across
features (SPEC §3 weighting).
"""

from __future__ import annotations

import math

__all__ = ["SCHEMA", "DIRECTIONS", "json_number", "budget_record", "uncertainty_record", "peak_location", "face_record", "analysed_share",
           "kind_count", "plural", "unit_name"]

SCHEMA = "cadartifact.advise/3"


DIRECTIONS = ("x1", "x2", "diagonal", "lateral", "total", "signal_error", "deviation")


def json_number(x):
    """A finite number rounded to 9 decimals, or None (JSON null) for None, inf and NaN."""
    return None if x is None or not math.isfinite(x) else round(float(x), 9)


def budget_record(net, budget, include_signal_error: bool = False, uncertainty=None) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.budget.Budget` (``advice`` None).

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


def peak_location(net, scheme=None, field: str = "total", current=None) -> dict:
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


def uncertainty_record(u) -> dict:
    """``{"peak", "u", "v", "reading", "coverage_factor"}`` of an :class:`~cadartifact.analysis.uncertainty.Uncertainty`
    (numbers rounded as every number of the document)."""
    return {"peak": json_number(u.peak), "u": json_number(u.u), "v": json_number(u.v), "reading": u.reading,
            "coverage_factor": json_number(u.factor), "estimated": bool(u.estimated)}


def face_record(net, advice) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.advice.advise.Advice`."""
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


