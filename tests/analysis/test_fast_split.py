"""The fast band split (issue 24) gives the numbers of the plain one: two roads to the same fields.

* The lateral part (:func:`cadartifact.analysis.bands.lateral_of`) takes a DCT-I along open directions;
  the reference here reflects the field evenly by hand and weighs one 2-D FFT of the whole period.
* The measured road's split (:func:`cadartifact.analysis.fields._bridged_bands`) goes one direction at a
  time on the domain's rows; the reference builds the bridged period in full, takes its 2-D FFT and
  splits it with :func:`cadartifact.analysis.bands.band_split` (what the code did before).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cadartifact.analysis import fields as F
from cadartifact.analysis.bands import _band_masks, _baseband, _one_piece, band_split, lateral_of
from cadartifact.analysis.baseband import baseband_at
from cadartifact.analysis.frames import AxisFrame


def _frame(n: int, periodic: bool, degree: int, polynomial: bool = False, levels: int = 3) -> AxisFrame:
    spans = n if periodic else n - degree
    offset = 0.0 if periodic else ((degree - 1) / 2) % 1.0
    return AxisFrame(n, periodic, spans, offset, np.arange(n, dtype=float), levels, polynomial=polynomial)


def _reflected_lateral(ripple, fu, fv):
    """The lateral part by hand: even reflection along open directions, one 2-D FFT of the period."""
    ext = ripple
    for axis, frame in enumerate((fu, fv)):
        if not frame.periodic and ext.shape[axis] > 2:
            ext = np.concatenate([ext, np.flip(np.take(ext, np.arange(1, ext.shape[axis] - 1), axis=axis), axis)],
                                 axis=axis)
    A, B = ext.shape[:2]
    w = _band_masks(np.fft.fftfreq(A, d=1.0 / fu.K), np.fft.fftfreq(B, d=1.0 / fv.K), _one_piece(fu, fv))["lateral"]
    return np.fft.ifft2(np.fft.fft2(ext, axes=(0, 1)) * w[:, :, None], axes=(0, 1)).real[: ripple.shape[0],
                                                                                          : ripple.shape[1]]


@settings(max_examples=40, deadline=None)
@given(nu=st.integers(2, 40), nv=st.integers(2, 40), pu=st.booleans(), pv=st.booleans(),
       levels=st.integers(1, 4), seed=st.integers(0, 2 ** 31))
def test_lateral_by_dct_equals_the_reflected_fft(nu, nv, pu, pv, levels, seed):
    fu, fv = (_frame(max(n, 4), per, 3, levels=levels) for n, per in ((nu, pu), (nv, pv)))
    rng = np.random.default_rng(seed)
    ripple = rng.normal(size=(nu, nv, 3))
    np.testing.assert_allclose(lateral_of(ripple, fu, fv), _reflected_lateral(ripple, fu, fv), atol=1e-12)


def _two_dimensional_split(field, frames, scheme):
    """The measured road's split as one 2-D transform of the whole bridged period (the reference)."""
    fu, fv = frames
    own = scheme.degrees
    V, poly = F._poly_fit(field, frames, own)
    rest = field - F.sandwich(V[0], poly, V[1])
    ext = F._bridge(F._bridge(rest, fu, 0, own[0]), fv, 1, own[1])
    ext = np.roll(ext, (fu.shift, fv.shift), axis=(0, 1))
    spec = np.fft.rfft2(ext, axes=(0, 1))
    bands = band_split(spec, fu, fv, lateral=False)
    smooth = bands["signal_error"] + F.sandwich(V[0], poly, V[1])
    return bands, smooth, _baseband(spec, fu, fv, poly)


class _Bicubic:
    degrees = (3, 3)
    reproduction_degree = 3


@settings(max_examples=25, deadline=None)
@given(nu=st.integers(4, 30), nv=st.integers(4, 30), pu=st.booleans(), pv=st.booleans(),
       polyu=st.booleans(), levels=st.integers(1, 3), seed=st.integers(0, 2 ** 31))
