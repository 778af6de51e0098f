"""Verification of advice on the real surface of the advised net (SPEC §5).

The advised net is built as a real B-spline surface with OCP (``Geom_BSplineSurface``) and
evaluated by OCCT on the check grid, independently of the numpy basis the search used; its
distance from the intent along the normal is measured on the whole (trimmed) face. It must meet
the tolerance, and the net one step coarser in the binding direction, fitted and evaluated the
same way, must not.
"""

from __future__ import annotations

import numpy as np

__all__ = ["verify_advice", "measure_on_occt"]


def measure_on_occt(scorer, net, x: np.ndarray, y: np.ndarray) -> dict:
    """``{"peak", "rms"}`` of OCCT's evaluation of ``net`` minus the scorer's intent on the grid ``x x y``."""
    from .exchange import evaluate_grid

    fu, fv = scorer.frames
    I, normal, keep = scorer.target(x, y)
    S = evaluate_grid(net, fu.param(x), fv.param(y))
    return scorer._measure(S - I, normal, keep)


def verify_advice(scorer, shape, binding, tolerance: float, advised) -> dict:
    """Measure the advised net (and one step coarser in the binding direction) on OCCT's surface.

    Returns
    -------
    dict
        ``{"method": "occt", "levels", "value", "meets", "region": "face"}`` and, with a binding
        direction, ``"coarser": {"shape", "value", "meets"}``.
    """
    from .fitting import candidate_net

    metric = scorer.metric
    levels = int(round(np.log2(scorer.K)))
    cu, cv = scorer.axes(*shape)
    got = measure_on_occt(scorer, advised, cu.x, cv.x)
    out = {"method": "occt", "levels": levels, "region": "face", "value": got[metric],
           "rms": got["rms"], "meets": bool(got[metric] <= tolerance)}
    if binding is not None:
        coarser = (shape[0] - 1, shape[1]) if binding == "u" else (shape[0], shape[1] - 1)
        Q, S, I, normal, keep, (au, av) = scorer.fit(*coarser)
        c = measure_on_occt(scorer, candidate_net(scorer.net, Q, au, av), au.x, av.x)
        out["coarser"] = {"shape": list(coarser), "value": c[metric], "meets": bool(c[metric] <= tolerance)}
    return out
