"""The uncertainty of the design intent, in model units, from the net alone (SPEC §4 "Uncertainty and decisions").

A finite net determines its intent only up to an uncertainty ``U``: the shapes its samples admit differ
between the samples, most near the borders, for short nets and for content near the Nyquist limit. ``U`` is
estimated as the spread of **admissible reconstructions**: the intent of :mod:`cadartifact.analysis.intent`
rebuilt with other choices that fit the same samples equally well,

* band limit ``F_MAX`` = 0.35 and 0.45 cycles per control point (the band edge),
* ridge weight ``RIDGE`` x 10 (how smooth the continuation is; / 10 moved the intent least of all and was
  dropped for its cost),
* trend degree - 1 (never below a line: a face's coordinates are ramps hundreds of times the shape, which no
  scheme leaves to the extension) and + 1 (what the polynomial takes, what the extension takes),
* the period of the extension 3 x the span instead of 2 x (the border continuation),

one direction at a time. Per direction ``d`` and check-grid point ``z`` the spread is
``D_d(z) = max_a |I_a(z) - I(z)|`` over the alternates ``a`` of that direction; the face's is

    U = k * s * max_z sqrt(D_u(z)^2 + D_v(z)^2),      U_d = k * s * max_z D_d(z)

over the (trimmed) face: ``s D`` is the standard uncertainty (``s``: :data:`TODAY_SCALE` or :data:`SPREAD_SCALE`), ``k`` =
:data:`COVERAGE_FACTOR` = 2 (about 95 %). ``s`` is calibrated on known shapes (issue 39, docs/uncertainty.md
"A sharper U", ``benchmarks/calibrate_net_reading.py``): clamped faces sampling a known shape, nets of 10-28
points, degrees 2-3, 0.1-0.4 cycles per point along u, v or the diagonal, cosines, sums of cosines, bumps.
``U`` must cover the intent's own whole-face error, which bounds the error of every value read against the
intent (today's net's and every candidate's): ``|true - value| <= max |intent - shape|``. On 120 cases the
97.5 % quantile of that error over ``2 D`` is 0.48 (the 95 % quantile, 0.37, let the advice claim a net 1.37 t
from the shape, a bump at 0.37 cycles per point: the alternates see least of content spread up to the band
edge), hence ``s`` = 0.5 (:data:`SPREAD_SCALE`) for every other net's value the advice reads against the
intent: a candidate's, and the advised net's unless it is today's net kept. Today's value needs less: today's net samples the shape, so its deviation
from the intent and the intent's own error largely cancel; the 97.5 % quantile of today's error
(``true - value``) over ``2 D`` is 0.27 on the same cases, hence ``s`` = 0.27 (:data:`TODAY_SCALE`) for today's
value, which the gate and today's decision read (``Uncertainty.peak``; the candidates' is
``Uncertainty.candidate``). Both are validated on families held out of the calibration (degree 5, the 30 degree
direction, the issue's whole mix on another seed).

**Cost.** The alternates' operators depend on a direction's geometry only and are cached
(:data:`_CACHE`). Each band-limit, ridge or period alternate is built by :func:`_fourier_part`: its Gram matrix
over the points outside the net in closed form (trigonometric sums of evenly spaced points) instead of a product
over them, and the pseudo-inverse of the symmetric ``A G^-1 A'`` by its eigenvalues instead of an SVD; each
alternate surface is contracted in the cheaper order (:func:`_applied`). On the real faces of
../shared/realdata this made U several times cheaper where it cost most (long rational directions of degree
10); ``benchmarks/bench_uncertainty.py`` measures U's share of the advice (docs/uncertainty.md).

For the ``surface`` reading (the surface less its ripple) the surface is known, and so are the control
points the scheme aliases: an intent that moves between the points moves nothing the split reads. What is left
open is the split's border convention: its ``U`` is :func:`cadartifact.analysis.border_convention.surface_uncertainty`
(the decision's callers ask it there); :func:`intent_uncertainty` answers that reading with zero,
``estimated = False``, as for a cage.

Periodic directions (a closed net samples a whole period: its trigonometric interpolant is unique below the
Nyquist limit) and exact lines and circles add no spread.

References
----------
ISO/IEC Guide 98-3 (GUM), §6 (expanded uncertainty ``U = k u``). ISO 14253-1:2017, *Decision rules for
verifying conformity or nonconformity with specifications*.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .intent import F_MAX, RIDGE, SOBOLEV, AxisIntent, Intent, axis_intent
from ..numerics.operator_cache import OperatorCache

__all__ = ["Uncertainty", "intent_uncertainty", "intent_spread", "ALTERNATES", "COVERAGE_FACTOR", "SPREAD_SCALE",
           "TODAY_SCALE"]

#: The admissible reconstructions, per direction: (name, band limit, ridge, trend degree change, extension).
ALTERNATES = (
    ("band 0.35", 0.35, RIDGE, 0, None),
    ("band 0.45", 0.45, RIDGE, 0, None),
    ("ridge x10", F_MAX, RIDGE * 10, 0, None),
    ("trend -1", F_MAX, RIDGE, -1, None),
    ("trend +1", F_MAX, RIDGE, +1, None),
    ("period 3L", F_MAX, RIDGE, 0, 3),
)


#: Coverage factor ``k`` of the ``net`` reading (about 95 %: ISO/IEC Guide 98-3 §6).
COVERAGE_FACTOR = 2.0

#: The standard uncertainty of a value read against the intent, per unit of the alternates' spread,
#: ``u = SPREAD_SCALE * D``: ``U = k u`` covers the intent's own whole-face error on 97.5 % of the calibration
#: family, which bounds the error of every candidate's value (docs/uncertainty.md "A sharper U").
SPREAD_SCALE = 0.5

#: The standard uncertainty of today's value (today's net against its own intent) per unit of the same spread:
#: ``U = k TODAY_SCALE D`` covers today's error (today's surface's true distance from the shape minus the reported
#: deviation) on 97.5 % of the calibration family. Today's error is far smaller than the intent's whole-face
#: error that bounds it (today's net samples the shape: its deviation and the intent's error largely cancel),
#: so the gate's decision on today's net reads a U about half the candidates' (docs/uncertainty.md).
TODAY_SCALE = 0.27



@dataclass(frozen=True)
class Uncertainty:
    """The intent's expanded uncertainty (model units).

    Attributes
    ----------
    peak : float
        ``U`` over the face.
    u, v : float
        Each direction's share ``U_d``.
    reading : str
        ``"net"`` or ``"surface"``.
    factor : float
        The coverage factor ``k`` applied to the spread.
    estimated : bool
        False where no estimate exists (the ``surface`` reading): ``U`` is then 0.
    candidate : float or None
        The ``net`` reading's ``U`` of a value read against the intent by any other net (a candidate of the
        advice): ``k SPREAD_SCALE D``, where ``peak`` is today's value's, ``k TODAY_SCALE D``. None where the
        reading gives no such U (the ``surface`` reading: :func:`cadartifact.advice.decision.candidate_margin`).
    """

    peak: float
    u: float
    v: float
    reading: str
    factor: float
    estimated: bool = True
    candidate: float | None = None

    def to_dict(self) -> dict:
        return {"peak": float(self.peak), "u": float(self.u), "v": float(self.v), "reading": self.reading,
                "coverage_factor": float(self.factor), "estimated": bool(self.estimated)}

    @staticmethod
    def zero(reading: str) -> Uncertainty:
        return Uncertainty(0.0, 0.0, 0.0, reading, 0.0, estimated=False)


def _judged(frame) -> bool:
    """Whether a direction's reconstruction is open to choice (open, and not exactly a line or a circle)."""
    return not (frame.periodic or frame.exact)


