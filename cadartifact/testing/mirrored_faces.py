"""Mirrored, reversed, transposed and moved copies of a face: the same surface, so the same advice (transposed
where ``u`` and ``v`` swap). Shared by the tests (not a test module itself)."""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet
from cadartifact.testing.arc_faces import placement

__all__ = ["copies"]


def _reverse(knots: np.ndarray) -> np.ndarray:
    return (knots[-1] + knots[0]) - knots[::-1]


def copies(net: ControlNet) -> dict:
    """The face's five copies, by name (``transpose`` swaps ``u`` and ``v``)."""
    P = np.asarray(net.points)
    W = None if net.weights is None else np.asarray(net.weights)
    ku, kv = (np.asarray(k, float) for k in net.knots)
    b = net.uv_bounds

    def make(points, weights, degrees, knots, bounds):
        return ControlNet(points=points, weights=weights, degrees=degrees, knots=knots, uv_bounds=bounds)

    su, sv = ku[-1] + ku[0], kv[-1] + kv[0]
    rot, shift = placement(11)
    return {
        "transpose": make(np.swapaxes(P, 0, 1), None if W is None else W.T, net.degrees[::-1], (kv, ku),
                          None if b is None else (b[2], b[3], b[0], b[1])),
        "reverse u": make(P[::-1], None if W is None else W[::-1], net.degrees, (_reverse(ku), kv),
                          None if b is None else (su - b[1], su - b[0], b[2], b[3])),
        "reverse v": make(P[:, ::-1], None if W is None else W[:, ::-1], net.degrees, (ku, _reverse(kv)),
                          None if b is None else (b[0], b[1], sv - b[3], sv - b[2])),
        "mirror x": make(P * np.array([-1.0, 1.0, 1.0]), W, net.degrees, (ku, kv), b),
        "rotate": make(P @ rot.T + shift, W, net.degrees, (ku, kv), b),
    }
