"""How close a face comes to itself away from its own neighbourhood: self-intersection (VDA 4955 G-SU-IS;
ModelCHECK C7_SELF_DIST "distance from itself", 0.020 mm).

A coarse screen, then an exact follow-up where it fires:

1. **Screen.** The face's samples (:func:`cadartifact.analysis.face_samples.sample_face`), thinned evenly in
   index to at most :data:`GRID` per direction. Two samples are a candidate pair when they are closer in space
   than the longer of their grid edges (``h``) while the path between them *on the surface* is long: the
   polyline through the grid along the straight index line from one to the other is longer than
   ``DETOUR * (d + h)``. Neighbours on a smooth face have a path about as long as their distance; two sheets
   that cross, or a fold pressed flat, have a long way round between points that are close in space. A
   direction whose first and last rows coincide (a closed surface, a periodic one over a full period) is
   walked the shorter way round (its last row left out: the first's points); an edge collapsed to a point
   keeps one sample.
2. **Follow-up.** From each of the closest candidate pairs, Gauss-Newton on ``min |S(u1, v1) - S(u2, v2)|^2``
   (the Jacobian ``[S_u1, S_v1, -S_u2, -S_v2]``, its least-squares step, parameters kept in the trim box) to the
   nearest pair of points near them: 0 where the sheets cross (a point of the intersection curve), the gap
   where they only come close. The value is the smallest, at the midpoint of its pair.

A self-intersection whose loop on the face is shorter than a few grid steps (about 3/32 of the face in either
direction) can be missed by the screen: the follow-up is exact, the screen is not.

References: VDA 4955 v4.1 (2006), G-SU-IS; PTC Creo ModelCHECK, *C7_SELF_DIST (Distance from Itself)*;
J. Nocedal, S. Wright, *Numerical Optimization*, 2nd ed., 2006, §10.3 (Gauss-Newton).
"""

from __future__ import annotations

import numpy as np

from .face_samples import Measured, sample_face, trim_box

__all__ = ["GRID", "DETOUR", "MAX_PAIRS", "self_distance"]

#: Samples per direction of the screen.
GRID = 32
#: A pair is "far on the surface" when its path is this many times longer than its distance plus h.
DETOUR = 3.0
#: Close pairs examined for their path, closest first (a bound on the screen's cost; the detail says so).
MAX_PAIRS = 2000


def _closed(S: np.ndarray, axis: int, size: float) -> bool:
    first, last = (S[0], S[-1]) if axis == 0 else (S[:, 0], S[:, -1])
    return float(np.linalg.norm(first - last, axis=-1).max()) <= 1e-9 * max(size, 1e-300)