#: The alternates' per-direction operators (their geometry only, never the points; emptied with the others).
_CACHE = OperatorCache(256)


def _fourier_part(frame, fmax: float, ridge: float):
    """The Fourier part of an open direction's intent with band limit ``fmax`` and ridge ``ridge``: what
    :class:`~cadartifact.analysis.intent.AxisIntent` builds, ``coef = G^-1 A' (A G^-1 A')^+`` with
    ``G = Bo' Bo / m + ridge W^2`` (``A``: the basis at the samples, ``(n, M)``; ``Bo``: at the ``m`` points
    outside the net, ``(m, M)``), with the Gram matrix ``Bo' Bo`` from the trigonometric sums
    ``C_j = sum_i cos(2 pi j x_i / T)``, ``S_j = sum_i sin(2 pi j x_i / T)``, ``|j| <= 2 k_max`` (in closed form:
    the points are evenly spaced):

        cos_j cos_k = (C_{j-k} + C_{j+k}) / 2,   sin_j sin_k = (C_{j-k} - C_{j+k}) / 2,
        cos_j sin_k = (S_{j+k} - S_{j-k}) / 2

    (``O(k_max)`` sines and cosines instead of an ``O(m M^2)`` product: on a 275-point direction,
    period 3 x the span, ``M`` = 719 and ``m`` = 4 200), and the pseudo-inverse of the symmetric
    ``A G^-1 A'`` by its eigenvalues (:func:`_pinv_sym`). The system is ill-conditioned (condition about 1e14
    on 40-point nets, hence the pseudo-inverse): against the product and the SVD, ``U`` moves by up to 0.22 %
    of itself (median 1e-7) on 80 known-shape faces (tests/analysis/test_uncertainty.py compares the two roads).

    Returns
    -------
    SimpleNamespace
        ``k`` ``(k_max,)``, ``nyquist`` (False), ``freqs`` and ``weights`` ``(M,)``, ``coef`` ``(M, n)``: the
        Fourier part :class:`~cadartifact.analysis.intent.AxisIntent` takes as ``fourier``."""
    from types import SimpleNamespace

    T, spans = frame.period, frame.spans
    kmax = max(int(np.ceil(fmax * T)) - 1, 0)
    k = np.arange(1, kmax + 1)
    # the points outside: np.linspace(spans, T, N + 1)[1:-1], N = 8 round(T - spans), step h, first x0
    N = 8 * int(round(T - spans))
    m, h = N - 1, (T - spans) / N
    x0 = spans + h
    # their sums in closed form (Dirichlet): sum_i exp(i w (x0 + i h)) = exp(i w (x0 + (m-1) h / 2)) D_m(w h / 2),
    # D_m(a) = sin(m a) / sin(a) (w h / 2 = pi j / (8 T) < pi / 8 here: never a multiple of pi but at j = 0)
    w = (2 * np.pi / T) * np.arange(2 * kmax + 1)
    half = w * h / 2
    D = np.full(len(w), float(m))
    D[1:] = np.sin(m * half[1:]) / np.sin(half[1:])
    centre = w * (x0 + (m - 1) * h / 2)
    C, S = np.cos(centre) * D, np.sin(centre) * D
    d, t = np.abs(k[:, None] - k[None, :]), k[:, None] + k[None, :]
    sgn = np.sign(k[:, None] - k[None, :])  # S_{j-k} = sgn * S_{|j-k|}
    M = 2 * kmax + 1
    G = np.empty((M, M))
    G[0, 0] = m
    G[0, 1:kmax + 1] = G[1:kmax + 1, 0] = C[k]
    G[0, kmax + 1:] = G[kmax + 1:, 0] = S[k]
    G[1:kmax + 1, 1:kmax + 1] = (C[d] + C[t]) / 2
    G[kmax + 1:, kmax + 1:] = (C[d] - C[t]) / 2
    cs = (S[t] - sgn * S[d]) / 2  # rows cos_j, columns sin_k
    G[1:kmax + 1, kmax + 1:] = cs
    G[kmax + 1:, 1:kmax + 1] = cs.T
    f = k / T
    freqs = np.concatenate([[0.0], f, f])
    weights = (1.0 + (freqs * spans) ** 2) ** (SOBOLEV / 2)
    G = G / m + ridge * np.diag(weights ** 2)
    xph = (2 * np.pi / T) * np.outer(frame.xs, k)
    A = np.hstack([np.ones((frame.n, 1)), np.cos(xph), np.sin(xph)])
    GiAt = np.linalg.solve(G, A.T)
    return SimpleNamespace(k=k, nyquist=False, freqs=freqs, weights=weights, coef=GiAt @ _pinv_sym(A @ GiAt))


