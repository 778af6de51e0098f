"""Faces exact along one direction: a rippled profile revolved by a circular arc, or extruded along a line.

A revolved face is a rational quadratic arc in ``u`` (3 poles, weights ``1, cos(theta / 2), 1``; Piegl and Tiller
§7.3, §8.5) about an axis, of a non-rational profile curve in ``v`` (degree 2-4, 8-14 poles, a ripple of the poles);
an extruded one is a straight degree-1 direction (2 poles) along a profile curve. Each is placed by a rotation and a
translation, may be transposed (the exact direction in ``v``), and is recognised by the reader's own recogniser
(:func:`cadartifact.exchange.canonical.recognise`), which sets ``exact`` and ``canonical`` as a file's face gets them.
Used by ``tests/advice/test_exact_directions.py``.
"""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots

__all__ = ["revolved_face", "extruded_face", "recognised", "placement"]


def placement(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A rotation ``(3, 3)`` and a translation ``(3,)`` drawn from ``seed`` (QR of a Gaussian matrix)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q, rng.uniform(-50.0, 50.0, size=3)


def _profile(rng, n: int, radius: float, ripple: float) -> tuple[np.ndarray, np.ndarray]:
    """Radial distances and heights of a profile's ``n`` poles: a bulge and a ripple of the poles."""
    s = np.linspace(0.0, 1.0, n)
    r = radius * (1.0 + 0.15 * np.sin(np.pi * s)) + ripple * np.cos(np.pi * np.arange(n) * rng.uniform(0.6, 0.95)
                                                                     + rng.uniform(0, 2 * np.pi))
    z = radius * 1.5 * s
    return r, z


def revolved_face(radius: float, angle_deg: float, degree: int, n: int, seed: int = 0, transpose: bool = False,
                  ripple: float | None = None, arcs: int = 1) -> ControlNet:
    """A profile revolved about an axis by ``arcs`` rational quadratic arcs (each ``angle_deg / arcs`` < 180).

    Returns
    -------
    ControlNet
        ``(2 arcs + 1) x n`` poles (transposed when ``transpose``): degree ``(2, degree)``, weights ``1, cos(theta/2),
        1, cos(theta/2), ...`` along the arcs (``theta`` each arc's angle), the arcs joined by double knots at
        ``k / arcs``; placed by :func:`placement` of ``seed``. Its axis is ``rotation[:, 2]`` through ``translation``.
    """
    rng = np.random.default_rng(seed)
    theta = np.radians(angle_deg) / arcs
    r, z = _profile(rng, n, radius, radius * 0.01 if ripple is None else ripple)
    m = 2 * arcs + 1
    pts = np.empty((m, n, 3))
    for i in range(m):
        phi, scale = i * theta / 2, (1.0 if i % 2 == 0 else 1.0 / np.cos(theta / 2))
        pts[i, :, 0] = r * scale * np.cos(phi)
        pts[i, :, 1] = r * scale * np.sin(phi)
        pts[i, :, 2] = z
    w = np.outer([1.0 if i % 2 == 0 else np.cos(theta / 2) for i in range(m)], np.ones(n))
    rot, shift = placement(seed)
    pts = pts @ rot.T + shift
    arc_knots = np.r_[[0.0] * 3, np.repeat(np.arange(1, arcs) / arcs, 2), [1.0] * 3]
    knots = (arc_knots, clamped_uniform_knots(n, degree))
    net = ControlNet(points=pts, weights=w, degrees=(2, degree), knots=knots)
    return transposed(net) if transpose else net


def extruded_face(length: float, degree: int, n: int, seed: int = 0, transpose: bool = False) -> ControlNet:
    """A rippled planar profile curve extruded along a line: ``2 x n`` poles, degree ``(1, degree)``."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 1.0, n)
    y = length * 0.2 * np.sin(np.pi * s) + length * 0.004 * np.cos(np.pi * np.arange(n) * rng.uniform(0.6, 0.95))
    prof = np.stack([length * s, y, np.zeros(n)], axis=-1)
    pts = np.stack([prof, prof + [0.0, 0.0, length * 0.7]], axis=0)
    rot, shift = placement(seed)
    pts = pts @ rot.T + shift
    net = ControlNet(points=pts, degrees=(1, degree), knots=(clamped_uniform_knots(2, 1),
                                                            clamped_uniform_knots(n, degree)))
    return transposed(net) if transpose else net


def transposed(net: ControlNet) -> ControlNet:
    """The same surface with ``u`` and ``v`` swapped."""
    return ControlNet(points=np.swapaxes(net.points, 0, 1), weights=None if net.weights is None else net.weights.T,
                      degrees=net.degrees[::-1], knots=net.knots[::-1], periodic=net.periodic[::-1],
                      uv_bounds=None if net.uv_bounds is None else tuple(np.asarray(net.uv_bounds)[[2, 3, 0, 1]]),
                      unit=net.unit)


def recognised(net: ControlNet) -> ControlNet:
    """The net with ``canonical`` and ``exact`` as the reader sets them (OCCT's recogniser on its surface)."""
    from cadartifact.exchange.canonical import recognise
    from cadartifact.exchange.load import occ_surface

    label, exact = recognise(occ_surface(net), net.uv_bounds)
    return net.replace(canonical=label, exact=tuple(exact))
