"""The predicted road on rational clamped faces (issue 23, item 5: "rational predicted road at clamped borders
within 10 % of the measured one"): not reached, and said.

Independent road: the measured road reads the real surface (exact NURBS evaluation). The predicted road
synthesises the uniform theory's infinite net from the control points; at a clamped border of a rational face
the homogeneous net is not such a lattice, and on this family the predicted road reads 1.6-258x the measured
one (median 11x, 2026-12-03). Faces are measured by default (``method="auto"``), so reported numbers are not
affected; a run that asks for the predicted road gets a caveat saying so.
"""

from __future__ import annotations

import numpy as np
import pytest

import cadartifact as ca
from cadartifact.net import ControlNet, clamped_uniform_knots


def _rational_face(seed: int, periodic_weights: bool = False) -> ControlNet:
    """A rational clamped face: a cosine sheet with a little noise, weights exp(a cos(...)) varying 10-40 %."""
    rng = np.random.default_rng(seed)
    p = int(rng.integers(2, 5))
    nu, nv = (int(x) for x in rng.integers(7, 15, 2))
    u, v = np.linspace(0, 1, nu), np.linspace(0, 1, nv)
    X, Y = np.meshgrid(100 * u, 80 * v, indexing="ij")
    Z = 10 * np.cos(2 * np.pi * (0.8 * u[:, None] + 0.5 * v[None, :]) + rng.uniform(0, 6)) \
        + 0.3 * rng.normal(size=X.shape)
    W = np.exp(rng.uniform(0.1, 0.4) * np.cos(2 * np.pi * (rng.uniform(0.1, 0.3) * np.arange(nu)[:, None]
                                                          + rng.uniform(0.1, 0.3) * np.arange(nv)[None, :])))
    return ControlNet(points=np.stack([X, Y, Z], -1), degrees=(p, p), weights=W,
                      knots=(clamped_uniform_knots(nu, p), clamped_uniform_knots(nv, p)))


SEEDS = range(100, 106)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_predicted_road_on_a_rational_clamped_face_says_it_departs(seed):
    net = _rational_face(seed)
    b = ca.budget(net, method="predicted")
    assert any("predicted road" in n and "clamped borders" in n for n in b.notes), b.notes
    assert not any("predicted road" in n for n in ca.budget(net).notes)  # the default measures: no caveat


def test_a_non_rational_face_on_the_predicted_road_has_no_such_caveat():
    net = _rational_face(100)
    plain = ControlNet(points=net.points, degrees=net.degrees, knots=net.knots)
    assert not any("predicted road" in n for n in ca.budget(plain, method="predicted").notes)


@pytest.mark.xfail(strict=True, reason="issue 23 item 5: the rational predicted road at clamped borders reads "
                                       "1.6-258x the measured road")
def test_the_predicted_road_is_within_10_percent_of_the_measured_one_on_rational_clamped_faces():
    ratios = []
    for seed in SEEDS:
        net = _rational_face(seed)
        ratios.append(ca.budget(net, method="predicted").stats["total"].peak
                      / ca.budget(net, method="measured").stats["total"].peak)
    assert np.all(np.abs(np.array(ratios) - 1) <= 0.1), ratios
