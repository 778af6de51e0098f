"""Before an honest no: the nets a write-and-measure check would accept (SPEC §5).

The search reads a candidate of the ``surface`` reading by the larger of its deviation from the intent and its own
ripple as its budget reads it (so that the advice passes the gate's reading). On short and high-degree candidates
that own-ripple reading takes part of the candidate's curvature for ripple (the Cartesian split's constant, largest
at degrees 4-5): a quintic face extended past its trim, whose 14x13 net lies within 0.00175 of the intent on
OCCT's surface, reads 0.038 of own ripple, and the search answered "no density within the limits conforms" at
t = 0.002. What is verified (SPEC §5) is the fitted surface against the intent over the trimmed face.

So before the advice says no, it searches the deviation alone (the fewest points on the frontier of "deviation +
U <= t", from today's density, as the search does) and measures the candidates it finds on OCCT's surface; the
first whose verified deviation + U stays within t is the advice. Nothing is claimed that this measure does not
support; when none passes, the honest no stands.
"""

from __future__ import annotations

from .density_search import corner, frontier

__all__ = ["verified_retry", "retry_note", "MAX_VERIFIED"]

#: Candidates measured on OCCT's surface at most before the honest no stands.
MAX_VERIFIED = 4


def verified_retry(scorer, deviation, t: float, margin: float, low, high, start) -> dict | None:
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

    Returns
    -------
    dict or None
        ``{"net": [a, b], "value": OCCT's deviation, "read": the search's deviation, "tried": [[a, b], ...]}``,
        or None when no candidate within the limits verifies.

    Notes
    -----
    Candidates: the deviation frontier's fewest-points net, then the corner the bounded doubling found, then one
    point more in each direction of the first (rounding between the fine grid's numpy basis and OCCT's
    evaluation): at most :data:`MAX_VERIFIED`, in order of points.
    """
    from ..analysis.fitting import candidate_net
    from .verification import measure_on_occt

    try:
        import OCP  # noqa: F401  (the verified measure is OCCT's: without it nothing is claimed)
    except ImportError:
        return None
    found, reachable, _ = corner(deviation, t, low, high, start)
    if not reachable:
        return None
    best, _ = frontier(lambda x, y: deviation(x, y) <= t, low, high, start, found=found)
    shapes = [tuple(best), tuple(found)] + [(best[0] + 1, best[1]), (best[0], best[1] + 1)]
    tried = []
    for a, b in sorted(dict.fromkeys(shapes), key=lambda s: (s[0] * s[1], shapes.index(s))):
        if a > high[0] or b > high[1] or len(tried) == MAX_VERIFIED:
            continue
        tried.append([int(a), int(b)])
        Q, S, I, normal, keep, (cu, cv) = scorer.fit(a, b)
        got = measure_on_occt(scorer, candidate_net(scorer.net, Q, cu, cv), cu.x, cv.x)[scorer.metric]
        if got + margin <= t:
            return {"net": [int(a), int(b)], "value": float(got), "read": float(deviation(a, b) - margin),
                    "tried": tried}
    return None


def retry_note(retried: dict, own: float, margin: float, t: float) -> str:
    """The note of an advice found by :func:`verified_retry`, with the record's numbers (``retried``)."""
    a, b = retried["net"]
    return (f"advised on the verified deviation: {a}x{b}'s own ripple reads {own:.4g} > {t:g} (the reading takes "
            f"part of a short or high-degree net's curvature for ripple), its surface measured on OCCT against the "
            f"intent reads {retried['value']:.4g} (+ U {margin:.3g}) <= {t:g}")
