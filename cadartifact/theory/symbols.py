"""Low-level array functions behind the scheme catalogue: symbols, limit stencils, cascades.

Everything here works on plain numpy arrays (no scheme objects) and imports numpy only.

Conventions (SPEC §1-2)
-----------------------
* A mask ``m`` is a 2-D array on the refined grid; axis 0 is the X1 (u, x) direction, axis 1
  is X2 (v, y). Its origin is the geometric centre of the array, so entry ``[a, b]`` sits at
  the offset ``k = (a - (s1-1)/2, b - (s2-1)/2)`` (half-integers for even sizes: dual schemes).
* Frequencies are in cycles per control point. The symbol of a mask is
  ``M(theta) = sum_k m_k exp(-i pi theta.k)``; with centred offsets symmetric masks have real
  symbols.
* The refinable function of a mask is ``phi(x) = sum_k m_k phi(2x - k)``; its Fourier transform
  is ``phi_hat(xi) = prod_{j>=0} M(xi / 2^j) / 4``.

Grids
-----
Functions taking ``wx, wy`` broadcast them like numpy. When they form an outer grid --
``wx`` of shape ``(1, N)`` (or ``(N,)``) with ``wy`` of shape ``(M, 1)``, or the transposed layout
``wx (N, 1)``, ``wy (1, M)`` -- sums over mask entries are evaluated as two small matrix products
``E_y m^T E_x^T`` instead of one exponential per entry per point.
"""

from __future__ import annotations

from math import comb

import numpy as np

__all__ = [
    "centred_offsets",
    "trig_sum",
    "mask_symbol",
    "box_mask",
    "box_symbol",
    "box_basis_hat",
    "bspline_row",
    "tensor_factors",
    "detect_box_arrows",
    "local_subdivision_matrix",
    "integer_samples",
    "cascade",
    "limit_stencil",
    "shifted_samples",
    "trim_symmetric",
    "sum_rule_order",
    "autocorrelation_mask",
    "ConvergenceError",
]

#: Entries below this fraction of the largest are treated as exact zeros in derived stencils.
ZERO_RTOL = 1e-15

#: Tolerance on the eigenvalue 1 of the local subdivision matrix and on the gap below it (loose
#: enough that a defective double eigenvalue 1, which eig splits by ~sqrt(eps), counts as double).
EIGEN_TOL = 1e-6


class ConvergenceError(ValueError):
    """The local subdivision matrix has no simple, dominant eigenvalue 1 (internal; catalogue.py
    turns it into a one-line SchemeError)."""


# ------------------------------------------------------------------ trigonometric sums
def centred_offsets(size: int) -> np.ndarray:
    """Offsets ``a - (size-1)/2`` of the entries of a centred axis of length ``size``."""
    return np.arange(size) - (size - 1) / 2.0


def _grid_layout(wx: np.ndarray, wy: np.ndarray):
    """``(x, y, transposed)`` when ``wx, wy`` broadcast as an outer grid, else None.

    ``transposed`` is False for ``out[i, j] = f(wx[j], wy[i])`` (``wx`` a row) and True for
    ``out[i, j] = f(wx[i], wy[j])`` (``wx`` a column).
    """
    if wy.ndim == 2 and wy.shape[1] == 1 and (wx.ndim == 1 or (wx.ndim == 2 and wx.shape[0] == 1)):
        return wx.reshape(-1), wy[:, 0], False
    if wx.ndim == 2 and wy.ndim == 2 and wx.shape[1] == 1 and wy.shape[0] == 1:
        return wx[:, 0], wy[0], True
    return None


def _symmetry(coef: np.ndarray) -> tuple[bool, bool, bool]:
    """(point, axis0, axis1) symmetry of a centred coefficient array, to rounding."""
    tol = 1e-14 * (np.abs(coef).max() if coef.size else 0.0)
    point = bool(np.all(np.abs(coef - coef[::-1, ::-1]) <= tol))
    axis0 = bool(np.all(np.abs(coef - coef[::-1, :]) <= tol))
    axis1 = bool(np.all(np.abs(coef - coef[:, ::-1]) <= tol))
    return point, axis0, axis1


