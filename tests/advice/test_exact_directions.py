"""A direction exactly a line or a circular arc keeps its poles, weights and knots; only the other is advised.

Faces: a rippled profile revolved by one rational quadratic arc (several radii, arc angles, profile degrees and
counts, placements, the arc in u or in v), a profile extruded along a straight degree-1 direction, and a canonical
cylinder patch. Each is recognised by the reader's recogniser (as a file's face is). The advised and resampled nets
keep the exact direction's count, degree, knots and weights bit for bit; the surface stays on the arcs: evaluated by
OCCT, every point of an iso along the arc is at one distance from the placement's axis and at one height along it
(an independent check: the axis is the generator's, not read from the net).
"""

from __future__ import annotations

import numpy as np
import pytest

import cadartifact as ca
from cadartifact.exchange.load import evaluate_grid
from cadartifact.testing.arc_faces import extruded_face, placement, recognised, revolved_face

#: (radius, arc angle in degrees, profile degree, profile poles, arc in v, seed)
ARCS = [(20.0, 60.0, 3, 10, False, 1), (50.0, 120.0, 2, 12, True, 2), (8.0, 90.0, 4, 9, False, 3),
        (120.0, 35.0, 3, 14, True, 4), (5.0, 150.0, 2, 8, False, 5)]


def _arc_spread(net, seed: int, arc_in_v: bool) -> float:
    """Largest spread, along each iso running along the arc, of the distance to the axis and the height along it,
    relative to the face's size (OCCT's evaluation)."""
    rot, shift = placement(seed)
    axis = rot[:, 2]
    u = np.linspace(net.knots[0][0], net.knots[0][-1], 37)
    v = np.linspace(net.knots[1][0], net.knots[1][-1], 41)
    S = evaluate_grid(net, u, v)
    if arc_in_v:
        S = np.swapaxes(S, 0, 1)  # (along the arc, across, 3)
    d = S - shift
    h = d @ axis
    rho = np.linalg.norm(d - h[..., None] * axis, axis=-1)
    size = float(np.ptp(S.reshape(-1, 3), axis=0).max())
    return float(max(np.ptp(rho, axis=0).max(), np.ptp(h, axis=0).max()) / size)


def _same_direction(a, b, k: int) -> None:
    """Direction ``k`` of ``a`` is ``b``'s: count, degree, knots and weights bit for bit."""
    assert a.shape[k] == b.shape[k] and a.degrees[k] == b.degrees[k]
    assert np.array_equal(a.knots[k], b.knots[k])
    wa, wb = np.asarray(a.weights), np.asarray(b.weights)
    wa, wb = (wa, wb) if k == 0 else (wa.T, wb.T)
    for j in range(wa.shape[1]):
        assert np.array_equal(wa[:, j], wb[:, 0])


@pytest.mark.parametrize("radius, angle, degree, n, arc_in_v, seed", ARCS)
def test_advice_keeps_an_exact_arc(radius, angle, degree, n, arc_in_v, seed):
    net = recognised(revolved_face(radius, angle, degree, n, seed=seed, transpose=arc_in_v, ripple=0.02 * radius))
    k = 1 if arc_in_v else 0
    assert net.exact[k] == "circle" and net.exact[1 - k] is None
    assert _arc_spread(net, seed, arc_in_v) < 1e-12
    t = 2e-4 * radius  # below today's ripple: the profile is refitted
    a = ca.advise(net, tolerance=t)
    assert not a.kept_today
    adv = a.advised_net
    _same_direction(adv, net, k)
    assert adv.exact[k] == "circle"
    assert _arc_spread(adv, seed, arc_in_v) < 1e-11
    assert a.reasons["uv"[k]]["change"] == 0 and "kept exactly" in a.reasons["uv"[k]]["reason"]
    assert any("kept exactly" in n for n in a.notes)
    if a.meets_tolerance:  # verified on OCCT's surface, with the kept direction's rational basis
        assert a.verification["meets"]
    # the resampled net of any density of the other direction too
    other = 2 * net.shape[1 - k]
    shape = (net.shape[0], other) if k == 0 else (other, net.shape[1])
    r = ca.resample(net, shape)
    _same_direction(r, net, k)
    assert r.shape == shape and _arc_spread(r, seed, arc_in_v) < 1e-11


def test_resample_refuses_another_count_along_an_exact_direction():
    net = recognised(revolved_face(20.0, 60.0, 3, 10, seed=1))
    with pytest.raises(ca.OptionError, match="kept exactly"):
        ca.resample(net, (5, 10))


@pytest.mark.parametrize("degree, n, transpose, seed", [(3, 10, False, 6), (2, 12, True, 7), (4, 9, False, 8)])
def test_advice_keeps_a_straight_direction(degree, n, transpose, seed):
    net = recognised(extruded_face(60.0, degree, n, seed=seed, transpose=transpose))
    k = 1 if transpose else 0
    assert net.exact[k] == "line"
    a = ca.advise(net, tolerance=0.01)
    adv = a.advised_net
    assert adv.shape[k] == 2 and adv.degrees[k] == 1 and np.array_equal(adv.knots[k], net.knots[k])
    assert adv.weights is None  # a non-rational direction stays non-rational
    # the surface stays ruled along the kept direction: each iso along it is a straight segment
    u = np.linspace(0, 1, 9)
    S = evaluate_grid(adv, u, np.linspace(0, 1, 23))
    S = S if k == 0 else np.swapaxes(S, 0, 1)
    chord = S[-1] - S[0]
    off = np.cross(S - S[0], chord / np.linalg.norm(chord, axis=-1)[:, None])
    assert np.abs(off).max() < 1e-9 * np.ptp(S.reshape(-1, 3), axis=0).max()


@pytest.mark.parametrize("radius, angle", [(10.0, 90.0), (40.0, 45.0)])
def test_canonical_face_is_never_replaced(radius, angle):
    cyl = recognised(revolved_face(radius, angle, 1, 2, seed=9, ripple=0.0))  # a straight profile: a cylinder
    assert cyl.exact == ("surface", "surface"), cyl.canonical
    a = ca.advise(cyl, tolerance=1e-4 * radius)
    assert a.kept_today and a.advised_net is cyl and a.shape == cyl.shape
    assert any("kept as it is" in n for n in a.notes)
