"""Candidate nets: the best net of a density for the design intent (SPEC §5).

A candidate of ``n'u x n'v`` points keeps the face's degrees (clipped to ``n' - 1``), its
parameter range and periodicity, with new uniform knots; its control points are the least-squares
fit of the intent on a check grid fine enough for both nets (``K`` samples per span of the finer),
its end poles on today's border (so corners stay and border curves are fits of today's):

    Q = Fu I Fv^T,   E = Bu Q Bv^T - I,

``B`` the candidate's B-spline basis at the grid's parameters, ``I`` the intent there, ``F`` the
fit (``pinv(B)`` periodic; open: end rows fixed, the rest ``pinv(B[:, 1:-1])`` of what they leave). ``E`` is the
error no placement of ``n'u x n'v`` points can remove in the least-squares sense: the candidate's
ripple, the detail lost above its Nyquist limit, and what the fit leaves (SPEC §5). Sampling the
intent at the new points instead (the old construction) leaves the whole attenuation in the
surface.

References
----------
L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997, §9.4 (least-squares surface
approximation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .frames import AxisFrame, fine_positions
from ..net import ControlNet, clamped_uniform_knots
from ..numerics.operator_cache import OperatorCache
from ..numerics.splines import basis_matrix
from ..numerics.tensor import sandwich

__all__ = ["CandidateAxis", "candidate_axis", "check_count", "candidate_net", "fit_points", "uniform_knots",
           "curve_distance", "fit_error", "error_planes"]


def uniform_knots(n: int, degree: int, lo: float, hi: float, periodic: bool) -> np.ndarray:
    """Uniform clamped knots over ``[lo, hi]`` (periodic: the ``n + 2p + 1`` flat sequence)."""
    if periodic:
        h = (hi - lo) / n
        return lo + h * (np.arange(n + 2 * degree + 1) - degree)
    return clamped_uniform_knots(n, degree, lo, hi)


def check_count(frame: AxisFrame, n_new: int, degree: int, K: int) -> int:
    """Samples of the check grid along one direction: ``K`` per span of the finer of the two nets; for a candidate
    of degree 1, rounded up so that its knots are on the grid (its error has a kink there, where it peaks: a grid
    between the knots read an advised piecewise-linear net 0.91 t from its intent that was 1.10 t, issue 22)."""
    if frame.periodic:
        return K * max(frame.n, n_new)
    spans = K * max(frame.spans, n_new - degree)
    if degree == 1 and n_new > 1:
        spans = -(-spans // (n_new - 1)) * (n_new - 1)
    return spans + 1


@dataclass(frozen=True, eq=False)
class CandidateAxis:
    """One direction of a candidate density.

    Attributes
    ----------
    n : int
        Candidate points.
    degree : int
    knots : (n + degree + 1,) float (periodic: ``n + 2 degree + 1``)
    x : (m,) float
        Check-grid positions in today's analysis coordinates.
    B : (m, n) float
        Candidate basis at the check grid.
    pinv : (n, m) float
        The fit: samples -> control points (least squares; open directions keep their end samples).
    weights : (n,) float or None
        A direction kept as today's (:mod:`cadartifact.advice.exact`): its weights (``B`` is then its rational
        basis); None: a non-rational candidate direction.
    kept : bool
        The direction is today's (its knots, degree, weights and count).
    """

    n: int
    degree: int
    knots: np.ndarray
    x: np.ndarray
    B: np.ndarray
    pinv: np.ndarray
    weights: np.ndarray | None = None
    kept: bool = False


_CACHE = OperatorCache(512)


def candidate_axis(frame: AxisFrame, n_new: int, degree: int, K: int) -> CandidateAxis:
    """The (cached) :class:`CandidateAxis` of ``n_new`` points along a frame's direction."""
    key = (frame.n, frame.periodic, frame.spans, frame.u0, frame.h, n_new, degree, K)

    def build():
        p = int(min(degree, n_new - 1))
        lo, hi = frame.u0, frame.u0 + frame.h * frame.spans
        t = uniform_knots(n_new, p, lo, hi, frame.periodic)
        x = fine_positions(frame, check_count(frame, n_new, p, K))
        B = basis_matrix(t, p, frame.param(x), n_new, frame.periodic)
        return CandidateAxis(n_new, p, t, x, B, _fit_operator(B, frame.periodic))

    return _CACHE.get(key, build)


