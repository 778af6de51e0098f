"""The *measured* road: the real surface evaluated on the fine grid, then band-split.

Independent of the spectral formulas, the surface comes from

* ``"face"``: exact NURBS evaluation of the face's own knots, degrees and weights
  (:func:`cadartifact.splines.evaluate`, checked against OCCT's evaluator in the tests),
  parameters from index space through the Greville abscissae;
* ``"uniform-bspline"``: a B-spline scheme applied to a net that is not that face (an OBJ
  cage, or another degree): uniform cardinal B-splines on the net extended like the intent;
* ``"subdivision"``: ``L`` steps of numerical subdivision with the scheme's mask, then its
  limit stencil (4-3, 4-8, Kobbelt, user masks).

The surface is linear in the control points (for fixed weights), so the trend and the
residual are evaluated separately: the trend's deviation is a polynomial-like, low-frequency
signal error; the residual's deviation is band-split exactly as the predicted road's.
"""

from __future__ import annotations

import numpy as np

from .errors import OptionError
from .fields import ArtifactFields, Axis, Intent, band_split
from .splines import basis_matrix, evaluate, index_to_param, periodic_greville

__all__ = ["measured_fields", "measurement_road", "subdivide", "apply_stencil", "cardinal_operator"]


def measurement_road(net, scheme) -> tuple[str, str]:
    """Which real surface the measured road evaluates, and why.

    Returns
    -------
    (road, reason) : (str, str)
        ``road`` in {"face", "uniform-bspline", "subdivision"}.
    """
    own = net.knots is not None and scheme.degrees is not None and tuple(scheme.degrees) == tuple(net.degrees)
    if own:
        return "face", "exact NURBS evaluation of the face (its own knots and weights)"
    if scheme.degrees is not None:
        return "uniform-bspline", f"uniform {scheme.name} B-spline of the net (net extended like the intent)"
    if any(s % 2 == 0 for s in scheme.mask.shape):
        raise OptionError("scheme", "an odd-size mask for numerical subdivision", f"{scheme.name} {scheme.mask.shape}")
    return "subdivision", f"numerical subdivision with the {scheme.name} mask and its limit stencil"


def _pad(points: np.ndarray, r: int, periodic: tuple[bool, bool]) -> np.ndarray:
    """Extend a (nu, nv, 3) array by ``r`` points per side: even reflection or wrap-around."""
    out = points
    for axis, per in enumerate(periodic):
        width = [(0, 0)] * out.ndim
        width[axis] = (r, r)
        out = np.pad(out, width, mode="wrap" if per else "reflect")
    return out


def _shifted_sum(a: np.ndarray, kernel: np.ndarray) -> np.ndarray:
    """``out[p] = sum_k kernel[k] a[p - k]`` over a centred odd kernel, zero outside ``a`` ("same" size)."""
    ka, kb = kernel.shape
    ra, rb = ka // 2, kb // 2
    big = np.pad(a, [(ra, ra), (rb, rb)] + [(0, 0)] * (a.ndim - 2))
    out = np.zeros_like(a)
    n0, n1 = a.shape[0], a.shape[1]
    for i in range(ka):
        for j in range(kb):
            w = kernel[i, j]
            if w != 0.0:
                # kernel offset (i-ra, j-rb) reads a[p - offset]
                out += w * big[2 * ra - i: 2 * ra - i + n0, 2 * rb - j: 2 * rb - j + n1]
    return out


def _separable(kernel: np.ndarray):
    """``(col, row)`` with ``kernel == outer(col, row)``, or None."""
    u, s, vt = np.linalg.svd(kernel)
    if s.size > 1 and s[1] > 1e-13 * s[0]:
        return None
    return u[:, 0] * s[0], vt[0]


def _convolve(a: np.ndarray, kernel: np.ndarray) -> np.ndarray:
    sep = _separable(kernel)
    if sep is None:
        return _shifted_sum(a, kernel)
    col, row = sep
    return _shifted_sum(_shifted_sum(a, col[:, None]), row[None, :])


def subdivide(points: np.ndarray, mask: np.ndarray, levels: int) -> np.ndarray:
    """``levels`` binary subdivision steps of a grid with an odd, centred mask.

    Parameters
    ----------
    points : (m, k, c) float
    mask : (2a+1, 2b+1) float
        Refined point ``p`` is ``sum_J mask[p - 2J] points[J]``.
    levels : int

    Returns
    -------
    (2^L (m-1) + 1, 2^L (k-1) + 1, c) float
        Values near the borders (within about the mask radius, in coarse spacings) are incomplete;
        pad the input and crop.
    """
    a = np.asarray(points, float)
    for _ in range(levels):
        up = np.zeros((2 * a.shape[0] - 1, 2 * a.shape[1] - 1) + a.shape[2:])
        up[::2, ::2] = a
        a = _convolve(up, mask)
    return a


