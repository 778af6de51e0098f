"""The scheme catalogue: masks, derived limit stencils, reproduction, symbols, errors (SPEC §2)."""

from math import comb, factorial

import numpy as np
import pytest

from cadartifact.theory import symbols as sy
from cadartifact.errors import CadArtifactError, OptionError, SchemeError
from cadartifact.theory.catalogue import SCHEME_NAMES, Scheme, box, bspline, scheme, schemes

NAMED = list(SCHEME_NAMES)

# SPEC §2 table, typed in (the code derives them from the masks)
SPEC_MASKS = {
    "bilinear": np.outer([1, 2, 1], [1, 2, 1]) / 4,
    "bicubic": np.outer([1, 4, 6, 4, 1], [1, 4, 6, 4, 1]) / 64,
    "4-3": np.array([[0, 1, 2, 1, 0], [1, 4, 6, 4, 1], [2, 6, 8, 6, 2], [1, 4, 6, 4, 1], [0, 1, 2, 1, 0]]) / 16,
    "4-8": np.array([[0, 0, 1, 2, 1, 0, 0], [0, 2, 6, 8, 6, 2, 0], [1, 6, 14, 18, 14, 6, 1],
                     [2, 8, 18, 24, 18, 8, 2], [1, 6, 14, 18, 14, 6, 1], [0, 2, 6, 8, 6, 2, 0],
                     [0, 0, 1, 2, 1, 0, 0]]) / 64,
    "kobbelt": np.outer([-1, 0, 9, 16, 9, 0, -1], [-1, 0, 9, 16, 9, 0, -1]) / 256,
}
SPEC_STENCILS = {
    "bilinear": np.array([[1.0]]),
    "bicubic": np.outer([1, 4, 1], [1, 4, 1]) / 36,
    "4-3": np.array([[1, 6, 1], [6, 20, 6], [1, 6, 1]]) / 48,
    "4-8": np.array([[0, 1, 6, 1, 0], [1, 44, 118, 44, 1], [6, 118, 280, 118, 6], [1, 44, 118, 44, 1],
                     [0, 1, 6, 1, 0]]) / 960,
    "kobbelt": np.array([[1.0]]),
}
SPEC_FACTS = {  # arrows, interpolating, reproduction degree
    "bilinear": ((2, 2, 0, 0), True, 1),
    "bicubic": ((4, 4, 0, 0), False, 3),
    "4-3": ((2, 2, 1, 1), False, 3),
    "4-8": ((2, 2, 2, 2), False, 3),
    "kobbelt": (None, True, 3),
}


def cardinal_bspline(p, x):
    """Centred cardinal B-spline of degree p by the truncated-power formula (independent of masks)."""
    x = np.asarray(x, dtype=float) + (p + 1) / 2
    return sum((-1) ** k * comb(p + 1, k) * np.maximum(x - k, 0.0) ** p for k in range(p + 2)) / factorial(p)


# ------------------------------------------------------------------ catalogue
def test_catalogue_names_and_aliases():
    assert schemes() == ["bilinear", "bicubic", "4-3", "4-8", "kobbelt"]
    assert scheme("Catmull-Clark") is scheme("bicubic") is scheme(" BICUBIC ")
    assert scheme("bspline(3)") is scheme("bspline(3,3)") is bspline(3)
    assert scheme("box(2, 2, 1, 1)") is box(2, 2, 1, 1)
    s = scheme("4-8")
    assert scheme(s) is s


@pytest.mark.parametrize("name", NAMED)
def test_masks_match_spec(name):
    s = scheme(name)
    np.testing.assert_allclose(s.mask, SPEC_MASKS[name], atol=1e-15)
    assert abs(s.mask.sum() - 4) < 1e-14
    for a in (0, 1):
        for b in (0, 1):
            assert abs(s.mask[a::2, b::2].sum() - 1) < 1e-14
    assert not s.mask.flags.writeable and not s.limit_stencil.flags.writeable


