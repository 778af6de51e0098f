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

import numpy as np

from .fields import Axis, bandlimited_basis_real

__all__ = ["AxisModel", "axis_model", "ripple_part", "sandwich", "tensor_error"]


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

    def limit_coef(self) -> np.ndarray:
        """``(m, m)``: Legendre coefficients of a trend -> those of its limit surface (exact: degree kept).

        The limit at integer ``J`` is ``sum_a s[a] trend(J + r - a)`` (the trend extends as a
        polynomial past the net); it is sampled on enough integers to fit exactly.
        """
        if "lc" in self._memo:
            return self._memo["lc"]
        m = self.degree + 1
        if self.stencil is None or m == 1:
            coef = np.eye(m)
        else:
            s = np.asarray(self.stencil, float)
            r = len(s) // 2
            M = max(self.n, m + 1)
            pad = _legvander(np.arange(-r, M + r), self.span, self.degree)  # (M+2r, m)
            # lim[J] = sum_a s[a] trend(J + r - a), as fields._trend_limit_coef
            lim = np.stack([np.convolve(pad[:, j], s, mode="valid") for j in range(m)], axis=1)  # (M, m)
            coef = np.linalg.pinv(_legvander(np.arange(M), self.span, self.degree)) @ lim
        self._memo["lc"] = coef
        return coef

    def fine_vander(self, levels: int) -> np.ndarray:
        """``(fine, m)``: the Legendre basis (this axis's scaling) on the fine grid."""
        return _legvander(Axis(self.n, self.periodic, levels).x, self.span, self.degree)

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



def ripple_part(err: np.ndarray, au: Axis, av: Axis) -> np.ndarray:
    """``err`` minus its base band (``|fx|, |fy| < 1/2``): the band split's low-pass, one axis at a time.

    The base-band mask is a product of per-axis masks, so two passes of 1-D FFTs (after the same
    extension as the band split: even reflection or wrap) equal the 2-D masked FFT.
    """
    low = err
    for axis, ax in ((0, au), (1, av)):
        n = low.shape[axis]
        f = ax.freqs(fine=True)
        keep = (np.abs(f) < 0.5 - 1e-12).reshape((-1, 1, 1) if axis == 0 else (1, -1, 1))
        spec = np.fft.fft(ax.extend(low, axis), axis=axis) * keep
        low = np.take(np.fft.ifft(spec, axis=axis).real, np.arange(n), axis=axis)
    return err - low


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

    The resampled net is today's trend plus today's band-limited residual at the new positions
    (SPEC §5); its surface is the trend's limit polynomial plus the residual synthesised through the
    scheme's transfer function.

    Parameters
    ----------
    P : (nu, nv, 3) float
        Today's control points.
    old, new : (AxisModel, AxisModel)
        Today's axes, and the candidate's axes built with TODAY's trend degrees.
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
    C = sandwich(ou.Vp, P, ov.Vp)  # trend coefficients (mu, mv, 3)
    R = P - sandwich(ou.Vn, C, ov.Vn)
    N_res = sandwich(ou.bandlimited(x_new[0]), R, ov.bandlimited(x_new[1]))
    surf = sandwich(nu_.fine_vander(levels) @ nu_.limit_coef(), C, nv_.fine_vander(levels) @ nv_.limit_coef()) + \
        sandwich(nu_.synthesis(levels), N_res, nv_.synthesis(levels))
    Fu, Gu = ou.intent(x_fine_old[0])
    Fv, Gv = ov.intent(x_fine_old[1])
    target = sandwich(Fu, P, Fv) + sandwich(Gu, R, Gv)
    err = surf - target
    if ripple:
        err = ripple_part(err, Axis(nu_.n, nu_.periodic, levels), Axis(nv_.n, nv_.periodic, levels))
    return err, target
