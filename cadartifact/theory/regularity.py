"""Sufficient tests of convergence and smoothness for any binary quad mask: the proof figures of a design.

Two finite computations, each a sufficient condition from the literature:

* **Sobolev exponent** (transition operator). With ``b`` the autocorrelation mask (symbol ``|M|^2 / 4``,
  :func:`~cadartifact.theory.symbols.autocorrelation_mask`) the transition operator
  ``(T v)(alpha) = sum_beta b(2 alpha - beta) v(beta)`` maps the sequences on
  ``Omega = [-R1, R1] x [-R2, R2]`` (``R`` the half-size of ``b``) into themselves, and so does it the subspace
  ``V_2k`` of sequences whose moments of degree ``< 2k`` vanish, when the mask satisfies the sum rules of order
  ``k`` (degree ``k - 1``). Then the limit function has ``phi in H^s`` for every ``s < nu_2``,

      nu_2 >= -log2(rho(T restricted to V_2k)) / 2,

  with equality when the shifts of ``phi`` are stable (Villemoes 1994; Jia 1999, Thm 4.1). The B-splines of
  degree ``p`` give ``p + 1/2`` exactly (tests). By the Sobolev embedding ``H^s subset C^r`` for ``s > r + 1`` in two
  dimensions (Cauchy-Schwarz on ``int |phi_hat| (1 + |xi|)^r``), ``phi`` is ``C^r`` for every ``r < nu_2 - 1``:
  the Hölder exponent is at least ``nu_2 - 1``.
* **Convergence** by the contractivity of the difference scheme: ``n`` steps shrink the differences of any net by
  ``gamma_n < 1`` (:func:`difference_contraction`, a small linear program per residue); then the refined nets
  converge uniformly to a continuous limit (Dyn, Gregory, Levin 1991; Dyn 1992, §3).

References
----------
L. Villemoes, "Wavelet analysis of refinement equations", SIAM J. Math. Anal. 25 (1994) 1433-1460.
R.-Q. Jia, "Characterization of smoothness of multivariate refinable functions in Sobolev spaces",
Trans. AMS 351 (1999) 4089-4112. N. Dyn, J. Gregory, D. Levin, "Analysis of uniform binary subdivision schemes
for curve design", Constr. Approx. 7 (1991) 127-147. N. Dyn, "Subdivision schemes in CAGD", Advances in Numerical
Analysis II (1992) 36-104.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import symbols as sy

__all__ = ["transition_matrix", "sobolev_exponent", "multistep_mask", "difference_contraction", "ContinuityProof",
           "continuity_proof", "proven_class", "MAX_CLAIMED"]

#: Highest smoothness class a proof names (C^0, C^1, C^2).
MAX_CLAIMED = 2
#: Safety margin on ``nu_2 - 1 > r`` (the eigenvalues are floating point).
MARGIN = 1e-6


def transition_matrix(mask) -> tuple[np.ndarray, np.ndarray]:
    """The transition operator of ``mask`` on its invariant box.

    Parameters
    ----------
    mask : (s1, s2) float
        A binary quad mask (sums to 4).

    Returns
    -------
    T : (n, n) float
        ``T[r, c] = b(2 alpha_r - alpha_c)``, ``b`` the autocorrelation mask (sum 4), ``n = (2 R1 + 1)(2 R2 + 1)``.
    points : (n, 2) float
        The integer points ``alpha`` of ``[-R1, R1] x [-R2, R2]`` (row-major).
    """
    b = sy.autocorrelation_mask(np.asarray(mask, dtype=float))
    R1, R2 = (b.shape[0] - 1) // 2, (b.shape[1] - 1) // 2
    i, j = np.meshgrid(np.arange(-R1, R1 + 1), np.arange(-R2, R2 + 1), indexing="ij")
    pts = np.stack([i.ravel(), j.ravel()], axis=1)
    u = 2 * pts[:, None, 0] - pts[None, :, 0]
    v = 2 * pts[:, None, 1] - pts[None, :, 1]
    ok = (np.abs(u) <= R1) & (np.abs(v) <= R2)
    T = np.zeros(u.shape)
    T[ok] = b[u[ok] + R1, v[ok] + R2]
    return T, pts.astype(float)


def sobolev_exponent(mask, order: int | None = None) -> float:
    """Lower bound of the L2-Sobolev exponent of the limit function: ``-log2(rho(T|V_2k)) / 2``.

    Parameters
    ----------
    mask : (s1, s2) float
    order : int, optional
        ``k``: the sum rules of order ``k`` (polynomial degree ``k - 1``) the mask satisfies; by default
        ``sum_rule_order(mask) + 1``. At most ``nu_2 <= k`` can be shown with order ``k``.

    Returns
    -------
    float
        ``nu_2``; ``-inf`` when the mask fails even the basic sum rules (no convergent scheme).
    """
    mask = np.asarray(mask, dtype=float)
    k = sy.sum_rule_order(mask) + 1 if order is None else int(order)
    if k < 1:
        return float("-inf")
    T, pts = transition_matrix(mask)
    scale = max(1.0, np.abs(pts).max())
    x, y = pts[:, 0] / scale, pts[:, 1] / scale
    moments = np.array([x ** e * y ** (q - e) for q in range(2 * k) for e in range(q + 1)])
    _, sv, vt = np.linalg.svd(moments)
    rank = int(np.sum(sv > 1e-11 * sv[0]))
    Q = vt[rank:].T  # orthonormal basis of V_2k
    if Q.shape[1] == 0:
        return float(k)
    rho = float(np.abs(np.linalg.eigvals(Q.T @ T @ Q)).max())
    if rho <= 0.0:
        return float(k)
    return min(float(k), -0.5 * np.log2(rho))


def multistep_mask(mask, steps: int) -> np.ndarray:
    """The mask of ``steps`` subdivision steps at once: symbol ``prod_{j < n} M(z^(2^j))`` (array indices, uncentred).

    Its coset sums modulo ``2^n`` are 1 when the mask's parity cosets sum to 1.
    """
    a = np.asarray(mask, dtype=float)
    out = a
    for j in range(1, int(steps)):
        step = 2 ** j
        dil = np.zeros(((a.shape[0] - 1) * step + 1, (a.shape[1] - 1) * step + 1))
        dil[::step, ::step] = a
        out = sy._convolve2(out, dil)
    return out


def _difference_norm(c: np.ndarray) -> float:
    """``min sum|u| + sum|v|`` over ``c = u - u(. - e1) + v - v(. - e2)`` (u, v on c's box): a linear program.

    Then ``|sum_beta c(beta) f(beta)| <= (sum|u| + sum|v|) max(|Delta1 f|_inf, |Delta2 f|_inf)``.
    """
    from scipy.optimize import linprog

    r, k = c.shape
    n = r * k
    rows = (r + 1) * (k + 1)
    E = np.zeros((rows, 2 * n))
    for i in range(r):
        for j in range(k):
            col = i * k + j
            E[i * (k + 1) + j, col] += 1.0  # u(beta) at beta
            E[(i + 1) * (k + 1) + j, col] -= 1.0  # - u(beta - e1) at beta + e1
            E[i * (k + 1) + j, n + col] += 1.0
            E[i * (k + 1) + j + 1, n + col] -= 1.0
    rhs = np.zeros((r + 1, k + 1))
    rhs[:r, :k] = c
    A = np.hstack([E, -E])
    res = linprog(np.ones(4 * n), A_eq=A, b_eq=rhs.ravel(), bounds=(0, None), method="highs")
    return float(res.fun) if res.status == 0 else float("inf")


def difference_contraction(mask, steps: int) -> float:
    """``gamma_n``: the factor by which ``n`` steps contract the differences of any net (a sufficient convergence test).

    ``Delta_i (S^n f)_alpha = sum_beta c_(alpha,i)(beta) f_beta`` with ``c(beta) = a_n(alpha - 2^n beta)
    - a_n(alpha - e_i - 2^n beta)`` (``a_n`` :func:`multistep_mask`), a zero-sum sequence written as differences of
    ``f`` with the least l1 weight (:func:`_difference_norm`). ``gamma_n = max_(alpha, i)`` of that weight, so
    ``max_i |Delta_i S^n f| <= gamma_n max_i |Delta_i f|``; ``gamma_n < 1`` for some ``n`` makes the differences of the
    refined nets vanish geometrically and the scheme converge uniformly (Dyn, Gregory, Levin 1991; Dyn 1992, §3).
    """
    a = multistep_mask(mask, steps)
    P = 2 ** int(steps)
    if np.any(np.abs(np.array([[a[i::P, j::P].sum() for j in range(P)] for i in range(P)]) - 1.0) > 1e-9):
        return float("inf")
    pad = np.zeros((a.shape[0] + 2 * P + 1, a.shape[1] + 2 * P + 1))
    pad[P:P + a.shape[0], P:P + a.shape[1]] = a
    worst = 0.0
    for r in range(P):
        for k in range(P):
            for e in ((1, 0), (0, 1)):
                # c(beta) = a_n(alpha - P beta) - a_n(alpha - e - P beta) for the residue alpha = (r, k), beta reflected
                base = pad[r + P::P, k + P::P]
                prev = pad[r + P - e[0]::P, k + P - e[1]::P]
                m1, m2 = min(base.shape[0], prev.shape[0]), min(base.shape[1], prev.shape[1])
                c = base[:m1, :m2] - prev[:m1, :m2]
                worst = max(worst, _difference_norm(c))
    return worst


@dataclass(frozen=True)
class ContinuityProof:
    """The figures that prove (sufficient tests) what a mask's subdivision converges to.

    Attributes
    ----------
    sum_rule_degree : int
        Degree of the polynomials the mask generates (sum rules; -1: not even constants).
    contraction : float
        ``gamma_n`` of :func:`difference_contraction` at the first ``n <= 3`` where it is below 1 (else at 3).
    contraction_steps : int
        That ``n``.
    convergent : bool
        ``contraction < 1``: the scheme converges uniformly (to a continuous limit).
    sobolev : float
        ``nu_2`` lower bound (:func:`sobolev_exponent`).
    holder : float
        ``nu_2 - 1``: the limit functions are ``C^r`` for every ``r`` below it.
    continuity : int
        The class proven: -1 when not convergent, else the largest ``r <= 2`` with ``holder > r``
        (:func:`proven_class`), at least 0.
    """

    sum_rule_degree: int
    contraction: float
    contraction_steps: int
    convergent: bool
    sobolev: float
    holder: float
    continuity: int

    def as_dict(self) -> dict:
        """Plain JSON-ready values."""
        return {"proven": f"C{self.continuity}" if self.continuity >= 0 else "none",
                "convergent": self.convergent,
                "difference_contraction": round(self.contraction, 9),
                "contraction_steps": self.contraction_steps,
                "sobolev_exponent": round(self.sobolev, 6),
                "holder_lower_bound": round(self.holder, 6),
                "sum_rule_degree": self.sum_rule_degree,
                "tests": "convergence: n-step difference scheme contracts (gamma_n < 1; Dyn 1992); smoothness: "
                         "Sobolev exponent by the transition operator (Jia 1999) and H^s in C^r for s > r + 1"}


def proven_class(sobolev: float) -> int:
    """The smoothness class ``C^r`` (``r <= 2``) that ``nu_2`` proves: the largest ``r`` with ``nu_2 - 1 > r``."""
    holder = sobolev - 1.0
    if not np.isfinite(holder):
        return MAX_CLAIMED if holder > 0 else -1
    return max(-1, min(MAX_CLAIMED, int(np.ceil(holder - MARGIN)) - 1))


def continuity_proof(mask, max_steps: int = 3) -> ContinuityProof:
    """:class:`ContinuityProof` of ``mask``: sum rules, difference contraction, Sobolev exponent."""
    mask = np.asarray(mask, dtype=float)
    degree = sy.sum_rule_order(mask)
    gamma, steps = float("inf"), 0
    if degree >= 0:
        for steps in range(1, int(max_steps) + 1):
            gamma = difference_contraction(mask, steps)
            if gamma < 1.0 - MARGIN:
                break
    convergent = bool(gamma < 1.0 - MARGIN)
    nu = sobolev_exponent(mask, degree + 1) if degree >= 0 else float("-inf")
    r = max(0, proven_class(nu)) if convergent else -1
    return ContinuityProof(degree, float(gamma), int(steps), convergent, float(nu), float(nu - 1.0), r)