def _fit_operator(B: np.ndarray, periodic: bool) -> np.ndarray:
    """``(n, m)``: samples -> control points. Periodic (or fewer than 3 points): least squares. Open: the end
    poles take the end samples (a clamped candidate passes through its end poles, so its border curves are
    the fits of today's border curves and its corners today's corners: neighbouring faces still meet,
    SPEC §5), the rest least squares of what the ends leave: ``pinv(B_inner) (I - B_0 e_0' - B_last e_last')``."""
    n, m = B.shape[1], B.shape[0]
    if periodic or n < 3:
        return np.linalg.pinv(B)
    E = np.zeros((n, m))
    E[0, 0] = E[-1, -1] = 1.0
    inner = np.linalg.pinv(B[:, 1:-1])  # (n-2, m)
    E[1:-1] = inner
    E[1:-1, 0] -= inner @ B[:, 0]  # the end samples' share, taken out column by column (no m x m matrix)
    E[1:-1, -1] -= inner @ B[:, -1]
    return E


def fit_points(target: np.ndarray, cu: CandidateAxis, cv: CandidateAxis) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares control points of a candidate and its surface on the check grid.

    Parameters
    ----------
    target : (mu, mv, 3) float
        The intent on the check grid ``cu.x x cv.x``.

    Returns
    -------
    (Q, surface) : ((n'u, n'v, 3) float, (mu, mv, 3) float)
    """
    Q = sandwich(cu.pinv, target, cv.pinv)
    return Q, sandwich(cu.B, Q, cv.B)


def error_planes(target: np.ndarray, normal, component: str) -> tuple:
    """What :func:`fit_error` reads of a check grid, made once per grid: the target and its normals one
    component per contiguous plane ``(3, mu, mv)``, and where the normal is zero (None: nowhere).

    Parameters
    ----------
    target, normal : (mu, mv, 3) float (``normal`` None, or ``component="vector"``: the Euclidean norm)
    component : str
        ``"normal"`` or ``"vector"`` (:func:`cadartifact.analysis.fields.project`).
    """
    planes = np.ascontiguousarray(np.moveaxis(target, -1, 0))
    if component == "vector" or normal is None:
        return planes, None, None
    normals = np.ascontiguousarray(np.moveaxis(normal, -1, 0))
    has = (normals[0] != 0.0) | (normals[1] != 0.0) | (normals[2] != 0.0)
    return planes, normals, None if has.all() else has


def fit_error(Q: np.ndarray, cu: CandidateAxis, cv: CandidateAxis, planes: tuple, keep: np.ndarray) -> dict:
    """``{"peak", "rms"}`` of ``|project(Bu Q Bv^T - target)|`` over the kept points of the check grid, without the
    whole surface in memory: rows of the grid a block at a time (each block stays in cache), each block's
    product over the few candidate rows its B-spline basis reaches (``p + 1`` per grid row). The projection is
    :func:`cadartifact.analysis.fields.project`'s (the signed normal part; the whole displacement where the
    normal is zero, or for ``component="vector"``), term for term: the same numbers as projecting the whole
    error at once, to rounding.

    Parameters
    ----------
    Q : (n'u, n'v, 3) float
    planes : tuple
        :func:`error_planes` of the grid's target.
    keep : (mu, mv) bool
    """
    target, normals, has = planes
    mu, mv = target.shape[1:]
    right = np.moveaxis(Q, -1, 0) @ cv.B.T  # (3, a, mv): a block of rows is Bu[rows] @ right
    nz = cu.B != 0.0  # a B-spline row has p + 1 non-zeros: a block of rows needs few rows of `right`
    first = np.where(nz.any(axis=1), nz.argmax(axis=1), 0)
    last = np.where(nz.any(axis=1), nz.shape[1] - nz[:, ::-1].argmax(axis=1), 0)

    def block(r0, r1):
        c0, c1 = int(first[r0:r1].min()), int(max(last[r0:r1].max(), first[r0:r1].min() + 1))
        return cu.B[r0:r1, c0:c1] @ right[:, c0:c1]

    everywhere = bool(keep.all())
    rows = max(1, _BLOCK_POINTS // max(mv, 1))
    peak, squares, count = 0.0, 0.0, 0
    for r0 in range(0, mu, rows):
        r1 = min(mu, r0 + rows)
        err = block(r0, r1)  # (3, r, mv)
        err -= target[:, r0:r1]
        if normals is None or has is not None:
            norm = np.sqrt(err[0] * err[0] + err[1] * err[1] + err[2] * err[2])
        if normals is None:
            f = norm
        else:
            if has is None:
                np.multiply(err, normals[:, r0:r1], out=err)
                f = err[0] + err[1]
                f += err[2]
            else:
                prod = err * normals[:, r0:r1]
                f = prod[0] + prod[1]
                f += prod[2]
            if has is not None:
                f = np.where(has[r0:r1], f, norm)
        np.abs(f, out=f)
        v = f.ravel() if everywhere else f[keep[r0:r1]]
        if v.size:
            peak = max(peak, float(v.max()))
            squares += float(np.dot(v, v))
            count += v.size
    return {"peak": peak, "rms": float(np.sqrt(squares / count)) if count else 0.0}


#: Grid points per block of :func:`fit_error` (three components of this many doubles stay in a core's cache).
_BLOCK_POINTS = 16384


def candidate_net(net: ControlNet, points: np.ndarray, cu: CandidateAxis, cv: CandidateAxis) -> ControlNet:
    """The candidate as a B-spline :class:`ControlNet` (a cage becomes a B-spline net); non-rational unless a
    direction is kept as today's (its weights ``a``: ``w_ij = a_i`` for every ``j``, and its ``exact`` kind)."""
    from ..net import NetOrigin

    origin = net.origin
    kind = "bspline" if origin.kind in ("array", "quad-chart", "converted") else origin.kind
    wu, wv = cu.weights, cv.weights
    weights = None if wu is None and wv is None else np.outer(np.ones(cu.n) if wu is None else wu,
                                                              np.ones(cv.n) if wv is None else wv)
    exact = tuple(e if axis.kept and e in ("line", "circle") else None for e, axis in zip(net.exact, (cu, cv)))
    return ControlNet(points=points, weights=weights, degrees=(cu.degree, cv.degree), knots=(cu.knots, cv.knots),
                      periodic=net.periodic, unit=net.unit, uv_bounds=net.uv_bounds, exact=exact,
                      origin=NetOrigin(file=origin.file, face=origin.face, name=origin.name, kind=kind))


