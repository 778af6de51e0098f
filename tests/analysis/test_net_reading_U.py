"""The sharper U of the ``net`` reading (issue 39 item 1; SPEC §4 "Uncertainty and decisions").

``U = k s D``: ``D`` the alternates' spread, ``s`` the standard uncertainty per unit of it, calibrated on known
shapes (nets 10-28, degrees 2-3, cosines, sums, bumps along u, v, the diagonal: benchmarks/calibrate_net_reading.py,
docs/uncertainty.md "A sharper U"), ``k`` = 2; two scales of one spread: today's value's (``TODAY_SCALE``, what
the gate decides with) and any candidate's (``SPREAD_SCALE``: the intent's own error, which bounds every value
against it, what the advice claims with). Checked here on families the calibration did not see: today's error
(today's net's true distance from the known shape minus the reported deviation, scipy's basis) within today's U
on at least 95 % of cases, and U sharp (the 95th percentile of ``|error| / U`` at least 0.6); the intent's own
error within the candidates' U on at least 95 %; and no conformance claimed for a net more than 1.1 t from the
known shape.
"""

from __future__ import annotations

import numpy as np
import pytest

from cadartifact.analysis.intent import design_intent
from cadartifact.analysis.uncertainty import (COVERAGE_FACTOR, SPREAD_SCALE, TODAY_SCALE, intent_spread,
                                              intent_uncertainty)
from cadartifact.testing.calibration import error_ratios, net_reading_claims, net_reading_rows
from cadartifact.testing.known_shapes import known_face, net_reading_family, shape_function
from cadartifact.theory.catalogue import bspline


@pytest.mark.parametrize("degrees, shape, f", [((2, 2), (12, 14), 0.15), ((3, 5), (20, 16), 0.3),
                                               ((5, 3), (26, 11), 0.38)])
def test_U_is_k_times_the_calibrated_standard_uncertainty(degrees, shape, f):
    """Today's U = k TODAY_SCALE D on the face and per direction, a candidate's k SPREAD_SCALE D, k = 2 (about
    95 %), both scales below the first calibration's 1, today's the sharper."""
    spans = (shape[0] - degrees[0], shape[1] - degrees[1])
    net, _ = known_face(degrees, shape, shape_function("cosine", f, 0.4, 1.0, spans))
    it = design_intent(net, bspline(*degrees), 3)
    U = intent_uncertainty(it, bspline(*degrees))
    D = intent_spread(it)
    assert COVERAGE_FACTOR == 2.0 and 0 < TODAY_SCALE < SPREAD_SCALE < 1
    assert U.factor == COVERAGE_FACTOR
    np.testing.assert_allclose((U.peak, U.u, U.v), np.multiply(D, COVERAGE_FACTOR * TODAY_SCALE), rtol=1e-12)
    np.testing.assert_allclose(U.candidate, D[0] * COVERAGE_FACTOR * SPREAD_SCALE, rtol=1e-12)


HELD_OUT = {"30 degrees": (3913, {"directions": ("30deg",)}), "the issue's mix, degrees 2/3/5": (3915, {})}


@pytest.fixture(scope="module", params=list(HELD_OUT))
def held_out(request):
    seed, kw = HELD_OUT[request.param]
    rows = net_reading_rows(net_reading_family(seed, 40, **kw))
    return request.param, error_ratios(rows), error_ratios(rows, SPREAD_SCALE, key="intent_error")


@pytest.mark.slow
def test_U_covers_on_a_held_out_family_and_is_sharp(held_out):
    """Families held out of the calibration (another direction; degree 5 and other seeds): today's U covers
    today's error on >= 95 % and the 95th percentile of |error| / U is >= 0.6 (2026-12-06: 30 degrees 97.5 % and
    0.677, the mix 95.0 % and 0.931; the benchmark's families 97.5-100 % and 0.60-0.81; the first calibration's U
    read 0.16-0.22, one scale of 0.5 for both values 0.32-0.44); the candidates' U covers the intent's own error on
    >= 95 % (100 %, 95 %)."""
    name, r, intent = held_out
    assert np.mean(r <= 1.0) >= 0.95, (name, np.sort(r)[-4:])
    assert np.percentile(r, 95) >= 0.6, (name, np.percentile(r, [50, 90, 95]))
    assert np.mean(intent <= 1.0) >= 0.95, (name, np.sort(intent)[-4:])


@pytest.mark.slow
def test_no_claim_beyond_1_1_t_of_the_true_shape():
    """The advice on the issue's mix (held out): no net claimed within tolerance is more than 1.1 t from the
    known shape (scipy's basis, along the shape's normal), and claims are not refused where the net says enough:
    at least 85 % of the cases at <= 0.3 cycles per point claimed."""
    rows = net_reading_claims(net_reading_family(3925, 24))
    beyond = [r["info"]["text"] for r in rows if r["claim"] and r["true"] > 1.1 * r["t"]]
    assert not beyond, beyond
    low = [r for r in rows if r["info"]["f"] <= 0.3]
    assert np.mean([r["claim"] for r in low]) >= 0.85, [r["info"]["text"] for r in low if not r["claim"]]
