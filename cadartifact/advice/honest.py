"""An answer or an honest no (SPEC §5): when no density within the search's limits conforms, say so and why.

The search (:func:`cadartifact.advice.density_search.corner`) stops a direction that stops improving and never
passes its growth limit; when it ends without a conforming density, the advice is the best density it found,
flagged as not conforming, with the reasons it can tell apart:

- ``"crease"``: the best candidate's error peaks within a span of a knot of today's face where the surface is
  only C1 or less (multiplicity ``>= p - 1``): a crease the join-keeping net cannot carry;
- ``"uncertainty"``: the best value is within the tolerance but not with the intent's uncertainty ``U`` added
  (the decision rule of SPEC §4);
- ``"stops improving"``: doubling a direction lowered the value by less than
  :data:`~cadartifact.advice.density_search.STALL` of it;
- ``"growth limit"``: a direction reached the search's bound while still improving.
"""

from __future__ import annotations

import numpy as np

from ..analysis.fields import project
from ..net import knot_multiplicities
from ..numerics.peaks import first_peak

__all__ = ["explain", "unverified_note", "REASONS"]

#: The reasons an honest no can give, in the order they are reported.
REASONS = ("crease", "uncertainty", "stops improving", "growth limit")


def _crease_near(scorer, shape) -> tuple[str, float, int] | None:
    """``(direction, knot, multiplicity)`` of a low-continuity knot of today's face within a span of where the
    candidate ``shape``'s error peaks, or None."""
    work = scorer.work
    if not work.is_bspline:
        return None
    Q, S, I, normal, keep, (cu, cv) = scorer.fit(*shape)
    f = np.abs(project(S - I, normal, scorer.component))
    f = np.where(keep, f, -np.inf)
    i, j = first_peak(f)  # equal peaks to rounding: the first, whatever the CPU's rounding
    for d, (axis, x) in enumerate(((cu, cu.x[i]), (cv, cv.x[j]))):
        frame, p = scorer.frames[d], work.degrees[d]
        u = float(frame.param(x))
        span = frame.h
        for value, m in knot_multiplicities(work.knots[d], p, work.shape[d], work.periodic[d]):
            if m >= max(p - 1, 1) and abs(value - u) <= span:
                return "uv"[d], float(value), int(m)
    return None


def explain(scorer, shape, trail: dict, raw: float, margin: float, t: float, unit: str, own: bool = False) -> dict:
    """Why no density conforms.

    Parameters
    ----------
    scorer : cadartifact.advice.scorer._Scorer
        The confirmation grid's scorer.
    shape : (int, int)
        The best density found.
    trail : dict
        The bounded search's trail (:func:`cadartifact.advice.density_search.corner`).
    raw : float
        The best density's value without the uncertainty.
    margin : float
        Its uncertainty ``U``: the candidates' (of the intent), or with ``own`` the net's own.
    t : float
        The tolerance.
    unit : str
    own : bool
        ``raw`` is the best net's own ripple (it binds), with the ``U`` the gate decides that net by.

    Returns
    -------
    dict
        ``{"why": [codes of :data:`REASONS`], "best": {"net", "value", "uncertainty"}, "reason": sentence}``.
    """
    why, words = [], []
    crease = _crease_near(scorer, shape)
    if crease is not None:
        d, value, m = crease
        why.append("crease")
        words.append(f"its error peaks at the knot {d} = {value:.6g} of multiplicity {m} (a crease the join-"
                     "keeping net cannot carry)")
    if raw <= t < raw + margin:
        why.append("uncertainty")
        words.append(f"{raw:.4g} is within {t:g} but not with " + (f"its own ripple's U = {margin:.3g}" if own else
                     f"the intent's uncertainty U = {margin:.3g}"))
    stalled = [d for d in trail.get("stalled", ()) if d in "uv"]
    if stalled:
        why.append("stops improving")
        words.append(f"doubling {' and '.join(stalled)} stopped improving it")
    limit = [d for d in trail.get("at_limit", ()) if d not in stalled]
    if limit:
        why.append("growth limit")
        words.append(f"{' and '.join(limit)} reached the search's growth limit")
    if not why:
        why.append("growth limit")
        words.append("the search's limits were reached")
    reason = (f"no density within the limits conforms: {'; '.join(words)}; the best found, {shape[0]}x{shape[1]}, "
              f"gives {raw:.4g} {unit}{' of its own ripple' if own else ''} (+ U {margin:.3g}) against {t:g}")
    return {"why": why, "best": {"net": [int(shape[0]), int(shape[1])], "value": float(raw),
                                 "uncertainty": float(margin)}, "reason": reason}


def unverified_note(verification: dict, target: float) -> str:
    """The note of an advice whose verification (OCCT's evaluation) did not confirm it: it is then not claimed."""
    return (f"not verified: OCCT's evaluation of the advised net reads {verification.get('value', float('nan')):.4g} "
            f"against {target:.4g} (the tolerance less U): the density is not claimed to conform")