@pytest.mark.parametrize("name", NAMED)
def test_limit_stencils_match_spec_table(name):
    np.testing.assert_allclose(scheme(name).limit_stencil, SPEC_STENCILS[name], atol=1e-14)


@pytest.mark.parametrize("name", NAMED)
def test_catalogue_facts(name):
    s = scheme(name)
    arrows, interp, d = SPEC_FACTS[name]
    assert s.arrows == arrows
    assert s.interpolating is interp
    assert s.reproduction_degree == d
    # derived again from the bare array, with the closed forms switched off
    g = Scheme.from_mask(np.array(SPEC_MASKS[name]), detect_arrows=False)
    assert g.arrows is None and g.reproduction_degree == d and g.interpolating is interp
    np.testing.assert_allclose(g.limit_stencil, SPEC_STENCILS[name], atol=1e-14)


@pytest.mark.parametrize("p,q", [(1, 1), (2, 2), (3, 3), (2, 3), (4, 1), (5, 5), (1, 6)])
def test_bspline_scheme(p, q):
    s = bspline(p, q)
    assert s.name == f"bspline({p},{q})" and s.degrees == (p, q) and s.arrows == (p + 1, q + 1, 0, 0)
    assert s.mask.shape == (p + 2, q + 2)
    np.testing.assert_allclose(s.mask, np.outer([comb(p + 1, i) for i in range(p + 2)],
                                                 [comb(q + 1, i) for i in range(q + 2)]) * 4 / 2 ** (p + q + 2))
    assert s.reproduction_degree == min(p, q)
    assert s.dual == (p % 2 == 0, q % 2 == 0)
    # limit stencil = cardinal B-spline values at the integers (both parities of degree)
    ru, rv = (s.limit_stencil.shape[0] - 1) // 2, (s.limit_stencil.shape[1] - 1) // 2
    expect = np.outer(cardinal_bspline(p, np.arange(-ru, ru + 1)), cardinal_bspline(q, np.arange(-rv, rv + 1)))
    np.testing.assert_allclose(s.limit_stencil, expect, atol=1e-14)


def test_box_arrows_detected_and_degrees():
    for arrows in [(2, 2, 1, 1), (2, 2, 2, 2), (2, 2, 1, 0), (3, 2, 0, 1), (1, 1, 1, 1)]:
        s = Scheme.from_mask(sy.box_mask(*arrows))
        assert s.arrows == arrows
        assert box(*arrows).reproduction_degree == s.reproduction_degree
    assert Scheme.from_mask(SPEC_MASKS["kobbelt"]).arrows is None
    assert box(2, 2, 0, 0).degrees == (1, 1) and box(2, 2, 1, 1).degrees is None


def test_interpolation_detection():
    assert scheme("bilinear").interpolating and scheme("kobbelt").interpolating
    assert not scheme("bicubic").interpolating and not bspline(2, 2).interpolating
    assert not scheme("4-8").interpolating


# ------------------------------------------------------------------ reproduction degree, by subdivision
def _conv_valid(a, k):
    out = np.zeros((a.shape[0] - k.shape[0] + 1, a.shape[1] - k.shape[1] + 1))
    for i in range(k.shape[0]):
        for j in range(k.shape[1]):
            out += k[i, j] * a[k.shape[0] - 1 - i: k.shape[0] - 1 - i + out.shape[0],
                               k.shape[1] - 1 - j: k.shape[1] - 1 - j + out.shape[1]]
    return out


