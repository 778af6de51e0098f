"""The intent's uncertainty U and the decision rule (issue 22; SPEC §4 "Uncertainty and decisions", §5).

Calibration on known shapes: clamped faces whose control points sample a known smooth shape at their Greville
abscissae (tests/known_shapes.py: nets of 6-40 points, degrees 1-5, content 0.05-0.45 cycles per point in four
directions, random phases; cosines, sums of cosines, bumps, polynomials; tolerances 0.2-10 % of the amplitude).
Every number is checked against the known shape itself, evaluated here, and the advised net is evaluated by
scipy's B-spline basis (not the tool's).
"""

from __future__ import annotations

import numpy as np
import pytest

from cadartifact.advice.advise import advise
from cadartifact.advice.decision import CONFORMS, NONCONFORMING, UNDECIDED, decide, unverifiable_note
from cadartifact.analysis.intent import design_intent
from cadartifact.analysis.uncertainty import COVERAGE_FACTOR, intent_uncertainty
from cadartifact.theory.catalogue import bspline

from known_shapes import calibration_family, known_face, shape_function

#: The calibration: seed and count (issue 22 asks for at least 500 cases).
SEED, CASES = 2022, 500


def _scipy_surface(net, u, v) -> np.ndarray:
    """A non-rational B-spline net on ``u x v`` by scipy's basis (an evaluator independent of the tool's)."""
    from scipy.interpolate import BSpline

    Bu = BSpline.design_matrix(u, np.asarray(net.knots[0], float), net.degrees[0]).toarray()
    Bv = BSpline.design_matrix(v, np.asarray(net.knots[1], float), net.degrees[1]).toarray()
    return np.einsum("ai,ijc,bj->abc", Bu, np.asarray(net.points, float), Bv)


def _independent_fit_error(truth, shape, degrees, u, v) -> float:
    """Whole-face error of the least-squares B-spline of ``shape`` (clamped uniform knots) fitted to the known
    shape on ``u x v`` (scipy's basis): what the best net of that density can do."""
    from scipy.interpolate import BSpline

    from cadartifact.net import clamped_uniform_knots

    mats = []
    for n, p, s in zip(shape, degrees, (u, v)):
        p = min(p, n - 1)
        mats.append(BSpline.design_matrix(s, clamped_uniform_knots(n, p), p).toarray())
    T = truth(u, v)
    Q = np.einsum("ia,abc,jb->ijc", np.linalg.pinv(mats[0]), T, np.linalg.pinv(mats[1]))
    S = np.einsum("ai,ijc,bj->abc", mats[0], Q, mats[1])
    return float(np.linalg.norm(S - T, axis=-1).max())


def test_the_decision_rule():
    """ISO 14253-1: conforms only when v + U <= t, does not conform when v - U > t, else undecided."""
    assert decide(0.04, 0.01, 0.05) == CONFORMS
    assert decide(0.045, 0.01, 0.05) == UNDECIDED
    assert decide(0.06, 0.01, 0.05) == UNDECIDED
    assert decide(0.061, 0.01, 0.05) == NONCONFORMING
    assert decide(float("nan"), 0.0, 0.05) == NONCONFORMING
    assert "cannot be verified" in unverifiable_note(0.2, 0.05)


def test_U_is_small_for_a_polynomial_net_and_grows_near_the_nyquist_limit():
    """A net sampling a polynomial of the trend's degree determines its shape (U below 1e-4 of its size: only
    the alternate with a trend one degree lower moves it); the same cosine sampled nearer the Nyquist limit is
    less determined."""
    net, _ = known_face((3, 3), (16, 16), lambda X, Y: (X / 13) ** 3 - 0.5 * (Y / 13) ** 2 * (X / 13))
    it = design_intent(net, bspline(3, 3), 3)
    assert intent_uncertainty(it, bspline(3, 3)).peak < 1e-4
    us = []
    for f in (0.1, 0.25, 0.4):
        net, _ = known_face((3, 3), (16, 16), shape_function("cosine", f, 0.0, 0.3, (13, 13)))
        us.append(intent_uncertainty(design_intent(net, bspline(3, 3), 3), bspline(3, 3)).peak)
    assert us[0] < us[1] < us[2], us


def test_the_surface_reading_says_its_U_is_not_estimated():
    """The surface reading has no validated estimate of its split's uncertainty yet: U = 0, said so in the
    record, and its decisions are the plain comparison with the tolerance."""
    net, _ = known_face((3, 3), (14, 12), shape_function("cosine", 0.3, 0.5, 0.0, (11, 9)))
    a = advise(net, 0.02, compare=False, verify=False)
    assert a.uncertainty.peak == 0 and not a.uncertainty.estimated
    assert a.to_dict()["uncertainty"]["estimated"] is False
    assert a.today_decision == (CONFORMS if a.today["peak"] <= 0.02 else NONCONFORMING)


