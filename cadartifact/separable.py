"""Fast artifact of a resampled net for tensor-product schemes: per-axis linear operators.

For a tensor-product scheme every step of :func:`cadartifact.advisor.artifact_at` is linear
and acts on each axis separately: the (tensor-degree) trend fit, the band-limited interpolant
of the residual (even reflection / wrap), resampling, the limit surface of the new net (trend
through the limit stencil, residual through the 1-D transfer function) and the low-pass of the
band split. So the error field is a short sum of ``A P B^T`` products of small real matrices,
computed with BLAS instead of large complex FFTs. The FFT path in :mod:`cadartifact.fields` is
the reference; a test keeps the two equal.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .fields import Axis, bandlimited_basis_real

__all__ = ["AxisModel", "axis_model", "sandwich", "tensor_error"]


def sandwich(A: np.ndarray, P: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A P B^T`` for each coordinate: ``A (a, n)``, ``P (n, m, c)``, ``B (b, m)`` -> ``(a, b, c)``."""
    n, m, c = P.shape
    tmp = (A @ P.reshape(n, m * c)).reshape(A.shape[0], m, c)  # (a, m, c)
    return np.tensordot(tmp, B, axes=(1, 1)).transpose(0, 2, 1)  # (a, b, c)


def _legvander(x: np.ndarray, span: float, degree: int) -> np.ndarray:
    from numpy.polynomial import legendre as L

    return L.legvander(2 * np.asarray(x, float) / max(span, 1e-300) - 1, degree)


class AxisModel:
    """One axis of a net under a 1-D scheme factor: trend, band-limited interpolation, synthesis.

    Parameters
    ----------
    n : int
        Control points.
    periodic : bool
    degree : int
        Trend degree along this axis (0 when periodic).
    transfer : callable
        ``transfer(xi, levels)``: the 1-D factor of the scheme's transfer function.
    stencil : (s,) float
        The 1-D limit stencil (odd size), or None for no polynomial signal error (dual axes).
    """

    def __init__(self, n, periodic, degree, transfer, stencil):
        self.n, self.periodic, self.degree = n, periodic, degree
        self.transfer, self.stencil = transfer, stencil
        self._memo: dict = {}
        self.span = float(max(n - 1, 1))
        self.N = n if periodic else 2 * (n - 1)
        self.Vn = _legvander(np.arange(n), self.span, degree)
        self.Vp = np.linalg.pinv(self.Vn)
        self.T_old = self.Vn @ self.Vp
        # DFT of the extended unit vectors: (N, n)
        ext = np.eye(n) if periodic else np.concatenate([np.eye(n), np.eye(n)[1:n - 1][::-1]], axis=0)
        self.F = np.fft.fft(ext, axis=0)
        self.Fr, self.Fi = np.ascontiguousarray(self.F.real), np.ascontiguousarray(self.F.imag)
        f = np.fft.fftfreq(self.N)
        self.f = f

    def trend(self, x) -> np.ndarray:
        """``(len(x), n)``: samples -> trend polynomial at ``x``."""
        return _legvander(x, self.span, self.degree) @ self.Vp

    def bandlimited(self, x) -> np.ndarray:
        """``(len(x), n)``: residual samples -> their band-limited interpolant at ``x``."""
        C, S = bandlimited_basis_real(x, self.f)
        return C @ self.Fr - S @ self.Fi

    def intent(self, x) -> tuple[np.ndarray, np.ndarray]:
        """The two factors ``(Tx, Bx)`` with intent = ``Tx P Ty^T + Bx R By^T``, ``R`` the residual."""
        return self.trend(x), self.bandlimited(x)

    def limit_trend(self, levels: int) -> np.ndarray:
        """``(fine, n)``: samples -> limit surface of their trend polynomial on the fine grid."""
        if ("lt", levels) in self._memo:
            return self._memo[("lt", levels)]
        ax = Axis(self.n, self.periodic, levels)
        m = self.degree + 1
        if self.stencil is None or m == 1:
            coef = np.eye(m)
        else:
            s = np.asarray(self.stencil, float)
            r = len(s) // 2
            pad = _legvander(np.arange(-r, self.n + r), self.span, self.degree)  # (n+2r, m)
            # lim[J] = sum_a s[a] trend(J + r - a), as fields._trend_limit_coef
            lim = np.stack([np.convolve(pad[:, j], s, mode="valid") for j in range(m)], axis=1)  # (n, m)
            coef = self.Vp @ lim
        out = self._memo[("lt", levels)] = _legvander(ax.x, self.span, self.degree) @ coef @ self.Vp
        return out

    def synthesis(self, levels: int) -> np.ndarray:
        """``(fine, n)``: residual samples -> predicted limit surface (1-D transfer) on the fine grid."""
        if ("syn", levels) in self._memo:
            return self._memo[("syn", levels)]
        ax = Axis(self.n, self.periodic, levels)
        K = ax.K
        xi = ax.freqs(fine=True)
        spec = np.tile(self.F, (K, 1)) * (K * self.transfer(xi, levels))[:, None]
        out = self._memo[("syn", levels)] = np.fft.ifft(spec, axis=0).real[: ax.fine_count]
        return out

    @staticmethod
    @lru_cache(maxsize=256)
    def lowpass(n: int, periodic: bool, levels: int) -> np.ndarray:
        """``(fine, fine)``: the base band (``|f| < 1/2``) of a fine-grid field, as the band split defines it."""
        ax = Axis(n, periodic, levels)
        a = ax.fine_count
        eye = np.eye(a)
        ext = ax.extend(eye, 0)
        f = ax.freqs(fine=True)
        keep = (np.abs(f) < 0.5 - 1e-12)[:, None]
        return np.fft.ifft(np.fft.fft(ext, axis=0) * keep, axis=0).real[:a]


