"""Verification of advice on the real surface of the resampled net.

The advised net is built as a real B-spline surface with OCP (``Geom_BSplineSurface``) and
evaluated by OCCT; nets under other schemes are measured by numerical subdivision. The
deviation from today's intent is band-split in the new net's bands and measured on the
interior (clamped ends are outside the uniform model; SPEC §5, "one step coarser must not").
"""

from __future__ import annotations

import numpy as np

from .budget import _stats
from .fields import FIELD_NAMES, ArtifactFields, Axis, band_split, intent_normals, project

__all__ = ["measure_resampled", "VERIFY_LEVELS"]

#: Fine samples per control spacing used to verify (K = 4).
VERIFY_LEVELS = 2


def measure_resampled(net, scheme, shape, intent, *, metric="peak", include_signal_error=False,
                      component="normal", levels: int = VERIFY_LEVELS) -> dict:
    """Measure the artifact of ``net`` resampled at ``shape`` on its real surface.

    Parameters
    ----------
    net : ControlNet
        Today's net.
    scheme : Scheme
    shape : (int, int)
    intent : Intent
        Today's intent (any levels).

    Returns
    -------
    dict
        ``{"method": "occt" | "subdivision" | "uniform-bspline", "levels", "value", "stats"}`` with
        ``value`` the ripple (or whole deviation) under ``metric`` on the interior.
    """
    from .advisor import _scale, carried_intent, resample
    from .budget import border_margin, region_mask
    from .measure import _evaluator, _param_axis, measurement_road

    new = resample(net, shape, scheme, intent=intent)
    au = Axis(new.shape[0], new.periodic[0], levels)
    av = Axis(new.shape[1], new.periodic[1], levels)
    su = _scale(net.shape[0], shape[0], net.periodic[0])
    sv = _scale(net.shape[1], shape[1], net.periodic[1])
    x_new = np.arange(new.shape[0]) * su
    y_new = np.arange(new.shape[1]) * sv
    trend_pts = intent.trend(x_new, y_new)  # the resampled net is today's trend + residual (linear)
    road, _ = measurement_road(new, scheme)
    if road == "face":
        from .exchange import evaluate_grid
        from .splines import evaluate

        u, v = _param_axis(new, 0, au.x), _param_axis(new, 1, av.x)
        surface = evaluate_grid(new, u, v)  # OCCT's evaluator on the real B-spline surface
        s_trend = evaluate(new, u, v, points=trend_pts)
        method = "occt"
    else:
        it_new = carried_intent(intent, new, levels)
        ev = _evaluator(it_new, scheme, road)
        surface = ev(new.points)
        s_trend = ev(trend_pts)
        method = road
    target = intent.evaluate(au.x * su, av.x * sv)
    target_trend = intent.trend(au.x * su, av.x * sv)
    err = surface - target
    # the trend's image is a polynomial-like signal error; band-split the residual's deviation only
    dev_res = (surface - s_trend) - (target - target_trend)
    spec = np.fft.fft2(av.extend(au.extend(dev_res, 0), 1), axes=(0, 1))
    bands = band_split(spec, au.freqs(fine=True), av.freqs(fine=True), (au.fine_count, av.fine_count))
    bands["signal_error"] = bands["signal_error"] + (s_trend - target_trend)
    normal = None if component == "vector" else intent_normals(target, au.K)
    scalars = {name: project(bands[name], normal, component) for name in FIELD_NAMES}
    scalars["deviation"] = project(err, normal, component)
    margin = border_margin(new, scheme)
    keep = region_mask(new.replace(uv_bounds=None),
                       ArtifactFields(x=au.x, y=av.x, surface=surface, intent=target), "interior", margin)
    stats = _stats(scalars, keep)
    key = "deviation" if include_signal_error else "total"
    return {"method": method, "levels": levels, "value": float(stats[key].get(metric)),
            "stats": {k: {"peak": s.peak, "rms": s.rms} for k, s in stats.items()}}