def test_split_by_direction_equals_the_two_dimensional_transform(nu, nv, pu, pv, polyu, levels, seed):
    fu = _frame(nu, pu, 3, polynomial=polyu and not pu, levels=levels).with_extension(F.MEASURED_EXTENSION)
    fv = _frame(nv, pv, 3, levels=levels).with_extension(F.MEASURED_EXTENSION)
    rng = np.random.default_rng(seed)
    X, Y = np.meshgrid(fu.x, fv.x, indexing="ij")
    a, b, c = rng.uniform(0.05, 0.7, 3)
    z = np.cos(2 * np.pi * (a * X / 4 + b * Y / 4) + c * 6) + 0.02 * np.cos(2 * np.pi * 0.7 * X) * np.sin(
        2 * np.pi * 0.6 * Y)
    field = np.stack([X, Y, z], axis=-1)
    size = float(np.abs(field).max())
    bands, smooth, bb = F._bridged_bands(field, (fu, fv), _Bicubic, lateral=False)
    ref, ref_smooth, ref_bb = _two_dimensional_split(field, (fu, fv), _Bicubic)
    # The bridge carries its end spans' fifth derivatives across a gap of about 2n spans, so rounding
    # grows there like n**5 (and with the shape's cycles across the face): on 30-span nets of this field
    # the two roads part by up to 7e-7 of its size. Neither road is the exact one; the bound is what
    # rounding does to the reference itself: the change 4 ulp of noise in the field make to it.
    noisy = field * (1 + 4 * np.finfo(float).eps * np.random.default_rng(seed + 1).standard_normal(field.shape))
    ref_n, ref_n_smooth, ref_n_bb = _two_dimensional_split(noisy, (fu, fv), _Bicubic)
    xs, ys = np.linspace(-1.5, fu.spans + 1.5, 11), np.linspace(-1.0, fv.spans + 1.0, 9)

    def at(smooth_part, bb_part):
        """The base band evaluated anywhere (inside and past the borders), through the public evaluator."""
        return baseband_at(F.ArtifactFields(x=fu.x, y=fv.x, surface=field, intent=smooth_part, baseband=bb_part),
                           xs, ys)

    pairs = {name: (bands[name], ref[name], ref_n[name]) for name in ("x1", "x2", "diagonal")}
    pairs["smooth"] = (smooth, ref_smooth, ref_n_smooth)
    pairs["baseband"] = (at(smooth, bb), at(ref_smooth, ref_bb), at(ref_n_smooth, ref_n_bb))
    for name, (fast, slow, slow_noisy) in pairs.items():
        atol = 1e-10 * size + 4 * float(np.abs(slow_noisy - slow).max())
        np.testing.assert_allclose(fast, slow, rtol=0, atol=atol, err_msg=name)


@settings(max_examples=30, deadline=None)
@given(nu=st.integers(3, 30), nv=st.integers(3, 30), m=st.integers(2, 9), n=st.integers(2, 9),
       terms=st.integers(1, 3), seed=st.integers(0, 2 ** 31))
def test_lateral_from_the_separable_form_equals_the_lateral_of_the_field(nu, nv, m, n, terms, seed):
    """The forward transforms taken on the operators of ``sum_k A_k P B_k^T`` give the lateral part of the
    field itself (both directions open; a periodic one ignores the separable form)."""
    fu, fv = _frame(max(nu, 4), False, 3), _frame(max(nv, 4), False, 3)
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(m, n, 3))
    ops = [(rng.normal(size=(nu, m)), rng.normal(size=(nv, n))) for _ in range(terms)]
    ripple = sum(F.sandwich(Au, P, Bv) for Au, Bv in ops)
    np.testing.assert_allclose(lateral_of(ripple, fu, fv, (P, *ops)), _reflected_lateral(ripple, fu, fv),
                               atol=1e-10 * max(1.0, float(np.abs(ripple).max())))
    fp = _frame(max(nv, 4), True, 3)
    np.testing.assert_allclose(lateral_of(ripple, fu, fp, (P, *ops)), _reflected_lateral(ripple, fu, fp),
                               atol=1e-10 * max(1.0, float(np.abs(ripple).max())))
