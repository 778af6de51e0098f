"""Rational clamped faces for the predicted road at clamped borders (issue 23, item 5).

A family of NURBS faces with clamped uniform knots and weights that vary: degrees 2-4 per direction,
6-14 control points per direction, weights varying by 10-45 % (a smooth field of random phase), control
points on a smooth shape (a dome with a tilt) plus a small ripple (a cosine of 0.1-0.45 cycles per control
point, random direction and phase). Used by ``tests/analysis/test_rational_borders.py`` and
``benchmarks/rational_borders.py``.
"""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots

__all__ = ["rational_face", "rational_family", "cut"]


def rational_face(seed: int, margin: int = 0) -> ControlNet:
    """One rational clamped face of the family, drawn from ``seed``.

    Parameters
    ----------
    seed : int
    margin : int
        Make the face ``margin`` control points longer at each end of each direction (the same draw: a longer
        face of which :func:`cut` at ``margin`` spans is the face of ``margin = 0`` in size, degrees and kind).

    Returns
    -------
    ControlNet
        ``(nu, nv)`` points with ``nu, nv`` in 6..14, degrees in 2..4, clamped uniform knots on [0, 1],
        weights ``(nu, nv)`` varying by 10-45 % of their mean.
    """
    rng = np.random.default_rng(seed)
    p, q = (int(d) for d in rng.integers(2, 5, size=2))
    nu, nv = (int(n) for n in rng.integers(6, 15, size=2))
    nu, nv = max(nu, p + 2) + 2 * margin, max(nv, q + 2) + 2 * margin
    size = rng.uniform(40.0, 120.0, size=2)
    s, t = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    # a smooth shape: a dome and a tilt, a few per cent of the size
    dome = rng.uniform(0.05, 0.2) * size.min() * (1 - (2 * s - 1) ** 2) * (1 - 0.5 * (2 * t - 1) ** 2)
    tilt = rng.uniform(-0.1, 0.1) * size[0] * s + rng.uniform(-0.1, 0.1) * size[1] * t
    # a small ripple: a cosine in index space, 0.1-0.45 cycles per control point, random direction and phase
    f, theta, phase = rng.uniform(0.1, 0.45), rng.uniform(0, np.pi), rng.uniform(0, 2 * np.pi)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    ripple = rng.uniform(0.002, 0.01) * size.min() * np.cos(2 * np.pi * f * (np.cos(theta) * i + np.sin(theta) * j)
                                                            + phase)
    pts = np.stack([size[0] * s, size[1] * t, dome + tilt + ripple], axis=-1)
    # weights varying by 10-45 % of their mean: a smooth field of random phase
    vary = rng.uniform(0.10, 0.45)
    a, b, c = rng.uniform(0, 2 * np.pi, size=3)
    field = np.cos(np.pi * s * rng.uniform(0.5, 1.5) + a) + np.cos(np.pi * t * rng.uniform(0.5, 1.5) + b) \
        + 0.5 * np.cos(np.pi * (s + t) + c)
    field = (field - field.min()) / max(np.ptp(field), 1e-12)
    w = 1.0 + vary * field
    w = w / w.mean()
    knots = (clamped_uniform_knots(nu, p), clamped_uniform_knots(nv, q))
    return ControlNet(points=pts, weights=w, degrees=(p, q), knots=knots)


def rational_family(count: int = 40, start: int = 0) -> list[ControlNet]:
    """``count`` faces of the family, seeds ``start .. start + count - 1``."""
    return [rational_face(seed) for seed in range(start, start + count)]


def cut(net: ControlNet, spans: int) -> ControlNet:
    """The face ``spans`` knot spans shorter at each end of each direction, exactly: the same surface there, a
    clamped face of its own (least squares of the homogeneous surface on the shorter clamped knots)."""
    from cadartifact.numerics.splines import basis_matrix

    H = np.concatenate([net.points * net.weights[..., None], net.weights[..., None]], axis=-1)
    mats, knots = [], []
    for axis in (0, 1):
        p, n, t = net.degrees[axis], net.shape[axis], np.asarray(net.knots[axis], float)
        lo, hi = t[p], t[n]
        h = (hi - lo) / (n - p)
        a, b = lo + spans * h, hi - spans * h
        m = n - 2 * spans
        new = clamped_uniform_knots(m, p, a, b)
        s = np.linspace(a, b, 6 * n + 7)
        mats.append(np.linalg.pinv(basis_matrix(new, p, s, m)) @ basis_matrix(t, p, s, n))
        knots.append(new)
    H = np.einsum("ia,abc,jb->ijc", mats[0], H, mats[1])
    w = H[..., 3]
    return ControlNet(points=H[..., :3] / w[..., None], weights=w, degrees=net.degrees, knots=tuple(knots))


#: Knot spans the border-free truth's longer face reaches past the face at every border.
TRUTH_MARGIN = 12


def border_free_truth(seed: int, margin: int = TRUTH_MARGIN) -> tuple[ControlNet, float]:
    """Face ``seed`` drawn ``margin`` spans longer at every border and cut back, and its border-free truth.

    Returns the cut face (:func:`cut`: the same surface as the longer face there, a clamped face of its own, of the
    family's size and degrees) and the longer face's measured total ripple peak over the region the cut face
    covers: the reading of the same surface as part of a longer one, which no border convention of the cut face
    touches.
    """
    from cadartifact.analysis.budget import budget

    whole = rational_face(seed, margin)
    face = cut(whole, margin)
    b = budget(whole, method="measured", keep_fields=True)
    K = 2 ** b.levels
    (nu, nv), (p, q) = face.shape, face.degrees
    inside = b.scalar_fields["total"][margin * K: margin * K + (nu - p) * K + 1,
                                      margin * K: margin * K + (nv - q) * K + 1]
    return face, float(np.abs(inside).max())