def _pinv_sym(Q: np.ndarray, rcond: float = 1e-13) -> np.ndarray:
    """The pseudo-inverse of a symmetric positive semi-definite matrix (``A G^-1 A'``) by its eigenvalues
    (symmetrised first; eigenvalues below ``rcond`` times the largest dropped): what ``numpy.linalg.pinv(Q,
    rcond)`` gives for such a matrix, its singular values being its eigenvalues, at a third of the cost."""
    w, V = np.linalg.eigh((Q + Q.T) / 2)
    keep = w > rcond * max(float(w[-1]), 0.0)
    return (V[:, keep] / w[keep]) @ V[:, keep].T


def _frame_key(frame) -> tuple:
    return (frame.n, frame.periodic, frame.spans, round(frame.offset, 12), frame.xs.round(12).tobytes(), frame.period)


def _alternate_axis(frame, degree: int, fmax: float, ridge: float) -> AxisIntent:
    """The cached alternate :class:`AxisIntent` of a band limit, ridge weight or period (:func:`_fourier_part`)."""
    key = _frame_key(frame) + (fmax, ridge)
    part = _CACHE.get(("fourier",) + key, lambda: _fourier_part(frame, fmax, ridge))
    return _CACHE.get(("axis", degree) + key, lambda: AxisIntent(frame, degree, fmax, ridge, fourier=part))


