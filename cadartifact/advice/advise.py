"""Density advice: the fewest control points whose best net stays within the tolerance (SPEC §5).

For a candidate density the candidate is the best net of that density for the design intent
(:mod:`cadartifact.analysis.fitting`); its error is its surface minus the intent on a check grid fine for
both nets, measured along the intent's normal (peak by default). Today's net is scored by the same
code against the same intent. The advice is the density with the fewest points whose error (and
whose boundary curves' distance from today's) stays within the tolerance; a face within the
tolerance today is never advised more points. The answer is verified on the real surface of the
advised net (OCCT).

>>> import cadartifact as ca
>>> a = ca.advise(net, tolerance=0.05)                 # doctest: +SKIP
>>> a.shape, a.meets_tolerance, a.reasons["u"]          # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..analysis.budget import Budget, Stat, analysis_net, budget_for
from ..analysis.baseband import release
from .density_search import (GROWTH, MAX_POINTS, TIE, _limits, _straight, corner, frontier, gallop,  # noqa: F401
                             predicted_hint)  # (_straight: face_instances)
from ..errors import OptionError, check_option
from ..analysis.fitting import candidate_net
from ..analysis.settings import READINGS, RunSettings, check_tolerance, resolve_scheme
from ..net import ControlNet, no_ripple_by_construction
from ..analysis.pieces import face_kind
from .exact import kept_phrase
from .honest import unverified_note
from .verification import unconfirmed
from .decision import CONFORMS, advised_uncertainty, candidate_margin, decide, scorer_uncertainty, unverifiable, unverifiable_note
from .scheme_comparison import NAMED_SCHEMES, compare_schemes
from .surface_margin import LazyMargin
from .scorer import _Scorer, _make_scorer, _own_claim, _real_on, _ripple_of, _trimmed  # noqa: F401 (_trimmed: face_instances)

__all__ = ["Advice", "advise", "advise_for", "resample", "clear_caches", "OBJECTIVES", "NAMED_SCHEMES"]


#: What the tolerance bounds: the candidate's whole error against the intent, or its ripple only.
OBJECTIVES = ("deviation", "ripple")

#: Check grid of the search (K = 4 per span); the answer is confirmed and walked at the requested levels.
SEARCH_LEVELS = 2

#: Nets above this many control points skip the scheme comparison unless asked for.
COMPARE_MAX_POINTS = 2000


def _not_worse(u_value: float, v_value: float) -> bool:
    """Whether one more ``u`` point does at least as well as one more ``v`` point (equal within :data:`TIE`)."""
    return u_value <= v_value + TIE * max(abs(u_value), abs(v_value))

#: Greedy steps of the confirmation before it searches the fine grid's frontier from where it stands.
GREEDY_STEPS = 4

#: A face within the tolerance today keeps its net unless the advice saves at least this share of points.
MIN_REDUCTION = 0.1


@dataclass(frozen=True, eq=False)
class Advice:
    """Density advice for one net.

    Attributes
    ----------
    net : ControlNet
        Today's net.
    scheme : str
    tolerance : float
    metric : str
    intent : str
        ``"surface"`` or ``"net"``: the reading of the design intent both today's net and the
        candidates are scored against.
    objective : str
        ``"deviation"`` (the candidate's whole error against the intent) or ``"ripple"``.
    current : Budget
        Today's budget.
    today : dict
        Today's net scored like a candidate: ``{"peak", "rms", "boundary"}``.
    shape : (int, int)
        Advised ``(n'u, n'v)``.
    stats : dict str -> Stat
        The advised net: ``deviation`` (its error against the intent), ``boundary`` (its border
        curves against today's) and its own ripple budget (``x1`` ... ``total``).
    meets_tolerance : bool
    binding : str or None
        ``"u"`` or ``"v"``: the direction in which one step coarser breaks the tolerance.
    reasons : dict
        Per direction ``"u"``, ``"v"``: ``{"today", "advised", "change", "coarser_value", "binding",
        "reason"}``.
    kept_today : bool
        Today's net meets the tolerance and no net of fewer points was found: it is the advice as is.
    advised_net : ControlNet
        The advised net (the fitted candidate, or today's net when kept).
    verification, comparison, comparison_note, notes
    """

    net: ControlNet
    scheme: str
    tolerance: float
    metric: str
    intent: str
    objective: str
    current: Budget
    today: dict
    shape: tuple
    stats: dict
    meets_tolerance: bool
    binding: str | None
    reasons: dict
    kept_today: bool
    advised_net: ControlNet
    verification: dict | None = None
    comparison: dict = field(default_factory=dict)
    comparison_note: str | None = None
    notes: list = field(default_factory=list)
    #: The intent's expanded uncertainty (:class:`~cadartifact.analysis.uncertainty.Uncertainty`), the decision
    #: for the advised net and for today's (:mod:`cadartifact.advice.decision`), and whether any net can conform.
    uncertainty: object = None
    decision: str | None = None
    today_decision: str | None = None
    verifiable: bool = True
    #: Per direction with joins kept (:mod:`cadartifact.advice.joins`): ``{"joins", "multiplicity", "today_spans",
    #: "advised_spans"}``; what of the surface's parameter range lies outside the trim (``{"u", "v", "share"}``);
    #: and, when no density within the limits conforms, why (:mod:`cadartifact.advice.honest`).
    joins: dict = field(default_factory=dict)
    outside_trim: dict | None = None
    no_density: dict | None = None
    #: When the search's own-ripple reading found no density and the deviation verified on OCCT found one
    #: (:func:`cadartifact.advice.retry.verified_retry`): ``{"net", "value", "read", "own_ripple", "tried"}``.
    retried: dict | None = None
    #: The ``U`` the claim on the advised net used (:class:`.surface_margin.CandidateUncertainty`, either reading)
    advised_uncertainty: object = None
    #: ``verify="later"``: the verification still to run (:func:`cadartifact.advice.verification.complete`)
    pending: object = field(default=None, repr=False, compare=False)

    @property
    def include_signal_error(self) -> bool:
        """Whether today's verdict counts the whole deviation (``net`` reading, deviation objective)."""
        return self.intent == "net" and self.objective == "deviation"

    @property
    def value(self) -> float:
        return self.stats["deviation" if self.objective == "deviation" else "total"].get(self.metric)

    @property
    def points(self) -> int:
        return int(self.shape[0] * self.shape[1])

    def resampled(self) -> ControlNet:
        """The advised net (best net of the advised density for the intent)."""
        return self.advised_net

    def to_dict(self) -> dict:
        """JSON-ready summary (the ``advice`` object of the advise schema)."""
        t = self.tolerance
        d = {
            "net": list(self.shape),
            "points": self.points,
            "intent": self.intent,
            "objective": self.objective,
            "budget": {k: {"peak": _f(s.peak), "rms": _f(s.rms)} for k, s in self.stats.items()},
            "share": {k: _f(s.get(self.metric) / t) for k, s in self.stats.items()},
            "today": {k: _f(v) for k, v in self.today.items()},
            "meets_tolerance": bool(self.meets_tolerance),
            "uncertainty": None if self.uncertainty is None else {k: _f(v) if isinstance(v, float) else v
                                                                  for k, v in self.uncertainty.to_dict().items()},
            "decision": self.decision,
            "today_decision": self.today_decision,
            "verifiable": bool(self.verifiable),
            "binding": self.binding,
            "reasons": self.reasons,
            "kept_today": bool(self.kept_today),
            "verification": self.verification,
            "comparison": self.comparison,
            "notes": list(self.notes),
            "joins": self.joins,
            "outside_trim": self.outside_trim,
            "no_density": self.no_density,
        }
        if self.comparison_note:
            d["comparison_note"] = self.comparison_note
        if self.advised_uncertainty is not None:
            d["advised_uncertainty"] = {k: _f(v) if isinstance(v, float) else v
                                        for k, v in self.advised_uncertainty.to_dict().items()}
        if self.retried is not None:
            d["retried"] = {k: _f(v) if isinstance(v, float) else v for k, v in self.retried.items()}
        return d


def _f(x):
    return None if x is None or not math.isfinite(x) else float(x)


def advise(net: ControlNet, tolerance: float, scheme=None, *, metric: str = "peak", intent: str = "surface",
           objective: str = "deviation", include_signal_error: bool | None = None, levels: int = 3,
           component: str = "normal", compare: bool | str = "auto", verify: bool = True,
           current: Budget | None = None) -> Advice:
    """Advise the control-point density that keeps the error within ``tolerance``.

    Parameters
    ----------
    net : ControlNet
    tolerance : float
        Model units.
    scheme : str or Scheme, optional
        Default: the net's own B-spline degrees; Catmull-Clark (bicubic) for cages.
    metric : {"peak", "rms"}
    intent : {"surface", "net"}
        The reading of the design intent (SPEC §4): the surface less its ripple (default), or the
        shape the control points sample.
    objective : {"deviation", "ripple"}
        Bound the candidate's whole error against the intent (default, SPEC §5), or its ripple.
    include_signal_error : bool, optional
        Former option: ``True`` is ``intent="net"`` (the tolerance then covers attenuation too).
    levels : int
        Check grid ``K = 2**levels`` samples per span of the finer net.
    component : {"normal", "vector"}
    compare : bool or "auto"
        Also advise the other named schemes (ripple of the intent sampled at their points);
        ``"auto"``: for cages and for a ``scheme`` named explicitly, of up to :data:`COMPARE_MAX_POINTS`
        points; not for a B-spline face under its own degrees (its file fixes its scheme).
    verify : bool or "later"
        Build the advised net as a real B-spline surface (OCCT), evaluate it and measure it against
        the intent on the whole face, and the same one step coarser in the binding direction.
        ``"later"``: leave that to :func:`cadartifact.advice.verification.complete` (while OCCT is busy).
    current : Budget, optional
        Today's budget of this net when the caller has it (same scheme, metric, levels, component and
        intent, default method and region, fields kept): it is not computed again.

    Returns
    -------
    Advice

    Notes
    -----
    Candidate ``n'u x n'v``: ``Q = pinv(Bu) I pinv(Bv)^T`` (least squares on the check grid), error
    ``E = Bu Q Bv^T - I``, value ``max |E . n|`` (or RMS) over the trimmed face, feasible when it is
    ``<= t - U`` (``U`` the intent's expanded uncertainty, :mod:`cadartifact.analysis.uncertainty`; the
    decision rule of ISO 14253-1, :mod:`cadartifact.advice.decision`) and the candidate's own ripple plus its
    ``U``, as the gate decides the net, is ``<= t`` (:func:`.scorer._own_claim`); the boundary curves' distance
    from today's is reported. The search walks the frontier
    ``n'v(n'u)`` (galloping from today's density) at ``K = 4``, then confirms at ``K = 2**levels``,
    growing until feasible and shrinking each direction while it stays so.
    """
    check_option("intent", intent, READINGS)
    check_option("objective", objective, OBJECTIVES)
    settings = RunSettings(tolerance=tolerance, metric=metric, scheme=scheme, intent="net" if include_signal_error
                           else intent, levels=levels, component=component)
    return advise_for(net, settings, objective=objective, compare=compare, verify=verify, current=current)


def advise_for(net: ControlNet, settings: RunSettings, *, objective: str = "deviation", compare: bool | str = "auto",
               verify: bool | str = True, current: Budget | None = None, uncertainty=None) -> Advice:
    """:func:`advise` under a run's settings (made and checked once, at the edge; see
    :mod:`cadartifact.analysis.settings`): ``settings.tolerance`` (required), ``scheme``, ``metric``,
    ``intent`` (the reading: ``"net"`` when the signal error counts), ``levels`` and ``component``.
    ``uncertainty``: the intent's :class:`~cadartifact.analysis.uncertainty.Uncertainty` under the same reading
    when the caller has it (:func:`~cadartifact.advice.decision.face_uncertainty`, as the gate's verdict computed
    it): not computed again."""
    check_option("objective", objective, OBJECTIVES)
    tolerance = check_tolerance(settings.tolerance)
    metric, levels, intent = settings.metric, settings.levels, settings.intent
    if not isinstance(net, ControlNet):
        raise OptionError("net", "a ControlNet", type(net).__name__)
    named = settings.scheme  # None: the face's own B-spline degrees (or bicubic for a cage)
    sch = resolve_scheme(net, named)
    settings = settings.replace(scheme=sch, method="auto", region="auto")  # the road and region advise() reads
    reuse = (current is not None and current.net is net and current.fields is not None and current.scheme == sch.name
             and (current.metric, current.levels, current.component, current.intent) == (metric, levels,
                                                                                         settings.component, intent)
             and current.options == ("auto", "auto"))  # the road and region advise() itself would use
    work = analysis_net(net, sch, tolerance)  # the spans the trimmed face uses (SPEC §4)
    if reuse and (current.work is None or current.work.shape != work.shape):
        reuse = False  # today's budget read another part of the surface (another tolerance)
    if not reuse:
        current = budget_for(net, settings, keep_fields=True)
    work = current.work if current.work is not None else work
    # one intent for both check grids (only the grid's density differs): the fields of today's budget
    scorers = {lv: _make_scorer(net, work, sch, settings.replace(levels=lv), current)
               for lv in sorted({min(SEARCH_LEVELS, levels), levels})}
    fine = scorers[levels]
    coarse = scorers[min(SEARCH_LEVELS, levels)]
    low, high = _limits(work, fine.degrees, fine.plans)
    # a direction kept exactly (:mod:`.exact`) has today's count; a face kept in both is not searched
    low, high = (tuple(work.shape[k] if fine.kept[k] else lim[k] for k in (0, 1)) for lim in (low, high))
    exact_face = all(fine.kept)
    t = tolerance
    # the intent's own uncertainty U (SPEC §4): a candidate conforms at value + U <= t
    unc = uncertainty if uncertainty is not None else scorer_uncertainty(fine, settings, current)
    # a candidate's U: the net reading's intent error (wider than today's U), or how far the intent moves (surface)
    lazy = None if unc.reading == "net" or exact_face or objective == "ripple" else LazyMargin(
        net, settings, work, current.fields, t)
    margin = candidate_margin(unc) if lazy is None else (
        lazy.exact() if unverifiable(lazy.bound, t) else lazy.bound)
    hopeless = unverifiable(margin, t)

    reading = {"own ripple": objective == "deviation" and intent == "surface"}

    def value(sc, a, b, own_ripple=True):
        """The candidate's value plus the intent's uncertainty, against the tolerance: its error against the
        intent and, for the surface reading, its own ripple plus that reading's U as the gate will decide it (so the
        gate confirms the advice; a budget per candidate, so only where the fine grid confirms). After a verified
        retry (:mod:`.retry`) the deviation alone."""
        if objective == "ripple":
            return _ripple_of(sc, a, b, settings) + margin
        d = sc.value(a, b)
        dev = d + (margin if lazy is None else lazy.margin(d))  # U_c read only where the bound B does not decide
        if dev > t or not reading["own ripple"] or not own_ripple:  # the net reading bounds the deviation
            return dev
        return max(dev, _own_claim(sc, a, b, settings))  # U_c bounds the deviation's change; the own ripple has its U

    trail = {}
    if hopeless or exact_face:  # no density can conform (SPEC §5 "an honest no"), or the face is exact as it is:
        a, b = work.shape  # no search, today's density stands
    else:
        # a feasible corner by bounded doubling (a direction that stops improving stops growing), then its frontier
        found, reachable, trail = corner(lambda x, y: value(coarse, x, y, own_ripple=False), t, low, high,
                                         work.shape)
        hint = predicted_hint(value(coarse, *found, own_ripple=False), t, found, coarse.degrees, low)
        a, b = frontier(lambda x, y: value(coarse, x, y, own_ripple=False) <= t, low, high, work.shape,
                        found=found, hint=hint)[0] if reachable else found
        # confirm on the fine grid: grow until it agrees (a few greedy steps, then a bounded corner and frontier of
        # the fine grid's own test from there: the own ripple need not fall at every step, and a greedy walk along
        # the direction that does not bind can climb to the search's bound), then shrink each direction while it
        # holds
        steps = 0
        while reachable and value(fine, a, b) > t and (a < high[0] or b < high[1]):
            if steps == GREEDY_STEPS:
                found, reachable, trail = corner(lambda x, y: value(fine, x, y), t, low, high, (a, b))
                a, b = frontier(lambda x, y: value(fine, x, y) <= t, low, high, (a, b), found=found)[0] \
                    if reachable else found
                break
            grow_u = a < high[0] and (b >= high[1] or _not_worse(value(fine, a + 1, b),
                                                                   value(fine, a, min(b + 1, high[1]))))
            a, b = (a + 1, b) if grow_u else (a, b + 1)
            steps += 1
        changed = value(fine, a, b) <= t
        while changed:
            changed = False
            if a > low[0] and value(fine, a - 1, b) <= t:
                a, changed = gallop(lambda x, y=b: value(fine, x, y) <= t, low[0], a - 1, a - 1), True
            if b > low[1] and value(fine, a, b - 1) <= t:
                b, changed = gallop(lambda y, x=a: value(fine, x, y) <= t, low[1], b - 1, b - 1), True
    meets = value(fine, a, b) <= t and not hopeless
    retried = None
    if not meets and not hopeless and not exact_face and reading["own ripple"]:
        # before an honest no, the nets a write-and-measure check would accept: the deviation verified on OCCT
        from .retry import verified_retry

        margin = margin if lazy is None else lazy.exact()  # near the tolerance: U_c itself
        retried = verified_retry(fine, lambda x, y: value(fine, x, y, own_ripple=False), t, margin, low, high,
                                 work.shape, best=(a, b))
        if retried is not None:
            own = _ripple_of(fine, *retried["net"], settings)
            retried["own_ripple"] = float(own)
            (a, b), meets, reading["own ripple"] = retried["net"], True, False
    margin = margin if lazy is None else lazy.settle()  # the claim's U from here on
    proportional = None
    if meets and any(fine.plans):  # each piece's spans on their own: whichever plan has fewer points
        from .per_piece import per_piece

        found = per_piece(fine, lambda sc, x, y: value(sc, x, y) <= t, (a, b))
        if found is not None:
            proportional, (fine, (a, b)) = (int(a), int(b)), found

    today = fine.today()
    notes = list(current.notes)
    today_decision = decide(today[metric], unc.peak, t)
    today_ok = today_decision == CONFORMS
    kept = False
    if exact_face and not hopeless:  # a canonical (or exact both ways) face is never replaced
        meets = today_ok
    if exact_face or today_ok and (not meets or a * b > (1.0 - MIN_REDUCTION) * work.shape[0] * work.shape[1]):
        # a face within the tolerance today is never advised more points, nor a net barely smaller
        # (SPEC §5: the advice is a fixed point; a flat frontier would otherwise wander)
        if (a, b) != tuple(work.shape):
            found = f"the fewest-points net found ({a}x{b}, {a * b} points)"
            why = ("no other density the search tried conforms" if not meets
                   else f"{found} is no smaller" if a * b >= work.shape[0] * work.shape[1]
                   else f"{found} saves less than {MIN_REDUCTION:.0%}")
            construction = no_ripple_by_construction(work)
            notes.append(f"no ripple by construction ({construction}): today's {work.shape[0]}x{work.shape[1]} "
                         f"is kept" if construction else
                         f"today's net meets the tolerance ({today[metric]:.4g} <= {tolerance:g}) and {why}: "
                         f"today's {work.shape[0]}x{work.shape[1]} is kept")
        a, b = work.shape
        kept, meets = True, meets or today_ok
    shape = (int(a), int(b))
    binding, reasons = _reasons(fine, shape, work, low, t, today, kept, value, margin)
    exact_note = kept_phrase(fine.kept) if exact_face or not kept else None
    if exact_note:
        notes.append(exact_note + (": the face is kept as it is" if exact_face else
                                   ": only the other direction is fitted and advised"))
    no_density = None
    if not meets and not hopeless:  # SPEC §5 "an answer or an honest no": the best found, and why none conforms
        from .honest import explain

        best = value(fine, a, b)  # the deviation with U_c, or the own ripple with its own U where that is larger
        own = None if best == value(fine, a, b, own_ripple=False) else _ripple_of(fine, a, b, settings)
        raw, u = (best - margin, margin) if own is None else (own, best - own)
        no_density = explain(fine, shape, trail, raw, u, t, net.unit or "model units", own is not None)
        notes.insert(0, no_density["reason"])
        binding = None
        for d in reasons.values():
            d["binding"], d["reason"] = False, no_density["reason"]
    if kept:
        advised = net
        sc = dict(today)
    else:
        Q, S, I, normal, keep, (cu, cv) = fine.fit(*shape)
        advised = candidate_net(net, Q, cu, cv)
        sc = fine.score(*shape)
    # kept: the advised net is today's, whose budget under the same options is `current` already
    known = current if kept else None
    stats = _advice_stats(advised, settings.replace(scheme=sch if kept else None), sc, known)
    if stats["boundary"].peak > t:
        notes.append(f"the advised net's border curves lie up to {stats['boundary'].peak:.3g} from today's (more than "
                     "the tolerance): neighbouring faces must follow")
    what = face_kind(work)
    if what and not kept and meets:
        kind = "jointed (its joins kept)" if any(fine.plans) else "uniform"
        if any(fine.kept):
            kind += f" in {'uv'[fine.kept.index(None)]} (its {'uv'[fine.kept.index(None) ^ 1]} kept exactly)"
        notes.append(f"this {work.shape[0]}x{work.shape[1]} {what} face is carried by a {shape[0]}x{shape[1]} {kind} "
                     f"net within {stats['deviation'].get(metric):.3g} (tolerance {t:g})")

    advised_u = advised_uncertainty(unc, kept, margin, lazy)
    claim = getattr(advised_u, "peak", margin)  # the U of the advised net's claim (a kept net's: today's)
    verification = pending = checked = None
    if verify:
        from .verification import verify_advice

        def check():
            try:
                own = None if not reading["own ripple"] else (  # the search's reading (see value()), less the
                    lambda x, y: _own_claim(fine, x, y, settings) - margin)  # reserve the target holds already
                got = verify_advice(fine, shape, binding, tolerance - claim, advised, tolerance - margin, own)
                unconfirmed(reasons, binding, got)
                return got
            finally:
                release(fine.fields)

        if verify == "later":
            pending = check
        else:
            verification = check()
            if not verification.get("meets", True) and meets:  # an answer only where it is verified (SPEC §5)
                meets, checked = False, verification["value"]
                notes.insert(0, unverified_note(verification, tolerance - claim))
    comparison, comparison_note = {}, None
    if compare == "auto":
        if net.is_bspline and named is None:
            # a B-rep face is the B-spline its file says: which other scheme would do better is a question for a
            # cage's author, and its answer cost most of a face's advice (issue 24)
            compare = False
            comparison_note = (f"off: a B-spline face's scheme is its file's (degrees {net.degrees[0]}x"
                               f"{net.degrees[1]}); pass compare=True (--compare) to advise the other schemes too")
        else:
            compare = net.size <= COMPARE_MAX_POINTS
            if not compare:
                comparison_note = f"skipped: net of {net.size} points (> {COMPARE_MAX_POINTS}); pass compare=True"
    if compare:
        comparison = compare_schemes(net, work, sch, shape, meets, settings, fine, growth=GROWTH,
                                     max_points=MAX_POINTS, objective=objective,
                                     value=None if hopeless else value)
    for sc in (coarse, fine):  # what the search kept of the intent's evaluation (the fields themselves stay)
        release(sc.fields)
    if hopeless:
        notes.insert(0, unverifiable_note(margin, t, net.unit or "model units"))
    raw = stats["deviation" if objective == "deviation" else "total"].get(metric)
    joins = _joins_report(fine, shape, kept, proportional, tolerance - margin, notes)
    if retried is not None and not kept:
        from .retry import retry_note

        notes.insert(0, retry_note(retried, retried["own_ripple"], margin, t))
    retried = retried if retried is not None and not kept else None
    return Advice(retried=retried, joins=joins, no_density=no_density, outside_trim=None if current.used is None else current.used.to_dict(),
                  net=net, scheme=sch.name, tolerance=tolerance, metric=metric, intent=intent, objective=objective,
                  uncertainty=unc, advised_uncertainty=advised_u, today_decision=today_decision, verifiable=not hopeless,
                  decision=CONFORMS if meets else decide(max(raw, checked or raw), claim, t),
                  current=current, today=today, shape=shape, stats=stats, meets_tolerance=bool(meets),
                  binding=binding, reasons=reasons, kept_today=kept, advised_net=advised,
                  verification=verification, comparison=comparison, comparison_note=comparison_note, notes=notes,
                  pending=pending)


def _joins_report(fine, shape, kept, proportional, target, notes) -> dict:
    """Per direction keeping its joins: the plan (``"today's"`` when kept, ``"per piece"`` when each piece's spans were found on their own
    and saved points, else ``"proportional"``), the spans and, per piece, :func:`.per_piece.piece_report`."""
    from .per_piece import piece_report

    out = {}
    for k, (d, plan, n) in enumerate(zip("uv", fine.plans, shape)):
        if plan is None:
            continue
        entry = dict(plan.to_dict(), plan="today's" if kept else "per piece" if plan.fixed is not None else "proportional",
                     advised_spans=list(plan.spans) if kept else plan.per(n - fine.degrees[k] - plan.extra))
        entry["pieces"] = None if kept else piece_report(fine, shape, k, target)
        out[d] = entry
    if proportional is not None and not kept:
        notes.append(f"each piece's spans found on its own: {shape[0]}x{shape[1]} ({shape[0] * shape[1]} points) "
                     f"against {proportional[0]}x{proportional[1]} ({proportional[0] * proportional[1]}) with the "
                     "pieces' spans in proportion")
    return out


def _advice_stats(advised, settings: RunSettings, score, known=None) -> dict:
    """The advised net's stats: its own budget under ``settings`` (``known``: that budget, already computed) with
    the candidate's deviation and border distance."""
    b = known if known is not None else budget_for(advised, settings)
    stats = {k: v for k, v in b.stats.items() if k != "deviation"}
    stats["deviation"] = Stat(peak=score["peak"], rms=score["rms"])
    stats["boundary"] = Stat(peak=score.get("boundary", 0.0), rms=score.get("boundary", 0.0))
    return stats


def _reasons(sc: _Scorer, shape, work, low, t, today, kept, value, margin: float = 0.0) -> tuple[str | None, dict]:
    """The binding direction and, per direction, why the advised count is what it is."""
    a, b = shape
    out, worse = {}, {}
    for d, (n_today, n_new, lo) in zip("uv", zip(work.shape, shape, low)):
        coarser = (a - 1, b) if d == "u" else (a, b - 1)
        val = value(sc, *coarser) if n_new - 1 >= lo and not sc.kept["uv".index(d)] else None
        # the value binds by the deviation + U_c, or by the own ripple (the gate's reading of the net) + its own U
        own = val is not None and val > value(sc, *coarser, own_ripple=False)
        if val is not None and val > t:
            worse[d] = val
        change = n_new - n_today
        exact = sc.kept["uv".index(d)] if not kept or all(sc.kept) else None
        if exact:
            why = f"kept exactly ({exact}): today's poles, weights and knots"
        elif kept:
            why = "today's net meets the tolerance: kept as is"
        elif val is None:
            why = f"at the fewest points the degree allows ({lo})"
        elif val > t:
            got = (f"{val:.4g} (its own ripple{' with its U' if sc.net.is_bspline else ''})" if own else
                   f"{val:.4g} (U {margin:.4g} included)" if margin > 0 else f"{val:.4g}")
            why = (f"one point fewer would give {got} > {t:g} (binding)" if change >= 0 else
                   f"today's {n_today} points spend {-change} on nothing the tolerance needs; "
                   f"one fewer would give {got} > {t:g}")
        else:
            why = f"one point fewer would also meet ({val:.4g}); the other direction binds"
        out[d] = {"today": int(n_today), "advised": int(n_new), "change": int(change),
                  "coarser_value": _f(val), "binding": bool(val is not None and val > t), "reason": why}
    binding = None
    if worse and not kept:
        # a tie to rounding (a face symmetric in u and v) binds u: rounding must not pick the direction
        top = max(worse.values())
        binding = next(d for d in "uv" if d in worse and worse[d] >= top * (1.0 - TIE))
    return binding, out


def resample(net: ControlNet, shape: tuple[int, int], scheme=None, *, intent: str = "surface",
             levels: int = 3) -> ControlNet:
    """The best net of a density for a net's design intent (least squares, SPEC §5).

    Parameters
    ----------
    net : ControlNet
    shape : (int, int)
        New ``(n'u, n'v)``.
    scheme : str or Scheme, optional
        Default as :func:`cadartifact.budget`.
    intent : {"surface", "net"}
    levels : int
        Check grid ``2**levels`` samples per span of the finer net.

    Returns
    -------
    ControlNet
        A B-spline net of the face's degrees (clipped to ``n' - 1``; a cage: the scheme's) over the
        same parameter range, uniform knots, no weights; its points fit the intent by least squares.
    """
    check_option("intent", intent, READINGS)
    sch = resolve_scheme(net, scheme)
    try:
        a, b = (int(s) for s in shape)
    except (TypeError, ValueError):
        raise OptionError("shape", "two integers (n'u, n'v)", shape) from None
    work = analysis_net(net, sch)
    sc = _make_scorer(net, work, sch, RunSettings(scheme=sch, intent=intent, levels=levels))
    low = tuple(d + 1 for d in sc.degrees)
    if a < low[0] or b < low[1]:
        raise OptionError("shape", f"at least {low[0]}x{low[1]} control points", (a, b))
    Q, S, I, normal, keep, (cu, cv) = sc.fit(a, b)
    return candidate_net(net, Q, cu, cv)


def clear_caches() -> None:
    """Forget the cached per-axis operators (intent, candidate bases, scheme syntheses): benchmarks measure cold
    runs."""
    from ..numerics.operator_cache import clear_all

    clear_all()