_MODELS: dict = {}


def axis_model(scheme, axis: int, n: int, periodic: bool, degree: int) -> AxisModel:
    """The (cached) :class:`AxisModel` of one axis of a tensor-product scheme."""
    key = (scheme.name, axis, n, periodic, degree)
    model = _MODELS.get(key)
    if model is None:
        st = np.asarray(scheme.limit_stencil, float).sum(axis=1 - axis)
        stencil = st if len(st) % 2 == 1 else None
        if axis == 0:
            transfer = lambda xi, L: np.asarray(scheme.transfer(xi, np.zeros_like(xi), L), float)  # noqa: E731
        else:
            transfer = lambda xi, L: np.asarray(scheme.transfer(np.zeros_like(xi), xi, L), float)  # noqa: E731
        if len(_MODELS) > 512:
            _MODELS.clear()
        model = _MODELS[key] = AxisModel(n, periodic, degree, transfer, stencil)
    return model


def tensor_error(P: np.ndarray, old: tuple, new: tuple, x_new: tuple, x_fine_old: tuple, levels: int,
                 ripple: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Error ``surface(n') - intent`` (and its ripple) on the new net's fine grid, by per-axis operators.

    Parameters
    ----------
    P : (nu, nv, 3) float
        Today's control points.
    old, new : (AxisModel, AxisModel)
        Today's and the candidate's axes.
    x_new : ((a,) float, (b,) float)
        The new control points' positions in today's index space.
    x_fine_old : ((A,) float, (B,) float)
        The new fine grid's positions in today's index space.

    Returns
    -------
    (err, target) : ((A, B, 3) float, (A, B, 3) float)
        ``err`` is the ripple part when ``ripple`` (else the whole error); ``target`` today's intent.
    """
    ou, ov = old
    nu_, nv_ = new
    R = P - sandwich(ou.T_old, P, ov.T_old)
    Tu, Bu = ou.intent(x_new[0])
    Tv, Bv = ov.intent(x_new[1])
    N = sandwich(Tu, P, Tv) + sandwich(Bu, R, Bv)
    R2 = N - sandwich(nu_.T_old, N, nv_.T_old)
    surf = sandwich(nu_.limit_trend(levels), N, nv_.limit_trend(levels)) + \
        sandwich(nu_.synthesis(levels), R2, nv_.synthesis(levels))
    Fu, Gu = ou.intent(x_fine_old[0])
    Fv, Gv = ov.intent(x_fine_old[1])
    target = sandwich(Fu, P, Fv) + sandwich(Gu, R, Gv)
    err = surf - target
    if ripple:
        err = err - sandwich(AxisModel.lowpass(nu_.n, nu_.periodic, levels), err,
                             AxisModel.lowpass(nv_.n, nv_.periodic, levels))
    return err, target