def trig_sum(coef, k1, k2, wx, wy, scale: float = np.pi):
    """Trigonometric sum ``sum_{a,b} coef[a,b] exp(-i scale (wx k1[a] + wy k2[b]))``.

    Parameters
    ----------
    coef : (s1, s2) float
        Coefficients (a mask, a stencil).
    k1 : (s1,) float, k2 : (s2,) float
        Offsets of the rows and columns; must be symmetric about 0 for the real fast path.
    wx, wy : array_like float
        Frequencies, broadcast together (outer grids are detected, see module notes).
    scale : float
        ``pi`` for symbols of refined-grid masks, ``2 pi`` for DTFTs of integer samples.

    Returns
    -------
    out : float or complex array of the broadcast shape
        Real when ``coef`` is point-symmetric about the origin (and the offsets are symmetric),
        because the sum is then ``sum coef cos(...)``.
    """
    coef = np.asarray(coef, dtype=float)
    k1 = np.asarray(k1, dtype=float)
    k2 = np.asarray(k2, dtype=float)
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)
    point, axis0, axis1 = _symmetry(coef)
    real = point and np.allclose(k1, -k1[::-1]) and np.allclose(k2, -k2[::-1])
    grid = _grid_layout(wx, wy)
    if grid is not None:
        x, y, transposed = grid
        px = scale * np.multiply.outer(x, k1)
        py = scale * np.multiply.outer(y, k2)
        if real:
            out = (np.cos(py) @ coef.T) @ np.cos(px).T
            # the sine-sine part vanishes when the mask is even along either axis
            if not (axis0 or axis1):
                out -= (np.sin(py) @ coef.T) @ np.sin(px).T
        else:
            out = (np.exp(-1j * py) @ coef.T) @ np.exp(-1j * px).T
        return out.T if transposed else out
    ex = np.exp(-1j * scale * np.multiply.outer(wx, k1))
    ey = np.exp(-1j * scale * np.multiply.outer(wy, k2))
    inner = ey @ coef.T  # wy.shape + (s1,)
    out = 0.0
    for a in range(coef.shape[0]):
        out = out + ex[..., a] * inner[..., a]
    out = np.asarray(out)
    return out.real if real else out


def mask_symbol(mask, wx, wy, centre=None):
    """Symbol ``M(theta) = sum_k m_k exp(-i pi theta.k)`` of a refined-grid mask.

    Parameters
    ----------
    mask : (s1, s2) float
        The mask; axis 0 is X1.
    wx, wy : array_like float
        ``theta`` in cycles per control point, broadcast together.
    centre : (float, float), optional
        Array position of the origin; default the geometric centre ``((s1-1)/2, (s2-1)/2)``.

    Returns
    -------
    M : float or complex array
        Real for masks symmetric about the centre (e.g. bspline degree p: ``4 cos(pi wx/2)^(p+1) ...``).

    References
    ----------
    SPEC §2; Augsdörfer, Dodgson, Sabin, "Artifact analysis on B-splines, box-splines and other
    surfaces defined by quadrilateral polyhedra", CAGD 28 (2011), §3.
    """
    mask = np.asarray(mask, dtype=float)
    s1, s2 = mask.shape
    c1, c2 = ((s1 - 1) / 2.0, (s2 - 1) / 2.0) if centre is None else centre
    return trig_sum(mask, np.arange(s1) - c1, np.arange(s2) - c2, wx, wy, np.pi)


# ------------------------------------------------------------------ box splines and B-splines
_BOX_FACTORS = (
    np.array([[0.5], [0.5]]),  # X1
    np.array([[0.5, 0.5]]),  # X2
    np.array([[0.5, 0.0], [0.0, 0.5]]),  # X1 + X2
    np.array([[0.0, 0.5], [0.5, 0.0]]),  # X1 - X2
)


def _convolve2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0] + b.shape[0] - 1, a.shape[1] + b.shape[1] - 1))
    for i in range(b.shape[0]):
        for j in range(b.shape[1]):
            if b[i, j] != 0.0:
                out[i:i + a.shape[0], j:j + a.shape[1]] += b[i, j] * a
    return out


def box_mask(n1: int, n2: int, n3: int, n4: int) -> np.ndarray:
    """Mask of the box-spline scheme with arrows ``(n1, n2, n3, n4)``.

    ``M(z) = 4 ((1+z1)/2)^n1 ((1+z2)/2)^n2 ((1+z1 z2)/2)^n3 ((1+z2/z1)/2)^n4`` (SPEC §2), an array
    of shape ``(n1+n3+n4+1, n2+n3+n4+1)`` summing to 4.
    """
    m = np.array([[4.0]])
    for f, n in zip(_BOX_FACTORS, (n1, n2, n3, n4)):
        for _ in range(int(n)):
            m = _convolve2(m, f)
    return m


