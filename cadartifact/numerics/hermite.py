"""Hermite interpolation in Bezier form: the bridges that continue a field past an open border.

A bridge of degree ``n = 2 M + 1`` matching value and ``M`` derivatives at both ends of [0, 1] is evaluated
from its Bezier points (Bernstein basis, positive), not from monomials: the bridge of a long face reaches far
beyond the face's values (1e5 times on a 72-point face), and the Hermite basis in monomials cancels terms many
orders larger still, so which way the rounding fell depended on the BLAS kernel (1e-4 of a real face's ripple
between two CPUs, 2026-12-03).

References
----------
G. Farin, *Curves and Surfaces for CAGD*, 5th ed., Morgan Kaufmann 2002, ch. 5 (Bezier derivatives) and 7.
"""

from __future__ import annotations

from math import comb, factorial

import numpy as np

from .operator_cache import OperatorCache

#: The bridges' operators, by size: a file's faces reuse a few (emptied with every shared operator cache).
_OPERATORS = OperatorCache(128)

__all__ = ["bernstein_basis", "end_derivatives", "gap_basis", "hermite_basis", "hermite_to_bezier"]


def hermite_to_bezier(order: int) -> np.ndarray:
    """Map a degree ``n = 2 order + 1`` polynomial's derivatives at ``t = 0`` to its first Bezier points.

    .. math:: b_j = \\sum_{k \\le j} \\binom{j}{k} \\frac{(n - k)!}{n!} P^{(k)}(0), \\quad j = 0..order

    At ``t = 1`` the same matrix maps ``(-1)**k P^(k)(1)`` to ``b_n, b_(n-1), ..., b_(n-order)``.

    Parameters
    ----------
    order : int
        Derivatives matched at each end (``>= 0``).

    Returns
    -------
    A : (order + 1, order + 1) float
        Lower triangular: ``b[:order + 1] = A @ [P(0), P'(0), ..., P^(order)(0)]``. Cached; read-only.

    References
    ----------
    G. Farin, *Curves and Surfaces for CAGD*, 5th ed., 2002, sec. 5.3 (derivatives of a Bezier curve).
    """
    _require_order(order)
    n = 2 * order + 1
    return _OPERATORS.get(("to_bezier", int(order)), lambda: _read_only(np.array(
        [[comb(j, k) * factorial(n - k) / factorial(n) if k <= j else 0.0 for k in range(order + 1)]
         for j in range(order + 1)])))


def bernstein_basis(t: np.ndarray, degree: int) -> np.ndarray:
    """The Bernstein polynomials of a degree on [0, 1], :math:`B_i^n(t) = \\binom{n}{i} t^i (1 - t)^{n - i}`.

    Parameters
    ----------
    t : (m,) float
        Parameters in [0, 1].
    degree : int
        ``n >= 0``.

    Returns
    -------
    B : (degree + 1, m) float
        ``B[i]`` is :math:`B_i^n` at ``t``.

    References
    ----------
    G. Farin, *Curves and Surfaces for CAGD*, 5th ed., 2002, sec. 5.1.
    """
    _require_order(degree, "degree")
    t = np.asarray(t, float)
    i = np.arange(degree + 1)[:, None]
    c = np.array([comb(degree, k) for k in range(degree + 1)], float)[:, None]
    return c * t[None, :] ** i * (1.0 - t[None, :]) ** (degree - i)


def gap_basis(count: int, degree: int) -> np.ndarray:
    """:func:`bernstein_basis` at the ``count`` points ``k / (count + 1)``, ``k = 1..count``, strictly inside
    [0, 1]: a bridge's samples across a gap of ``count`` fine steps. Cached (a face's bridges reuse a few gaps);
    read-only.

    Returns
    -------
    B : (degree + 1, count) float
    """
    return _OPERATORS.get(("gap", int(count), int(degree)), lambda: _read_only(
        bernstein_basis(np.arange(1, count + 1, dtype=float) / float(count + 1), degree)))


def end_derivatives(samples: int, degree: int, order: int) -> np.ndarray:
    """Value and derivatives ``1..order`` (per sample step) at the first of ``samples`` equally spaced samples,
    from their least-squares polynomial of ``degree`` (Taylor basis, ``pinv``); derivatives above ``degree`` are
    zero. Cached; read-only.

    .. math:: P = \\mathrm{pinv}(V)_{0..order}, \\quad V_{sk} = s^k / k!, \\; s = 0..samples - 1, \\; k = 0..degree

    Returns
    -------
    P : (order + 1, samples) float
        ``P @ values[:samples]`` gives ``[f(0), f'(0), ..., f^(order)(0)]``.
    """
    return _OPERATORS.get(("ends", int(samples), int(degree), int(order)),
                          lambda: _read_only(_end_derivatives(samples, degree, order)))


def _end_derivatives(samples: int, degree: int, order: int) -> np.ndarray:
    s = np.arange(samples, dtype=float)
    fact = np.cumprod(np.r_[1.0, np.arange(1.0, degree + 1)])
    V = s[:, None] ** np.arange(degree + 1)[None, :] / fact[None, :]  # Taylor basis at s = 0
    P = np.linalg.pinv(V)[: order + 1]
    if P.shape[0] < order + 1:  # too few samples for the higher derivatives: take them as zero
        P = np.vstack([P, np.zeros((order + 1 - P.shape[0], samples))])
    return P


def _read_only(a: np.ndarray) -> np.ndarray:
    """A cached operator, shared by its callers: none may write into it."""
    a.flags.writeable = False
    return a


def hermite_basis(t: np.ndarray, order: int) -> np.ndarray:
    """The degree ``n = 2 order + 1`` Hermite basis on [0, 1], each function in Bernstein form.

    .. math:: H_k^0 = \\sum_j A_{jk} B_j^n, \\qquad H_k^1 = (-1)^k \\sum_j A_{jk} B_{n-j}^n

    with ``A`` = :func:`hermite_to_bezier` (the two ends' Bezier points do not overlap: ``order + 1`` each of
    ``n + 1``). ``H_k^0`` has ``k``-th derivative 1 at 0 and every other matched derivative 0 at both ends.

    Parameters
    ----------
    t : (m,) float
        Parameters in [0, 1].
    order : int
        Derivatives matched at each end (``>= 0``).

    Returns
    -------
    H : (2 order + 2, m) float
        Value and derivatives ``1..order`` at 0, then the same at 1.

    References
    ----------
    G. Farin, *Curves and Surfaces for CAGD*, 5th ed., 2002, ch. 7 (Hermite interpolation).
    """
    _require_order(order)
    n = 2 * order + 1
    B = bernstein_basis(t, n)
    A = hermite_to_bezier(order)
    at0 = A.T @ B[: order + 1]
    at1 = (A.T @ B[::-1][: order + 1]) * ((-1.0) ** np.arange(order + 1))[:, None]
    return np.vstack([at0, at1])


def _require_order(value: int, name: str = "order") -> None:
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 0:
        raise ValueError(f"{name}: expected an integer >= 0, received {value!r}")
