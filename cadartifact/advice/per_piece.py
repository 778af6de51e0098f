"""Each piece's density found on its own (SPEC §5 "Joins are kept", issue 23 item 2).

The density search (:mod:`.density_search`) finds one count per direction, its spans shared among the pieces
between the face's joins in proportion to today's (:mod:`.joins`). A face whose pieces need different densities
(one wavy, one flat) then carries spans the flat piece does not need. From the proportional answer, each piece's
spans are searched on their own: piece by piece (the widest first), the fewest spans of that piece with the others
held for which the whole candidate still conforms (galloping down from its spans, the predicate being the
advice's own test), two rounds at most. The advice is whichever plan has fewer points within the tolerance:
the per-piece plan starts from the proportional one and only removes spans, so it is never more.

Cost: a piece whose spans cannot fall costs one candidate; one that falls from ``s`` to ``s'`` about
``2 log2(s - s')``. Directions of more than :data:`MAX_PIECES` pieces, and searches beyond :data:`MAX_TRIALS`
candidates, keep the proportional plan (or what was found until then: every step conforms).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .density_search import gallop

__all__ = ["per_piece", "piece_report", "MAX_PIECES", "MAX_TRIALS"]

#: A direction of more pieces than this is not searched piece by piece.
MAX_PIECES = 12

#: Candidates the per-piece search may score at most.
MAX_TRIALS = 60


def _points(degree: int, plan, per) -> int:
    return int(degree + sum(per) + plan.extra)


def _demand(plan) -> tuple:
    return plan.demand if plan.demand is not None else (0.0,) * len(plan.spans)


def per_piece(scorer, ok, shape):
    """The per-piece plan from the proportional answer ``shape``.

    Parameters
    ----------
    scorer : cadartifact.advice.scorer._Scorer
        The confirmation grid's scorer (its ``plans``: the proportional ones).
    ok : callable
        ``ok(scorer, a, b) -> bool``: whether a candidate conforms (the advice's own test).
    shape : (int, int)
        The proportional answer (conforming).

    Returns
    -------
    (scorer, shape) or None
        A scorer whose plans fix each piece's spans (:attr:`~.joins.JoinPlan.fixed`) and the shape of its answer,
        when it has fewer points than ``shape``; None otherwise.
    """
    plans = list(scorer.plans)
    per = {d: plan.per(shape[d] - scorer.degrees[d] - plan.extra) for d, plan in enumerate(plans)
           if plan is not None and len(plan.spans) <= MAX_PIECES}
    if not per or all(max(s) <= 1 for s in per.values()):
        return None
    seen: dict = {}

    def variant(state):
        fixed = [plan if d not in state else dataclasses.replace(plan, fixed=tuple(state[d]))
                 for d, plan in enumerate(plans)]
        sh = tuple(shape[d] if d not in state else _points(scorer.degrees[d], plans[d], state[d]) for d in (0, 1))
        return scorer.with_plans(fixed), sh

    def holds(state) -> bool:
        key = tuple((d, tuple(s)) for d, s in sorted(state.items()))
        if key not in seen:
            if len(seen) >= MAX_TRIALS:
                return False  # out of budget: a step not tried is a step not taken
            sc, sh = variant(state)
            seen[key] = bool(ok(sc, *sh))
        return seen[key]

    state = {d: list(s) for d, s in per.items()}
    if not holds(state):  # the same knots as the proportional answer: holds unless the budget is spent
        return None
    for _ in range(2):
        changed = False
        # directions and pieces in an order the geometry sets (most spans, then most bending: the plan's demand),
        # not their index: a transposed or reversed face takes the same steps
        for d in sorted(state, key=lambda d: (-sum(state[d]), -sum(_demand(plans[d])), d)):
            need = _demand(plans[d])
            for k in np.lexsort((np.arange(len(state[d])), -np.asarray(need), -np.asarray(state[d]))):
                s = state[d][k]
                if s <= 1:
                    continue

                def pred(x, d=d, k=int(k)):
                    trial = {e: list(v) for e, v in state.items()}
                    trial[d][k] = int(x)
                    return holds(trial)

                new = gallop(pred, 1, s, s - 1)
                if new < s:
                    state[d][k], changed = int(new), True
        if not changed:
            break
    sc, sh = variant(state)
    if sh[0] * sh[1] >= shape[0] * shape[1]:
        return None
    return sc, sh


def piece_report(scorer, shape, direction: int, target: float) -> list[dict]:
    """Per piece of a direction keeping its joins: its parameter range, today's and the advised spans, the points
    it adds to the net (its spans, plus ``p`` for the first piece or ``m - 1`` for the join before it: they sum to
    the direction's count), the advised net's peak deviation from the intent over the piece (the other direction
    whole) and whether it is within ``target`` (the tolerance less the intent's uncertainty)."""
    from ..analysis.fields import project

    plan, p = scorer.plans[direction], scorer.degrees[direction]
    per = plan.per(shape[direction] - p - plan.extra)
    Q, S, I, normal, keep, axes = scorer.fit(*shape)
    f = np.where(keep, np.abs(project(S - I, normal, scorer.component)), 0.0)
    u = scorer.frames[direction].param(axes[direction].x)
    edges = [plan.lo, *plan.joins, plan.hi]
    out = []
    for k, (lo, hi) in enumerate(zip(edges[:-1], edges[1:])):
        rows = (u >= lo - 1e-12 * max(1.0, abs(lo))) & (u <= hi + 1e-12 * max(1.0, abs(hi)))
        part = f[rows] if direction == 0 else f[:, rows]
        dev = float(part.max()) if part.size else 0.0
        out.append({"range": [float(lo), float(hi)], "today_spans": int(plan.spans[k]), "advised_spans": int(per[k]),
                    "points": int(per[k] + (p if k == 0 else plan.mult - 1)), "deviation": dev,
                    "meets_tolerance": bool(dev <= target)})
    return out
