"""Advice keeps the face's joins (SPEC §5 "Joins are kept").

A face whose knots have interior multiplicity ``m >= p`` (a deliberate G1/C0 join) is advised with its joins:
the candidate of ``n'`` points along such a direction has the same join knots at the same multiplicity and
uniform knots within each piece. One count per direction is searched; its spans are shared among the pieces in
proportion to today's spans of each piece (at least one each), so the density search stays two-dimensional:

    n' = p + S + J (m - 1),    S = sum_k S_k,    S_k ~ S s_k / sum(s),

``J`` the joins, ``s_k`` today's spans of piece ``k``. From the count found, each piece's spans are then
searched on their own (:mod:`.per_piece`): the advice is whichever of the two plans has fewer points within the
tolerance. One uniform net across a crease cannot carry it, and the search never tries to.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.fitting import CandidateAxis, _fit_operator
from ..analysis.frames import AxisFrame
from ..net import ControlNet, bezier_direction, knot_multiplicities
from ..numerics.operator_cache import OperatorCache
from ..numerics.splines import basis_matrix

__all__ = ["JoinPlan", "join_plan", "jointed_axis", "jointed_knots", "piece_spans", "smooth_join"]

#: A direction with more joins than this is advised with one uniform net (as before joins were kept).
MAX_JOINS = 40


@dataclass(frozen=True)
class JoinPlan:
    """The joins of one open direction of a face.

    Attributes
    ----------
    joins : tuple of float
        Interior knot values of multiplicity ``>= p``.
    mult : int
        Their multiplicity in the candidates (``min(m, p)`` of today's: the largest of them).
    spans : tuple of int
        Today's spans of each piece (``len(joins) + 1``): the proportions the candidate's spans follow.
    lo, hi : float
        The direction's parameter range.
    fixed : tuple of int, optional
        A candidate's own spans per piece (found piece by piece, :mod:`.per_piece`): a candidate of that many
        spans in all has exactly these; of another count, its spans in proportion to these. None: in proportion
        to today's (``spans``).
    demand : tuple of float, optional
        Per piece, how much its poles bend (:func:`piece_demand`): which piece gets a span that proportions leave
        to a tie (two equal pieces, an odd count), so that a mirrored or reversed face gets the mirrored candidate
        (the order of the pieces would give the span to whichever comes first).
    """

    joins: tuple
    mult: int
    spans: tuple
    lo: float
    hi: float
    fixed: tuple | None = None
    demand: tuple | None = None

    @property
    def extra(self) -> int:
        """Knots the joins add beyond one per join: ``J (m - 1)``."""
        return len(self.joins) * (self.mult - 1)

    def per(self, total: int) -> list[int]:
        """A candidate's spans per piece for ``total`` spans in all (``fixed`` or today's in proportion)."""
        return piece_spans(total, self.fixed if self.fixed is not None else self.spans, self.demand)

    def min_points(self, degree: int) -> int:
        """Fewest points of a candidate that keeps the joins (one span per piece)."""
        return degree + len(self.spans) + len(self.joins) * (self.mult - 1)

    def to_dict(self) -> dict:
        return {"joins": [float(j) for j in self.joins], "multiplicity": int(self.mult),
                "today_spans": [int(s) for s in self.spans]}


def join_plan(net: ControlNet, axis: int) -> JoinPlan | None:
    """The :class:`JoinPlan` of a direction, or None (a cage, periodic, no join, every span a piece, too many).

    A join is an interior knot of multiplicity ``> p``, or ``p`` where the surface is not G2 across it
    (:func:`smooth_join`): a crease or a G1 join. A smooth surface written piecewise is not held to its knots, nor
    is a direction of mostly one-span pieces (fewer than 1.5 spans per piece on average: a chain written
    piecewise, like a piecewise-Bezier direction, advised one uniform net as before) or of more than
    :data:`MAX_JOINS` joins."""
    if not net.is_bspline or net.periodic[axis]:
        return None
    t, p, n = np.asarray(net.knots[axis], float), int(net.degrees[axis]), net.shape[axis]
    if p < 1 or bezier_direction(t, p, n, False):
        return None
    mults = knot_multiplicities(t, p, n, False)
    joins = [(v, m) for v, m in mults if m >= p and not (m == p and smooth_join(net, axis, v))]
    if not joins or len(joins) > MAX_JOINS:
        return None
    lo, hi = float(t[p]), float(t[n])
    edges = [lo] + [v for v, _ in joins] + [hi]
    spans = tuple(max(1, sum(1 for v, _ in mults if a < v < b) + 1) for a, b in zip(edges[:-1], edges[1:]))
    if 3 * len(spans) > 2 * sum(spans):  # mostly one-span pieces: a chain written piecewise, not a few joins
        return None
    return JoinPlan(tuple(float(v) for v, _ in joins), min(p, max(m for _, m in joins)), spans, lo, hi,
                    demand=piece_demand(net, axis, edges))


def piece_demand(net: ControlNet, axis: int, edges) -> tuple:
    """Per piece between consecutive ``edges``: the summed length of the second differences of the poles along
    ``axis`` whose Greville abscissae lie in it, ``sum |P[i-1] - 2 P[i] + P[i+1]|``. The same numbers for the face
    moved, mirrored, transposed or reversed (the pieces then reversed): a tie-break that follows the geometry, not
    the order of the pieces."""
    P = np.moveaxis(np.asarray(net.points, float), axis, 0)
    bend = np.zeros(len(P))
    bend[1:-1] = np.linalg.norm(P[:-2] - 2 * P[1:-1] + P[2:], axis=-1).sum(axis=1)
    g = net.greville()[axis]
    eps = 1e-9 * (edges[-1] - edges[0])
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        inside = (g > a + eps) & (g < b - eps)
        on_edge = (np.abs(g - a) <= eps) | (np.abs(g - b) <= eps)  # a pole on a join: half to either side
        out.append(float(bend[inside].sum() + 0.5 * bend[on_edge].sum()))
    scale = max(max(out), 1e-300)
    return tuple(round(x / scale, 9) for x in out)  # rounded: the reversed face's sums agree to the last digits


#: A join is smooth when the unit tangents either side differ by at most this (radians) and the curvature vectors
#: by at most ten times this share of the larger (or of 1 / the face's size).
G2_RTOL = 1e-4


def smooth_join(net: ControlNet, axis: int, value: float) -> bool:
    """Whether the surface is geometrically smooth (G2) across the knot ``value`` along ``axis``: a smooth surface
    written with a knot of multiplicity ``p`` (piecewise Bezier, a sweep in pieces), which a uniform net may
    cross. A crease (tangent jump) or a G1 join (curvature jump) is not smooth.

    One-sided second-order differences at the join (``d = 1e-3`` of the shorter neighbouring span) give
    ``S'`` and ``S''`` either side along 9 isocurves of the other direction; the unit tangent ``T = S'/|S'|``
    and the curvature vector ``k = (S'' - (S''.T) T) / |S'|^2`` are compared (:data:`G2_RTOL`).
    """
    from ..numerics.splines import evaluate

    t, p, n = np.asarray(net.knots[axis], float), net.degrees[axis], net.shape[axis]
    distinct = np.unique(t[p: n + 1])
    k = int(np.argmin(np.abs(distinct - value)))
    if k == 0 or k == len(distinct) - 1:
        return False
    d = 1e-3 * min(distinct[k] - distinct[k - 1], distinct[k + 1] - distinct[k])
    a = value + d * np.arange(-3, 4)
    o = np.asarray(net.knots[1 - axis], float)
    q, m = net.degrees[1 - axis], net.shape[1 - axis]
    lo, hi = o[q], (o[m + q] if net.periodic[1 - axis] else o[m])
    S = evaluate(net, a, np.linspace(lo, hi, 9)) if axis == 0 else np.swapaxes(
        evaluate(net, np.linspace(lo, hi, 9), a), 0, 1)
    size = float(np.ptp(np.asarray(net.points).reshape(-1, 3), axis=0).max())

    def side(s0, s1, s2, s3, sign):
        d1 = sign * (-3 * s0 + 4 * s1 - s2) / (2 * d)
        d2 = (2 * s0 - 5 * s1 + 4 * s2 - s3) / d ** 2
        speed = np.linalg.norm(d1, axis=-1, keepdims=True)
        T = d1 / np.maximum(speed, 1e-300)
        kv = (d2 - np.sum(d2 * T, axis=-1, keepdims=True) * T) / np.maximum(speed, 1e-300) ** 2
        return T, kv

    TL, kL = side(S[3], S[2], S[1], S[0], -1.0)
    TR, kR = side(S[3], S[4], S[5], S[6], 1.0)
    if np.linalg.norm(TL - TR, axis=-1).max() > G2_RTOL:
        return False
    scale = max(float(np.linalg.norm(kL, axis=-1).max()), float(np.linalg.norm(kR, axis=-1).max()),
                1.0 / max(size, 1e-300))
    return bool(np.linalg.norm(kL - kR, axis=-1).max() <= 10 * G2_RTOL * scale)


def piece_spans(total: int, weights, demand=None) -> list[int]:
    """``total`` spans shared among pieces in proportion to ``weights`` (at least one each; largest remainders; a
    tie goes to the piece of the larger ``demand``, then the first)."""
    w = np.asarray(weights, float)
    k = len(w)
    total = max(int(total), k)
    raw = total * w / w.sum()
    need = np.zeros(k) if demand is None else np.asarray(demand, float)
    out = np.maximum(1, np.floor(raw)).astype(int)
    while out.sum() > total:  # the ones raised to 1 took spans from the others
        over = np.round(np.where(out > 1, out - raw, -np.inf), 9)
        i = int(np.lexsort((np.arange(k), need, -over))[0])
        out[i] -= 1
    order = np.lexsort((np.arange(k), -need, -np.round(raw - np.floor(raw), 9)))
    i = 0
    while out.sum() < total:
        out[order[i % k]] += 1
        i += 1
    return [int(s) for s in out]


def jointed_knots(n_new: int, degree: int, plan: JoinPlan) -> np.ndarray:
    """The candidate's flat knots: clamped, the joins at ``plan.mult``, uniform within each piece."""
    p = int(degree)
    per = plan.per(n_new - p - plan.extra)
    edges = [plan.lo, *plan.joins, plan.hi]
    t = [plan.lo] * (p + 1)
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        t.extend(np.linspace(a, b, per[k] + 1)[1:-1])
        t.extend([b] * (plan.mult if k < len(per) - 1 else p + 1))
    return np.asarray(t, float)


