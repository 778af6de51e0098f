"""One face's analysis, for every door: the gate, ``advise`` and the CadQuery hook.

:func:`analyse_face` takes a control net and the run's settings and returns the face's record (the face entry
of the advise document, :mod:`cadartifact.runs.records`): today's budget, the intent's uncertainty ``U`` and the
decision; the density advice, the gate's verdict, the PDQ criteria and the peak's location when the door's
:class:`FaceOptions` ask for them. The doors differ only in the options they pass (the table below and
docs/design.md), how they render the records and their exit codes.

=====================  ===================  ===================  =====================  ====================
option                 gate                 advise               hook ``check``         hook ``report``
=====================  ===================  ===================  =====================  ====================
``advice``             policy's ``advise``  ``"all"``            ``"none"`` (worst:     ``"all"`` (with tol)
                       (default failing)                         ``"all"``)
``compare``            False                ``--compare``        False                  ``compare=``
                                            (``"auto"``)
``verify``             ``"failing"`` with   ``--verify`` (True)  False                  ``verify=``
                       ``--verify``
``verdict, criteria``  True                 False                False                  False
``peak``               True                 True                 False                  False
``finite``             True                 True                 False                  False
``reading``            ``"run"``            ``"run"``            ``"intent"``           ``"intent"`` without
                                                                                        tol, else ``"run"``
=====================  ===================  ===================  =====================  ====================

The work is split in two phases so that a face can be shared with the reader child
(:mod:`cadartifact.runs.face_sharing`): :func:`start_face` needs no OCCT evaluation unless the advice is verified
at once; :func:`finish_face` runs what needs OCCT (a verification left for later, the peak's location).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..errors import CadArtifactError, OptionError, check_option

__all__ = ["ADVICE", "ADVISE", "GATE", "HOOK_CHECK", "HOOK_REPORT", "NON_FINITE_VALUE", "READINGS", "FaceOptions",
           "FaceWork", "NonFiniteResult", "analyse_face", "analysed", "beyond", "finish_face", "start_face"]

#: Which faces get the density advice: every face, those the gate's verdict warns or fails, none.
ADVICE = ("all", "failing", "none")
#: Under which reading today's net is scored: the run's (``settings.reading``: the net's when the signal error
#: counts) or the settings' ``intent`` as given (the CadQuery hook's ``check`` and ``report`` without a tolerance).
READINGS = ("run", "intent")


#: :class:`NonFiniteResult`'s message when the analysis's value is not finite; each door adds its own hint (the gate
#: and advise worded it differently before they shared this pipeline, and their documents keep their words).
NON_FINITE_VALUE = "the analysis gave a non-finite value"


class NonFiniteResult(CadArtifactError):
    """The face's coordinates, or what its analysis gave, are not finite (the door says which face and file)."""


@dataclass(frozen=True)
class FaceOptions:
    """What a door asks of the face pipeline (every field has the cheapest default: a budget only).

    Attributes
    ----------
    advice : {"all", "failing", "none"}
        Which faces get the density advice (needs a tolerance). ``"failing"``: the faces whose gate verdict warns
        or fails (needs ``verdict``); a face without advice says why in ``advice_skipped`` (with ``verdict``).
    compare : bool or "auto"
        The advice's scheme comparison (:func:`cadartifact.advice.advise.advise_for`).
    verify : bool or "failing"
        Verify the advice on OCCT's surface: every advised face, or only those today's budget does not meet.
    verdict : bool
        Add the gate's verdict (``verdict``, ``verdict_reason``, ``value``, ``advice_skipped``:
        :func:`cadartifact.runs.verdicts.face_verdict`); ``settings`` is then a gate ``FileSettings``.
    criteria : bool
        Add the PDQ criteria of ``settings.profile`` (``ripple_verdict``, ``criteria``; needs ``verdict``).
    peak : bool
        Add ``entity_line`` (None: the door that has the file sets it) and ``peak_at`` (where the ripple peaks, on
        faces beyond the tolerance or that warn: :func:`beyond`).
    finite : bool
        Fail with :class:`NonFiniteResult` on coordinates whose squares overflow, or a non-finite budget.
    reading : {"run", "intent"}
        See :data:`READINGS`. ``"intent"`` also decides on ``settings.compared`` rather than on the deviation
        whenever the reading is the net's.
    """

    advice: str = "none"
    compare: bool | str = False
    verify: bool | str = False
    verdict: bool = False
    criteria: bool = False
    peak: bool = False
    finite: bool = False
    reading: str = "run"

    def __post_init__(self):
        check_option("advice", self.advice, ADVICE)
        check_option("reading", self.reading, READINGS)
        if self.verify not in (True, False, "failing"):
            raise OptionError("verify", "True, False or 'failing'", self.verify)
        if self.compare not in (True, False, "auto"):
            raise OptionError("compare", "True, False or 'auto'", self.compare)
        if (self.advice == "failing" or self.criteria) and not self.verdict:
            raise OptionError("verdict", "True with advice='failing' or criteria", self.verdict)

    def replace(self, **changes) -> FaceOptions:
        """A copy with ``changes`` (validated again)."""
        return replace(self, **changes)


