"""The *measured* road's real surfaces, evaluated on the fine grid.

Independent of the spectral formulas, the surface comes from

* ``"face"``: exact NURBS evaluation of the face's own knots, degrees and weights
  (:func:`cadartifact.numerics.splines.evaluate`, checked against OCCT's evaluator in the tests),
  parameters affine in the analysis coordinates (:mod:`cadartifact.analysis.frames`);
* ``"uniform-bspline"``: a B-spline scheme applied to a net that is not that face (an OBJ
  cage): uniform cardinal B-splines on the net continued by its intent past its borders;
* ``"subdivision"``: ``L`` steps of numerical subdivision with the scheme's mask, then its
  limit stencil (4-3, 4-8, Kobbelt, user masks).
"""

from __future__ import annotations

import numpy as np

from ..errors import OptionError
from ..numerics.splines import basis_matrix, evaluate
from ..numerics.tensor import sandwich

__all__ = ["real_surface", "measurement_road", "subdivide", "apply_stencil", "cardinal_operator"]


def measurement_road(net, scheme) -> tuple[str, str]:
    """Which real surface the measured road evaluates, and why.

    Returns
    -------
    (road, reason) : (str, str)
        ``road`` in {"face", "uniform-bspline", "subdivision"}.
    """
    own = net.is_bspline and scheme.degrees is not None and tuple(scheme.degrees) == tuple(net.degrees)
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


def real_surface(intent, scheme) -> np.ndarray:
    """The real surface of the intent's net on its fine grid, ``(a, b, 3)`` (``(a, b, 4)`` homogeneous for
    a rational intent).

    ``face``: the face's own NURBS (knots, degrees, weights) at the parameters of the fine grid.
    A cage has no surface past its border rows: it is continued there by its intent (which passes
    through its points), then ``uniform-bspline``: the uniform cardinal B-spline of the continued net;
    ``subdivision``: ``levels`` steps of the scheme's mask and its limit stencil.
    """
    net = intent.net
    fu, fv = intent.frames
    road, _ = measurement_road(net, scheme)
    if intent.homogeneous and road != "face":
        raise OptionError("scheme", "the face's own degrees for a rational net", scheme.name)
    if road == "face":
        # rational: the homogeneous surface (w S, w), a non-rational B-spline of (w P, w)
        return evaluate(net, fu.param(fu.x), fv.param(fv.x), points=intent.lifted_points,
                        homogeneous=intent.homogeneous)
    if road == "uniform-bspline":
        r = max(scheme.degrees) // 2 + 2
        pts = intent.evaluate(np.arange(-r, fu.n + r, dtype=float), np.arange(-r, fv.n + r, dtype=float))
        mats = []
        for f, deg in zip((fu, fv), scheme.degrees):
            m = f.n + 2 * r
            t = -r - (deg + 1) / 2 + np.arange(m + deg + 1, dtype=float)
            mats.append(basis_matrix(t, deg, f.x, n=m))
        return sandwich(mats[0], pts, mats[1])
    mask = np.asarray(scheme.mask, float)
    stencil = np.asarray(scheme.limit_stencil, float)
    r = max(mask.shape) // 2 + max(stencil.shape) // 2 + 2
    K = fu.K
    pts = intent.evaluate(np.arange(-r, fu.n + r, dtype=float), np.arange(-r, fv.n + r, dtype=float))
    fine = apply_stencil(subdivide(pts, mask, fu.levels), stencil)
    return fine[r * K: r * K + fu.fine_count, r * K: r * K + fv.fine_count]