_CACHE = OperatorCache(256)


def jointed_axis(frame: AxisFrame, n_new: int, degree: int, K: int, plan: JoinPlan) -> CandidateAxis:
    """The (cached) :class:`~cadartifact.analysis.fitting.CandidateAxis` of ``n_new`` points keeping the joins.

    The check grid is uniform within each piece, ``K`` samples per span of the finer of today's piece and the
    candidate's (a join's sample shared): a narrow piece (an extension of a few per cent) is sampled as finely
    as a wide one, so that its poles are fitted and its error measured (a grid even over the whole direction
    left a 0.5 % extension without a sample inside it: its poles undetermined and its error unseen).
    """
    key = (frame.n, frame.spans, frame.u0, frame.h, n_new, degree, K, plan)

    def build():
        p = int(degree)
        t = jointed_knots(n_new, p, plan)
        per = plan.per(n_new - p - plan.extra)
        edges = [plan.lo, *plan.joins, plan.hi]
        parts = []
        for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
            u = np.linspace(a, b, K * max(per[k], plan.spans[k]) + 1)
            parts.append(u if k == 0 else u[1:])
        x = (np.concatenate(parts) - frame.u0) / frame.h
        B = basis_matrix(t, p, frame.param(x), n_new, False)
        return CandidateAxis(n_new, p, t, x, B, _fit_operator(B, False))

    return _CACHE.get(key, build)