#: What each door asks (the run's choices, such as the gate policy's ``advise`` or ``--verify``, replace fields).
GATE = FaceOptions(verdict=True, criteria=True, peak=True, finite=True)
ADVISE = FaceOptions(advice="all", compare="auto", verify=True, peak=True, finite=True)
HOOK_CHECK = FaceOptions(reading="intent")
HOOK_REPORT = FaceOptions(advice="all")


@dataclass
class FaceWork:
    """One face between the two phases: its record, its :class:`~cadartifact.advice.advise.Advice` (None without
    advice) and today's budget with its fields (:class:`~cadartifact.analysis.budget.Budget`) where phase two
    locates the peak on it (the surface reading), else None."""

    net: object
    record: dict
    advice: object = None
    current: object = None


def analyse_face(net, settings, options: FaceOptions = FaceOptions()) -> dict:
    """One face's record, as every door builds it.

    Parameters
    ----------
    net : ControlNet
    settings : RunSettings or FileSettings
        The run's settings (:class:`~cadartifact.analysis.settings.RunSettings`), or a gate file's
        (:class:`~cadartifact.gate.policy.FileSettings`: its ``run`` is read, and its verdict policy with
        ``options.verdict``). Without a tolerance the record has no shares, decision, uncertainty nor advice.
    options : FaceOptions
        What the door asks for.

    Returns
    -------
    dict
        The face entry of the advise document (:func:`cadartifact.runs.records.face_record`), plus the gate's
        keys with ``options.verdict`` and ``options.criteria``, and ``entity_line`` and ``peak_at`` with
        ``options.peak``.

    Raises
    ------
    NonFiniteResult
        With ``options.finite``, for coordinates or results that are not finite.
    CadArtifactError
        As the budget and the advice raise them.
    """
    return analysed(net, settings, options).record


def analysed(net, settings, options: FaceOptions = FaceOptions()) -> FaceWork:
    """:func:`analyse_face`'s two phases in a row; the :class:`FaceWork` with the record, the advice and today's
    budget."""
    return finish_face(start_face(net, settings, options), settings, options)


def _run(settings):
    """The :class:`~cadartifact.analysis.settings.RunSettings` of a run's or a gate file's settings."""
    return getattr(settings, "run", settings)


