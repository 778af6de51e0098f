"""Where the measured road cuts a direction: half a cycle per control point in index space (SPEC §1, §4).

Second road: the Greville abscissae of clamped uniform knots (:func:`cadartifact.net.greville`), counted: a direction
with no interior (``L <= p`` spans) has ``n - 1`` Greville intervals over its ``L`` spans, and its cut is half a
cycle per interval; from ``2 p - 1`` spans on its interior's abscissae are one span apart, and the cut is half a
cycle per span.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cadartifact.analysis.frames import AxisFrame, axis_frames, index_space_cut
from cadartifact.net import ControlNet, clamped_uniform_knots, greville


def _frame(n, p, periodic=False):
    spans = n if periodic else n - p
    return AxisFrame(n, periodic, spans, 0.0, np.zeros(n), 3)


@pytest.mark.parametrize("p", [2, 3, 4, 5])
def test_without_an_interior_the_cut_is_half_a_cycle_per_greville_interval(p):
    for L in range(1, p + 1):
        n = L + p
        xs = greville(clamped_uniform_knots(n, p, 0.0, float(L)), p, n)
        assert np.all(np.diff(xs) < 1.0 + 1e-12)  # no two abscissae a whole span apart: all of it is ends
        assert index_space_cut(_frame(n, p)) == pytest.approx((len(xs) - 1) / (2.0 * L))


@pytest.mark.parametrize("p", [2, 3, 4, 5])
def test_with_an_interior_of_unit_spacing_the_cut_is_half_a_cycle_per_span(p):
    for L in range(2 * p - 1, 2 * p + 12):
        n = L + p
        xs = greville(clamped_uniform_knots(n, p, 0.0, float(L)), p, n)
        assert np.any(np.isclose(np.diff(xs), 1.0))
        assert index_space_cut(_frame(n, p)) == 0.5


@settings(max_examples=60, deadline=None)
@given(p=st.integers(1, 7), L=st.integers(1, 40))
def test_the_cut_over_a_direction_never_falls_with_more_spans_or_a_higher_degree(p, L):
    """Knot insertion (``L + 1``) and degree elevation (``p + 1``) re-express the same surface: its base band over
    the direction (cycles over the face, ``cut * L``) must not shrink (SPEC §4 "Invariance")."""
    over = lambda n, q: index_space_cut(_frame(n, q)) * (n - q)  # noqa: E731
    assert over(L + 1 + p, p) >= over(L + p, p)
    assert over(L + p + 1, p + 1) >= over(L + p, p)
    assert index_space_cut(_frame(L + p, p)) >= 0.5


def test_cages_and_periodic_directions_keep_half_a_cycle_per_span():
    cage = ControlNet(points=np.random.default_rng(1).normal(size=(6, 5, 3)))
    assert all(f.cut == 0.5 and index_space_cut(f) == 0.5 for f in axis_frames(cage))
    assert index_space_cut(_frame(8, 3, periodic=True)) == 0.5


def test_the_measured_period_puts_a_bin_at_the_cut():
    from cadartifact.analysis.fields import measured_frames

    for n, p in [(7, 5), (8, 4), (7, 3), (9, 5), (20, 3), (5, 3), (7, 4)]:  # alignments 4, 8, 8, 10, 2, 1, 1
        net = ControlNet(points=np.random.default_rng(n).normal(size=(n, 6, 3)), degrees=(p, 2),
                         knots=(clamped_uniform_knots(n, p), clamped_uniform_knots(6, 2)))
        periods = []
        for pad in (0, 2, 4):  # the convention's period and its two variants (border_convention.PERIOD_LATITUDE)
            f = measured_frames(axis_frames(net), (pad, 0))[0]
            bins = np.fft.rfftfreq(f.K * f.period, d=1.0 / f.K)
            assert np.isclose(bins, f.cut).any(), (n, p, pad, f.period, f.cut)
            periods.append(f.period)
        assert periods[0] < periods[1] < periods[2], periods
