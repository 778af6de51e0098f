"""The continuous stage against surfaces built without symbols, and explicit alias sums with tail bounds."""

from math import comb, factorial

import numpy as np
import pytest

from cadartifact.theory.catalogue import scheme

OMEGAS = [(0.125, 0.25), (0.375, -0.125), (0.25, 0.25), (0.0, 0.375), (-0.5, 0.125)]


def cardinal_bspline(p, x):
    """Centred cardinal B-spline of degree p (truncated powers), evaluated directly."""
    x = np.asarray(x, dtype=float) + (p + 1) / 2
    return sum((-1) ** k * comb(p + 1, k) * np.maximum(x - k, 0.0) ** p for k in range(p + 2)) / factorial(p)


def periodic_basis(p, n, k):
    """(n k, n) matrix of the periodic uniform B-spline basis of degree p sampled at x = i/k."""
    x = np.arange(n * k) / k
    j = np.arange(n)
    d = (x[:, None] - j[None, :]) % n
    d = np.where(d > n / 2, d - n, d)  # nearest periodic image (support is narrower than n/2)
    return cardinal_bspline(p, d)


def class_amplitudes(spectrum, omega, n, k):
    """RSS of the FFT coefficients at Omega + m per alias class (|m| < k/2)."""
    size = n * k
    F = np.fft.fft2(spectrum) / size ** 2
    m = np.arange(-(k // 2) + 1, k // 2)
    m1, m2 = np.meshgrid(m, m, indexing="ij")
    b1 = (np.rint(omega[0] * n).astype(int) + n * m1) % size
    b2 = (np.rint(omega[1] * n).astype(int) + n * m2) % size
    c = np.abs(F[b1, b2]) ** 2
    x1 = c[(m1 != 0) & (m2 == 0)].sum()
    x2 = c[(m1 == 0) & (m2 != 0)].sum()
    d = c[(m1 != 0) & (m2 != 0)].sum()
    return F[b1[m1 == 0][m2[m1 == 0] == 0], b2[m1 == 0][m2[m1 == 0] == 0]][0], np.sqrt([x1, x2, d])


@pytest.mark.parametrize("p,q,k,tol", [(3, 3, 64, 1e-6), (2, 3, 128, 1e-6), (1, 2, 256, 1e-5)])
def test_continuous_equals_fft_of_directly_evaluated_bspline_surface(p, q, k, tol):
    """Periodic uniform B-spline surface from a sinusoid net, evaluated by its basis functions on a
    fine grid (k samples per control interval), FFT, amplitudes per class: agree to 1e-6 (alias
    folding beyond |m| = k/2 is the only difference; sinc^2 of degree 1 folds ~4e-6 at k = 256)."""
    n = 8
    s = scheme(f"bspline({p},{q})")
    Bu, Bv = periodic_basis(p, n, k), periodic_basis(q, n, k)
    j = np.arange(n)
    for omega in OMEGAS:
        net = np.exp(2j * np.pi * (omega[0] * j[:, None] + omega[1] * j[None, :]))
        surface = Bu @ net @ Bv.T
        signal, amps = class_amplitudes(surface, omega, n, k)
        r = s.response(*omega, "continuous")
        assert abs(signal - r.signal) < tol
        np.testing.assert_allclose(amps, [r.x1, r.x2, r.diagonal], atol=tol)


@pytest.mark.parametrize("name", ["4-3", "4-8", "box(2,2,1,0)", "kobbelt"])
def test_continuous_equals_fft_of_cascade_surface(name):
    """Limit surface on 2^-6 Z^2 by convolving the upsampled net with the space-domain cascade samples."""
    n, L = 8, 6
    s = scheme(name)
    k = 2 ** L
    bs = s.basis_samples(L)
    j = np.arange(n)
    for omega in OMEGAS:
        net = np.exp(2j * np.pi * (omega[0] * j[:, None] + omega[1] * j[None, :]))
        up = np.zeros((n * k, n * k), complex)
        up[::k, ::k] = net
        # circular convolution with phi(offset / k) via FFT (the kernel is placed by its offsets)
        ker = np.zeros((n * k, n * k))
        ker[np.ix_(bs.ix % (n * k), bs.iy % (n * k))] += bs.values
        surface = np.fft.ifft2(np.fft.fft2(up) * np.fft.fft2(ker))
        signal, amps = class_amplitudes(surface, omega, n, k)
        r = s.response(*omega, "continuous")
        assert abs(signal - r.signal) < 1e-7
        np.testing.assert_allclose(amps, [r.x1, r.x2, r.diagonal], atol=1e-6 if name == "kobbelt" else 1e-7)


def _tail(n, M):
    """Bound on sum_{|m| > M} sinc^(2n)(w + m) for |w| <= 1/2: 2 sum_{m > M} (pi (m - 1/2))^(-2n)."""
    return 2.0 / (np.pi ** (2 * n) * (2 * n - 1) * (M - 0.5) ** (2 * n - 1))


@pytest.mark.parametrize("name", ["bilinear", "bicubic", "4-3", "4-8", "box(2,2,1,0)", "box(3,2,0,1)"])
def test_continuous_equals_truncated_alias_sums_within_proven_tail(name):
    """Explicit sums of the closed-form box-spline transform over |m| <= M; the neglected aliases are
    bounded using |sinc| <= 1, sum_m sinc^2(w + m) = 1 and the X1/X2 factors' decay."""
    s = scheme(name)
    n1, n2 = s.arrows[:2]
    M = 150
    m = np.arange(-M, M + 1)
    m1, m2 = np.meshgrid(m, m, indexing="ij")
    for wx, wy in OMEGAS + [(0.01, 0.3), (0.45, 0.45)]:
        c = np.abs(s.basis_hat(wx + m1, wy + m2)) ** 2
        sums = [c[(m1 != 0) & (m2 == 0)].sum(), c[(m1 == 0) & (m2 != 0)].sum(), c[(m1 != 0) & (m2 != 0)].sum()]
        bounds = [_tail(n1, M), _tail(n2, M), _tail(n1, M) + _tail(n2, M)]
        r = s.response(wx, wy, "continuous")
        for got, want, bound in zip(sums, (r.x1 ** 2, r.x2 ** 2, r.diagonal ** 2), bounds):
            assert -1e-15 <= want - got <= bound + 1e-15, (want, got, bound)


def test_limit_vs_continuous_rms():
    """SPEC says sqrt(beta^2 + gamma^2 + delta^2) at refined vertices overstates the continuous RMS
    artifact by 4-40 %. Measured: it overstates for bicubic, 4-8 (about 1-44 %), kobbelt (6-50 %) and
    bilinear (22-68 %); for 4-3 it UNDERSTATES near the diagonal, where the refined-vertex samples
    cancel ripples that the continuous surface has."""
    def ratio(name, w):
        lim = scheme(name).response(*w, "limit")
        con = scheme(name).response(*w, "continuous")  # vectorised over arrays
        return np.sqrt((lim.x1 ** 2 + lim.x2 ** 2 + lim.diagonal ** 2) / (con.x1 ** 2 + con.x2 ** 2 + con.diagonal ** 2))

    expected = {"bilinear": 1.568, "bicubic": 1.186, "4-3": 1.187, "4-8": 1.091, "kobbelt": 1.339}
    for name, value in expected.items():
        assert abs(ratio(name, (0.1, 0.2)) - value) < 1e-3
    w = np.linspace(-0.35, 0.35, 29)
    for name in ("bicubic", "4-8"):
        r = ratio(name, (w[None, :], w[:, None]))[np.hypot(w[None, :], w[:, None]) > 0.02]
        assert 1.0 < r.min() and r.max() < 1.45
    assert ratio("4-3", (0.05, 0.05)) < 0.4  # understated on the diagonal