def _ipow(a: np.ndarray, n: int) -> np.ndarray:
    """``a**n`` for a small non-negative integer by multiplication (faster than pow on big arrays)."""
    if n == 0:
        return np.ones_like(a)
    out = None
    base = a
    while n:
        if n & 1:
            out = base if out is None else out * base
        n >>= 1
        if n:
            base = base * base
    return out


def box_symbol(arrows, wx, wy) -> np.ndarray:
    """Closed-form symbol of a box-spline mask: ``4 prod_d cos(pi theta.d / 2)^(n_d)``.

    Parameters
    ----------
    arrows : (int, int, int, int)
        ``(n1, n2, n3, n4)`` along X1, X2, X1+X2, X1-X2.
    wx, wy : array_like float
        ``theta`` in cycles per control point (outer grids use 1-D cosines only:
        ``cos(A+B) = cos A cos B - sin A sin B``).

    Returns
    -------
    M : float array of the broadcast shape
    """
    n1, n2, n3, n4 = (int(n) for n in arrows)
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)
    grid = _grid_layout(wx, wy)
    if grid is None:
        ax, ay = 0.5 * np.pi * wx, 0.5 * np.pi * wy
        out = 4.0 * _ipow(np.cos(ax), n1) * _ipow(np.cos(ay), n2)
        if n3:
            out = out * _ipow(np.cos(ax + ay), n3)
        if n4:
            out = out * _ipow(np.cos(ax - ay), n4)
        return out
    x, y, transposed = grid
    cx, sx = np.cos(0.5 * np.pi * x), np.sin(0.5 * np.pi * x)
    cy, sy = np.cos(0.5 * np.pi * y), np.sin(0.5 * np.pi * y)
    out = np.multiply.outer(4.0 * _ipow(cy, n2), _ipow(cx, n1))
    if n3 and n3 == n4:
        # cos(A+B) cos(A-B) = cos^2 A - sin^2 B
        out *= _ipow(np.subtract.outer(-sy * sy, -cx * cx), n3)
    else:
        if n3:
            out *= _ipow(np.multiply.outer(cy, cx) - np.multiply.outer(sy, sx), n3)
        if n4:
            out *= _ipow(np.multiply.outer(cy, cx) + np.multiply.outer(sy, sx), n4)
    return out.T if transposed else out


def box_basis_hat(arrows, wx, wy) -> np.ndarray:
    """Fourier transform of the centred box spline: ``prod_d sinc(xi.d)^(n_d)``, ``sinc x = sin(pi x)/(pi x)``."""
    n1, n2, n3, n4 = (int(n) for n in arrows)
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)
    out = _ipow(np.sinc(wx), n1) * _ipow(np.sinc(wy), n2)
    if n3:
        out = out * _ipow(np.sinc(wx + wy), n3)
    if n4:
        out = out * _ipow(np.sinc(wx - wy), n4)
    return out


def bspline_row(degree: int) -> np.ndarray:
    """1-D mask of the uniform B-spline of ``degree``: binomial row of length ``degree+2`` summing to 2."""
    return np.array([comb(degree + 1, i) for i in range(degree + 2)], dtype=float) / 2.0 ** degree


def tensor_factors(mask: np.ndarray, rtol: float = 1e-13):
    """``(u, v)`` with ``mask = outer(u, v)`` and ``sum u = sum v = 2``, or None when not rank one."""
    mask = np.asarray(mask, dtype=float)
    u = mask.sum(axis=1) / 2.0
    v = mask.sum(axis=0) / 2.0
    if abs(u.sum() - 2.0) > 1e-9:
        return None
    if np.max(np.abs(np.outer(u, v) - mask)) > rtol * np.abs(mask).max():
        return None
    return u, v


def detect_box_arrows(mask: np.ndarray, atol: float = 1e-12):
    """The arrows ``(n1, n2, n3, n4)`` when ``mask`` equals a box-spline mask, else None."""
    mask = np.asarray(mask, dtype=float)
    s1, s2 = mask.shape
    for n3 in range(min(s1, s2)):
        for n4 in range(min(s1, s2) - n3):
            n1, n2 = s1 - 1 - n3 - n4, s2 - 1 - n3 - n4
            if n1 < 0 or n2 < 0:
                continue
            if np.allclose(box_mask(n1, n2, n3, n4), mask, rtol=0, atol=atol):
                return (n1, n2, n3, n4)
    return None