def _refine(s, data, stencil=True):
    """One step of subdivision (then the limit stencil) on a finite net: (values, x, y), positions in
    control units, valid region only."""
    n1, n2 = data.shape
    up = np.zeros((2 * n1 - 1, 2 * n2 - 1))
    up[::2, ::2] = data
    out = _conv_valid(up, s.mask)  # out[i] is full-convolution index i + s-1, at refined position i + s-1 - c
    (s1, s2), (l1, l2) = s.mask.shape, (s.limit_stencil.shape if stencil else (1, 1))
    if stencil:
        out = _conv_valid(out, s.limit_stencil)
    x = (np.arange(out.shape[0]) + (s1 - 1) / 2 + (l1 - 1) / 2) / 2
    y = (np.arange(out.shape[1]) + (s2 - 1) / 2 + (l2 - 1) / 2) / 2
    return out, x, y


def _poly_fit_residual(values, x, y, degree):
    X, Y = np.meshgrid(x, y, indexing="ij")
    cols = [X.ravel() ** i * Y.ravel() ** j for i in range(degree + 1) for j in range(degree + 1 - i)]
    A = np.stack(cols, axis=1)
    coef, *_ = np.linalg.lstsq(A, values.ravel(), rcond=None)
    return np.abs(A @ coef - values.ravel()).max() / np.abs(values).max()


def _poly_net(degree, rng, n=16):
    i, j = np.meshgrid(np.arange(float(n)), np.arange(float(n)), indexing="ij")
    u, v = (i - 7.5) / 8, (j - 7.5) / 8
    data = sum(rng.normal() * u ** a * v ** b for a in range(degree + 1) for b in range(degree + 1 - a))
    return data + u ** degree  # make sure the top degree is present


@pytest.mark.parametrize("name", NAMED + ["bspline(2,2)", "bspline(2,4)", "box(2,2,1,0)"])
def test_reproduction_degree_by_subdivision(name):
    """Sum rules: one step maps degree <= d nets to polynomial nets (so the limit surface is a polynomial
    too) and a degree d+1 net to a rippled one."""
    s = scheme(name)
    d = s.reproduction_degree
    rng = np.random.default_rng(7)
    for deg, ok in ((d, True), (d + 1, False)):
        for stencil in (False, True):
            if stencil and not ok:
                continue  # the limit at refined vertices can hide ripples (4-8, see below)
            vals, x, y = _refine(s, _poly_net(deg, rng), stencil)
            res = _poly_fit_residual(vals, (x - 7.5) / 8, (y - 7.5) / 8, deg)
            assert (res < 1e-11) if ok else (res > 1e-9), (deg, stencil, res)


def test_4_8_limit_surface_reproduces_more_than_its_sum_rules():
    """Recorded fact: 4-8's limit surface (Strang-Fix order 6) reproduces quintics although its
    refined nets do not; reproduction_degree follows the sum rules (3), as the contract says."""
    s = scheme("4-8")
    rng = np.random.default_rng(1)
    for deg in (4, 5):
        vals, x, y = _refine(s, _poly_net(deg, rng), stencil=True)
        assert _poly_fit_residual(vals, (x - 7.5) / 8, (y - 7.5) / 8, deg) < 1e-11
        vals, x, y = _refine(s, _poly_net(deg, rng), stencil=False)
        assert _poly_fit_residual(vals, (x - 7.5) / 8, (y - 7.5) / 8, deg) > 1e-9


# ------------------------------------------------------------------ symbols, two roads
W = np.linspace(-1.3, 1.7, 23)


@pytest.mark.parametrize("name", NAMED + ["bspline(2,3)", "box(2,2,1,0)", "box(3,2,0,1)"])
def test_closed_form_symbol_equals_mask_sum(name):
    s = scheme(name)
    grid = s.symbol(W[None, :], W[:, None])
    naive = sum(s.mask[a, b] * np.exp(-1j * np.pi * (W[None, :] * (a - (s.mask.shape[0] - 1) / 2)
                                                       + W[:, None] * (b - (s.mask.shape[1] - 1) / 2)))
                for a in range(s.mask.shape[0]) for b in range(s.mask.shape[1]))
    np.testing.assert_allclose(grid, naive.real, atol=1e-13)
    assert np.abs(naive.imag).max() < 1e-13
    # generic array route, grid and scattered points, both grid layouts
    np.testing.assert_allclose(sy.mask_symbol(s.mask, W[None, :], W[:, None]), grid, atol=1e-13)
    np.testing.assert_allclose(sy.mask_symbol(s.mask, W[:, None], W[None, :]), grid.T, atol=1e-13)
    X, Y = np.meshgrid(W, W)
    np.testing.assert_allclose(sy.mask_symbol(s.mask, X.ravel(), Y.ravel()), grid.ravel(), atol=1e-13)


