"""Responses of a scheme to one sinusoid: signal and artifact amplitudes per direction (SPEC §3).

Control data ``A_J = exp(2 pi i Omega.J)`` (``Omega`` in cycles per control point). With
``V in {0, X1, X2, X1+X2}`` (signal, X1, X2, diagonal):

* ``one_step``: ``a, b, c, d = M(Omega + V) / 4`` (paper §3);
* ``limit``: ``alpha_V = M(Omega + V) / 4 * L(Omega + V)``, the limit surface at the refined
  vertices (paper §6-7);
* ``continuous``: the limit surface ``sum_m phi_hat(Omega + m) exp(2 pi i (Omega + m).x)`` itself:
  ``signal = phi_hat(Omega)`` and per alias class (X1: ``m2 = 0``, X2: ``m1 = 0``, diagonal: both
  non-zero) the root-sum-square of ``phi_hat(Omega + m)`` over its aliases ``m != 0``, i.e. the
  amplitude of one sinusoid with the same RMS.

Continuous alias sums are exact (no truncated alias sums)
---------------------------------------------------------
With ``m = 2 m' + V`` and ``phi_hat(xi) = M(xi)/4 phi_hat(xi/2)``,
``R(xi) = sum_{m != 0} |phi_hat(xi + m)|^2`` obeys

    R(xi) = sum_{V != 0} |M(xi + V)/4|^2 S((xi + V)/2) + |M(xi)/4|^2 R(xi/2),

where ``S(eta) = sum_m |phi_hat(eta + m)|^2 = sum_n psi(n) exp(-2 pi i eta.n)`` is exact because
``psi = phi * phi(-.)`` is refinable with mask ``(m correlated with m)/4`` whose limit stencil gives
``psi`` at the integers. The X1 class obeys the same recursion with ``S`` replaced by the line sum
``sum_m1 |phi_hat(eta1 + m1, eta2)|^2 = sum_n1 exp(-2 pi i eta1 n1) G(n1, eta2)``, where
``G(n1, eta) = int psi(n1, y) exp(-2 pi i eta y) dy`` satisfies the vector refinement
``G(., eta) = B(eta) G(., eta/2)`` (``B`` built from the rows of the autocorrelation mask); the
diagonal class uses ``S`` at ``V = X1+X2`` and the off-line sums ``sum_{m2 != 0}`` of the same
vectors, which obey a recursion of their own. No class is obtained by subtracting the others, so
zeros stay zeros (the diagonal on the axes, X1 and X2 on the diagonals of 4-3 and 4-8). The
recursion is cut after ``J`` halvings where the dropped remainder is ``O(2^(-2 J (d+1)))`` relative
(``d`` the reproduction degree), below ``2^-60``. Tensor-product masks factor into 1-D sums
(``x1^2 = R_x(wx) |phi_y_hat(wy)|^2``, ``diagonal^2 = R_x R_y``), accurate to rounding relative to
each class. For other masks each squared class amplitude is accurate to about 1e-16 relative
plus 1e-17 absolute (the symbol of the autocorrelation near its multiple zeros), i.e. a class
amplitude below ~1e-8 of the signal carries a few 1e-9 of absolute error: irrelevant for energies,
percentages and tolerances.

References
----------
Augsdörfer, Dodgson, Sabin, "Artifact analysis on B-splines, box-splines and other surfaces
defined by quadrilateral polyhedra", CAGD 28 (2011), §3-7; SPEC §3 (errata, continuous stage).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import symbols as sy
from ..errors import OptionError, check_option
from .symbols import box_symbol, mask_symbol, trig_sum  # noqa: F401  (re-exported low-level API)

__all__ = ["Response", "response", "STAGES", "mask_symbol", "trig_sum", "box_symbol",
           "alias_rest_1d", "alias_class_sums"]

#: The stages a response can be asked for.
STAGES = ("one_step", "limit", "continuous")

_STAGE_ALIASES = {"one-step": "one_step"}

_SHIFTS = ((0, 0), (1, 0), (0, 1), (1, 1))  # V = 0, X1, X2, X1+X2


def _out(a):
    """0-d arrays become numpy scalars; others are made read-only."""
    a = np.asarray(a)
    if a.ndim == 0:
        return a[()]
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Response:
    """Signal and artifact amplitudes of one scheme at frequencies ``(wx, wy)``.

    Attributes
    ----------
    signal, x1, x2, diagonal : float arrays (broadcast shape of wx, wy)
        Signed amplitudes (``a, b, c, d`` / ``alpha, beta, gamma, delta`` of the paper; only 4-3 gives
        negative values inside the Nyquist square). Continuous stage: ``signal = phi_hat(Omega)``
        and non-negative root-sum-squares per class. Complex only for masks that are not
        point-symmetric.
    stage : str
        ``"one_step"``, ``"limit"`` or ``"continuous"``.
    wx, wy : float arrays
        The frequencies, cycles per control point.
    """

    signal: np.ndarray
    x1: np.ndarray
    x2: np.ndarray
    diagonal: np.ndarray
    stage: str
    wx: np.ndarray
    wy: np.ndarray

    def __post_init__(self):
        check_option("stage", self.stage, STAGES)
        for name in ("signal", "x1", "x2", "diagonal", "wx", "wy"):
            object.__setattr__(self, name, _out(getattr(self, name)))

    @property
    def energy(self):
        """Artifact energy ``sqrt((b^2 + c^2 + d^2) / 3)`` (paper §4)."""
        sq = lambda a: np.abs(a) ** 2  # noqa: E731
        return _out(np.sqrt((sq(self.x1) + sq(self.x2) + sq(self.diagonal)) / 3.0))

    @property
    def percent(self):
        """Artifact energy as a percentage of the remaining signal, ``100 energy / |a|``.

        ``inf`` where the signal is 0 and the energy is not, 0 where both vanish.
        """
        e = np.asarray(self.energy)
        s = np.abs(np.asarray(self.signal))
        with np.errstate(divide="ignore", invalid="ignore"):
            p = 100.0 * e / s
        p = np.where(s == 0, np.where(e > 0, np.inf, 0.0), p)
        return _out(p)

    @property
    def lateral(self):
        """Lateral artifact (SPEC §3): ``sqrt(((b sin phi1)^2 + (c sin phi2)^2 + (d sin phid1 sin phid2)^2) / 3)``.

        ``sin phi1 = |wy|/|Omega|``, ``sin phi2 = |wx|/|Omega|``, ``sin phid1 sin phid2 = |wx^2 - wy^2| / (2 |Omega|^2)``;
        0 at ``Omega = 0``. Zero on the axes for every scheme and on the diagonals for 4-3 and 4-8.
        """
        wx = np.asarray(self.wx, dtype=float)
        wy = np.asarray(self.wy, dtype=float)
        r2 = wx * wx + wy * wy
        zero = r2 == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.sqrt(r2)
            s1 = np.where(zero, 0.0, np.abs(wy) / r)
            s2 = np.where(zero, 0.0, np.abs(wx) / r)
            sd = np.where(zero, 0.0, np.abs(wx * wx - wy * wy) / (2.0 * r2))
        val = ((np.abs(self.x1) * s1) ** 2 + (np.abs(self.x2) * s2) ** 2 + (np.abs(self.diagonal) * sd) ** 2) / 3.0
        return _out(np.sqrt(val))


def response(scheme, wx, wy, stage: str = "limit") -> Response:
    """Amplitudes of signal and artifacts for control data ``exp(2 pi i Omega.J)``.

    Parameters
    ----------
    scheme : Scheme
        A :class:`~cadartifact.theory.catalogue.Scheme` (``cadartifact.scheme(name)`` makes one from a
        catalogue name; ``Scheme.response`` calls this function). The scheme is handed in: this module sits
        below the catalogue and does not import it.
    wx, wy : array_like float
        ``Omega`` in cycles per control point (Nyquist square ``|w| <= 1/2``), broadcast together;
        pass ``wx`` as ``(1, N)`` and ``wy`` as ``(M, 1)`` for a fast grid.
    stage : {"one_step", "limit", "continuous"}
        ``"one-step"`` is accepted too.

    Returns
    -------
    Response
        ``one_step``: ``a, b, c, d = M(Omega + V)/4``; ``limit``: ``alpha_V = M(Omega + V)/4 L(Omega + V)``;
        ``continuous``: ``phi_hat(Omega)`` and per-class root-sum-squares of the aliases (module notes).
        Periodic with period 2 in each ``w`` (antiperiodic signs on dual axes) for the first two.

    Examples
    --------
    >>> from cadartifact.theory.catalogue import scheme
    >>> round(float(response(scheme("bilinear"), 0.1, 0.2).percent), 2)
    6.27
    """
    if isinstance(scheme, str) or not hasattr(scheme, "mask"):
        raise OptionError("scheme", "a Scheme (cadartifact.scheme(name) makes one from a catalogue name)",
                          scheme)
    s = scheme
    stage = _STAGE_ALIASES.get(stage, stage) if isinstance(stage, str) else stage
    check_option("stage", stage, STAGES)
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)
    if stage == "continuous":
        vals = _continuous(s, wx, wy)
    elif s.tensor:
        vals = _discrete_tensor(s, wx, wy, stage == "limit")
    else:
        # M/4 * L is the symbol of the convolved coefficients (m * L)/4: one trigonometric sum per V
        # (one matrix product on grids) instead of two sums and a product
        coef = _limit_coefficients(s) if stage == "limit" else s.mask / 4.0
        k1, k2 = sy.centred_offsets(coef.shape[0]), sy.centred_offsets(coef.shape[1])
        vals = [trig_sum(coef, k1, k2, wx + v1, wy + v2, np.pi) for v1, v2 in _SHIFTS]
    return Response(*vals, stage=stage, wx=wx, wy=wy)


def _limit_coefficients(s) -> np.ndarray:
    """Cached ``(m * L) / 4`` (full 2-D convolution, centred like the mask)."""
    if "limit_coef" not in s._cache:
        m, L = s.mask, s.limit_stencil
        out = np.zeros((m.shape[0] + L.shape[0] - 1, m.shape[1] + L.shape[1] - 1))
        for a in range(L.shape[0]):
            for b in range(L.shape[1]):
                out[a:a + m.shape[0], b:b + m.shape[1]] += L[a, b] * m
        s._cache["limit_coef"] = out / 4.0
    return s._cache["limit_coef"]


def _discrete_tensor(s, wx, wy, limit: bool):
    """one_step / limit of a tensor-product mask: 1-D factors, one outer product per class."""
    ax, ay = s._axes
    fx, fy = [], []
    for axis, w, out in ((ax, wx, fx), (ay, wy, fy)):
        for v in (0, 1):
            a = axis.symbol(w + v) / 2.0
            if limit:
                a = a * axis.stencil_symbol(w + v)
            out.append(a)
    return [fx[v1] * fy[v2] for v1, v2 in _SHIFTS]


# ------------------------------------------------------------------ continuous stage
def _recursion_depth(xi_max: float, order: int) -> int:
    """Halvings after which ``R(xi/2^J)`` is below ``2^-60`` of ``R(xi)`` (decay ``eta^(2(order+1))``)."""
    lead = int(np.ceil(np.log2(max(xi_max, 1.0))))
    return lead + int(np.ceil(60.0 / (2.0 * (max(order, 0) + 1)))) + 2


def alias_rest_1d(axis, w) -> np.ndarray:
    """``sum_{m != 0} |phi_hat(w + m)|^2`` for the 1-D factor ``axis`` of a tensor scheme (exact recursion).

    ``R(w) = |U(w+1)/2|^2 S((w+1)/2) + |U(w)/2|^2 R(w/2)`` with ``S(eta) = sum_n psi(n) cos(2 pi eta n)``.
    """
    w = np.asarray(w, dtype=float)
    psi = axis.psi
    k = sy.centred_offsets(len(psi))
    J = _recursion_depth(np.abs(w).max(initial=0.0), axis.order)
    total = np.zeros(w.shape)
    weight = np.ones(w.shape)
    wj = w
    for _ in range(J):
        up = axis.symbol(wj + 1.0) / 2.0
        S = np.cos(2.0 * np.pi * np.multiply.outer((wj + 1.0) / 2.0, k)) @ psi
        total = total + weight * np.abs(up) ** 2 * S
        weight = weight * np.abs(axis.symbol(wj) / 2.0) ** 2
        wj = wj / 2.0
    return np.maximum(total, 0.0)


def _continuous(s, wx, wy):
    if s.tensor:
        ax, ay = s._axes
        px, py = ax.basis_hat(wx), ay.basis_hat(wy)
        rx, ry = alias_rest_1d(ax, wx), alias_rest_1d(ay, wy)
        signal = px * py
        x1 = np.sqrt(rx) * np.abs(py)
        x2 = np.abs(px) * np.sqrt(ry)
        diag = np.sqrt(rx) * np.sqrt(ry)
        return [_realify(signal), x1, x2, diag]
    r1, r2, rd = alias_class_sums(s, wx, wy)
    return [_realify(s.basis_hat(wx, wy)), np.sqrt(r1), np.sqrt(r2), np.sqrt(rd)]


def _realify(a):
    a = np.asarray(a)
    if np.iscomplexobj(a) and np.all(np.abs(a.imag) <= 1e-15 * np.maximum(1.0, np.abs(a.real))):
        return a.real
    return a


def _autocorrelation_data(s):
    """Cached: psi at the integers (2-D) and the line-sum refinement data for both axes."""
    cache = s._cache
    if "psi" not in cache:
        a = sy.autocorrelation_mask(s.mask)
        psi = sy.limit_stencil(a)
        cache["psi"] = psi
        cache["line"] = (_line_data(a, psi), _line_data(a.T, psi.T))
    return cache["psi"], cache["line"]


def _line_data(a: np.ndarray, psi: np.ndarray) -> dict:
    """Data for ``G(n1, eta) = int psi(n1, y) exp(-2 pi i eta y) dy`` along axis 0 of the autocorrelation mask ``a``.

    ``coef[n1, n1', k2] = a[2 n1 - n1', k2] / 2`` so that ``G(., eta) = B(eta) G(., eta/2)`` with
    ``B(eta) = coef . exp(-i pi eta k2)``; ``g0 = G(., 0)`` (integer samples of the marginal
    ``int psi(x, y) dy``); ``rows[n1, n2] = psi(n1, n2)``; ``even`` whether ``a`` is even in ``k2`` (then
    ``G(., eps) - G(., 0) = O(eps^2)``); ``factor`` whether every row of ``a`` has alternating sum 0, i.e. the
    mask has a ``(1 + z2)`` factor, so ``phi_hat(xi1, m2) = 0`` for ``m2 != 0`` and ``H(., 0) = 0`` exactly.
    """
    R1, R2 = (a.shape[0] - 1) // 2, (a.shape[1] - 1) // 2
    k2 = sy.centred_offsets(a.shape[1])
    n1 = np.arange(-R1, R1 + 1)
    coef = np.zeros((len(n1), len(n1), a.shape[1]))
    for i, n in enumerate(n1):
        for j, nn in enumerate(n1):
            k1 = 2 * n - nn
            if -R1 <= k1 <= R1:
                coef[i, j] = a[k1 + R1] / 2.0
    marginal = sy.limit_stencil(a.sum(axis=1) / 2.0)
    g0 = np.zeros(len(n1))
    h = (len(marginal) - 1) // 2
    g0[R1 - h: R1 + h + 1] = marginal
    rows = np.zeros((len(n1), 2 * R2 + 1))
    h1, h2 = (psi.shape[0] - 1) // 2, (psi.shape[1] - 1) // 2
    rows[R1 - h1: R1 + h1 + 1, R2 - h2: R2 + h2 + 1] = psi
    tol = 1e-15 * np.abs(a).max()
    even = bool(np.allclose(a, a[:, ::-1], rtol=0, atol=tol))
    factor = bool(np.all(np.abs(a @ (-1.0) ** np.arange(a.shape[1])) <= 16 * tol))
    return dict(coef=coef, k2=k2, g0=g0, n1=n1, rows=rows, n2=np.arange(-R2, R2 + 1), even=even, factor=factor)


def _line_sweep(data: dict, eta_base: np.ndarray, levels: int):
    """``G(., eta_base / 2^t)`` and ``H(., eta_base / 2^t)`` for ``t = 1..levels`` (lists of ``(P, n)``).

    ``H(., eta) = sum_{m2 != 0} G(., eta + m2)`` obeys ``H(., eta) = B(eta + 1) F(., (eta + 1)/2) + B(eta) H(., eta/2)``
    with ``F(n1, theta) = sum_n2 psi(n1, n2) exp(-2 pi i theta n2)`` (all aliases, exact). Both are swept from
    ``eta ~ 0`` (``G(., 0) = g0``; ``H(., 0) = 0`` for masks with a ``(1 + z2)`` factor, else ``F(., 0) - g0``) up to
    the wanted levels, doubling ``eta`` at each step.
    """
    coef, k2, g0, n1 = data["coef"], data["k2"], data["g0"], data["n1"]
    eta_max = np.abs(eta_base).max(initial=0.0)
    tiny = 2.0 ** (-28 if data["even"] else -54)
    deep = max(levels, int(np.ceil(np.log2(max(eta_max, tiny) / tiny))))
    n = len(n1)
    flat = coef.reshape(n * n, len(k2))
    P = len(eta_base)
    g = np.broadcast_to(g0, (P, n)).astype(complex)
    h0 = np.zeros(n) if data["factor"] else data["rows"].sum(axis=1) - g0
    h = np.broadcast_to(h0, (P, n)).astype(complex)
    outg, outh = [None] * (levels + 1), [None] * (levels + 1)

    def B(theta):  # (P, n, n)
        E = np.exp(-1j * np.pi * np.multiply.outer(k2, theta))
        return (flat @ E).reshape(n, n, -1).transpose(2, 0, 1)

    for t in range(deep, 0, -1):
        eta = eta_base / 2.0 ** t  # g, h hold G(., eta), H(., eta)
        if t <= levels:
            outg[t], outh[t] = g, h
        F = np.exp(-2j * np.pi * np.multiply.outer(eta + 0.5, data["n2"])) @ data["rows"].T  # F(., eta + 1/2)
        B2 = B(2.0 * eta)
        h = np.einsum("pij,pj->pi", B(2.0 * eta + 1.0), F) + np.einsum("pij,pj->pi", B2, h)
        g = np.einsum("pij,pj->pi", B2, g)
    return outg[1:], outh[1:]


def alias_class_sums(s, wx, wy):
    """``(R_X1, R_X2, R_D)``: sums of ``|phi_hat(Omega + m)|^2`` over the X1 aliases (``m1 != 0 = m2``), the X2
    aliases (``m2 != 0 = m1``) and the diagonal ones (both non-zero), for any mask.

    Exact recursions in ``Omega -> Omega/2`` (module notes); every class has its own, so no class is
    obtained by subtracting the others and zeros stay zeros (e.g. the diagonal class on the axes).
    """
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)
    psi, (line1, line2) = _autocorrelation_data(s)
    kp1, kp2 = sy.centred_offsets(psi.shape[0]), sy.centred_offsets(psi.shape[1])
    xi_max = max(np.abs(wx).max(initial=0.0), np.abs(wy).max(initial=0.0))
    J = _recursion_depth(xi_max, s.reproduction_degree)
    # line sums need G, H(n1, wy / 2^(j+1)) and G, H(n2, wx / 2^(j+1)) for j < J
    uy, inv_y = np.unique(wy.ravel(), return_inverse=True)
    ux, inv_x = np.unique(wx.ravel(), return_inverse=True)
    G1, H1 = _line_sweep(line1, uy, J)
    G2, H2 = _line_sweep(line2, ux, J)
    n1, n2 = line1["n1"], line2["n1"]
    shape = np.broadcast_shapes(wx.shape, wy.shape)
    R1, R2, RD = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    weight = np.ones(shape)
    for j in range(J):
        x, y = wx / 2.0 ** j, wy / 2.0 ** j
        q0, q1, q2, q3 = (np.abs(s.symbol(x + v1, y + v2) / 4.0) ** 2 for v1, v2 in _SHIFTS)
        S = np.real(trig_sum(psi, kp1, kp2, (x + 1.0) / 2.0, (y + 1.0) / 2.0, 2.0 * np.pi))
        pick_y = lambda A: A[j][inv_y].reshape(wy.shape + (len(n1),))  # noqa: E731  at y/2
        pick_x = lambda A: A[j][inv_x].reshape(wx.shape + (len(n2),))  # noqa: E731  at x/2
        e1 = np.exp(-2j * np.pi * np.multiply.outer((x + 1.0) / 2.0, n1))
        e2 = np.exp(-2j * np.pi * np.multiply.outer((y + 1.0) / 2.0, n2))
        line_1 = np.real(_pair_sum(e1, pick_y(G1)))  # sum_m1 |phi_hat((x+1)/2 + m1, y/2)|^2
        line_2 = np.real(_pair_sum(pick_x(G2), e2))
        off_1 = np.real(_pair_sum(e1, pick_y(H1)))  # same point, all aliases with m2 != 0
        off_2 = np.real(_pair_sum(pick_x(H2), e2))
        R1 = R1 + weight * q1 * line_1
        R2 = R2 + weight * q2 * line_2
        RD = RD + weight * (q3 * S + q1 * off_1 + q2 * off_2)
        weight = weight * q0
    return np.maximum(R1, 0.0), np.maximum(R2, 0.0), np.maximum(RD, 0.0)


def _pair_sum(ex: np.ndarray, ey: np.ndarray):
    """``sum_n ex[..., n] * ey[..., n]`` over the broadcast of their leading shapes (outer grids by matmul)."""
    if ex.ndim == 3 and ey.ndim == 3:
        if ex.shape[0] == 1 and ey.shape[1] == 1:  # ex (1, N, n), ey (M, 1, n) -> (M, N)
            return ey[:, 0, :] @ ex[0].T
        if ex.shape[1] == 1 and ey.shape[0] == 1:  # ex (N, 1, n), ey (1, M, n) -> (N, M)
            return ex[:, 0, :] @ ey[0].T
    if ex.ndim == 2 and ey.ndim == 3 and ey.shape[1] == 1:  # ex (N, n) broadcast as (1, N, n)
        return ey[:, 0, :] @ ex.T
    out = 0.0
    for i in range(ex.shape[-1]):
        out = out + ex[..., i] * ey[..., i]
    return np.asarray(out)
