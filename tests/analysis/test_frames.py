"""Where the measured road cuts a direction: half a cycle per control point, counted in index space (SPEC §1, §4).

Second road: the Greville abscissae of clamped uniform knots (:func:`cadartifact.net.greville`), counted. The cut
over a direction lies between the interior's count (half a cycle per span) and the index count (half a cycle per
Greville interval, ``n - 1`` of them); it is the latter in the limit of the shortest direction, the former from
``2 p`` spans on, and it widens strictly in between.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadartifact.analysis.frames import MAX_CROWDED_DEGREE, MAX_CUT, AxisFrame, axis_frames, index_space_cut
from cadartifact.net import ControlNet, clamped_uniform_knots, greville


def _frame(n, p, periodic=False):
    spans = n if periodic else n - p
    return AxisFrame(n, periodic, spans, 0.0, np.zeros(n), 3)


def _over(L, p):
    """The base band over the direction, in cycles: ``cut * L``."""
    return index_space_cut(_frame(L + p, p)) * L


@pytest.mark.parametrize("p", [2, 3, 4, 5])
def test_the_cut_lies_between_the_interior_count_and_the_greville_count(p):
    for L in range(1, 4 * p):
        n = L + p
        intervals = len(greville(clamped_uniform_knots(n, p, 0.0, float(L)), p, n)) - 1
        assert L / 2 <= _over(L, p) <= intervals / 2 + 1e-12
        if L >= 2 * p:  # the interior's abscissae are one span apart, and so is the count
            assert index_space_cut(_frame(n, p)) == 0.5
    # the shortest direction: all the ends' intervals count, less what the one-cycle cap keeps out
    assert _over(1, p) == pytest.approx(min((p - 1) * (1 - 1 / (2 * p)) + 1, 2 * MAX_CUT) / 2)


@settings(max_examples=80, deadline=None)
@given(p=st.integers(1, 9), L=st.integers(1, 40))
def test_more_spans_or_a_higher_degree_always_widen_the_band(p, L):
    """Knot insertion (``L + 1``) and degree elevation (``p + 1``) re-express the same surface: its base band over
    the direction must widen (SPEC §4 "Invariance"), strictly while the ends count (below ``2 p`` spans, degree
    at most 5, under the cap)."""
    assert _over(L + 1, p) >= _over(L, p) and _over(L, p + 1) >= _over(L, p)
    if 2 <= p <= MAX_CROWDED_DEGREE and L < 2 * p and index_space_cut(_frame(L + 1 + p, p)) < MAX_CUT:
        assert _over(L + 1, p) > _over(L, p)
    assert 0.5 <= index_space_cut(_frame(L + p, p)) <= MAX_CUT


def test_degrees_above_5_count_their_ends_as_degree_5():
    for L in range(1, 12):
        assert index_space_cut(_frame(L + 10, 10)) == index_space_cut(_frame(L + 5, 5))


def test_cages_and_periodic_directions_keep_half_a_cycle_per_span():
    cage = ControlNet(points=np.random.default_rng(1).normal(size=(6, 5, 3)))
    assert all(f.cut == 0.5 and index_space_cut(f) == 0.5 for f in axis_frames(cage))
    assert index_space_cut(_frame(8, 3, periodic=True)) == 0.5


def test_the_measured_period_puts_a_bin_at_the_cut():
    from cadartifact.analysis.fields import measured_frames

    for n, p in [(7, 5), (8, 4), (7, 3), (9, 5), (20, 3), (5, 3), (7, 4), (13, 4)]:
        net = ControlNet(points=np.random.default_rng(n).normal(size=(n, 6, 3)), degrees=(p, 2),
                         knots=(clamped_uniform_knots(n, p), clamped_uniform_knots(6, 2)))
        periods = []
        for pad in (0, 2, 4):  # the convention's period and its two variants (border_convention.PERIOD_LATITUDE)
            f = measured_frames(axis_frames(net), (pad, 0))[0]
            bins = np.fft.rfftfreq(f.K * f.period, d=1.0 / f.K)
            assert np.isclose(bins, f.cut).any(), (n, p, pad, f.period, f.cut)
            periods.append(f.period)
        assert periods[0] < periods[1] < periods[2], periods
