"""Periodic subdivision simulated numerically: the independent road of tests/theory/test_bruteforce.py and
tests/theory/test_design.py.

Nothing here uses a symbol: nets ``A_J = exp(2 pi i Omega.J)`` on an ``N x N`` torus (``Omega`` on the ``1/N``
grid so they are exactly periodic) are upsampled with zeros, circularly convolved with the mask, and projected by
inner products onto ``exp(i pi (Omega + V).x)`` at the refined positions ``x`` (SPEC §3 check list).
"""

import numpy as np

#: The four modulations' shifts ``V`` of a refinement step.
SHIFTS = ((0, 0), (1, 0), (0, 1), (1, 1))


def sinusoid_nets(omegas, n):
    """The nets ``exp(2 pi i Omega.J)`` on an ``n x n`` torus, one per row of ``omegas (K, 2)``."""
    j = np.arange(n)
    return np.exp(2j * np.pi * (omegas[:, 0, None, None] * j[None, :, None] + omegas[:, 1, None, None] * j[None, None, :]))


def circular_convolve(values, kernel):
    """``out[P] = sum_a kernel[a] values[P - a]`` on the torus (batch axis 0); array indices of the kernel."""
    out = np.zeros_like(values)
    for a in range(kernel.shape[0]):
        for b in range(kernel.shape[1]):
            if kernel[a, b] != 0:
                out += kernel[a, b] * np.roll(values, (a, b), axis=(1, 2))
    return out


def subdivide(nets, mask, steps=1):
    """``steps`` periodic subdivision steps; level-L index Q sits at ``Q - (2^L - 1) c`` level-L units."""
    out = nets
    for _ in range(steps):
        up = np.zeros((out.shape[0], 2 * out.shape[1], 2 * out.shape[2]), complex)
        up[:, ::2, ::2] = out
        out = circular_convolve(up, mask)
    return out


def project(values, freqs, positions):
    """Inner products of ``values (K, M1, M2)`` with ``exp(2 pi i f.x)`` for ``freqs (K, 2)`` (cycles per unit)."""
    p1, p2 = positions
    e = np.exp(-2j * np.pi * (freqs[:, 0, None, None] * p1[None, :, None] + freqs[:, 1, None, None] * p2[None, None, :]))
    return (values * e).mean(axis=(1, 2))


def omega_grid(n):
    """The frequencies ``k / n`` (``k`` in ``-n/2 .. n/2``) of the whole Nyquist square, as ``(K, 2)``."""
    k = np.arange(-(n // 2), n // 2 + 1)
    return np.stack(np.meshgrid(k, k, indexing="ij"), axis=-1).reshape(-1, 2) / n
