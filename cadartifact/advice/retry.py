"""Before an honest no: the nets a write-and-measure check would accept (SPEC §5).

The search reads a candidate of the ``surface`` reading by the larger of its deviation from the intent and its own
ripple as its budget reads it (so that the advice passes the gate's reading). On short and high-degree candidates
that own-ripple reading takes part of the candidate's curvature for ripple (the Cartesian split's constant, largest
at degrees 4-5): a quintic face extended past its trim, whose 14x13 net lies within 0.00175 of the intent on
OCCT's surface, reads 0.038 of own ripple, and the search answered "no density within the limits conforms" at
t = 0.002. What is verified (SPEC §5) is the fitted surface against the intent over the trimmed face.

So before the advice says no, it reads the deviation alone (the fewest points on the frontier of "deviation +
U <= t", from today's density, as the search does, and the nets around the search's best) and measures the
candidates within t on OCCT's surface; the first whose verified deviation + U stays within t is the advice.
Nothing is claimed that this measure does not support; when none passes, the honest no stands.
"""

from __future__ import annotations

from .density_search import corner, frontier

__all__ = ["verified_retry", "retry_note", "MAX_VERIFIED", "RADIUS"]

#: Candidates measured on OCCT's surface at most before the honest no stands.
MAX_VERIFIED = 4
#: Points per direction around the search's best (and the deviation frontier's net) the retry reads.
RADIUS = 3


def verified_retry(scorer, deviation, t: float, margin: float, low, high, start, best=None) -> dict | None:
    """The fewest-points net whose deviation, verified on OCCT's surface, stays within ``t`` with ``U`` added.

    Parameters
    ----------
    scorer : cadartifact.advice.scorer._Scorer
        The confirmation grid's scorer (its fit and intent are what the advice's verification measures).
    deviation : callable(a, b) -> float
        The candidate's deviation from the intent plus ``U`` as the search reads it (no own ripple).
    t : float
        The tolerance.
    margin : float
        The intent's uncertainty ``U``.
    low, high : (int, int)
        The search's limits.
    start : (int, int)
        Where the search started (today's density).
    best : (int, int), optional
        The best density the search found.

    Returns
    -------
    dict or None
        ``{"net": [a, b], "value": OCCT's deviation, "read": the search's deviation, "tried": [[a, b], ...]}``,
        or None when no candidate verifies.

    Notes
    -----
    Candidates: the deviation frontier's fewest-points net (when the bounded doubling finds a corner), that
    corner, and every net within :data:`RADIUS` points per direction of the search's best and of the frontier's
    net (the deviation of a face with joins is not monotone: how the spans fall to the pieces moves it by 30 %
    from one count to the next, so a gallop can step over the one that fits). Those whose deviation + U on the
    check grid is within ``t`` are measured on OCCT's surface, fewest points first (then the lower deviation), at
    most :data:`MAX_VERIFIED`.
    """
    from ..analysis.fitting import candidate_net
    from .verification import measure_on_occt

    try:
        import OCP  # noqa: F401  (the verified measure is OCCT's: without it nothing is claimed)
    except ImportError:
        return None
    centres = [tuple(best)] if best is not None else []
    found, reachable, _ = corner(deviation, t, low, high, start)
    if reachable:
        near, _ = frontier(lambda x, y: deviation(x, y) <= t, low, high, start, found=found)
        centres += [tuple(near), tuple(found)]
    shapes = set(centres)
    for ca, cb in centres:
        shapes.update((a, b) for a in range(max(low[0], ca - RADIUS), min(high[0], ca + RADIUS) + 1)
                      for b in range(max(low[1], cb - RADIUS), min(high[1], cb + RADIUS) + 1))
    read = {s: deviation(*s) for s in shapes}
    tried = []
    for a, b in sorted((s for s in shapes if read[s] <= t), key=lambda s: (s[0] * s[1], read[s], s)):
        if len(tried) == MAX_VERIFIED:
            break
        tried.append([int(a), int(b)])
        Q, S, I, normal, keep, (cu, cv) = scorer.fit(a, b)
        got = measure_on_occt(scorer, candidate_net(scorer.net, Q, cu, cv), cu.x, cv.x)[scorer.metric]
        if got + margin <= t:
            return {"net": [int(a), int(b)], "value": float(got), "read": float(read[(a, b)] - margin),
                    "tried": tried}
    return None


def retry_note(retried: dict, own: float, margin: float, t: float) -> str:
    """The note of an advice found by :func:`verified_retry`, with the record's numbers (``retried``)."""
    a, b = retried["net"]
    return (f"advised on the verified deviation: {a}x{b}'s own ripple reads {own:.4g} > {t:g} (the reading takes "
            f"part of a short or high-degree net's curvature for ripple), its surface measured on OCCT against the "
            f"intent reads {retried['value']:.4g} (+ U {margin:.3g}) <= {t:g}")
