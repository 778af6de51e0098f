"""The gate's verdict of one face record, and its PDQ criteria: today's value against the tolerance by the
decision rule, the policy's caps, the criteria's verdicts. The face pipeline (:mod:`cadartifact.runs.face`) adds
them to the record where the door asks (``FaceOptions.verdict``, ``criteria``); the gate
(:mod:`cadartifact.gate.run`) judges whole files from these records."""

from __future__ import annotations

__all__ = ["VERDICTS", "worst_verdict", "face_verdict", "add_criteria"]

#: Verdicts from best to worst.
VERDICTS = ("pass", "warn", "fail", "error")


def worst_verdict(verdicts) -> str:
    return max(verdicts, key=VERDICTS.index, default="pass")


def face_verdict(record: dict, settings) -> tuple[str, str, float]:
    """Verdict of one face record of the advise document.

    Parameters
    ----------
    record : dict
        A face entry (:func:`cadartifact.runs.records.face_record`).
    settings : FileSettings
        Its ``run.compared`` names the statistic (``"total"``, or ``"deviation"`` with the signal error),
        ``metric`` the metric, ``undecided`` the verdict of an undecided face.

    Returns
    -------
    verdict : {"pass", "warn", "fail"}
    reason : str
        One line with the numbers.
    value : float
        ``budget[total | deviation][metric]``, the number compared with the tolerance.

    Notes
    -----
    The decision rule of ISO 14253-1 with the record's uncertainty ``U`` (``record["uncertainty"]["peak"]``,
    0 without one; :func:`cadartifact.advice.decision.decide`): ``fail`` if ``value - U > t``; undecided if
    ``value - U <= t < value + U``: the policy's ``undecided`` verdict (default ``warn``); otherwise
    (conforms) ``warn`` if ``value >= warn_fraction * t``, else ``pass``. A face with non-uniform knots is
    capped at ``warn`` when the policy says ``measured = "warn"`` (default ``"fail"``: gated like any other face).
    """
    from ..advice.decision import NONCONFORMING, UNDECIDED, decide
    from .records import unit_name

    value = record["budget"][settings.run.compared][settings.metric]
    t = settings.tolerance
    what = "deviation" if settings.include_signal_error else "ripple"
    u = unit_name(record.get("units"))  # the face's own unit, next to its numbers
    U = float((record.get("uncertainty") or {}).get("peak") or 0.0)
    decision = decide(value, U, t)
    pm = f" +/- {U:.2g}" if U > 0 else ""
    if decision == NONCONFORMING:
        verdict, reason = "fail", f"{what} {settings.metric} {value:.4g}{pm} {u} exceeds tolerance {t:g} {u}"
    elif decision == UNDECIDED:
        verdict = settings.undecided  # the policy's value (FileSettings, checked against UNDECIDED when read)
        reason = (f"{what} {settings.metric} {value:.4g}{pm} {u} is undecided against tolerance {t:g} {u} (the "
                  f"intent's uncertainty straddles it; policy undecided = {verdict!r})")
    elif value >= settings.warn_fraction * t:
        verdict, reason = "warn", (f"{what} {settings.metric} {value:.4g}{pm} {u} is within tolerance {t:g} {u} but "
                                   f"above {settings.warn_fraction:g} of it")
    else:
        verdict, reason = "pass", f"{what} {settings.metric} {value:.4g}{pm} {u} within tolerance {t:g} {u}"
    if verdict == "fail" and not record.get("uniform", True) and settings.measured == "warn":
        verdict = "warn"
        reason += " (non-uniform knots: capped at warn by policy measured = 'warn')"
    return verdict, reason, value


def add_criteria(rec: dict, net, settings) -> dict:
    """Add the PDQ criteria of ``settings.profile`` to a face's gate record (:mod:`cadartifact.analysis.quality`).

    ``ripple_verdict`` keeps the ripple's verdict; ``criteria`` is the list of criteria (None without a
    profile); ``verdict`` becomes the worst of the ripple's and the evaluated criteria's, and when a criterion
    makes it worse the reason says which (``; PDQ criteria: fail on waviness 5 > 3 inflections``).
    """
    from ..analysis.quality import CRITERIA, FACE_CRITERIA, criteria
    from .records import unit_name

    rec["ripple_verdict"] = rec["verdict"]
    profile = getattr(settings, "profile", None)
    if profile is None:
        rec["criteria"] = None
    else:
        try:
            rec["criteria"] = [c.to_dict() for c in criteria(net, profile)]
        except Exception as exc:  # noqa: BLE001 - never silent: every criterion says it was not evaluated
            from ..analysis.quality import Criterion
            from ..errors import one_line

            why = one_line(f"the criteria could not be computed ({type(exc).__name__}: {exc})")
            rec["criteria"] = [Criterion(k, False, limit=profile.limit(k), reason=why).to_dict()
                               for k in FACE_CRITERIA]
    if not rec["criteria"]:
        return rec
    for c in rec["criteria"]:  # the face's own unit
        c["unit"] = c["unit"].replace("model units", unit_name(rec.get("units")))
    worst = worst_verdict(c["verdict"] for c in rec["criteria"] if c["verdict"])
    if VERDICTS.index(worst) > VERDICTS.index(rec["verdict"]):
        found = []
        for c in rec["criteria"]:
            if c["verdict"] in ("warn", "fail"):
                sense = ">" if CRITERIA[c["criterion"]][3] == "above" else "<"
                found.append(f"{c['verdict']} on {c['criterion']} {c['value']:.4g} {sense} "
                             f"{c['threshold'][c['verdict']]:g} {c['unit']}")
        rec["verdict"] = worst
        rec["verdict_reason"] += "; PDQ criteria: " + ", ".join(found)
        if rec.get("advice_skipped") == "face passes (--advise failing)":
            rec["advice_skipped"] = "the ripple passes: the face warns or fails on PDQ criteria only (--advise failing)"
    return rec
