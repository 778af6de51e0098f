"""Directions the advice keeps as they are: exact lines and circles, one Bezier piece (SPEC §5).

A direction that is exactly a line or a circular arc (``ControlNet.exact``, :mod:`cadartifact.exchange.canonical`),
a single polynomial piece (a Bezier direction, ``n = p + 1``) or a straight degree-1 direction carries no ripple
(SPEC §4) and is represented exactly by today's poles, weights and knots: a uniform non-rational candidate would
only approximate it (a degree-2 circular arc of 3 poles came back as a 4-pole approximation 0.069 mm off at
t = 0.05). Every candidate keeps such a direction's basis; only the other direction is fitted and advised.

With weights ``w_ij = a_i b_j`` the surface is ``S(u, v) = sum_i R_i(u) C_i(v)``, ``R_i = N_i a_i / sum_k N_k a_k``
the kept direction's rational basis, ``C_i(v)`` the i-th row's curve. The candidate is
``S'(u, v) = sum_i R_i(u) sum_j M_j(v) Q_ij``: today's knots, degree and weights ``a_i`` along ``u`` (weights
``a_i`` for every ``j``), uniform non-rational B-splines ``M_j`` along ``v``. The fit along ``u`` recovers the
rows, and the fit along ``v`` is an affine combination of them (its rows sum to one: the basis is a partition of
unity), so every ``v``-iso of the candidate is the same kind of arc as today's (an affine map between the rows of an
arc's poles, as a revolution's, commutes with it). A face kept in both directions (a canonical surface) is never
replaced. Weights that are not a product ``a b^T`` cannot keep one direction's basis alone: such a face is kept.

References
----------
L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997, §7.3 (circular arcs as rational quadratics),
§8.5 (surfaces of revolution: weights ``w_i w_j``).
"""

from __future__ import annotations

import numpy as np

from ..analysis.fitting import CandidateAxis, _fit_operator, check_count
from ..analysis.frames import fine_positions
from ..errors import OptionError
from ..net import ControlNet
from ..numerics.operator_cache import OperatorCache
from ..numerics.splines import basis_matrix

__all__ = ["kept_directions", "kept_axis", "kept_phrase", "WEIGHTS_RTOL"]

#: Weights are a product ``a b^T`` when ``|w - a b^T| <= WEIGHTS_RTOL max|w|``.
WEIGHTS_RTOL = 1e-12


def _straight_degree_one(net: ControlNet, k: int) -> bool:
    from .density_search import _straight

    return net.degrees[k] == 1 and _straight(net.points, k)


def _why(net: ControlNet, k: int) -> str | None:
    """Why direction ``k`` of a face is kept, or None."""
    kind = net.exact[k]
    if kind == "surface":
        return f"exactly a canonical surface ({net.canonical})" if net.canonical else "exactly a canonical surface"
    if kind in ("line", "circle"):
        return f"exactly a {'straight line' if kind == 'line' else 'circular arc'}"
    if not net.periodic[k] and net.shape[k] == net.degrees[k] + 1:
        return f"one Bezier piece of degree {net.degrees[k]}"
    if _straight_degree_one(net, k):
        return "straight (degree 1)"
    return None


def _weights_split(weights, k: int) -> np.ndarray | None:
    """The weights ``a`` along direction ``k`` when ``w = a b^T`` (today's own: the column of the largest weight),
    else None (``None`` weights: None too, the direction is non-rational)."""
    if weights is None:
        return None
    w = np.asarray(weights, float)
    w2 = w if k == 0 else w.T
    i, j = np.unravel_index(np.argmax(np.abs(w2)), w2.shape)
    a, b = w2[:, j], w2[i, :] / w2[i, j]
    if np.abs(w2 - np.outer(a, b)).max() > WEIGHTS_RTOL * np.abs(w2).max():
        return None
    return a.copy()


def kept_directions(net: ControlNet, work: ControlNet) -> tuple:
    """Per direction ``u``, ``v``: why the advice keeps its poles, weights and knots (a short phrase), or None.

    Parameters
    ----------
    net : ControlNet
        Today's face (its ``exact``, its own knots).
    work : ControlNet
        The net the advice reads (:func:`cadartifact.analysis.budget.analysis_net`: the spans the trim uses).

    Returns
    -------
    (str or None, str or None)
        Both directions kept when the face is canonical, when both are exact, or when one is and its weights
        are not a product ``a b^T`` (a face then kept as is).
    """
    if not (net.is_bspline and work.is_bspline):
        return (None, None)
    why = [_why(net, k) for k in (0, 1)]
    for k in (0, 1):
        if why[k] is not None and why[1 - k] is None and work.weights is not None \
                and _weights_split(work.weights, k) is None:
            why[1 - k] = "its weights are not a product of one per direction (the face is kept)"
    return tuple(why)


def kept_phrase(kept: tuple) -> str | None:
    """One line for an advice's notes: which directions keep their poles, weights and knots, and why."""
    parts = [f"{d} {why}" for d, why in zip("uv", kept) if why]
    if not parts:
        return None
    return f"kept exactly (poles, weights and knots): {'; '.join(parts)}"


_CACHE = OperatorCache(64)


def kept_axis(work: ControlNet, frame, k: int, n: int, K: int) -> CandidateAxis:
    """The :class:`~cadartifact.analysis.fitting.CandidateAxis` of direction ``k`` as today's: its knots, degree and
    weights ``a`` (``w = a b^T``), the rational basis ``R_i = N_i a_i / sum N a`` on a check grid of ``K`` samples per
    span; ``n`` must be today's count."""
    if n != work.shape[k]:
        raise OptionError("shape", f"{work.shape[k]} points in {'uv'[k]} (a direction kept exactly)", n)
    a = _weights_split(work.weights, k)
    knots = np.asarray(work.knots[k], float)
    key = (k, frame.n, frame.periodic, frame.spans, frame.u0, frame.h, K, knots.tobytes(),
           None if a is None else a.tobytes())

    def build():
        p = int(work.degrees[k])
        x = fine_positions(frame, check_count(frame, n, p, K))
        B = basis_matrix(knots, p, frame.param(x), n, frame.periodic)
        if a is not None:
            B = B * a[None, :]
            B = B / B.sum(axis=1, keepdims=True)
        return CandidateAxis(n, p, knots, x, B, _fit_operator(B, frame.periodic), weights=a, kept=True)

    return _CACHE.get(key, build)
