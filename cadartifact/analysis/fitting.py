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
           "curve_distance"]


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
    """

    n: int
    degree: int
    knots: np.ndarray
    x: np.ndarray
    B: np.ndarray
    pinv: np.ndarray


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


def candidate_net(net: ControlNet, points: np.ndarray, cu: CandidateAxis, cv: CandidateAxis) -> ControlNet:
    """The candidate as a B-spline :class:`ControlNet` (non-rational; a cage becomes a B-spline net)."""
    from ..net import NetOrigin

    origin = net.origin
    kind = "bspline" if origin.kind in ("array", "quad-chart", "converted") else origin.kind
    return ControlNet(points=points, degrees=(cu.degree, cv.degree), knots=(cu.knots, cv.knots),
                      periodic=net.periodic, unit=net.unit, uv_bounds=net.uv_bounds,
                      origin=NetOrigin(file=origin.file, face=origin.face, name=origin.name, kind=kind))


def curve_distance(points: np.ndarray, curve: np.ndarray) -> float:
    """Largest distance of ``points (k, 3)`` to the polyline ``curve (m, 3)`` (closest point on each segment):
    how far a candidate's border curve lies from today's, whatever either's parametrisation."""
    a, b = curve[:-1], curve[1:]
    d = b - a
    L2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(np.einsum("kij,ij->ki", points[:, None, :] - a[None], d) / L2, 0.0, 1.0)
    near = a[None] + t[..., None] * d[None]
    return float(np.sqrt(np.min(np.sum((points[:, None, :] - near) ** 2, axis=-1), axis=1)).max())
