"""The density search: fewest points ``n'u n'v`` on a monotone feasibility predicate (SPEC §5).

The error of a candidate falls as either density rises (the band structure); the search walks the
frontier ``n'v(n'u)`` of the feasible region, galloping from a hint (today's density), so an answer near
the hint costs a few evaluations. Property tests check it against brute force (``tests/advice/test_advice.py``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # an annotation only
    from ..net import ControlNet

__all__ = ["frontier", "gallop", "first_true", "corner", "predicted_hint"]


def first_true(lo: int, hi: int, pred) -> int:
    """Smallest n in [lo, hi] with pred(n) (pred monotone, pred(hi) True)."""
    while lo < hi:
        mid = (lo + hi) // 2
        if pred(mid):
            hi = mid
        else:
            lo = mid + 1
    return lo


def gallop(pred, lo: int, hi: int, hint: int) -> int:
    """Smallest x in [lo, hi] with pred(x) (pred monotone, pred(hi) True), searched from a hint.

    Steps of 1, 2, 4... away from ``hint`` (down if pred(hint), else up), then bisection: about
    ``2 log2 |answer - hint|`` evaluations.
    """
    h = min(hi, max(lo, hint))
    if pred(h):
        top, step = h, 1
        while top - step >= lo and pred(top - step):
            top, step = top - step, 2 * step
        return first_true(max(lo, top - step + 1), top, pred)
    bottom, step = h, 1
    while True:
        nxt = min(hi, bottom + step)
        if nxt == hi or pred(nxt):
            return first_true(bottom + 1, nxt, pred)
        bottom, step = nxt, 2 * step


#: A doubling that lowers the value by less than this share "stops improving": the direction is not grown further.
STALL = 0.1
#: Two values this close (relative) are a tie: for the corner's pick (:func:`_lowest`), the binding direction and
#: the direction the confirmation grows (:mod:`.advise`); a tie goes to ``u``, so rounding noise of a symmetric face
#: does not turn its advised net (6x7 or 7x6 as 1e-13 of noise fell). The measured road's bridge carries rounding
#: into values at about 1e-9 of them (its fourth derivatives are fitted on one span's samples): 1e-7 is a tie.
TIE = 1e-7


def _lowest(vals: dict) -> str:
    """The key of the lowest value; a tie within :data:`TIE` goes to the first key (``u``, then ``v``, then
    ``uv``), so that rounding noise cannot turn a symmetric face's search."""
    low = min(vals.values())
    return next(k for k in vals if vals[k] <= low + TIE * abs(low))


def corner(value, t: float, lo: tuple[int, int], hi: tuple[int, int], start: tuple[int, int]):
    """A feasible corner ``value(a, b) <= t`` by doubling from ``start``, bounded: a direction whose doubling
    lowers the value by less than :data:`STALL` of it (or that reached its bound) stops growing; when none grows
    the search ends without a corner.

    Returns
    -------
    (shape, reachable, trail) : ((int, int), bool, dict)
        The corner (or the best density tried), whether it is feasible, and ``trail``: ``{"best": (a, b),
        "value", "stalled": [directions that stopped improving], "at_limit": [directions at their bound]}``.
    """
    a, b = (max(l, min(h, s)) for l, h, s in zip(lo, hi, start))
    v = value(a, b)
    best = ((a, b), v)
    grow = [a < hi[0], b < hi[1]]
    stalled, at_limit = set(), set()
    while v > t:
        tries = {}
        if grow[0]:
            tries["u"] = (min(hi[0], 2 * a), b)
        if grow[1]:
            tries["v"] = (a, min(hi[1], 2 * b))
        if grow[0] and grow[1]:
            tries["uv"] = (min(hi[0], 2 * a), min(hi[1], 2 * b))
        if not tries:
            break
        vals = {k: value(*s) for k, s in tries.items()}
        helps = {k: x <= (1.0 - STALL) * v for k, x in vals.items()}
        if not (helps.get("uv") and not helps.get("u") and not helps.get("v")):  # together only: keep both
            for k, d in (("u", 0), ("v", 1)):
                if k in vals and not helps[k]:
                    grow[d] = False
                    stalled.add(k)
        ok = [k for k in vals if vals[k] <= t]
        pick = min(ok, key=lambda k: tries[k][0] * tries[k][1]) if ok else _lowest(vals)
        if not ok and vals[pick] > (1.0 - STALL) * v:
            stalled.update(k for k in ("u", "v") if k in tries)
            break
        (a, b), v = tries[pick], vals[pick]
        if v < best[1]:
            best = ((a, b), v)
        for d, n in enumerate((a, b)):
            if n >= hi[d]:
                grow[d] = False
                at_limit.add("uv"[d])
    reachable = v <= t
    trail = {"best": best[0] if not reachable else (a, b), "value": best[1] if not reachable else v,
             "stalled": sorted(stalled), "at_limit": sorted(at_limit)}
    return (a, b) if reachable else best[0], reachable, trail


