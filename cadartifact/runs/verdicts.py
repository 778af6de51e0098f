"""One face's gate record and verdict, wherever the face is analysed (this process, the reader child, a
pool worker or a Dask worker): today's budget against the tolerance, and the density advice where the
policy asks for it. The gate (:mod:`cadartifact.gate.run`) judges whole files from these records."""

from __future__ import annotations

from ..errors import CadArtifactError

__all__ = ["VERDICTS", "worst_verdict", "face_verdict", "advice_wanted", "face_entry", "add_criteria"]

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


def advice_wanted(settings, verdict: str) -> str | None:
    """None when the face gets the density advice under ``settings.advise``, else why it does not."""
    if settings.advise == "all" or (settings.advise == "failing" and verdict in ("warn", "fail")):
        return None
    if settings.advise == "none":
        return "not computed (--advise none)"
    return "face passes (--advise failing)"


def face_entry(net, settings, verify: bool) -> tuple[dict, object]:
    """One face's gate record (today's budget and verdict, and the advice where ``settings.advise`` asks)
    and today's :class:`~cadartifact.budget.Budget` with its fields when it is the ``surface`` reading's
    (what :func:`cadartifact.runs.records.peak_location` needs: it is not computed again), else None.

    The verdict needs today's budget only; the advice (a density search, the costly part) is added
    only for the faces ``settings.advise`` selects. A face without advice keeps the record's schema:
    ``advice`` is None and ``advice_skipped`` says why (None where the advice was computed).
    """
    from ..advice.advise import advise_for
    from ..analysis.budget import budget_for
    from .records import budget_record, face_record

    run = settings.run
    key = run.compared
    # the reading advise() scores today's net under (include_signal_error is the net reading)
    reading = run.reading
    scored = run.replace(intent=reading)
    current = budget_for(net, scored, keep_fields=reading == "surface")

    def finite(rec):
        if rec["budget"][key][settings.metric] is None:  # report.face_record maps inf/NaN to None
            raise CadArtifactError("the analysis gave a non-finite value (coordinates too large?)")
        return rec

    from ..advice.decision import face_uncertainty

    unc = face_uncertainty(net, scored, current)  # the same U the advice's rule uses (SPEC §4)
    rec = finite(budget_record(net, current, reading == "net", unc))
    verdict, reason, value = face_verdict(rec, settings)
    skipped = advice_wanted(settings, verdict)
    if skipped is None:
        # verification costs a real-surface evaluation: only for faces that fail today
        check = verify and not current.meets(settings.include_signal_error)
        adv = advise_for(net, scored, compare=False, verify=check,
                         current=current if current.fields is not None else None, uncertainty=unc)
        rec = finite(face_record(net, adv))
        verdict, reason, value = face_verdict(rec, settings)
    rec.update(verdict=verdict, verdict_reason=reason, value=value, advice_skipped=skipped)
    add_criteria(rec, net, settings)
    return rec, (current if reading == "surface" else None)


def add_criteria(rec: dict, net, settings) -> dict:
    """Add the PDQ criteria of ``settings.profile`` to a face's gate record (:mod:`cadartifact.analysis.quality`).

    ``ripple_verdict`` keeps the ripple's verdict; ``criteria`` is the list of criteria (None without a
    profile); ``verdict`` becomes the worst of the ripple's and the evaluated criteria's, and when a criterion
    makes it worse the reason says which (``; PDQ criteria: fail on waviness 5 > 3 inflections``).
    """
    from ..analysis.quality import CRITERIA, criteria
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
            rec["criteria"] = [Criterion(k, False, limit=profile.limit(k), reason=why).to_dict() for k in CRITERIA]
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