def _alternates(intent: Intent, axis: int):
    """The admissible alternate per-direction intents along ``axis`` (the other direction as it is)."""
    frame, ax = intent.frames[axis], intent.axes[axis]
    for _name, fmax, ridge, ddeg, ext in ALTERNATES:
        deg = ax.degree + ddeg
        if deg < min(1, ax.degree) or deg > frame.n - 1:  # every scheme reproduces lines: never below a line
            continue
        if ddeg:  # a trend alternate reuses the intent's Fourier part
            alt = axis_intent(frame, deg, fmax, ridge, like=ax)
        else:  # another band limit, ridge or period
            alt = _alternate_axis(frame if ext is None else dataclasses.replace(frame, extension=ext), deg, fmax,
                                  ridge)
        if alt is not ax:
            yield alt


def _applied(ax: AxisIntent, x: np.ndarray, H: np.ndarray) -> np.ndarray:
    """``ax.full_at(x) @ H`` (``(len(x), k)`` for ``H`` of ``(n, k)``; ``a = len(x)``, ``M`` Fourier terms),
    in the cheaper order: the operator first (``a M n + a n k`` products), or contracted from the right,
    ``trend(x) (Vp H) + basis(x) (coef (rest H))`` (``(a + n) M k + n^2 k``), which forms no ``(a, n)``
    operator: far cheaper for a long direction beside a short one (a 275-point direction beside a 7-point
    one: 20 instead of 216 million products per alternate)."""
    a, (n, k), M = len(x), H.shape, len(ax.freqs)
    if (a + n) * M * k + n * n * k < a * M * n + a * n * k:
        return ax.trend_at(x) @ (ax.Vp @ H) + ax.basis(x) @ (ax.coef @ (ax.rest @ H))
    return ax.full_at(x) @ H


def _spread_net(intent: Intent, x, y) -> tuple[np.ndarray, np.ndarray]:
    """``(D_u, D_v)``: each direction's pointwise spread of the ``net`` reading on ``x x y``.

    Along ``u`` the alternate surfaces are ``I_a = R_a P R_v'`` (``R``: a direction's rows ``full_at``, ``(a, nu)``
    and ``(b, nv)``), so with ``H = P R_v'`` formed once (``(nu, c, b)``, flattened to ``(nu, c b)``) each
    alternate costs one :func:`_applied`; along ``v`` the same with ``H = R_u P`` (``(nv, c, a)``). A rational
    intent (``c = 4``) is compared after the projection of each surface. Returns two ``(a, b)`` arrays.
    """
    P = intent.lifted_points
    homogeneous = P.shape[-1] == 4
    rows = [intent.axes[0].full_at(x), intent.axes[1].full_at(y)]
    out = []
    for axis, pts in ((0, x), (1, y)):
        D = np.zeros((len(x), len(y)))
        if _judged(intent.frames[axis]):
            other = rows[1 - axis]
            # H: the points contracted with the other direction's rows, this direction first, flattened
            H = np.tensordot(P, other, axes=([1 - axis], [1]))  # (n_axis, c, len(other))
            shape = H.shape
            H = H.reshape(shape[0], -1)
            base = rows[axis] @ H
            if homogeneous:
                base_s = _project(base, shape)
            for alt in _alternates(intent, axis):
                surf = _applied(alt, pts, H)
                diff = _project(surf, shape) - base_s if homogeneous else (surf - base).reshape(
                    (len(pts),) + shape[1:])
                dist = np.sqrt(np.sum(diff * diff, axis=1))  # (len(pts), len(other))
                D = np.maximum(D, dist if axis == 0 else dist.T)
        out.append(D)
    return out[0], out[1]


