"""The face is what its trim keeps (SPEC §4): the spans of a surface its trimmed face uses.

Exports often extend a surface by a few per cent beyond its trim and join the extension with a knot of
multiplicity ``p``. Spans wholly outside the face's uv bounds are no part of the face: the analysis and the
advice work on the surface cut down to the spans the trim touches (:func:`used_net`), exactly the same surface
there (knot insertion to multiplicity ``p`` at each cut, then the poles between the cuts).

A trim that reaches past a join (a knot of multiplicity ``>= p``) by less than the tolerance in model units, or
past any knot by less than :data:`ROUNDING` of the range (rounding: real exports show 1e-9), counts as not
reaching it: the span beyond is dropped.

Periodic directions are left whole here (a trim across the seam would need the unrolled direction); a periodic
direction opened at a junction (:func:`cadartifact.analysis.pieces.split_net`) with a trim across the opening
keeps both parts: the piece's ``trim_gaps`` leave out what lies between them.

A face read under another scheme is a cage of its poles (pole ``i`` at index ``i``): its trim is carried over as
the uv bounds mapped through the Greville abscissae of its knots (:func:`cage_bounds`), in the cage's index
coordinates, so the foreign scheme's reading covers the same part of the face.

References
----------
L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997, §5.2 (knot insertion, algorithm A5.1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..net import ControlNet, knot_runs, lifted

__all__ = ["UsedRegion", "used_net", "insert_knot", "crop_direction", "cage_bounds"]

#: Share of a direction's parameter range a trim may overshoot a knot and still count as stopping there.
ROUNDING = 1e-7


@dataclass(frozen=True)
class UsedRegion:
    """What a trimmed face uses of its surface.

    Attributes
    ----------
    ranges : ((float, float), (float, float))
        Per direction ``(u, v)``, the parameter interval kept (knot values).
    full : ((float, float), (float, float))
        The surface's whole parameter interval per direction.
    outside : (float, float)
        Per direction, the share of the surface's parameter range outside the kept interval.
    share : float
        Share of the parameter area ``1 - (1 - outside_u)(1 - outside_v)`` outside the face.
    """

    ranges: tuple
    full: tuple
    outside: tuple
    share: float

    def to_dict(self) -> dict:
        return {"u": float(self.outside[0]), "v": float(self.outside[1]), "share": float(self.share)}


def insert_knot(knots: np.ndarray, P: np.ndarray, degree: int, u: float, times: int = 1):
    """Insert ``u`` into a clamped open direction ``times`` times (Boehm; same surface).

    Parameters
    ----------
    knots : (n + p + 1,) float
    P : (n, ...) float
        Poles along axis 0 (homogeneous ``(w P, w)`` for a rational net: insertion is linear there).
    degree : int
    u : float
        Strictly inside the parameter range.
    times : int

    Returns
    -------
    (knots, P) : ((n + p + 1 + times,) float, (n + times, ...) float)

    Notes
    -----
    With ``t_k <= u < t_{k+1}`` and ``s`` the multiplicity of ``u``:
    ``Q_i = a_i P_i + (1 - a_i) P_{i-1}``, ``a_i = (u - t_i) / (t_{i+p} - t_i)`` for ``k-p+1 <= i <= k-s``,
    ``Q_i = P_i`` before and ``P_{i-1}`` after.
    """
    t = np.asarray(knots, float)
    P = np.asarray(P, float)
    p = int(degree)
    for _ in range(int(times)):
        k = int(np.searchsorted(t, u, side="right")) - 1
        s = int(np.sum(np.abs(t - u) <= 1e-12 * max(1.0, abs(u))))
        n = len(P)
        Q = np.empty((n + 1,) + P.shape[1:])
        Q[: k - p + 1] = P[: k - p + 1]
        Q[k - s + 1:] = P[k - s:]
        for i in range(k - p + 1, k - s + 1):
            a = (u - t[i]) / (t[i + p] - t[i])
            Q[i] = a * P[i] + (1.0 - a) * P[i - 1]
        t = np.insert(t, k + 1, u)
        P = Q
    return t, P


def crop_direction(knots: np.ndarray, P: np.ndarray, degree: int, lo: float, hi: float):
    """The clamped direction over ``[lo, hi]`` (knot values inside the range): ``(knots, poles)``, the same
    surface there."""
    t, p = np.asarray(knots, float), int(degree)
    scale = max(1.0, float(np.abs(t).max()))
    for cut in (lo, hi):
        if t[p] + 1e-12 * scale < cut < t[len(t) - p - 1] - 1e-12 * scale:
            m = int(np.sum(np.abs(t - cut) <= 1e-12 * scale))
            if m < p:
                t, P = insert_knot(t, P, p, cut, p - m)
    close = lambda v: np.abs(t - v) <= 1e-12 * scale  # noqa: E731
    j = int(np.flatnonzero(close(lo))[-1]) - p + 1  # t[j .. j+p-1] = lo: pole j-1 is interpolated there
    k = int(np.flatnonzero(close(hi))[0])  # t[k .. k+p-1] = hi: pole k-1
    Pc = P[j - 1: k]
    tc = np.array(t[j - 1: k + p + 1], float)
    tc[: p + 1], tc[-(p + 1):] = lo, hi
    return tc, Pc


def _past(net: ControlNet, axis: int, bound: float, knot: float, other: tuple) -> float:
    """Largest distance (model units) between the surface at ``bound`` and at ``knot`` along ``axis``, over the
    other direction's kept range: how far a trim's overshoot of a knot reaches in the model."""
    from ..numerics.splines import evaluate

    s = np.linspace(other[0], other[1], 9)
    a, b = np.array([bound, knot], float), s
    S = evaluate(net, a, b) if axis == 0 else np.swapaxes(evaluate(net, b, a), 0, 1)
    return float(np.linalg.norm(S[0] - S[1], axis=-1).max())


def _range(net: ControlNet, axis: int, b0: float, b1: float, other, tolerance) -> tuple[float, float]:
    """The knot interval a trim ``[b0, b1]`` touches along ``axis``, with overshoots below the tolerance
    (model units) or :data:`ROUNDING` of the range dropped."""
    p, n = net.degrees[axis], net.shape[axis]
    t = np.asarray(net.knots[axis], float)
    lo_all, hi_all = float(t[p]), float(t[n])
    scale = max(1.0, float(np.abs(t).max()))
    runs = [(v, m) for v, _, m in knot_runs(t, scale) if lo_all <= v <= hi_all]
    values = [v for v, _ in runs]
    joins = {v for v, m in runs if m >= p and lo_all < v < hi_all}
    rounding = ROUNDING * (hi_all - lo_all)

    def short(bound, knot):
        """An overshoot that counts as not reaching ``knot``: rounding anywhere; less than the tolerance (model
        units) past a join (SPEC §4: an extension's join), where the new surface may end short of the trim's
        pcurves by that much."""
        if abs(knot - bound) <= rounding:
            return True
        return tolerance is not None and knot in joins and _past(net, axis, bound, knot, other) < tolerance

    b0, b1 = max(b0, lo_all), min(b1, hi_all)
    if b1 <= b0:
        return lo_all, hi_all
    lo = max(v for v in values if v <= b0 + 1e-12 * scale)
    hi = min(v for v in values if v >= b1 - 1e-12 * scale)
    nxt = min((v for v in values if v > lo + 1e-12 * scale), default=hi)
    if lo < b0 and nxt < hi and short(b0, nxt):
        lo = nxt
    prv = max((v for v in values if v < hi - 1e-12 * scale), default=lo)
    if hi > b1 and prv > lo and short(b1, prv):
        hi = prv
    return lo, hi


def used_net(net: ControlNet, tolerance: float | None = None) -> tuple[ControlNet, UsedRegion | None]:
    """The surface cut down to the spans its trimmed face uses.

    Parameters
    ----------
    net : ControlNet
        A B-spline face (a cage, or a face without uv bounds, is returned as is).
    tolerance : float, optional
        Model units: a trim past a join by less than this counts as stopping at the join.

    Returns
    -------
    (net, region) : (ControlNet, UsedRegion or None)
        ``net`` itself when nothing lies outside the trim (``region`` then None or with zero shares);
        else a new clamped net over the kept knot intervals (same degrees, weights, uv bounds, origin).
    """
    if not net.is_bspline or net.uv_bounds is None:
        return net, None
    u0, u1, v0, v1 = (float(b) for b in net.uv_bounds)
    full, ranges = [], []
    for axis in (0, 1):
        t, p, n = np.asarray(net.knots[axis], float), net.degrees[axis], net.shape[axis]
        full.append((float(t[p]), float(t[len(t) - p - 1]) if net.periodic[axis] else float(t[n])))
    for axis, (b0, b1) in enumerate(((u0, u1), (v0, v1))):
        if net.periodic[axis]:
            ranges.append(full[axis])
            continue
        other = full[1 - axis] if net.periodic[1 - axis] else (
            max(full[1 - axis][0], (v0, u0)[axis]), min(full[1 - axis][1], (v1, u1)[axis]))
        if other[1] <= other[0]:
            other = full[1 - axis]
        ranges.append(_range(net, axis, b0, b1, other, tolerance))
    outside = tuple(1.0 - (r[1] - r[0]) / (f[1] - f[0]) if f[1] > f[0] else 0.0 for r, f in zip(ranges, full))
    region = UsedRegion(tuple(ranges), tuple(full), outside, 1.0 - (1.0 - outside[0]) * (1.0 - outside[1]))
    if all(o <= 0.0 for o in outside):
        return net, region
    P = lifted(net)
    knots = list(net.knots)
    for axis in (0, 1):
        if outside[axis] <= 0.0:
            continue
        moved = np.moveaxis(P, axis, 0)
        knots[axis], moved = crop_direction(knots[axis], moved, net.degrees[axis], *ranges[axis])
        P = np.moveaxis(moved, 0, axis)
    if net.weights_vary:
        w = P[..., 3]
        points, weights = P[..., :3] / w[..., None], w
    else:
        points = P
        weights = None if net.weights is None else np.full(P.shape[:2], float(np.asarray(net.weights).flat[0]))
    return net.replace(points=points, weights=weights, knots=tuple(knots)), region


def cage_bounds(net: ControlNet) -> tuple[float, float, float, float] | None:
    """A trimmed face's uv bounds in the index coordinates of its poles read as a cage (another scheme's net).

    Along an open direction the parameter ``u`` maps to ``x`` by interpolating the pole indices over the
    Greville abscissae ``xi_i = (t_{i+1} + ... + t_{i+p}) / p`` (the parameter each pole stands for); a periodic
    direction is kept whole (``0`` to ``n``). None for a cage, a face without uv bounds, or one whose bounds
    cover its surface.
    """
    if not net.is_bspline or net.uv_bounds is None:
        return None
    out, trimmed = [], False
    for axis in (0, 1):
        t, p, n = np.asarray(net.knots[axis], float), int(net.degrees[axis]), net.shape[axis]
        if net.periodic[axis] or p < 1:
            out += [0.0, float(n - (0 if net.periodic[axis] else 1))]
            continue
        lo, hi = float(t[p]), float(t[n])
        b0, b1 = (float(b) for b in net.uv_bounds[2 * axis: 2 * axis + 2])
        scale = ROUNDING * max(hi - lo, 1e-300)
        trimmed = trimmed or b0 > lo + scale or b1 < hi - scale
        xi = np.array([t[i + 1: i + p + 1].mean() for i in range(n)])
        idx = np.arange(n, dtype=float)
        out += [float(np.interp(max(b0, lo), xi, idx)), float(np.interp(min(b1, hi), xi, idx))]
    return tuple(out) if trimmed else None
