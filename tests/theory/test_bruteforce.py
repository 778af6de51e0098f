"""Independent road: subdivide periodic sinusoid nets numerically and project onto the modulations
(cadartifact/testing/periodic_nets.py).

Nothing here uses a symbol: nets ``A_J = exp(2 pi i Omega.J)`` on an ``N x N`` torus (``Omega`` on the
``1/N`` grid so they are exactly periodic) are upsampled with zeros, circularly convolved with the
mask (and the limit stencil), and the result is projected by inner products onto
``exp(i pi (Omega + V).x)`` at the refined positions ``x`` (SPEC §3 check list).
"""

import numpy as np
import pytest

from cadartifact.testing.periodic_nets import SHIFTS, circular_convolve, omega_grid, project, sinusoid_nets, subdivide
from cadartifact.theory.catalogue import SCHEME_NAMES, Scheme, scheme


def skew_scheme():
    """A mask that is not point-symmetric (complex symbols, a non-symmetric limit stencil)."""
    m = np.array(scheme("bicubic").mask)
    m[0, 1] += 0.02
    m[2, 1] -= 0.02
    m[3, 4] += 0.01
    m[1, 4] -= 0.01
    return Scheme.from_mask(m, "skew")


SCHEMES = list(SCHEME_NAMES) + ["bspline(2,3)", "bspline(2,2)", "bspline(4,1)", "box(2,2,1,0)",
                                "box(2,2,2,0)", "box(3,2,0,1)", "skew"]


def get(name):
    return skew_scheme() if name == "skew" else scheme(name)


@pytest.mark.parametrize("name", SCHEMES)
def test_one_step_and_limit_equal_simulation(name):
    """Over the whole Nyquist square (13 x 13 frequencies), to 1e-12."""
    s = get(name)
    n = 12
    om = omega_grid(n)
    refined = subdivide(sinusoid_nets(om, n), s.mask)
    c = [(k - 1) / 2 for k in s.mask.shape]
    pos = [np.arange(2 * n) - c[0], np.arange(2 * n) - c[1]]  # refined units
    L = s.limit_stencil
    limit = circular_convolve(refined, L)
    lpos = [pos[0] - (L.shape[0] - 1) / 2, pos[1] - (L.shape[1] - 1) / 2]  # out[P] = sum_b L[b] R[P - b]
    one = s.response(om[:, 0], om[:, 1], "one_step")
    lim = s.response(om[:, 0], om[:, 1], "limit")
    for V, a, alpha in zip(SHIFTS, (one.signal, one.x1, one.x2, one.diagonal),
                           (lim.signal, lim.x1, lim.x2, lim.diagonal)):
        f = (om + np.array(V)) / 2  # cycles per refined unit
        np.testing.assert_allclose(project(refined, f, pos), a, atol=1e-12)
        np.testing.assert_allclose(project(limit, f, lpos), alpha, atol=1e-12)


@pytest.mark.parametrize("name", SCHEMES)
def test_transfer_equals_simulated_limit_on_the_fine_grid(name):
    """L steps, then the grid stencil: the limit surface on 2^-L Z^2, every alias r mod 2^L, vs transfer."""
    s = get(name)
    n = 4
    om = np.array([[1, 2], [-1, 1], [2, -1]]) / n
    nets = sinusoid_nets(om, n)
    G = s.grid_stencil
    for L in (1, 2, 3):
        fine = subdivide(nets, s.mask, L)
        cl = [(2 ** L - 1) * (k - 1) / 2 for k in s.mask.shape]
        lim = circular_convolve(fine, G)
        # output index Q sits at Q - c_L - (len(G) - 1)/2 level-L units: an integer (grid 2^-L Z)
        pos = [(np.arange(fine.shape[1]) - cl[0] - (G.shape[0] - 1) / 2) / 2 ** L,
               (np.arange(fine.shape[2]) - cl[1] - (G.shape[1] - 1) / 2) / 2 ** L]
        assert all(np.allclose(p, np.round(p * 2 ** L) / 2 ** L) for p in pos)
        for r1 in range(2 ** L):
            for r2 in range(2 ** L):
                f = om + np.array([r1, r2])
                np.testing.assert_allclose(project(lim, f, pos), s.transfer(f[:, 0], f[:, 1], L), atol=1e-12)


@pytest.mark.parametrize("name", ["bicubic", "4-3", "4-8", "bspline(3,5)"])
def test_subdivision_without_stencil_converges_to_the_limit_values(name):
    """Level-L control points at the level-1 vertices approach alpha_V like 4^-L (C2 schemes);
    two Richardson steps (ratios 4 and 16) at L = 6 agree to 1e-8."""
    s = scheme(name)
    n = 8
    om = np.array([[1, 2], [3, -1], [2, 2]]) / n
    c = [(k - 1) / 2 for k in s.mask.shape]
    lim = s.response(om[:, 0], om[:, 1], "limit")
    ref = np.array([lim.signal, lim.x1, lim.x2, lim.diagonal])
    nets = sinusoid_nets(om, n)
    ests, fine = [], nets
    for L in range(1, 7):
        fine = subdivide(fine, s.mask, 1)
        k = 2 ** (L - 1)
        # level-L index Q = k P - k c + (2^L - 1) c has the position of level-1 vertex P
        off = [int(round((2 ** L - 1) * ci - k * ci)) for ci in c]
        sub = np.roll(fine, (-off[0], -off[1]), axis=(1, 2))[:, ::k, ::k]
        pos = [np.arange(2 * n) - c[0], np.arange(2 * n) - c[1]]
        ests.append(np.array([project(sub, (om + np.array(V)) / 2, pos) for V in SHIFTS]))
    errs = [np.abs(e - ref).max() for e in ests]
    ratios = [a / b for a, b in zip(errs[2:], errs[3:])]
    assert all(3.9 < r < 4.5 for r in ratios), ratios
    r1 = [(4 * b - a) / 3 for a, b in zip(ests, ests[1:])]
    r2 = [(16 * b - a) / 15 for a, b in zip(r1, r1[1:])]
    assert np.abs(r2[-1] - ref).max() < 1e-8


@pytest.mark.parametrize("name", ["bilinear", "kobbelt"])
def test_interpolating_schemes_keep_their_limit_values_at_every_level(name):
    s = scheme(name)
    n = 8
    om = np.array([[1, 2], [3, -1], [-4, 4]]) / n
    lim = s.response(om[:, 0], om[:, 1], "limit")
    fine = subdivide(sinusoid_nets(om, n), s.mask, 4)
    c = (s.mask.shape[0] - 1) // 2
    off = 15 * c - 8 * c
    sub = np.roll(fine, (-off, -off), axis=(1, 2))[:, ::8, ::8]
    pos = np.arange(2 * n) - c
    for V, alpha in zip(SHIFTS, (lim.signal, lim.x1, lim.x2, lim.diagonal)):
        np.testing.assert_allclose(project(sub, (om + np.array(V)) / 2, (pos, pos)), alpha, atol=1e-13)