# ------------------------------------------------------------------ refinable functions in space
def local_subdivision_matrix(mask: np.ndarray) -> np.ndarray:
    """``S[n, j] = m[2n - j]`` over the integer points ``n, j`` of ``[0, s1-1] x [0, s2-1]``.

    With array (uncentred) indices the refinable function ``phi~(x) = sum_a m_a phi~(2x - a)`` is
    supported on that box, and its integer samples satisfy ``v = S v``. Works for 1-D masks too.
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    shape = mask.shape
    pts = np.stack(np.meshgrid(*[np.arange(s) for s in shape], indexing="ij"), axis=-1).reshape(-1, len(shape))
    n = len(pts)
    S = np.zeros((n, n))
    for row, p in enumerate(pts):
        a = 2 * p[None, :] - pts  # mask index for every column j
        ok = np.all((a >= 0) & (a < np.array(shape)), axis=1)
        S[row, ok] = mask[tuple(a[ok].T)]
    return S


def integer_samples(mask: np.ndarray) -> np.ndarray:
    """Samples of ``phi~`` (uncentred refinable function) at the integers of its support box.

    The eigenvector of :func:`local_subdivision_matrix` for eigenvalue 1, normalised to sum 1.

    Raises
    ------
    ConvergenceError
        When eigenvalue 1 is not simple, or another eigenvalue has modulus >= 1, or the
        eigenvector sums to 0 (no limit stencil).
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    S = local_subdivision_matrix(mask)
    lam, vec = np.linalg.eig(S)
    near_one = np.abs(lam - 1.0) < EIGEN_TOL
    order = np.argsort(-np.abs(lam))
    if near_one.sum() != 1:
        mods = ", ".join(f"{abs(x):.4g}" for x in lam[order][:4])
        raise ConvergenceError(f"eigenvalue 1 of the local subdivision matrix is not simple "
                               f"(largest moduli {mods})")
    others = np.abs(lam[~near_one])
    if others.size and others.max() >= 1.0 - EIGEN_TOL:
        raise ConvergenceError(f"the local subdivision matrix has an eigenvalue of modulus "
                               f"{others.max():.4g} >= 1 besides 1")
    v = np.real(vec[:, np.argmax(near_one)])
    if abs(v.sum()) < 1e-8 * np.abs(v).max():
        raise ConvergenceError("the eigenvector of eigenvalue 1 sums to 0: no limit stencil")
    # polish by power iteration (eig leaves ~1e-14 residuals on larger matrices; the other
    # eigenvalues are < 1 in modulus, so v <- S v / sum contracts towards the exact eigenvector)
    v = v / v.sum()
    for _ in range(500):
        w = S @ v
        w /= w.sum()
        done = np.abs(w - v).max() <= 1e-17 * np.abs(w).max()
        v = w
        if done:
            break
    v[np.abs(v) < ZERO_RTOL * np.abs(v).max()] = 0.0
    return (v / v.sum()).reshape(mask.shape)


def cascade(mask: np.ndarray, samples: np.ndarray, levels: int) -> np.ndarray:
    """Refine integer samples of ``phi~`` to the grid ``Z / 2^levels`` (space-domain cascade).

    ``phi~(i / 2^(l+1)) = sum_a m_a phi~(i / 2^l - a)``: level ``l+1`` is the level-``l`` array
    convolved with the mask dilated by ``2^l``.

    Parameters
    ----------
    mask : (s1, s2) float (or 1-D)
    samples : array of the mask's shape
        ``phi~`` at the integers ``[0, s-1]``.
    levels : int

    Returns
    -------
    f : ((s1-1) 2^L + 1, (s2-1) 2^L + 1) float
        ``f[i, j] = phi~(i / 2^L, j / 2^L)``.
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    f = np.asarray(samples, dtype=float)
    shape = mask.shape
    for level in range(levels):
        step = 2 ** level
        new_shape = tuple((s - 1) * 2 * step + 1 for s in shape)
        out = np.zeros(new_shape)
        for a in np.ndindex(*shape):
            w = mask[a]
            if w == 0.0:
                continue
            # out[i] += w * f[i - step a]; f's index range [0, (s-1) step] shifted by step a
            sl = tuple(slice(step * ai, step * ai + fs) for ai, fs in zip(a, f.shape))
            out[sl] += w * f
        f = out
    return f


def trim_symmetric(arr: np.ndarray, rtol: float = ZERO_RTOL) -> np.ndarray:
    """Remove zero border pairs (first and last row/column together) so the centre stays put."""
    arr = np.asarray(arr, dtype=float)
    tol = rtol * np.abs(arr).max()
    for axis in range(arr.ndim):
        while arr.shape[axis] > 2:
            first = np.take(arr, 0, axis=axis)
            last = np.take(arr, -1, axis=axis)
            if np.all(np.abs(first) <= tol) and np.all(np.abs(last) <= tol):
                arr = np.take(arr, np.arange(1, arr.shape[axis] - 1), axis=axis)
            else:
                break
    return arr


def shifted_samples(mask: np.ndarray, samples: np.ndarray, shift) -> np.ndarray:
    """Samples of the centred ``phi`` at ``Z + shift`` per axis (``shift`` 0 or 1/2), trimmed.

    ``phi(x) = phi~(x + c)``, ``c = (s-1)/2``; one cascade level gives ``phi~`` on ``Z/2``,
    and the wanted points are the level-1 indices ``i`` with ``i = s - 1 + 2 shift (mod 2)``.
    The result is symmetric about the origin in position (odd length for shift 0, even for 1/2).
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    f1 = cascade(mask, samples, 1)
    idx = []
    for s, sh in zip(mask.shape, np.broadcast_to(shift, (mask.ndim,))):
        start = (s - 1 + int(round(2 * sh))) % 2
        idx.append(np.arange(start, 2 * (s - 1) + 1, 2))
    out = f1[np.ix_(*idx)]
    out[np.abs(out) < ZERO_RTOL * np.abs(out).max()] = 0.0
    return trim_symmetric(out)


