"""Verification of advice on the real surface of the advised net (SPEC §5).

The advised net is built as a real B-spline surface with OCP (``Geom_BSplineSurface``) and
evaluated by OCCT on the check grid, independently of the numpy basis the search used; its
distance from the intent along the normal is measured on the whole (trimmed) face. It must meet
the tolerance, and the net one step coarser in the binding direction, fitted and evaluated the
same way, must not.
"""

from __future__ import annotations

import numpy as np

__all__ = ["complete", "verify_advice", "measure_on_occt", "unconfirmed"]


def measure_on_occt(scorer, net, x: np.ndarray, y: np.ndarray) -> dict:
    """``{"peak", "rms"}`` of OCCT's evaluation of ``net`` minus the scorer's intent on the grid ``x x y``."""
    from ..exchange.load import evaluate_grid

    fu, fv = scorer.frames
    I, normal, keep = scorer.target(x, y)
    S = evaluate_grid(net, fu.param(x), fv.param(y))
    return scorer._measure(S - I, normal, keep)


def complete(advice):
    """``advice`` with its verification run, when it was advised with ``verify="later"`` (else as is)."""
    from dataclasses import replace

    if advice.pending is None:
        return advice
    got = advice.pending()
    unconfirmed(advice.reasons, advice.binding, got)
    if got.get("meets", True) or not advice.meets_tolerance:
        return replace(advice, verification=got, pending=None)
    # an answer only where it is verified (SPEC §5): OCCT's reading did not confirm it
    from .decision import decide
    from .honest import unverified_note

    # the U the advised net's claim used (a kept net: today's; a candidate: its own), as check() compared with
    u = getattr(advice.advised_uncertainty, "peak", 0.0)
    return replace(advice, verification=got, pending=None, meets_tolerance=False,
                   decision=decide(got["value"], u, advice.tolerance),
                   notes=[unverified_note(got, advice.tolerance - u)] + list(advice.notes))


def unconfirmed(reasons: dict, binding, verification: dict) -> None:
    """Where OCCT's surface finds the coarser net within the target after all, the binding direction's reason says
    so, with the JSON's number (``verification.coarser``): the text never claims what the record contradicts."""
    c = (verification or {}).get("coarser")
    if binding is None or not c or not c.get("meets"):
        return
    d = reasons[binding]
    d["reason"] += (f"; not confirmed: on OCCT's surface {c['shape'][0]}x{c['shape'][1]} reads {c['value']:.4g}, "
                    "within the tolerance less U")


def verify_advice(scorer, shape, binding, tolerance: float, advised, target: float | None = None,
                  own_ripple=None) -> dict:
    """Measure the advised net (and one step coarser in the binding direction) on OCCT's surface.

    ``meets`` compares with the tolerance; the coarser net is compared with the search's ``target``
    (the tolerance less the intent's reserve), which it must exceed, by the search's own reading: the larger of
    its deviation on OCCT's surface and, where the search counts it, ``own_ripple(a, b)`` (its own ripple plus its
    own ``U``, less the reserve the target holds: the search's ``max(dev + U_c, own + U_own) <= t``), so that the
    JSON's ``coarser`` and the explanation's "would give ... (binding)" tell one story.

    Returns
    -------
    dict
        ``{"method": "occt", "levels", "value", "meets", "region": "face"}`` and, with a binding
        direction, ``"coarser": {"shape", "value", "meets"}``; for the ``net`` reading also
        ``"samples"``: the largest distance of OCCT's surface from today's control points at their
        Greville abscissae (the points are samples of the shape: a check that needs no intent).
    """
    target = tolerance if target is None else target
    metric = scorer.metric
    if not advised.is_bspline or (advised is scorer.net and scorer.work is not scorer.net):
        # today's net kept as the advice where the scheme reads it as a cage (a cage, or a face under another
        # scheme): its own surface under the scheme was scored already
        today = scorer.today()
        return {"method": "today", "levels": int(round(np.log2(scorer.K))), "region": "face",
                "value": today[metric], "rms": today["rms"], "meets": bool(today[metric] <= tolerance)}
    from ..analysis.fitting import candidate_net

    levels = int(round(np.log2(scorer.K)))
    cu, cv = scorer.axes(*shape)
    got = measure_on_occt(scorer, advised, cu.x, cv.x)
    out = {"method": "occt", "levels": levels, "region": "face", "value": got[metric],
           "rms": got["rms"], "meets": bool(got[metric] <= tolerance)}
    if binding is not None:
        coarser = (shape[0] - 1, shape[1]) if binding == "u" else (shape[0], shape[1] - 1)
        Q, S, I, normal, keep, (au, av) = scorer.fit(*coarser)
        c = measure_on_occt(scorer, candidate_net(scorer.net, Q, au, av), au.x, av.x)
        value = c[metric] if own_ripple is None else max(c[metric], float(own_ripple(*coarser)))
        out["coarser"] = {"shape": list(coarser), "value": value, "meets": bool(value <= target)}
    if scorer.reading == "net" and scorer.work.is_bspline and scorer.work is scorer.net:
        out["samples"] = _sample_distance(scorer.net, advised)
    return out


def _sample_distance(net, advised) -> float:
    """Largest distance of OCCT's evaluation of ``advised`` from ``net``'s points at their Greville parameters."""
    from ..exchange.load import evaluate_grid
    from ..numerics.splines import periodic_greville

    pars = []
    for k in range(2):
        t, p, n = net.knots[k], net.degrees[k], net.shape[k]
        if net.periodic[k]:
            lo, hi = t[p], t[len(t) - p - 1]
            pars.append(lo + np.mod(periodic_greville(t, p, n) - lo, hi - lo))
        else:
            pars.append(net.greville()[k])
    S = evaluate_grid(advised, pars[0], pars[1])
    return float(np.linalg.norm(S - net.points, axis=-1).max())
