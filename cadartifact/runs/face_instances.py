"""Faces that are one shape moved: analysed once, reported for each.

Models repeat features: the holes of a bolt pattern, the fillets around them, the panels of a
patterned skin. A face whose control points are another face's moved rigidly (a rotation and a
translation), with the same degrees, weights, periodicity and knots up to a shift of its parameters,
and its trims (uv bounds) shifted alike, has the same budget, advice, comparison and verification:
every number the analysis reports is a distance, a share or a density, all invariant under a rigid
motion of the points and a shift of the parameters. Only where the peak lies moves with the face.
The reader gives such faces with the last bits of their points, weights and knots differing
(1e-11 of the face's size in the NIST models), so they are matched to :data:`RTOL` of it.

Measured on ``../shared/realdata/step`` (``tests/runs/test_face_instances.py``): each matched face's own
analysis agrees with its instance's to 1e-6 in every number and exactly in every density, verdict and
note. Mirror images are analysed on their own (a reflection reverses the parametrisation's handedness).

>>> plan = instances(nets)                                    # doctest: +SKIP
>>> [rep for rep, motion in plan]                              # doctest: +SKIP
[0, 1, 1, 3, 1]
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

__all__ = ["Motion", "NOTE", "RTOL", "congruence", "instance_record", "instances", "rigid_motion"]

#: How a repeat's note begins (the text report counts these instead of printing each).
NOTE = "the same shape as face "

#: Largest mismatch of two faces that count as one shape moved, relative to the face's size (points)
#: and to its parameter ranges (knots, uv bounds) and largest weight. 1e-9 of a 100 mm face is 0.1 nm.
RTOL = 1e-9


@dataclass(frozen=True)
class Motion:
    """How an instance sits against the face it repeats.

    Attributes
    ----------
    rotation : (3, 3) float
        Proper rotation ``R`` (``det R = +1``).
    translation : (3,) float
        ``t``: the instance's points are ``R p + t``.
    shift : (float, float)
        Its parameters are the face's plus ``shift`` (u, v).
    residual : float
        Largest point mismatch after the motion, relative to the face's size.
    """

    rotation: np.ndarray
    translation: np.ndarray
    shift: tuple[float, float]
    residual: float

    def apply(self, xyz) -> np.ndarray:
        """Points ``(..., 3)`` of the face moved onto the instance: ``R p + t``."""
        return np.asarray(xyz, float) @ self.rotation.T + self.translation


def rigid_motion(p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The proper rigid motion that best maps the points ``p`` onto ``q`` (Kabsch).

    Parameters
    ----------
    p, q : (n, 3) float
        Corresponding points.

    Returns
    -------
    rotation : (3, 3) float
    translation : (3,) float
    residual : float
        ``max_i |R p_i + t - q_i|`` (model units).

    Notes
    -----
    With centroids ``cp, cq`` and ``H = (p - cp)^T (q - cq) = U S V^T``, ``R = V diag(1, 1, d) U^T``,
    ``d = sign det(V U^T)``, ``t = cq - R cp``: the least-squares proper rotation (W. Kabsch, "A solution
    for the best rotation to relate two sets of vectors", Acta Cryst. A32, 1976).
    """
    p, q = np.asarray(p, float).reshape(-1, 3), np.asarray(q, float).reshape(-1, 3)
    cp, cq = p.mean(axis=0), q.mean(axis=0)
    u, _, vt = np.linalg.svd((p - cp).T @ (q - cq))
    d = 1.0 if np.linalg.det(vt.T @ u.T) >= 0 else -1.0
    rotation = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    translation = cq - rotation @ cp
    residual = float(np.abs(p @ rotation.T + translation - q).max())
    return rotation, translation, residual


def _key(net) -> tuple:
    """What two instances share exactly (a bucket of candidates)."""
    return (net.shape, net.degrees, tuple(net.periodic), tuple(len(k) for k in net.knots), net.weights is None,
            net.uv_bounds is None, net.unit, net.origin.kind, net.canonical, tuple(net.exact))


def _radii(net) -> np.ndarray:
    """Each control point's distance from the centroid: invariant under rigid motions, in index order."""
    pts = net.points.reshape(-1, 3)
    return np.linalg.norm(pts - pts.mean(axis=0), axis=1)


def _size(net) -> float:
    return float(np.ptp(net.points.reshape(-1, 3), axis=0).max())