def frontier(ok, lo: tuple[int, int], hi: tuple[int, int], start: tuple[int, int],
             found: tuple[int, int] | None = None, hint: tuple[int, int] | None = None) -> tuple[tuple[int, int], bool]:
    """Fewest-points feasible density on the frontier ``n'v(n'u)``; ``(shape, reachable)``.

    A feasible corner is found by doubling from ``start``; the frontier's ends are the smallest
    ``n'u`` feasible with ``n'v`` at the corner and the smallest ``n'v`` with ``n'u`` there; from the
    first, each step adds one ``u`` point and lowers ``n'v`` while the predicate holds (galloping),
    until ``n'u`` times the smallest ``n'v`` cannot beat the best. Exact for a predicate monotone in
    both directions within the corner's box. ``hint``: where the ends' gallops start (default ``start``; see
    :func:`predicted_hint`): it changes which densities are tried, never the answer of a monotone predicate.
    """
    if found is not None:  # a feasible corner found already (:func:`corner`)
        a, b = found
    else:
        a, b = (max(l, min(h, s)) for l, h, s in zip(lo, hi, start))
    while not ok(a, b):
        if a >= hi[0] and b >= hi[1]:
            return (a, b), False
        a, b = min(hi[0], 2 * a), min(hi[1], 2 * b)
    best = (a, b)
    hi = (a, b)
    hint = start if hint is None else hint
    a_min = gallop(lambda x: ok(x, hi[1]), lo[0], a, hint[0])
    b_floor = gallop(lambda y: ok(hi[0], y), lo[1], b, hint[1])
    a, b = a_min, gallop(lambda y: ok(a_min, y), b_floor, hi[1], b_floor)
    while True:
        if b > b_floor and ok(a, b - 1):
            b = gallop(lambda y, x=a: ok(x, y), b_floor, b - 1, b - 1)
        if a * b < best[0] * best[1]:
            best = (a, b)
        if a >= hi[0] or (a + 1) * b_floor >= best[0] * best[1]:
            return best, True
        a += 1


def predicted_hint(value: float, t: float, shape: tuple[int, int], degrees, lo: tuple[int, int]) -> tuple[int, int]:
    """Where a direction's frontier end is expected from one value: a fit's error falls as ``n^-(p+1)``
    (degree ``p``), so ``value`` at ``shape`` reaches ``t`` near ``n (value / t)^(1 / (p + 1))`` points per
    direction (each on its own, the other kept at ``shape``). A hint for :func:`frontier`'s gallops, which
    then start near the answer instead of at today's density (a 100x100 net advised 14x9 tried 99, 97, 93,
    85, 69, 37, 20 points before): never more than ``shape``, never less than ``lo``."""
    if not (value > 0.0) or not np.isfinite(value) or t <= 0.0:
        return tuple(int(l) for l in lo)
    ratio = min(1.0, value / t)
    return tuple(int(min(n, max(l, math.ceil(n * ratio ** (1.0 / (max(int(p), 0) + 1)) - 1e-9))))
                 for n, p, l in zip(shape, degrees, lo))


#: Largest advised density per direction, as a multiple of today's (and an absolute cap).
GROWTH, MAX_POINTS = 8, 2000


def _limits(work: ControlNet, degrees, plans=(None, None)) -> tuple[tuple[int, int], tuple[int, int]]:
    """Search bounds per direction; a straight degree-1 direction is never advised more points than today's
    (it carries no ripple and more points cannot make it straighter); a direction keeping its joins
    (:class:`cadartifact.advice.joins.JoinPlan`) needs a span per piece."""
    low = tuple(d + 1 if plan is None else plan.min_points(d) for d, plan in zip(degrees, plans))
    high = [max(l + 1, min(MAX_POINTS, GROWTH * n)) for l, n in zip(low, work.shape)]
    for k in (0, 1):
        if work.is_bspline and work.degrees[k] == 1 and _straight(work.points, k):
            high[k] = max(low[k], work.shape[k])
    return low, tuple(high)


def _straight(points: np.ndarray, axis: int, rtol: float = 1e-9) -> bool:
    """Whether every row of control points along ``axis`` lies on one line (relative to the net's size)."""
    P = np.moveaxis(np.asarray(points, float), axis, 0)  # (n, m, 3)
    d = P[-1] - P[0]  # (m, 3)
    rel = P - P[0]
    norm = np.linalg.norm(d, axis=-1)
    size = float(np.ptp(P.reshape(-1, 3), axis=0).max())
    unit = np.where(norm[:, None] > 0, d / np.where(norm > 0, norm, 1.0)[:, None], 0.0)
    off = rel - (rel * unit).sum(-1, keepdims=True) * unit
    return bool(np.linalg.norm(off, axis=-1).max() <= rtol * size)
