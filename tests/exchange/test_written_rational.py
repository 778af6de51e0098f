"""Rational faces with an exact circular-arc direction are written: the arc bit for bit, the rest refitted.

The family (cadartifact.testing.arc_faces.revolved_face): a rippled profile revolved about an axis by one or
several rational quadratic arcs (degree 2, 3 poles per arc, weights 1, cos(theta/2), 1, arcs joined by double
knots), the arc in u or in v, several radii, angles, profile degrees and placements, written to STEP in mm and
inches and read back (the reader recognises the arc: ``exact``). Advised at a tolerance below the profile's ripple
and written with ``advise --write-resampled``'s road (:func:`write_advised`):

* the written face, read back, keeps the arc direction's count, degree, knots and weights bit for bit (the file
  carries them as the advice made them, the poles to STEP's 15 digits) and stays on the circles as the advice left
  it (evaluated with OCCT, every iso along the arc at one distance from the generator's axis and one height along
  it: one arc to 1e-9 of the face's size; several arcs: the advice's own refit leaves them 1.5e-7 off, a strict
  xfail below);
* it lies within t + the old face's ripple (+ its edge tolerance) of the old face: the writer's projection both ways,
  and a second road (both faces evaluated with the numpy rational basis, nearest sample by scipy's KD-tree, then the
  distance to its tangent plane);
* the file reads back and advising it again is a fixed point: today's net conforms, or the advice is within one point
  per direction of the written net.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

pytest.importorskip("OCP")
pytest.importorskip("scipy")

from scipy.spatial import cKDTree  # noqa: E402

from cadartifact.exchange.load import evaluate_grid, read  # noqa: E402
from cadartifact.exchange.step import write_step  # noqa: E402
from cadartifact.numerics.splines import basis_matrix  # noqa: E402
from cadartifact.runs.advising import advise_files, write_advised  # noqa: E402
from cadartifact.testing.arc_faces import placement, revolved_face  # noqa: E402

#: (radius, arc angle in degrees, arcs, profile degree, profile poles, arc in v, unit, seed, tolerance)
FAST = [(30.0, 120.0, 1, 3, 12, False, "MM", 2, 0.005), (30.0, 120.0, 2, 3, 12, True, "INCH", 2, 0.005)]
SLOW = [(12.0, 90.0, 1, 2, 10, True, "MM", 3, 0.002), (60.0, 200.0, 3, 3, 14, False, "INCH", 4, 0.01),
        (25.0, 150.0, 2, 4, 11, False, "MM", 5, 0.004)]


def quiet(call, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return call(*args, **kwargs)


def evaluate(net, n=160):
    """Points ``(n, n, 3)`` of ``net`` on its knot range by the numpy basis (rational: homogeneous, divided)."""
    u = np.linspace(net.knots[0][0], net.knots[0][-1], n)
    v = np.linspace(net.knots[1][0], net.knots[1][-1], n)
    Bu = basis_matrix(np.asarray(net.knots[0]), net.degrees[0], u, net.shape[0])
    Bv = basis_matrix(np.asarray(net.knots[1]), net.degrees[1], v, net.shape[1])
    w = np.ones(net.shape) if net.weights is None else np.asarray(net.weights)
    H = np.einsum("ai,ijk,bj->abk", Bu, np.asarray(net.points) * w[..., None], Bv)
    W = np.einsum("ai,ij,bj->ab", Bu, w, Bv)
    return H / W[..., None]


def second_road(new, old) -> float:
    """The larger of the two directed distances between the sampled faces: nearest sample, then its tangent plane."""
    def directed(p, Q):
        normal = np.cross(np.gradient(Q, axis=0), np.gradient(Q, axis=1))
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        q, m = Q.reshape(-1, 3), normal.reshape(-1, 3)
        _, index = cKDTree(q).query(p.reshape(-1, 3))
        gap = p.reshape(-1, 3) - q[index]
        return float(np.abs(np.einsum("ij,ij->i", gap, m[index])).max())

    return max(directed(new, old), directed(old, new))


def arc_spread(net, seed: int, arc_in_v: bool) -> float:
    """Largest spread along each iso running along the arc of the distance to the generator's axis and of the height
    along it, relative to the face's size (OCCT's evaluation)."""
    rot, shift = placement(seed)
    axis = rot[:, 2]
    S = evaluate_grid(net, np.linspace(net.knots[0][0], net.knots[0][-1], 37),
                      np.linspace(net.knots[1][0], net.knots[1][-1], 41))
    if arc_in_v:
        S = np.swapaxes(S, 0, 1)
    d = S - shift
    h = d @ axis
    rho = np.linalg.norm(d - h[..., None] * axis, axis=-1)
    size = float(np.ptp(S.reshape(-1, 3), axis=0).max())
    return float(max(np.ptp(rho, axis=0).max(), np.ptp(h, axis=0).max()) / size)


def check(case, tmp_path):
    radius, angle, arcs, degree, n, arc_in_v, unit, seed, tol = case
    k = 1 if arc_in_v else 0
    made = revolved_face(radius, angle, degree, n, seed=seed, transpose=arc_in_v, ripple=0.02 * radius, arcs=arcs)
    source = write_step([made], tmp_path / "revolved.step", unit=unit)
    (old,) = quiet(read, source).nets
    assert old.exact[k] == "circle" and old.weights is not None and old.shape[k] == 2 * arcs + 1
    keep = []
    quiet(advise_files, [source], tol, keep=keep)
    ((_, _, advice),) = keep
    assert not advice.kept_today
    advised = advice.advised_net
    assert advised.weights is not None and advised.shape[k] == old.shape[k]
    out = tmp_path / "written.step"
    (f,) = quiet(write_advised, keep, out)["files"]
    assert f["refused"] == [] and [r["face"] for r in f["faces"]] == [0], f["refused"]
    (record,) = f["faces"]
    assert record["valid"] and record["model_valid"] and record["max_distance"] <= record["allowed_distance"]
    (new,) = quiet(read, out).nets
    assert new.shape == advised.shape and new.exact[k] == "circle"
    # the arc as the advice kept it, bit for bit: knots and weights along it, in every row of the other direction
    assert np.array_equal(new.knots[k], old.knots[k]) and np.array_equal(new.knots[k], advised.knots[k])
    w_new, w_old = (np.asarray(new.weights), np.asarray(old.weights)) if k == 0 else \
        (np.asarray(new.weights).T, np.asarray(old.weights).T)
    assert all(np.array_equal(w_new[:, j], w_old[:, 0]) for j in range(w_new.shape[1]))
    assert np.array_equal(np.asarray(new.weights), np.asarray(advised.weights))
    # the poles as STEP's text carries them (OCCT writes 15 significant digits)
    assert np.allclose(np.asarray(new.points), np.asarray(advised.points), rtol=0, atol=1e-12 * radius * 10), \
        np.abs(np.asarray(new.points) - np.asarray(advised.points)).max()
    # on the circles as the advice made it (the writer adds nothing); one arc: to 1e-9 of the face's size
    spread = arc_spread(new, seed, arc_in_v)
    assert arc_spread(old, seed, arc_in_v) < 1e-12 and abs(spread - arc_spread(advised, seed, arc_in_v)) < 1e-11
    assert arcs > 1 or spread < 1e-9
    # within t + ripple of the old face, by a second road
    allowed = record["allowed_distance"]
    distance = second_road(evaluate(new), evaluate(old))
    assert abs(distance - record["max_distance"]) <= 0.1 * allowed and distance <= 1.05 * allowed
    # advising the written face again: a fixed point
    again = []
    quiet(advise_files, [out], tol, keep=again)
    ((_, _, second),) = again
    if not second.kept_today:
        assert all(abs(a - b) <= 1 for a, b in zip(second.advised_net.shape, new.shape)), \
            (second.advised_net.shape, new.shape)
    return record


@pytest.mark.parametrize("case", FAST, ids=[f"{c[2]}-arc-{'v' if c[5] else 'u'}-{c[6].lower()}" for c in FAST])
def test_an_exact_arc_face_is_written_with_its_arc_kept(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("case", SLOW, ids=[f"{c[2]}-arc-{'v' if c[5] else 'u'}-{c[6].lower()}-d{c[3]}" for c in SLOW])
def test_an_exact_arc_face_is_written_with_its_arc_kept_more(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.xfail(strict=True, reason="the advice keeps a multi-span arc's knots and weights bit for bit but its "
                   "refit leaves the isos 1.5e-7 of the face's size off the circles (one arc: 2e-13)")
@pytest.mark.parametrize("arc_in_v", [False, True], ids=["u", "v"])
def test_the_advice_keeps_a_multi_span_arc_on_its_circles(arc_in_v):
    import cadartifact as ca
    from cadartifact.testing.arc_faces import recognised

    net = recognised(revolved_face(30.0, 120.0, 3, 12, seed=2, transpose=arc_in_v, ripple=0.6, arcs=2))
    assert net.exact[1 if arc_in_v else 0] == "circle"
    assert arc_spread(ca.advise(net, tolerance=0.005).advised_net, 2, arc_in_v) < 1e-9