def congruence(face, other, rtol: float = RTOL, *, decided: dict | None = None) -> Motion | None:
    """The motion that makes ``other`` an instance of ``face``, or None.

    Parameters
    ----------
    face, other : ControlNet
        B-spline faces (cages are never matched: they carry no parameters to compare).
    rtol : float
        Relative tolerance: points against the face's size, knots and uv bounds against each
        direction's parameter range, weights against the largest weight.
    decided : dict, optional
        A memo of :func:`_decisions` by ``id(net)``, for a caller comparing one face with many.

    Returns
    -------
    Motion or None
        None unless the degrees, periodicity, knot counts, unit, kind and exact directions are equal,
        the knots and uv bounds equal up to one shift per direction, the weights equal, and the points
        related by a proper rigid motion, each within ``rtol``, and the analysis reads both alike
        where it decides at finer tolerances (:func:`_decisions`).
    """
    if not face.is_bspline or not other.is_bspline or _key(face) != _key(other):
        return None
    shift = []
    for ka, kb in zip(face.knots, other.knots):
        ka, kb = np.asarray(ka, float), np.asarray(kb, float)
        s = float(kb[0] - ka[0])
        if np.abs(kb - ka - s).max() > rtol * float(ka[-1] - ka[0]):
            return None
        shift.append(s)
    if face.uv_bounds is not None:
        ranges = [float(k[-1] - k[0]) for k in face.knots]
        for k, (a, b) in enumerate(zip(face.uv_bounds, other.uv_bounds)):
            if abs(b - a - shift[k // 2]) > rtol * ranges[k // 2]:
                return None
    if face.weights is not None and np.abs(face.weights - other.weights).max() > rtol * np.abs(face.weights).max():
        return None
    size = _size(face)
    if np.abs(_radii(face) - _radii(other)).max() > 2.0 * rtol * size:  # cheap: most non-matches stop here
        return None
    rotation, translation, residual = rigid_motion(face.points, other.points)
    if residual > rtol * size:
        return None
    memo = {} if decided is None else decided
    for net in (face, other):
        if id(net) not in memo:
            memo[id(net)] = _decisions(net)
    if memo[id(face)] != memo[id(other)]:
        return None
    return Motion(rotation, translation, (shift[0], shift[1]), residual / size)


def _decisions(net) -> tuple:
    """The analysis's own yes/no readings of a face, taken at tolerances finer than :data:`RTOL` or on absolute
    coordinates: where a repeat would read differently it is analysed on its own, so that reuse never hands
    a face another path's record (weights varying, knots uniform, interior knot multiplicities, directions
    that are one polynomial or exact, trimmed inside the surface, straight degree-1 rows)."""
    from ..advice.advise import _straight, _trimmed
    from ..analysis.frames import axis_frames
    from ..net import knot_multiplicities

    frames = axis_frames(net)
    mults = tuple(tuple(m for _, m in knot_multiplicities(k, d, n, pr))
                  for k, d, n, pr in zip(net.knots, net.degrees, net.shape, net.periodic))
    straight = tuple(bool(d == 1 and _straight(net.points, k)) for k, d in enumerate(net.degrees))
    kinds = tuple((f.polynomial, f.exact, f.periodic, f.spans) for f in frames)
    return net.weights_vary, net.knots_uniform, mults, kinds, _trimmed(net, frames), straight


def instances(nets: list, rtol: float = RTOL) -> list[tuple[int, Motion | None]]:
    """Per net, ``(index of the first net it repeats, motion)``; ``(own index, None)`` for the first of each shape.

    Parameters
    ----------
    nets : list of ControlNet
    rtol : float
        As :func:`congruence`.

    Returns
    -------
    list of (int, Motion or None)

    Notes
    -----
    Nets are bucketed by what must be equal exactly; within a bucket a new net is compared, by the
    distances of its points from their centroid (one array operation against all the bucket's
    shapes), with each shape seen so far, and the rigid motion is fitted only where those agree.
    """
    plan: list[tuple[int, Motion | None]] = []
    buckets: dict = {}  # key -> (rep indices, their radii stacked, their sizes)
    decided: dict = {}  # _decisions per net, for the reps compared with many
    for i, net in enumerate(nets):
        if not net.is_bspline:
            plan.append((i, None))
            continue
        key = _key(net)
        reps, radii, sizes = buckets.get(key, ([], None, None))
        mine = _radii(net)
        found = None
        if reps:
            close = np.abs(radii - mine).max(axis=1) <= 2.0 * rtol * sizes
            for r in np.flatnonzero(close):
                motion = congruence(nets[reps[r]], net, rtol, decided=decided)
                if motion is not None:
                    found = (reps[r], motion)
                    break
        if found is not None:
            plan.append(found)
            continue
        plan.append((i, None))
        size = np.array([_size(net)])
        buckets[key] = (reps + [i], mine[None, :] if radii is None else np.vstack([radii, mine]),
                        size if sizes is None else np.concatenate([sizes, size]))
    return plan


#: Below this share of a face's size a rigid match is exact to rounding: the note says this bound, not the
#: residual itself, whose digits depend on the CPU's BLAS kernel.
ROUNDING = 1e-12


def _within(residual: float) -> str:
    return f"to rounding: within {ROUNDING:.0e}" if residual <= ROUNDING else f"within {residual:.0e}"


def instance_record(record: dict, face, net, motion: Motion) -> dict:
    """The document record of ``net``, an instance of ``face``, from ``face``'s record.

    The numbers, verdict and advice are ``face``'s; the face's own index, name and entity replace
    ``face``'s, a note says whose analysis it reuses, and ``peak_at`` (when present) moves with the
    face: its parameters by the shift, its point by the motion.
    """
    from .records import json_number

    rec = copy.deepcopy(record)
    rec.update(face=net.origin.face, name=net.origin.name, kind=net.origin.kind,
               entity=getattr(net.origin, "entity", None))
    rec["notes"] = list(rec.get("notes") or []) + [
        f"{NOTE}{face.origin.face}, moved rigidly ({_within(motion.residual)} of "
        "its size): its analysis is reused"]
    for c in rec.get("criteria") or []:  # the PDQ criteria's worst places move with the face
        if c.get("at") is not None:
            c["at"]["uv"] = [round(t + s, 9) for t, s in zip(c["at"]["uv"], motion.shift)]
            if c["at"].get("xyz") is not None and all(x is not None for x in c["at"]["xyz"]):
                c["at"]["xyz"] = [json_number(x) for x in motion.apply(c["at"]["xyz"])]
    peak = rec.get("peak_at")
    if peak is not None:
        if peak.get("uv") is not None:
            peak["uv"] = [round(t + s, 9) for t, s in zip(peak["uv"], motion.shift)]
        if peak.get("xyz") is not None and all(c is not None for c in peak["xyz"]):
            peak["xyz"] = [json_number(c) for c in motion.apply(peak["xyz"])]
    return rec