def apply_stencil(a: np.ndarray, stencil: np.ndarray) -> np.ndarray:
    """Limit points of a grid: ``sum_n stencil[n] a[p - n]`` (odd centred stencil, "same" size)."""
    return _convolve(np.asarray(a, float), np.asarray(stencil, float))


def _param_axis(net, axis: int, x: np.ndarray) -> np.ndarray:
    """Parameters of index coordinates ``x`` along one direction of a B-spline face."""
    knots, p, n, per = net.knots[axis], net.degrees[axis], net.shape[axis], net.periodic[axis]
    if per:
        period = knots[len(knots) - p - 1] - knots[p]
        return index_to_param(periodic_greville(knots, p, n), x, periodic=True, period=period)
    return index_to_param(net.greville()[axis], x)


def cardinal_operator(n: int, degree: int, x: np.ndarray, periodic: bool) -> np.ndarray:
    """``(len(x), n)``: control points -> the uniform cardinal B-spline of degree ``degree`` at index ``x``.

    Pole ``J`` is centred at ``J`` (knots ``J - (p+1)/2 + k``); the net is extended past its
    ends like the intent (even reflection, or wrap-around when periodic).
    """
    r = degree // 2 + 2
    m = n + 2 * r
    t = -r - (degree + 1) / 2 + np.arange(m + degree + 1, dtype=float)
    fold = np.pad(np.eye(n), ((r, r), (0, 0)), mode="wrap" if periodic else "reflect")
    return basis_matrix(t, degree, x, n=m) @ fold


def _evaluator(intent: Intent, scheme, road: str):
    """A function mapping control points ``(nu, nv, 3)`` to the surface on the fine grid."""
    net = intent.net
    au, av = intent.axes
    if road == "face":
        u = _param_axis(net, 0, au.x)
        v = _param_axis(net, 1, av.x)
        return lambda pts: evaluate(net, u, v, points=pts)
    if road == "uniform-bspline":
        from .separable import sandwich

        mats = [cardinal_operator(ax.n, deg, ax.x, per) for ax, deg, per in zip((au, av), scheme.degrees, net.periodic)]
        return lambda pts: sandwich(mats[0], np.asarray(pts, float), mats[1])
    # numerical subdivision
    mask = np.asarray(scheme.mask, float)
    stencil = np.asarray(scheme.limit_stencil, float)
    r = max(mask.shape) // 2 + max(stencil.shape) // 2 + 2
    K = au.K

    def run(pts):
        fine = apply_stencil(subdivide(_pad(pts, r, net.periodic), mask, au.levels), stencil)
        return fine[r * K: r * K + au.fine_count, r * K: r * K + av.fine_count]

    return run


def measured_fields(intent: Intent, scheme, fast: bool = True) -> ArtifactFields:
    """Artifact fields of the real surface (the *measured* road).

    Parameters
    ----------
    intent : Intent
        From :func:`cadartifact.fields.design_intent` with the same scheme.
    scheme : Scheme
    fast : bool
        When the real surface is a sum of products of per-axis matrices (a non-rational or
        constant-weight face, a uniform B-spline), band-split the factors
        (:func:`cadartifact.separable.tensor_fields`); False forces the 2-D FFT path.

    Returns
    -------
    ArtifactFields
        ``method == "measured"``; bands as in the predicted road. The trend's deviation is
        counted as signal error; the residual's deviation is extended (even reflection / wrap)
        on the fine grid and band-split by FFT.
    """
    road, _ = measurement_road(intent.net, scheme)
    if fast:
        from .separable import tensor_fields

        out = tensor_fields(intent, scheme, road)
        if out is not None:
            return out
    ev = _evaluator(intent, scheme, road)
    au, av = intent.axes
    nu, nv = intent.net.shape
    trend_pts = intent.trend(np.arange(nu), np.arange(nv))
    s_trend = ev(trend_pts)
    s_res = ev(intent.residual)
    intent_fine = intent.evaluate()
    trend_fine = intent.trend(au.x, av.x)
    dev = s_res - (intent_fine - trend_fine)
    if fast:
        from .separable import split_field

        bands = split_field(dev, au, av)
    else:
        spec = np.fft.fft2(av.extend(au.extend(dev, 0), 1), axes=(0, 1))
        bands = band_split(spec, au.freqs(fine=True), av.freqs(fine=True), (au.fine_count, av.fine_count))
    bands["signal_error"] = bands["signal_error"] + (s_trend - trend_fine)
    return ArtifactFields(x=au.x, y=av.x, surface=s_trend + s_res, intent=intent_fine, bands=bands,
                          method="measured", levels=au.levels)