def _paths(S: np.ndarray, p: np.ndarray, q: np.ndarray, closed) -> np.ndarray:
    """(k,) lengths of the polylines through the grid along the index lines from ``p[k]`` to ``q[k]`` ((k, 2) grid
    indices; the shorter way round a closed direction)."""
    a, b = S.shape[:2]
    if not len(p):
        return np.zeros(0)
    steps = []
    for k, n in enumerate((a, b)):
        d = q[:, k] - p[:, k]
        if closed[k]:  # rows 0 and n - 1 are one: n - 1 distinct rows around
            m = n - 1
            d = (d + m // 2) % m - m // 2
        steps.append(d)
    count = np.maximum(np.abs(steps[0]), np.abs(steps[1]))
    t = np.minimum(np.arange(int(count.max()) + 1)[None, :] / np.maximum(count, 1)[:, None], 1.0)  # (k, L)
    i = np.round(p[:, :1] + t * steps[0][:, None]).astype(int)
    j = np.round(p[:, 1:] + t * steps[1][:, None]).astype(int)
    i = i % (a - 1) if closed[0] else np.clip(i, 0, a - 1)
    j = j % (b - 1) if closed[1] else np.clip(j, 0, b - 1)
    return np.linalg.norm(np.diff(S[i, j], axis=1), axis=-1).sum(axis=1)


def _refine(net, box, x: np.ndarray, iterations: int = 30) -> tuple[np.ndarray, float]:
    """Gauss-Newton on ``|S(x[0], x[1]) - S(x[2], x[3])|^2`` from ``x``, kept in the box."""
    lo = np.array([box[0], box[2], box[0], box[2]])
    hi = np.array([box[1], box[3], box[1], box[3]])
    for _ in range(iterations):
        a = sample_face(net, x[[0]], x[[1]])
        b = sample_face(net, x[[2]], x[[3]])
        r = a.S[0, 0] - b.S[0, 0]
        J = np.stack([a.Su[0, 0], a.Sv[0, 0], -b.Su[0, 0], -b.Sv[0, 0]], axis=1)  # (3, 4)
        step = np.linalg.lstsq(J, -r, rcond=None)[0]
        x = np.clip(x + step, lo, hi)
        if np.linalg.norm(step) <= 1e-14 * (1.0 + np.linalg.norm(x)):
            break
    a = sample_face(net, x[[0]], x[[1]]).S[0, 0]
    b = sample_face(net, x[[2]], x[[3]]).S[0, 0]
    return x, float(np.linalg.norm(a - b))


def self_distance(face) -> Measured:
    """The smallest distance between two parts of the face that are far apart on it (0: it intersects itself)."""
    fs, net = face.samples, face.net
    iu = np.unique(np.linspace(0, len(fs.u) - 1, min(GRID, len(fs.u))).round().astype(int))
    iv = np.unique(np.linspace(0, len(fs.v) - 1, min(GRID, len(fs.v))).round().astype(int))
    S = fs.S[np.ix_(iu, iv)]
    a, b = S.shape[:2]
    size = float(np.linalg.norm(S.reshape(-1, 3).max(axis=0) - S.reshape(-1, 3).min(axis=0)))
    closed = (_closed(S, 0, size), _closed(S, 1, size))
    # h: each sample's longest grid edge
    eu = np.linalg.norm(np.diff(S, axis=0), axis=-1)
    ev = np.linalg.norm(np.diff(S, axis=1), axis=-1)
    h = np.zeros((a, b))
    h[:-1] = np.maximum(h[:-1], eu)
    h[1:] = np.maximum(h[1:], eu)
    h[:, :-1] = np.maximum(h[:, :-1], ev)
    h[:, 1:] = np.maximum(h[:, 1:], ev)
    keep = np.ones((a, b), bool)
    if closed[0]:
        keep[-1] = False  # the same points as row 0
    if closed[1]:
        keep[:, -1] = False
    for edge in ((0, None), (-1, None), (None, 0), (None, -1)):  # an edge collapsed to a point: one sample of it
        row = S[edge[0]] if edge[0] is not None else S[:, edge[1]]
        if np.linalg.norm(row - row[0], axis=-1).max() <= 1e-9 * max(size, 1e-300):
            if edge[0] is not None:
                keep[edge[0], 1:] = False
            else:
                keep[1:, edge[1]] = False
    flat = np.flatnonzero(keep.ravel())
    P, H = S.reshape(-1, 3)[flat], h.ravel()[flat]
    idx = np.stack(np.unravel_index(flat, (a, b)), axis=1)
    sq = (P * P).sum(axis=1)
    found = []
    for s0 in range(0, len(P), 512):  # all pairs, in blocks (at most GRID^4 / 2 distances)
        d2 = sq[s0:s0 + 512, None] + sq[None, :] - 2.0 * P[s0:s0 + 512] @ P.T
        reach = np.maximum(H[s0:s0 + 512, None], H[None, :])
        p, q = np.nonzero(d2 < reach * reach)
        keep = (s0 + p < q) & (np.abs(idx[s0 + p] - idx[q]).max(axis=1) >= 3)  # each pair once, 3 steps apart
        p, q = p[keep], q[keep]
        found.append(np.stack([s0 + p, q], axis=1))
    pq = np.concatenate(found) if found else np.zeros((0, 2), int)
    d = np.linalg.norm(P[pq[:, 0]] - P[pq[:, 1]], axis=-1)
    total = len(pq)
    order = np.argsort(d, kind="stable")[:MAX_PAIRS]
    pq, d = pq[order], d[order]
    far = _paths(S, idx[pq[:, 0]], idx[pq[:, 1]], closed) > DETOUR * (d + np.maximum(H[pq[:, 0]], H[pq[:, 1]]))
    tried, best = 0, None
    for p, q in pq[far]:
        pi, qi = idx[p], idx[q]
        tried += 1
        x0 = np.array([fs.u[iu[pi[0]]], fs.v[iv[pi[1]]], fs.u[iu[qi[0]]], fs.v[iv[qi[1]]]])
        x, dist = _refine(net, trim_box(net), x0)
        if best is None or dist < best[0]:
            best = (dist, x)
        if tried >= 8:
            break
    screen = (f"screen: {a} x {b} samples, {total} close pair(s)"
              + (f" (the {MAX_PAIRS} closest examined)" if total > MAX_PAIRS else "")
              + f", {tried} far apart on the face")
    if best is None:
        return Measured(np.inf, detail=f"no two parts of the face come close ({screen})")
    dist, x = best
    mid = 0.5 * (sample_face(net, x[[0]], x[[1]]).S[0, 0] + sample_face(net, x[[2]], x[[3]]).S[0, 0])
    return Measured(dist, (x[0], x[1]), mid, detail=f"closest approach {dist:.4g} between uv ({x[0]:.6g}, "
                                                     f"{x[1]:.6g}) and ({x[2]:.6g}, {x[3]:.6g}) ({screen})")
