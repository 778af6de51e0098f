"""numerics.peaks.first_peak against a plain loop: the first entry (C order) within rounding of the largest."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st

from cadartifact.numerics.peaks import first_peak


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), shape=st.tuples(st.integers(1, 6), st.integers(1, 6)))
def test_the_first_of_near_equal_peaks(seed, shape):
    rng = np.random.default_rng(seed)
    values = np.round(rng.normal(size=shape), 1)  # ties are common
    values[rng.random(shape) < 0.2] = -np.inf
    if np.isinf(values).all():
        values[0, 0] = 0.0
    top = values.max()
    values = values + np.where(values == top, 1e-12 * rng.random(shape), 0.0)  # equal to rounding
    top = values.max()
    want = next((i, j) for i in range(shape[0]) for j in range(shape[1]) if values[i, j] >= top - 1e-9 * abs(top))
    assert first_peak(values) == want
