"""The density search: fewest points ``n'u n'v`` on a monotone feasibility predicate (SPEC §5).

The error of a candidate falls as either density rises (the band structure); the search walks the
frontier ``n'v(n'u)`` of the feasible region, galloping from a hint (today's density), so an answer near
the hint costs a few evaluations. Property tests check it against brute force (``tests/test_advice.py``).
"""

from __future__ import annotations

__all__ = ["frontier", "gallop", "first_true"]


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


def frontier(ok, lo: tuple[int, int], hi: tuple[int, int], start: tuple[int, int]) -> tuple[tuple[int, int], bool]:
    """Fewest-points feasible density on the frontier ``n'v(n'u)``; ``(shape, reachable)``.

    A feasible corner is found by doubling from ``start``; the frontier's ends are the smallest
    ``n'u`` feasible with ``n'v`` at the corner and the smallest ``n'v`` with ``n'u`` there; from the
    first, each step adds one ``u`` point and lowers ``n'v`` while the predicate holds (galloping),
    until ``n'u`` times the smallest ``n'v`` cannot beat the best. Exact for a predicate monotone in
    both directions within the corner's box.
    """
    a, b = (max(l, min(h, s)) for l, h, s in zip(lo, hi, start))
    while not ok(a, b):
        if a >= hi[0] and b >= hi[1]:
            return (a, b), False
        a, b = min(hi[0], 2 * a), min(hi[1], 2 * b)
    best = (a, b)
    hi = (a, b)
    a_min = gallop(lambda x: ok(x, hi[1]), lo[0], a, start[0])
    b_floor = gallop(lambda y: ok(hi[0], y), lo[1], b, start[1])
    a, b = a_min, gallop(lambda y: ok(a_min, y), b_floor, hi[1], b_floor)
    while True:
        if b > b_floor and ok(a, b - 1):
            b = gallop(lambda y, x=a: ok(x, y), b_floor, b - 1, b - 1)
        if a * b < best[0] * best[1]:
            best = (a, b)
        if a >= hi[0] or (a + 1) * b_floor >= best[0] * best[1]:
            return best, True
        a += 1

