"""The Hermite bridge in Bezier form (cadartifact/numerics/hermite.py) against scipy's own construction.

Independent road: ``scipy.interpolate.BPoly.from_derivatives`` builds the same interpolant from the end
derivatives by its own recurrence; the Bezier points and the values must agree, and every basis function must
have the end derivatives it stands for.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BPoly

from cadartifact.analysis.clamped import lattice_continuation, uniform_equivalent
from cadartifact.numerics.hermite import bernstein_basis, hermite_basis, hermite_to_bezier


@settings(max_examples=40, deadline=None)
@given(order=st.integers(0, 7), seed=st.integers(0, 2**31 - 1))
def test_the_bezier_points_and_values_are_scipys(order, seed):
    rng = np.random.default_rng(seed)
    y0, y1 = rng.normal(size=order + 1), rng.normal(size=order + 1)
    reference = BPoly.from_derivatives([0.0, 1.0], [y0, y1])
    A = hermite_to_bezier(order)
    points = np.r_[A @ y0, (A @ (y1 * (-1.0) ** np.arange(order + 1)))[::-1]]
    size = np.abs(reference.c).max()
    assert np.abs(points - reference.c[:, 0]).max() <= 1e-13 * size
    t = np.linspace(0.0, 1.0, 29)
    assert np.abs(np.r_[y0, y1] @ hermite_basis(t, order) - reference(t)).max() <= 1e-12 * size


@pytest.mark.parametrize("order", range(0, 7))
def test_each_basis_function_has_the_end_derivatives_it_stands_for(order):
    n = 2 * order + 1
    for k in range(2 * order + 2):
        unit = np.zeros(2 * order + 2)
        unit[k] = 1.0
        f = BPoly.from_derivatives([0.0, 1.0], [unit[: order + 1], unit[order + 1:]])
        t = np.linspace(0.0, 1.0, 17)
        assert np.allclose(hermite_basis(t, order)[k], f(t), atol=1e-12)
    assert np.allclose(bernstein_basis(np.linspace(0, 1, 9), n).sum(axis=0), 1.0)  # a partition of unity


@pytest.mark.parametrize("call, message", [
    (lambda: hermite_to_bezier(-1), "order: expected an integer >= 0, received -1"),
    (lambda: hermite_basis(np.array([0.5]), -2), "order: expected an integer >= 0, received -2"),
    (lambda: bernstein_basis(np.array([0.5]), 1.5), "degree: expected an integer >= 0, received 1.5"),
    (lambda: lattice_continuation(5, 3, -3), "gap: expected an integer >= 0, received -3"),
    (lambda: uniform_equivalent(3, 3), "n: expected an integer >= 4, received 3"),
])
def test_bad_parameters_say_which_expected_and_received(call, message):
    with pytest.raises(ValueError, match=message):
        call()