def test_advice_states_U_and_today_s_decision():
    """The advice carries U (peak and per direction), the decision for the advised net and today's."""
    net, _ = known_face((3, 3), (14, 12), shape_function("cosine", 0.2, 0.5, 0.0, (11, 9)))
    a = advise(net, 0.02, intent="net", compare=False, verify=False)
    d = a.to_dict()
    assert set(d["uncertainty"]) >= {"peak", "u", "v", "coverage_factor"}
    assert d["uncertainty"]["coverage_factor"] == COVERAGE_FACTOR
    assert d["decision"] == (CONFORMS if a.meets_tolerance else d["decision"])
    assert d["today_decision"] == decide(a.today["peak"], a.uncertainty.peak, 0.02)
    assert max(a.uncertainty.u, a.uncertainty.v) <= a.uncertainty.peak + 1e-12


def test_an_honest_no_when_U_alone_reaches_the_tolerance():
    """A 10-point net sampling content at 0.42 cycles per point cannot support a tolerance of 0.1 % of its
    amplitude: the advice says so and claims nothing."""
    net, _ = known_face((2, 2), (10, 10), shape_function("cosine", 0.42, np.pi / 4, 0.0, (8, 8)))
    a = advise(net, 0.001, intent="net", compare=False, verify=False)
    assert not a.meets_tolerance and not a.verifiable
    assert any("cannot be verified from these control points" in n for n in a.notes)
    assert a.shape == net.shape  # no number advised


#: The calibration's check grid: K = 4 per span (``levels=2``; the default is 8). A coarser check grid reads
#: a candidate's peak less exactly, so its claims are the riskier ones; it keeps 600 advice runs affordable.
LEVELS = 2

#: The 500 cases run as five seeded chunks (xdist spreads them over the cores); each asserts on its own.
CHUNKS = 5


def _calibration(seed, count, **family):
    rows = []
    u, v = np.linspace(0, 1, 161), np.linspace(0, 1, 157)
    for net, truth, info in calibration_family(seed, count, **family):
        t = info["tolerance"]
        a = advise(net, t, intent="net", compare=False, verify=False, levels=LEVELS)
        it = design_intent(net, bspline(*net.degrees), 3)
        fu, fv = it.frames
        intent_error = float(np.linalg.norm(it.evaluate(fu.x, fv.x) - truth(fu.param(fu.x), fv.param(fv.x)),
                                            axis=-1).max())
        true = float(np.linalg.norm(_scipy_surface(a.resampled(), u, v) - truth(u, v), axis=-1).max())
        (nu, nv), f = info["shape"], info["f"]
        eligible = min(nu, nv) >= 16 and f <= 0.3 and t >= 0.02
        fit = _independent_fit_error(truth, a.shape, net.degrees, u, v) if eligible else None
        rows.append({"info": info, "claim": bool(a.meets_tolerance), "true": true, "t": t, "U": a.uncertainty.peak,
                     "intent_error": intent_error, "eligible": eligible and fit <= t / 2,
                     "today": a.today_decision})
    return rows


def _summary(rows) -> str:
    claims = [r for r in rows if r["claim"]]
    return (f"cases {len(rows)}, claims {len(claims)}, false claims "
            f"{sum(r['true'] > 1.1 * r['t'] for r in claims)}, coverage of U "
            f"{np.mean([r['intent_error'] <= r['U'] + 1e-9 for r in rows]):.4f}, today's net decided "
            f"{np.mean([r['today'] != UNDECIDED for r in rows]):.3f}, worst claimed true/t "
            f"{max((r['true'] / r['t'] for r in claims), default=0):.3f}")


@pytest.mark.slow
@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_calibration_on_known_shape_families(chunk):
    """Issue 22, item 3 (500 seeded cases in five chunks of 100): no false claim (true whole-face distance of the
    advised net > 1.1 t while conformance is claimed), and U covers the intent's true whole-face error in at
    least 95 % of the cases (of each chunk, so of the whole)."""
    rows = _calibration(SEED + chunk, CASES // CHUNKS)
    print("\n" + _summary(rows))
    false = [r["info"]["text"] + f" true/t={r['true'] / r['t']:.3f}" for r in rows if r["claim"] and r["true"] > 1.1 * r["t"]]
    assert not false, false
    assert np.mean([r["intent_error"] <= r["U"] + 1e-9 for r in rows]) >= 0.95


@pytest.mark.slow
def test_claims_are_not_refused_where_the_net_supports_them():
    """Issue 22, item 3: on nets of 16 points or more, content up to 0.3 cycles per point and tolerances of at
    least 2 % of the amplitude, wherever an independent least-squares fit of the true shape meets t/2 at the
    advised density, conformance is claimed in at least 80 % of the cases (100 seeded cases of that kind)."""
    rows = _calibration(SEED + 100, 100, nmin=16, fmax=0.3, tol_range=(0.02, 0.1))
    eligible = [r for r in rows if r["eligible"]]
    claimed = np.mean([r["claim"] for r in eligible])
    print(f"\n{_summary(rows)}; eligible {len(eligible)}, claimed among them {claimed:.3f}")
    assert len(eligible) >= 25 and claimed >= 0.8  # 35 of the 100 are eligible (the fit must meet t/2)
    assert not [r for r in rows if r["claim"] and r["true"] > 1.1 * r["t"]]