def limit_stencil(mask: np.ndarray) -> np.ndarray:
    """Limit stencil of a convergent mask: ``phi`` (centred) sampled at the integers, trimmed.

    The limit point at refined vertex ``P`` is ``sum_n L_n R_{P-n}`` (a convolution). For a
    primal (odd-size) axis these are the eigenvector entries themselves; for a dual (even-size)
    axis one cascade step moves them to the integers of the centred function.

    Raises
    ------
    ConvergenceError
        See :func:`integer_samples`.
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    v = integer_samples(mask)
    L = shifted_samples(mask, v, 0.0)
    return L / L.sum()


def autocorrelation_mask(mask: np.ndarray) -> np.ndarray:
    """Mask of ``psi = phi * phi(-.)``: ``a_k = sum_j m_j m_(j-k) / 2^dim``, odd size, symbol ``|M|^2 / 2^dim``.

    ``psi_hat = |phi_hat|^2`` and ``psi`` is refinable with this mask, so ``psi`` at the integers
    (its limit stencil) gives ``sum_m |phi_hat(xi + m)|^2 = sum_n psi(n) exp(-2 pi i xi.n)``.
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    if mask.ndim == 1:
        return np.convolve(mask, mask[::-1]) / 2.0
    return _convolve2(mask, mask[::-1, ::-1]) / 4.0


def sum_rule_order(mask: np.ndarray, max_degree: int = 24, rtol: float = 1e-9) -> int:
    """Largest ``d`` such that ``M(Omega + V)`` vanishes to order ``d+1`` at 0 for every ``V != 0``.

    Equivalently the modulated moments ``sum_a m_a (-1)^(V.a) k^alpha`` vanish for ``|alpha| <= d``
    (``k`` centred offsets), for each non-zero parity coset ``V``. Returns -1 when even the
    coset sums differ. Works for 1-D masks (``V = 1``) and 2-D masks (``V in {X1, X2, X1+X2}``).
    """
    mask = np.atleast_1d(np.asarray(mask, dtype=float))
    grids = np.meshgrid(*[np.arange(s) for s in mask.shape], indexing="ij")
    offs = [g - (s - 1) / 2.0 for g, s in zip(grids, mask.shape)]
    scale = max(1.0, max(np.abs(o).max() for o in offs))
    offs = [o / scale for o in offs]
    if mask.ndim == 1:
        signs = [(-1.0) ** grids[0]]
        exps = lambda q: [(q,)]  # noqa: E731
    else:
        signs = [(-1.0) ** grids[0], (-1.0) ** grids[1], (-1.0) ** (grids[0] + grids[1])]
        exps = lambda q: [(i, q - i) for i in range(q + 1)]  # noqa: E731
    total = np.abs(mask).sum()
    d = -1
    for q in range(max_degree + 1):
        for sign in signs:
            for alpha in exps(q):
                mom = np.sum(mask * sign * np.prod([o ** e for o, e in zip(offs, alpha)], axis=0))
                if abs(mom) > rtol * total:
                    return d
        d = q
    return d
