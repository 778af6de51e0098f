"""The band split on the fine grid: masks and lateral weights per frequency (SPEC §3, §4).

A deviation on the lattice-aligned periodic fine grid is split by frequency at each direction's cut
(:attr:`~cadartifact.analysis.frames.AxisFrame.cut`, half a cycle per control point: ``1/2`` cycle per
span) into base band (``|fx|, |fy|`` below it), X1 (``|fx|`` at or above it only), X2 (``|fy|`` only) and
diagonal (both); the lateral part weighs each ripple bin by the SPEC §3 factor of the frequency it aliases. Used by
both roads of :mod:`cadartifact.analysis.fields`.

References
----------
P. J. Augsdörfer, N. A. Dodgson, M. A. Sabin, *Artifact analysis on B-splines, box-splines and
other surfaces defined by quadrilateral polyhedra*, CAGD 2011.
"""

from __future__ import annotations

import numpy as np

from .frames import AxisFrame

__all__ = ["band_split", "lateral_factors", "lateral_of"]


def _fine_freqs(frame: AxisFrame) -> np.ndarray:
    return np.fft.fftfreq(frame.K * frame.period, d=1.0 / frame.K)


def lateral_factors(fu: np.ndarray, fv: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SPEC §3 lateral factors ``(sin phi1, sin phi2, sin phid1 sin phid2)``, each ``(a, b)``, of the
    frequency each bin aliases (folded into the base band: ``w = f - round(f)``)."""
    wu = (fu - np.round(fu))[:, None]
    wv = (fv - np.round(fv))[None, :]
    r2 = wu ** 2 + wv ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        s1 = np.where(r2 > 0, np.abs(wv) / np.sqrt(r2), 0.0)
        s2 = np.where(r2 > 0, np.abs(wu) / np.sqrt(r2), 0.0)
        sd = np.where(r2 > 0, np.abs(wu ** 2 - wv ** 2) / (2 * r2), 0.0)
    return s1, s2, sd


def _band_masks(fu: np.ndarray, fv: np.ndarray, smooth: tuple[bool, bool] = (False, False)) -> dict:
    """Band masks and lateral weights of frequencies in cycles per control point (a direction cut elsewhere than
    half a cycle per span passes them scaled by ``0.5 / cut``); a direction in ``smooth`` has no ripple band (one
    polynomial piece)."""
    hu = (np.abs(fu) >= 0.5 - 1e-12)[:, None] & (not smooth[0])
    hv = (np.abs(fv) >= 0.5 - 1e-12)[None, :] & (not smooth[1])
    x1, x2, dg = hu & ~hv, ~hu & hv, hu & hv
    s1, s2, sd = lateral_factors(fu, fv)
    return {"signal_error": ~hu & ~hv, "x1": x1, "x2": x2, "diagonal": dg, "lateral": x1 * s1 + x2 * s2 + dg * sd}


def _one_piece(*frames) -> tuple:
    """Per frame, whether its direction has no ripple band (:attr:`AxisFrame.ripple_free`: one polynomial
    piece, or exactly a line or circle)."""
    return tuple(bool(f.ripple_free) for f in frames)


def _crop(a: np.ndarray, fu: AxisFrame, fv: AxisFrame) -> np.ndarray:
    """The domain part of a periodic fine-grid array (``x = 0`` first)."""
    iu = (fu.shift + np.arange(fu.fine_count)) % a.shape[0]
    iv = (fv.shift + np.arange(fv.fine_count)) % a.shape[1]
    return a[np.ix_(iu, iv)]


def band_split(spectrum: np.ndarray, fu: AxisFrame, fv: AxisFrame, lateral: bool = True) -> dict:
    """Split a periodic fine-grid deviation, given by its half spectrum, into bands over the domain.

    Parameters
    ----------
    spectrum : (K Tu, K Tv // 2 + 1, 3) complex
        ``rfft2`` of the deviation on the lattice-aligned periodic fine grid.
    fu, fv : AxisFrame

    Returns
    -------
    dict str -> (fu.fine_count, fv.fine_count, 3) float
        ``signal_error, x1, x2, diagonal, lateral, total``.
    """
    A, B = fu.K * fu.period, fv.K * fv.period
    fa, fb = _fine_freqs(fu), np.abs(_fine_freqs(fv)[: B // 2 + 1])
    smooth = _one_piece(fu, fv)
    # the four bands are tensor products of a u mask and a v mask: invert along u per u mask, keep the
    # domain's rows, then along v per v mask, keep its columns (no full-size inverse per band)
    hu = (np.abs(fa) >= fu.cut - 1e-12) & (not smooth[0])
    hv = (fb >= fv.cut - 1e-12) & (not smooth[1])
    iu = (fu.shift + np.arange(fu.fine_count)) % A
    iv = (fv.shift + np.arange(fv.fine_count)) % B
    rows = {}
    for name_u, mu in (("lo", ~hu), ("hi", hu)):
        rows[name_u] = np.fft.ifft(spectrum * mu[:, None, None], axis=0)[iu] if mu.any() else None
    pick = {"signal_error": ("lo", ~hv), "x1": ("hi", ~hv), "x2": ("lo", hv), "diagonal": ("hi", hv)}
    out = {}
    for name, (name_u, mv) in pick.items():
        r = rows[name_u]
        if r is None or not mv.any():
            out[name] = np.zeros((fu.fine_count, fv.fine_count) + spectrum.shape[2:])
        else:
            out[name] = np.fft.irfft(r * mv[None, :, None], n=B, axis=1)[:, iv]
    if lateral:
        # the lateral factors of frequencies in cycles per control point, as lateral_of takes them
        m = _band_masks(fa * (0.5 / fu.cut), fb * (0.5 / fv.cut), smooth)["lateral"]
        out["lateral"] = _crop(np.fft.irfft2(spectrum * m[:, :, None], s=(A, B), axes=(0, 1)), fu, fv)
    out["total"] = out["x1"] + out["x2"] + out["diagonal"]
    return out


def baseband_bins(fu: AxisFrame, fv: AxisFrame) -> tuple[list, list]:
    """Per direction, the fine-grid bins of the base band (``|f| <`` the frame's :attr:`AxisFrame.cut`; every bin
    of a direction with no ripple band) and their frequencies: ``([ku, kv], [fu_k, fv_k])``."""
    idx, freqs = [], []
    for frame in (fu, fv):
        f = _fine_freqs(frame)
        k = np.arange(len(f)) if _one_piece(frame)[0] else np.flatnonzero(np.abs(f) < frame.cut - 1e-12)
        idx.append(k)
        freqs.append(f[k])
    return idx, freqs


def _baseband(half_spec: np.ndarray, fu: AxisFrame, fv: AxisFrame, poly: np.ndarray) -> dict:
    """The base-band bins of a half fine-grid spectrum, with a polynomial, for :func:`baseband_at`.

    The full spectrum's bins are read off the half spectrum (``X[k, l] = conj(X[-k, -l])`` for the
    columns ``rfft2`` leaves out): no transform of the whole grid.
    """
    A, B = fu.K * fu.period, fv.K * fv.period
    (ku, kv), freqs = baseband_bins(fu, fv)
    direct = kv <= B // 2
    out = np.empty((len(ku), len(kv)) + half_spec.shape[2:], complex)
    out[:, direct] = half_spec[np.ix_(ku, kv[direct])]
    mirrored = ~direct
    if mirrored.any():
        out[:, mirrored] = np.conj(half_spec[np.ix_((-ku) % A, (B - kv[mirrored]) % B)])
    return {"spec": out, "freqs": freqs, "frames": (fu, fv), "poly": poly}


def _dct1(a: np.ndarray, axis: int = -1) -> np.ndarray:
    """DCT-I along ``axis`` (unnormalised, as ``scipy.fft.dct(type=1)``): the real half spectrum of the
    whole-sample even reflection, ``rfft([a_0 .. a_{N-1}, a_{N-2} .. a_1])``. Its own inverse up to
    ``1 / (2 (N - 1))``. By numpy's FFT: importing ``scipy.fft`` costs a gate process 0.1-0.4 s.

    Fastest along the last axis of a C-contiguous array (the reflection is written straight into the
    transform's buffer, and the FFT runs over contiguous lines)."""
    a = np.moveaxis(a, axis, -1)
    N = a.shape[-1]
    ext = np.empty(a.shape[:-1] + (2 * (N - 1),))
    ext[..., :N] = a
    ext[..., N:] = a[..., N - 2:0:-1]
    return np.moveaxis(np.fft.rfft(ext, axis=-1).real, -1, axis)


def _transposed(a: np.ndarray) -> np.ndarray:
    """``(c, m, n) -> (c, n, m)``, C-contiguous: the next transform runs along contiguous lines."""
    return np.ascontiguousarray(a.transpose(0, 2, 1))


def lateral_of(ripple: np.ndarray, fu: AxisFrame, fv: AxisFrame, terms: tuple | None = None) -> np.ndarray:
    """The lateral part of a domain ripple field (SPEC §3 weights per alias band).

    The field is continued by even reflection along each open direction (whole-sample symmetric, period
    ``2 (N - 1)``) and periodically along a periodic one, weighted per frequency and transformed back. The
    DFT of a whole-sample symmetric sequence is its DCT-I (:func:`_dct1`), and the weights are even in each
    frequency, so the transforms go one direction at a time on real data instead of one complex 2-D transform
    of the field reflected both ways (four times the samples): the same numbers to rounding. The work is done
    component by component, each transform along the last axis of a contiguous array (about 0.7 of the time
    of transforms along strided axes on a 793 x 793 x 3 field).

    Parameters
    ----------
    ripple : (a, b, 3) float
    fu, fv : AxisFrame
    terms : tuple, optional
        ``(P, (A_1, B_1), (A_2, B_2), ...)`` with ``ripple = sum_k A_k P B_k^T`` (``P`` : (m, n, 3),
        ``A_k`` : (a, m), ``B_k`` : (b, n)): the field's separable form, which spares its forward
        transforms when both directions are open (the same numbers to rounding).

    Returns
    -------
    (a, b, 3) float
    """
    frames = (fu, fv)
    is_open = [not f.periodic and ripple.shape[a] > 2 for a, f in enumerate(frames)]
    both_periodic = not any(is_open)
    freqs = []
    for a, f in enumerate(frames):
        N = ripple.shape[a]
        if is_open[a]:
            # the reflected period's frequencies 0..Nyquist, spelt as np.fft.fftfreq spells them: the
            # lateral factor of a bin aliasing zero frequency in both directions is 0/0, and today's
            # reports took it from fftfreq's rounding
            freqs.append(np.arange(N) * (1.0 / (2 * (N - 1) * (1.0 / f.K))))
        elif a == 1 and both_periodic:
            freqs.append(np.fft.rfftfreq(N, d=1.0 / f.K))
        else:
            freqs.append(np.fft.fftfreq(N, d=1.0 / f.K))
    # SPEC §3's factors are of frequencies in cycles per control point: a span is 0.5 / cut points
    w = _band_masks(freqs[0] * (0.5 / fu.cut), freqs[1] * (0.5 / fv.cut), _one_piece(fu, fv))["lateral"]
    A, B = ripple.shape[:2]
    if terms is not None and all(is_open):
        # the forward DCT-I of sum_k A_k P B_k^T is sum_k DCT(A_k) P DCT(B_k)^T: the operators' columns are
        # transformed instead of the field, and the field's two forward transforms are two products
        from ..numerics.tensor import sandwich_left

        points = terms[0]
        s = sum(np.tensordot(sandwich_left(_dct1(Au, 0), points), _dct1(Bv, 0), axes=(1, 1))
                for Au, Bv in terms[1:])  # (a, c, b)
        s *= w[:, None, :]
        s = _dct1(_dct1(s).transpose(1, 2, 0))  # back along v, then (c, b, a) and along u
        s /= 4.0 * (A - 1) * (B - 1)
        return s.transpose(2, 1, 0).reshape(ripple.shape)
    if both_periodic:
        return np.fft.irfft2(np.fft.rfft2(ripple, axes=(0, 1)) * w[:, :, None], s=(A, B), axes=(0, 1))
    r = np.moveaxis(ripple.reshape(A, B, -1), 2, 0)  # (c, a, b), a view
    if all(is_open):
        s = _transposed(_dct1(r))  # along v, then (c, b, a)
        s = _dct1(s) * w.T  # along u
        s = _dct1(_transposed(_dct1(s)))  # back along u, then along v: (c, a, b)
        s /= 4.0 * (A - 1) * (B - 1)
    elif is_open[1]:  # u periodic
        s = _transposed(_dct1(r))  # (c, b, a)
        s = np.fft.ifft(np.fft.fft(s) * w.T).real
        s = _dct1(_transposed(s)) / (2.0 * (B - 1))
    else:  # v periodic
        s = _dct1(_transposed(r))  # along u: (c, b, a)
        s = _transposed(s)
        s = _transposed(np.fft.ifft(np.fft.fft(s) * w).real)
        s = _dct1(s) / (2.0 * (A - 1))  # (c, b, a)
        s = s.transpose(0, 2, 1)
    return np.moveaxis(s, 0, 2).reshape(ripple.shape)