def curve_distance(points: np.ndarray, curve: np.ndarray) -> float:
    """Largest distance of ``points (k, 3)`` to the polyline ``curve (m, 3)`` (closest point on each segment):
    how far a candidate's border curve lies from today's, whatever either's parametrisation.

    Exact, and cheap when the two are sampled alike (a candidate's border on today's check grid): each point's
    distance to the few segments around its own index is an upper bound of its distance to the polyline; the
    points are then scanned against every segment in decreasing order of that bound, until the bound falls to
    the largest exact distance found (no later point can beat it). Each distance is the same expression as a
    full scan's, so the result is the full scan's (to rounding).
    """
    points, curve = np.asarray(points, float), np.asarray(curve, float)
    a, b = curve[:-1], curve[1:]
    d = b - a
    L2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    k, s = len(points), len(a)
    if k * s <= 4096:
        return float(_segment_distances(points, a, d, L2).min(axis=1).max())
    # the window: segments around each point's own position along the curve (same share of its length)
    centre = np.rint(np.arange(k) * (s - 1) / max(k - 1, 1)).astype(int)
    idx = np.clip(centre[:, None] + np.arange(-_WINDOW, _WINDOW + 1)[None, :], 0, s - 1)  # (k, w)
    diff = points[:, None, :] - a[idx]
    t = np.clip(np.einsum("kwi,kwi->kw", diff, d[idx]) / L2[idx], 0.0, 1.0)
    near = a[idx] + t[..., None] * d[idx]
    bound = np.sqrt(np.min(np.sum((points[:, None, :] - near) ** 2, axis=-1), axis=1))
    best, ranked = 0.0, np.argsort(-bound, kind="stable")
    for start in range(0, k, _BLOCK):
        order = ranked[start:start + _BLOCK]
        if bound[order[0]] <= best:
            break
        exact = _segment_distances(points[order], a, d, L2).min(axis=1)
        best = max(best, float(exact.max()))
    return best


#: Segments either side of a point's own position in :func:`curve_distance`'s window, and points per exact scan.
_WINDOW, _BLOCK = 2, 16


def _segment_distances(points: np.ndarray, a: np.ndarray, d: np.ndarray, L2: np.ndarray) -> np.ndarray:
    """``(k, s)`` distances of ``points (k, 3)`` to the segments ``a + t d`` (``t`` in [0, 1])."""
    t = np.clip(np.einsum("kij,ij->ki", points[:, None, :] - a[None], d) / L2, 0.0, 1.0)
    near = a[None] + t[..., None] * d[None]
    return np.sqrt(np.sum((points[:, None, :] - near) ** 2, axis=-1))