def test_bspline_symbol_is_cosine_power_even_for_dual_masks():
    s = bspline(2, 3)
    wx, wy = W[None, :], W[:, None]
    np.testing.assert_allclose(s.symbol(wx, wy) / 4, np.cos(np.pi * wx / 2) ** 3 * np.cos(np.pi * wy / 2) ** 4,
                               atol=1e-14)


def test_asymmetric_mask_has_complex_symbol_and_matches_naive_sum():
    m = np.array(SPEC_MASKS["bicubic"], dtype=float)
    m[0, 0] += 0.01  # same coset: (0,0) and (2,0)
    m[2, 0] -= 0.01
    s = Scheme.from_mask(m, "skew")
    assert s.arrows is None and not s.symmetric
    wx, wy = W[None, :], W[:, None]
    naive = sum(m[a, b] * np.exp(-1j * np.pi * (wx * (a - 2) + wy * (b - 2))) for a in range(5) for b in range(5))
    np.testing.assert_allclose(s.symbol(wx, wy), naive, atol=1e-13)


@pytest.mark.parametrize("name", ["4-3", "4-8", "box(2,2,1,0)"])
def test_basis_hat_closed_form_equals_infinite_product(name):
    s = scheme(name)
    g = Scheme.from_mask(s.mask, detect_arrows=False)
    wx, wy = W[None, :] * 3, W[:, None] * 3
    np.testing.assert_allclose(g.basis_hat(wx, wy), s.basis_hat(wx, wy), atol=1e-13)


# ------------------------------------------------------------------ transfer and the space-domain cascade
def _dtft_of_samples(bs, wx, wy):
    L = bs.levels
    ex = np.exp(-2j * np.pi * np.multiply.outer(wx, bs.ix) / 2 ** L)
    ey = np.exp(-2j * np.pi * np.multiply.outer(wy, bs.iy) / 2 ** L)
    return np.einsum("ij,pi,pj->p", bs.values, ex, ey) / 4 ** L


@pytest.mark.parametrize("name", NAMED + ["bspline(2,3)", "bspline(4,4)", "box(2,2,1,0)"])
def test_transfer_equals_dft_of_cascade_samples(name):
    s = scheme(name)
    rng = np.random.default_rng(3)
    for L in range(4):
        xi = rng.uniform(-2 ** L / 2, 2 ** L / 2, size=(40, 2))
        np.testing.assert_allclose(s.transfer(xi[:, 0], xi[:, 1], L), _dtft_of_samples(s.basis_samples(L), *xi.T),
                                   atol=1e-13)
    # the generic (matrix) road gives the same transfer
    g = Scheme.from_mask(s.mask, detect_arrows=False)
    f = np.linspace(-4, 4, 17)
    np.testing.assert_allclose(g.transfer(f[:, None], f[None, :], 3), s.transfer(f[:, None], f[None, :], 3),
                               atol=1e-13)


@pytest.mark.parametrize("name", NAMED + ["bspline(2,2)"])
def test_transfer_tends_to_basis_hat(name):
    s = scheme(name)
    xi = np.linspace(-1.5, 1.5, 13)
    errs = [np.abs(s.transfer(xi[None, :], xi[:, None], L) - s.basis_hat(xi[None, :], xi[:, None])).max()
            for L in (3, 6, 9, 12)]
    assert errs[-1] < 1e-7 and all(b <= a + 1e-15 for a, b in zip(errs, errs[1:]))