def start_face(net, settings, options: FaceOptions = FaceOptions(), *, later: bool = False) -> FaceWork:
    """Phase one: today's budget, ``U``, the record, the verdict, the advice and the criteria.

    ``later``: the advice's verification is left for :func:`finish_face` (no OCCT evaluation here).
    """
    import numpy as np

    from ..advice.decision import face_uncertainty
    from ..analysis.budget import budget_for
    from .records import budget_record

    run = _run(settings)
    if options.finite and not np.isfinite(np.sum(net.points ** 2)):  # squared norms overflow: nothing finite follows
        raise NonFiniteResult(f"coordinates too large to analyse (max |x| = {np.abs(net.points).max():.3g})")
    reading = run.reading if options.reading == "run" else run.intent
    scored = run.replace(intent=reading)
    # the fields stay for the advice's search and the peak's location (the net reading's only for a sure advice)
    current = budget_for(net, scored, keep_fields=run.reading == "surface" or options.advice == "all")
    unc = None if run.tolerance is None else face_uncertainty(net, scored, current)  # the U the advice's rule uses
    key_deviation = reading == "net" if options.reading == "run" else run.include_signal_error
    rec = budget_record(net, current, key_deviation, unc)
    if options.verdict or run.tolerance is None or options.advice != "all":
        # checked before the verdict; a sure advice (advise's) is checked with its record, after its search, as
        # advise always did (a search on a non-finite face raises its own error first)
        rec = _finite(rec, run, options)
    verdict = reason = value = skipped = None
    if options.verdict:
        from .verdicts import face_verdict

        verdict, reason, value = face_verdict(rec, settings)
    adv = None
    if run.tolerance is not None:
        skipped = _advice_skipped(options.advice, verdict)
        if skipped is None:
            from ..advice.advise import advise_for
            from .records import face_record

            # a verification costs a real-surface evaluation: "failing" verifies the faces today's net does not meet
            verify = options.verify is True or (options.verify == "failing"
                                                and not current.meets(run.include_signal_error))
            adv = advise_for(net, scored, compare=options.compare, verify="later" if verify and later else verify,
                             current=current if current.fields is not None else None, uncertainty=unc)
            rec = _finite(face_record(net, adv), run, options)
            if options.verdict:
                verdict, reason, value = face_verdict(rec, settings)
    if options.verdict:
        rec.update(verdict=verdict, verdict_reason=reason, value=value, advice_skipped=skipped)
    if options.criteria:
        from .verdicts import add_criteria

        add_criteria(rec, net, settings)
    if options.peak:
        rec["entity_line"] = None  # set by the door that has the file's entity index; the records' key order
        rec["peak_at"] = None
    # today's budget waits for phase two only where the peak is read on it (its fields are large)
    kept = options.peak and run.reading == "surface" and beyond(rec)
    return FaceWork(net, rec, adv, current if kept else None)


def finish_face(work: FaceWork, settings, options: FaceOptions = FaceOptions()) -> FaceWork:
    """Phase two: the verification :func:`start_face` left for later, and the peak's location (``options.peak``,
    faces :func:`beyond` the tolerance) on today's budget."""
    from ..advice.verification import complete

    if work.advice is not None and work.advice.pending is not None:
        work.advice = complete(work.advice)
        work.record["advice"] = work.advice.to_dict()
    if options.peak and beyond(work.record):
        work.record["peak_at"] = _peak_at(work.net, work.record["scheme"], _run(settings).compared, work.current)
    work.current = None  # its fields can go
    return work


def beyond(rec: dict) -> bool:
    """Whether a face's record is beyond the tolerance or warns: its peak is located."""
    return rec["meets_tolerance"] is False or rec.get("ripple_verdict", rec.get("verdict")) in ("warn", "fail")


def _advice_skipped(mode: str, verdict: str | None) -> str | None:
    """None when the face gets the advice under ``mode`` (:data:`ADVICE`), else why it does not."""
    if mode == "all" or (mode == "failing" and verdict in ("warn", "fail")):
        return None
    if mode == "none":
        return "not computed (--advise none)"
    return "face passes (--advise failing)"


def _finite(rec: dict, run, options: FaceOptions) -> dict:
    """The record, or :class:`NonFiniteResult` where ``options.finite`` asks and the compared value or the ripple
    is not finite (:func:`cadartifact.runs.records.json_number` maps inf and NaN to None)."""
    if options.finite and any(rec["budget"][k][run.metric] is None for k in (run.compared, "total")):
        raise NonFiniteResult(NON_FINITE_VALUE)
    return rec


def _peak_at(net, scheme: str, key: str, current):
    """:func:`cadartifact.runs.records.peak_location`, or None where it cannot say (a location helps; it never fails
    a run). Other exceptions pass: each door words them as its document does; so does OCCT's evaluation crashing
    or hanging in the reader child (:class:`~cadartifact.execution.child.ChildFailed`): the face's error, a face
    never passes on a location that could not be made."""
    from ..execution.child import ChildFailed
    from .records import peak_location

    try:
        return peak_location(net, scheme, key, current)
    except ChildFailed:
        raise
    except (CadArtifactError, ValueError, KeyError):
        return None