def _project(flat: np.ndarray, shape) -> np.ndarray:
    """Homogeneous ``(len, c * len(other))`` products -> projected points ``(len, 3, len(other))``."""
    a = flat.reshape((flat.shape[0],) + shape[1:])
    return a[:, :3] / a[:, 3:4]


def intent_uncertainty(intent, scheme=None, reading: str = "net", keep=None) -> Uncertainty:
    """The expanded uncertainty ``U`` of a face's design intent (model units).

    Parameters
    ----------
    intent : Intent or PiecewiseIntent
        The ``net`` reading's intent (a split face: each piece's, the face's ``U`` is the largest).
    scheme : Scheme, optional
        The analysis scheme (the ``surface`` reading's split needs it).
    reading : {"net", "surface"}
    keep : callable, optional
        ``keep(x, y) -> (a, b) bool``: the part of the check grid that is the face (its trim).

    Returns
    -------
    Uncertainty
        Today's value's ``U = k s max_z sqrt(D_u^2 + D_v^2)`` and ``U_d = k s max_z D_d`` (module docstring),
        ``k`` = :data:`COVERAGE_FACTOR`, ``s`` = :data:`TODAY_SCALE`; ``candidate``: the same with ``s`` =
        :data:`SPREAD_SCALE` (any other net's value against the intent); the ``surface`` reading: zero,
        ``estimated=False``.
    """
    if reading == "surface":  # the border convention's U needs the face and the run (module docstring)
        return Uncertainty.zero("surface")
    factor = COVERAGE_FACTOR
    pieces = getattr(intent, "pieces", None)
    if pieces is not None:  # a split face (cadartifact.analysis.pieces): each piece's own intent
        from .intent import design_intent

        parts = [intent_uncertainty(design_intent(p.net, scheme_of(p.net), intent.levels), scheme_of(p.net),
                                    reading) for p in pieces]
        return Uncertainty(max(p.peak for p in parts), max(p.u for p in parts), max(p.v for p in parts),
                           reading, factor, candidate=max(p.candidate or 0.0 for p in parts))
    if not isinstance(intent, Intent) or not isinstance(intent.axes[0], AxisIntent):
        return Uncertainty.zero(reading)
    scale = factor * TODAY_SCALE
    D, Du, Dv = intent_spread(intent, keep)
    return Uncertainty(scale * D, scale * Du, scale * Dv, reading, factor, candidate=factor * SPREAD_SCALE * D)


def intent_spread(intent: Intent, keep=None) -> tuple[float, float, float]:
    """The alternates' spread ``(D, D_u, D_v)`` of an (unsplit) intent over the (trimmed) face, model units:
    ``D = max_z sqrt(D_u(z)^2 + D_v(z)^2)`` and ``D_d = max_z D_d(z)`` (module docstring); ``U`` is
    ``COVERAGE_FACTOR * TODAY_SCALE`` times these (today's value), ``COVERAGE_FACTOR * SPREAD_SCALE`` times ``D`` (a
    candidate's)."""
    x, y = (_grid(f) for f in intent.frames)
    Du, Dv = _spread_net(intent, x, y)
    D = np.sqrt(Du ** 2 + Dv ** 2)
    if keep is not None:
        mask = np.asarray(keep(x, y), bool)
        if mask.any():
            D, Du, Dv = D[mask], Du[mask], Dv[mask]
    top = lambda a: float(a.max()) if a.size else 0.0  # noqa: E731
    return top(D), top(Du), top(Dv)


#: Samples per span of the grid the spread is taken on (the alternates differ smoothly between the points).
GRID_PER_SPAN = 4


def _grid(frame) -> np.ndarray:
    """The check grid of the spread: :data:`GRID_PER_SPAN` samples per span over the domain."""
    count = GRID_PER_SPAN * frame.spans + (0 if frame.periodic else 1)
    return np.arange(count) / GRID_PER_SPAN


def scheme_of(net):
    """A piece's analysis scheme: its own B-spline degrees."""
    from ..theory.catalogue import bspline

    return bspline(*net.degrees)