def test_basis_samples_match_bspline_values_and_limit_stencil():
    for p, q in [(3, 3), (2, 3), (1, 2)]:
        s = bspline(p, q)
        bs = s.basis_samples(3)
        expect = np.outer(cardinal_bspline(p, bs.ix / 8), cardinal_bspline(q, bs.iy / 8))
        np.testing.assert_allclose(bs.values, expect, atol=1e-14)
        assert abs(bs.values.sum() / 64 - 1) < 1e-13  # partition of unity
    s = scheme("4-8")
    b0 = s.basis_samples(0)
    np.testing.assert_allclose(b0.values[1:-1, 1:-1] if b0.values.shape[0] > 5 else b0.values,
                               s.limit_stencil, atol=1e-14)


def test_transfer_level_one_is_limit_response_for_primal_schemes():
    w = np.linspace(-0.5, 0.5, 11)
    for name in NAMED:
        s = scheme(name)
        r = s.response(w[None, :], w[:, None], "limit")
        for (v1, v2), val in zip(((0, 0), (1, 0), (0, 1), (1, 1)), (r.signal, r.x1, r.x2, r.diagonal)):
            np.testing.assert_allclose(s.transfer(w[None, :] + v1, w[:, None] + v2, 1), val, atol=1e-14)


# ------------------------------------------------------------------ bad input
def test_unknown_name_lists_valid_names():
    with pytest.raises(SchemeError) as exc:
        scheme("loop")
    msg = str(exc.value)
    assert "loop" in msg and all(n in msg for n in ("bilinear", "bicubic", "4-3", "4-8", "kobbelt", "bspline(p,q)"))
    assert "\n" not in msg


@pytest.mark.parametrize("bad,needle", [
    (np.ones((3, 3)), "summing to 4"),
    (np.array([[2.0, 0.0], [0.0, 2.0]]), "coset"),
    (np.ones((3,)), "2-D"),
    (np.full((3, 3), np.nan), "finite"),
    ([["a", "b"]], "2-D array of numbers"),
])
def test_bad_masks(bad, needle):
    with pytest.raises(SchemeError) as exc:
        Scheme.from_mask(bad)
    assert needle in str(exc.value) and str(exc.value).startswith("mask:")


def test_non_convergent_masks():
    # piecewise constant (double eigenvalue 1) and a 4-point scheme with a huge tension parameter
    with pytest.raises(SchemeError, match="convergent"):
        Scheme.from_mask(np.ones((2, 2)))
    w = 2.0
    u = np.array([-w, 0, 0.5 + w, 1, 0.5 + w, 0, -w])
    with pytest.raises(SchemeError, match="convergent"):
        Scheme.from_mask(np.outer(u, u))
    with pytest.raises(SchemeError):
        box(1, 1, 0, 0)
    with pytest.raises(SchemeError):
        box(0, 0, 2, 2)  # diagonal-only: cosets do not sum to 1


@pytest.mark.parametrize("call", [lambda: bspline(0, 3), lambda: bspline(3, 0), lambda: scheme("bspline(0,3)"),
                                  lambda: bspline(2.5), lambda: box(-1, 2, 0, 0)])
def test_bad_degrees(call):
    with pytest.raises(SchemeError) as exc:
        call()
    assert "integer >=" in str(exc.value)


def test_bad_levels_and_inconsistent_arrows():
    s = scheme("bicubic")
    with pytest.raises(OptionError, match="levels"):
        s.transfer(0.1, 0.1, -1)
    with pytest.raises(OptionError, match="levels"):
        s.basis_samples(1.5)
    with pytest.raises(SchemeError, match="arrows"):
        Scheme("wrong", sy.box_mask(2, 2, 0, 0), arrows=(2, 2, 1, 1))
    assert issubclass(SchemeError, CadArtifactError)
