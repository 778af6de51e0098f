"""The decision rule: conforms, does not conform, or undecided (SPEC §4 "Uncertainty and decisions", §5).

A value ``v`` (a face's error against its intent, model units) known to within an expanded uncertainty ``U``
(:mod:`cadartifact.analysis.uncertainty`) is judged against a tolerance ``t`` by the rule of
ISO 14253-1 (conformance zone reduced by ``U``, non-conformance zone enlarged by it):

* ``v + U <= t``: **conforms** (proven within the tolerance);
* ``v - U > t``: **does not conform** (proven beyond it);
* otherwise **undecided**.

No claim of conformance is made that the net cannot support: the advice claims ``meets_tolerance`` only for
a net that conforms, and where ``U`` alone is near ``t`` (``U >= UNVERIFIABLE_SHARE * t``) no density can
conform and the advice says so instead of giving a number.

References
----------
ISO 14253-1:2017, *Geometrical product specifications (GPS) - Inspection by measurement of workpieces and
measuring equipment - Part 1: Decision rules for verifying conformity or nonconformity with specifications*.
"""

from __future__ import annotations

import math

__all__ = ["DECISIONS", "CONFORMS", "UNDECIDED", "NONCONFORMING", "UNVERIFIABLE_SHARE", "decide", "unverifiable",
           "unverifiable_note", "scorer_uncertainty", "face_uncertainty", "candidate_margin",
           "advised_uncertainty"]

CONFORMS, UNDECIDED, NONCONFORMING = "conforms", "undecided", "does not conform"
#: The three outcomes of the rule, best first.
DECISIONS = (CONFORMS, UNDECIDED, NONCONFORMING)

#: Share of the tolerance from which the intent's uncertainty alone leaves no room for a conforming net.
UNVERIFIABLE_SHARE = 0.9


def decide(value: float, uncertainty: float, tolerance: float) -> str:
    """The ISO 14253-1 decision for a value with expanded uncertainty ``U`` against a tolerance ``t``.

    ``"conforms"`` when ``value + U <= t``, ``"does not conform"`` when ``value - U > t``, else
    ``"undecided"``; a value that is not finite does not conform.
    """
    if value is None or not math.isfinite(value):
        return NONCONFORMING
    if value + uncertainty <= tolerance:
        return CONFORMS
    if value - uncertainty > tolerance:
        return NONCONFORMING
    return UNDECIDED


def unverifiable(uncertainty: float, tolerance: float) -> bool:
    """Whether ``U`` alone is near ``t`` (``U >= UNVERIFIABLE_SHARE t``): no net can be shown to conform."""
    return uncertainty >= UNVERIFIABLE_SHARE * tolerance


def unverifiable_note(uncertainty: float, tolerance: float, unit: str = "mm") -> str:
    """The advice's honest no when the intent's uncertainty leaves no room (SPEC §5)."""
    return (f"the net determines its shape only to +/-{uncertainty:.3g} {unit}: a tolerance of {tolerance:g} {unit} "
            "cannot be verified from these control points")


def candidate_margin(uncertainty) -> float:
    """The ``U`` a candidate net's value carries (model units): the ``net`` reading's ``Uncertainty.candidate``
    (the intent's own error bounds any net's value against it, ``k SPREAD_SCALE D``), wider than today's value's
    ``Uncertainty.peak`` (``k TODAY_SCALE D``: :mod:`cadartifact.analysis.uncertainty`). 0 for the ``surface``
    reading: its candidates' U is the intent's own change (:class:`~cadartifact.advice.surface_margin.LazyMargin`)."""
    if uncertainty is None or uncertainty.reading != "net":
        return 0.0
    return float(uncertainty.peak if uncertainty.candidate is None else uncertainty.candidate)


def advised_uncertainty(uncertainty, kept: bool, margin: float, lazy=None):
    """The U the advised net's decision used, for the record
    (:class:`~cadartifact.advice.surface_margin.CandidateUncertainty`), or None where none is estimated.

    ``net`` reading: today's value's U when today's net is kept, else the candidates' ``margin``
    (:func:`candidate_margin`). ``surface`` reading: today's U when kept, else what the candidates' margin
    ``lazy`` (:class:`~cadartifact.advice.surface_margin.LazyMargin`) read: ``U_c`` or its bound."""
    from .surface_margin import CandidateUncertainty, kept_uncertainty

    if uncertainty is not None and uncertainty.reading != "net":
        return lazy and (kept_uncertainty(uncertainty) if kept else lazy.record())
    if uncertainty is None or not uncertainty.estimated:
        return None
    peak, construction = ((uncertainty.peak, "today's net kept: today's value's U") if kept else
                          (margin, "a candidate's value against the intent: k SPREAD_SCALE D"))
    return CandidateUncertainty(float(peak), "net", float(uncertainty.factor), True, construction)


def scorer_uncertainty(scorer, settings=None, current=None):
    """The :class:`~cadartifact.analysis.uncertainty.Uncertainty` of a density search's intent (its reading,
    over the trimmed face); the ``surface`` reading's is today's reading's border latitude
    (:func:`face_uncertainty`, which needs the run's ``settings`` and today's budget ``current``)."""
    if scorer.reading == "surface" and settings is not None:
        return face_uncertainty(scorer.net, settings, current)
    return _of_intent(scorer.intent, scorer.work, scorer.scheme, scorer.reading)


def face_uncertainty(net, settings, current=None):
    """Today's net's :class:`~cadartifact.analysis.uncertainty.Uncertainty` under a run's reading
    (``settings.reading``): the intent of today's budget's fields when it kept them, else built here."""
    from ..analysis.budget import analysis_net
    from ..analysis.intent import design_intent
    from ..analysis.settings import resolve_scheme

    if settings.reading == "surface":  # the border convention's latitude: no intent of the net reading needed
        from ..analysis.border_convention import surface_uncertainty

        value = None if current is None else current.value(settings.include_signal_error)
        return surface_uncertainty(net, settings, value, getattr(current, "work", None),
                                   getattr(current, "scalar_fields", None), getattr(current, "region", None))
    sch = resolve_scheme(net, settings.scheme)
    work = analysis_net(net, sch)
    fields = getattr(current, "fields", None)
    it = (fields.baseband or {}).get("intent") if fields is not None and fields.baseband else None
    if it is None:
        from types import SimpleNamespace

        from ..analysis.pieces import split_net

        pieces = split_net(work)
        split = len(pieces) > 1 or pieces[0].net is not work
        it = SimpleNamespace(pieces=pieces, levels=settings.levels) if split else design_intent(work, sch,
                                                                                                settings.levels)
    return _of_intent(it, work, sch, settings.reading)


def _of_intent(it, work, scheme, reading: str):
    """:func:`~cadartifact.analysis.uncertainty.intent_uncertainty` of an intent over the trimmed face (a split
    face's pieces carry their own region)."""
    from ..analysis.budget import trim_mask
    from ..analysis.uncertainty import intent_uncertainty

    keep = None
    if getattr(it, "pieces", None) is None:
        keep = lambda x, y: trim_mask(work, it.frames, x, y)  # noqa: E731
    return intent_uncertainty(it, scheme, reading, keep)
