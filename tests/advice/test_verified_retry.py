"""An honest no only after the search has tried the nets a write-and-measure check would accept.

The search reads a candidate of the surface reading by the larger of its deviation from the intent and its own
ripple as its budget reads it. On a quintic face extended past its trim the own-ripple reading of its 14x13 net is
0.038 while the net lies within 0.00175 of the intent on OCCT's surface: the search answered "no density within
the limits conforms" at t = 0.002 (and at 0.001, 21x13: 0.0294 read against 0.000965 measured). Before the honest
no the advice now searches the deviation alone and measures what it finds on OCCT's surface (the verification of
SPEC §5), and claims a net only where that measure + U stays within t.

Checked here, on faces extended past their trims (joins of multiplicity p and p - 1, bent), jointed faces and
bumps near a border, degrees 2, 3, 5:

- where the retry answers, the claim is what a third road measures: the advised net evaluated with scipy's
  B-spline basis against the intent, along its normals, on the trimmed check grid;
- where the advice still says no, no net in a window of three times today's counts per direction (the search's
  range reaches eight) has a deviation within t - U that OCCT's surface confirms (brute force); the first retry
  (the deviation frontier only) failed this on two quintic faces, whose fitting net lies beside the search's best;
- mirrored, reversed, transposed and moved copies get the same answer.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("OCP")
pytest.importorskip("scipy")

import cadartifact as ca  # noqa: E402
from cadartifact.analysis.budget import budget_for  # noqa: E402
from cadartifact.analysis.fields import project  # noqa: E402
from cadartifact.analysis.fitting import candidate_net  # noqa: E402
from cadartifact.analysis.settings import RunSettings, resolve_scheme  # noqa: E402
from cadartifact.advice.density_search import _limits  # noqa: E402
from cadartifact.advice.scorer import _make_scorer  # noqa: E402
from cadartifact.advice.verification import measure_on_occt  # noqa: E402
from cadartifact.testing.extended_faces import (bordered_bump_face, extended_face, jointed_face,  # noqa: E402
                                                 smooth_face)
from cadartifact.testing.mirrored_faces import copies  # noqa: E402


def quintic_extended_seed(seed):
    return extended_face(smooth_face(n=(14, 8), degree=5, amplitude=6.0, seed=seed), sides=("u0", "v1"), ext=0.03,
                         bend=0.02, trim="third")


#: (face's seed, tolerance, the net that verifies) the search answered "out of reach" before the retry: the
#: deviation frontier finds the first two; the last two lie beside the search's best (18x15: b = 14 fits 0.00074
#: and 0.00099, b = 15-17 0.00102-0.00107; the join plan moves the deviation from one count to the next).
RETRIED = [(1, 0.002, (14, 13)), (1, 0.001, (21, 13)), (5, 0.001, (15, 14)), (7, 0.001, (15, 14))]

FAMILY = {
    "quadratic extended, bent": lambda: extended_face(smooth_face(n=(11, 8), degree=2, amplitude=6.0, seed=1),
                                                      sides=("u0", "v1"), ext=0.03, bend=0.02, trim="third"),
    "cubic extended all sides, p-1": lambda: extended_face(smooth_face(n=(12, 8), degree=3, amplitude=5.0, seed=0),
                                                           sides=("u0", "u1", "v0", "v1"), ext=0.02, mult=2),
    "quintic extended, bent": lambda: quintic_extended_seed(1),
    "quintic extended, bent, seed 5": lambda: quintic_extended_seed(5),
    "quintic jointed": lambda: jointed_face(pieces=2, degree=5, seed=1),
    "quintic bump at a border, p-1": lambda: extended_face(bordered_bump_face(n=(13, 13), degree=5, seed=1),
                                                           sides=("u0",), ext=0.02, mult=4),
    "cubic bump at a border": lambda: bordered_bump_face(n=(11, 11), degree=3, seed=0),
}


def _scorer(net, t):
    sch = resolve_scheme(net, None)
    settings = RunSettings(tolerance=t, scheme=sch, levels=3, method="auto", region="auto")
    current = budget_for(net, settings, keep_fields=True)
    return _make_scorer(net, current.work, sch, settings, current), current.work


def _scipy_surface(net, u, v):
    from scipy.interpolate import BSpline

    Bu, Bv = (BSpline.design_matrix(np.clip(x, k[p], k[-p - 1]), k, p).toarray()
              for x, k, p in ((u, np.asarray(net.knots[0]), net.degrees[0]), (v, np.asarray(net.knots[1]),
                                                                               net.degrees[1])))
    return np.einsum("ai,ijk,bj->abk", Bu, np.asarray(net.points), Bv)


@pytest.mark.parametrize("seed, t, shape", RETRIED)
def test_the_retry_advises_the_net_its_verification_supports(seed, t, shape):
    advice = ca.advise(quintic_extended_seed(seed), tolerance=t)
    d = advice.to_dict()
    assert advice.meets_tolerance and d["no_density"] is None
    r = d.get("retried")  # an optional key
    if r is not None:
        assert advice.shape == shape and r["net"] == list(shape) and r["own_ripple"] > t  # what kept the search
        assert r["value"] == pytest.approx(d["verification"]["value"], rel=1e-9, abs=1e-12)
        assert any("advised on the verified deviation" in n for n in advice.notes)
    else:  # under the surface reading's 32-span border convention the search itself reaches a verified net, whose
        # own ripple + its U conforms as the gate decides it: seed 7 at 0.001 takes 18x14, its 15x14 and 17x14 read
        # 0.00095 and 0.00097 + U 0.00007 (the gate: undecided)
        assert advice.shape[0] * advice.shape[1] <= (shape[0] + 3) * (shape[1] + 1)
    # the advised net's own U (how far its value moves under the border convention's latitude) holds every claim
    margin = d["advised_uncertainty"]["peak"]
    assert d["advised_uncertainty"]["estimated"] and margin > 0.0
    assert d["verification"]["method"] == "occt" and d["verification"]["value"] + margin <= t
    shape = advice.shape
    # a third road: scipy's basis on the trimmed check grid, against the same intent, along its normals
    sc, work = _scorer(advice.net, t)
    cu, cv = sc.axes(*shape)
    I, normal, keep = sc.target(cu.x, cv.x)
    fu, fv = sc.frames
    S = _scipy_surface(advice.advised_net, fu.param(cu.x), fv.param(cv.x))
    road = float(np.abs(project(S - I, normal, sc.component))[keep].max())
    assert road == pytest.approx(d["verification"]["value"], rel=1e-6, abs=1e-9)
    assert road + margin <= t


@pytest.mark.parametrize("seed, t", [(1, 0.002), pytest.param(5, 0.001, marks=pytest.mark.slow)])
def test_copies_get_the_same_answer_after_a_retry(seed, t):
    net = quintic_extended_seed(seed)
    first = ca.advise(net, tolerance=t)
    assert first.meets_tolerance  # retried, or (under the 32-span border convention) found by the search
    for name, copy in copies(net).items():
        other = ca.advise(copy, tolerance=t)
        assert (other.shape[::-1] if name == "transpose" else other.shape) == first.shape, name
        assert other.meets_tolerance == first.meets_tolerance and other.decision == first.decision, name
        assert other.value == pytest.approx(first.value, rel=1e-6, abs=1e-12), name


def _verified_in_window(net, t, u, factor=3):
    """Brute force: every net of up to ``factor`` times today's counts per direction (within the search's limits)
    whose deviation + U on the check grid is within t, measured on OCCT's surface; the first that verifies."""
    sc, work = _scorer(net, t)
    low, high = _limits(work, sc.degrees, sc.plans)
    low, high = (tuple(work.shape[k] if sc.kept[k] else lim[k] for k in (0, 1)) for lim in (low, high))
    top = [min(h, factor * n) for h, n in zip(high, work.shape)]
    for a in range(low[0], top[0] + 1):
        for b in range(low[1], top[1] + 1):
            if sc.value(a, b) + u > t:
                continue
            Q, S, I, normal, keep, (cu, cv) = sc.fit(a, b)
            got = measure_on_occt(sc, candidate_net(sc.net, Q, cu, cv), cu.x, cv.x)[sc.metric]
            if got + u <= t:
                return (a, b), got
    return None


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(FAMILY))
@pytest.mark.parametrize("t", [0.01, 0.002, 0.001])
def test_no_honest_no_where_a_net_in_range_verifies(name, t):
    advice = ca.advise(FAMILY[name](), tolerance=t)
    # every claim holds with the advised net's own U (tests/advice/test_surface_margin.py: it covers the change of
    # the advised net's value under the border convention's period variants)
    u = advice.advised_uncertainty.peak
    if advice.meets_tolerance:  # an answer: verified
        assert advice.verification["value"] + u <= t
        return
    assert advice.no_density is not None
    assert _verified_in_window(advice.net, t, u) is None
