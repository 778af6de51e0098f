"""Verification of advice on the real surface of the resampled net.

The advised net is built as a real B-spline surface with OCP (``Geom_BSplineSurface``) and
evaluated by OCCT; nets under other schemes are measured by numerical subdivision. The
deviation from today's intent is band-split in the new net's bands and measured on the
interior (clamped ends are outside the uniform model; SPEC §5, "one step coarser must not").

The band split is global: the residual's deviation in the first and last ``p`` spans of a
clamped direction (where the clamped basis functions differ from the uniform ones, about a
millimetre on a steep hull end) would leak into the interior through the split's brick-wall
filter. A B-spline is local, so past those spans the real surface IS the uniform spline of the
same points (checked here, ``uniform_match``); the split therefore takes the real (OCCT) surface
there and, inside the clamped spans only, the uniform spline of the net extended like the
intent. ``value_clamped`` keeps the split of the raw clamped field for comparison.
"""

from __future__ import annotations

import numpy as np

from .budget import _stats
from .fields import FIELD_NAMES, ArtifactFields, Axis, intent_normals, project

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
        ``value`` the ripple (or whole deviation) under ``metric`` on the interior. For OCCT faces
        with uniform spans also ``uniform_match`` (max distance of OCCT's surface from the uniform
        spline past the clamped spans), ``clamped_ends`` (a note) and, for ripple, ``value_clamped``
        (the split of the raw clamped field).
    """
    from .advisor import _scale, carried_intent, resample
    from .budget import border_margin, region_mask
    from .measure import _evaluator, _param_axis, measurement_road
    from .separable import split_field

    new = resample(net, shape, scheme, intent=intent)
    au = Axis(new.shape[0], new.periodic[0], levels)
    av = Axis(new.shape[1], new.periodic[1], levels)
    su = _scale(net.shape[0], shape[0], net.periodic[0])
    sv = _scale(net.shape[1], shape[1], net.periodic[1])
    x_new = np.arange(new.shape[0]) * su
    y_new = np.arange(new.shape[1]) * sv
    trend_pts = intent.trend(x_new, y_new)  # the resampled net is today's trend + residual (linear)
    road, _ = measurement_road(new, scheme)
    extra = {}
    if road == "face":
        from .exchange import evaluate_grid
        from .splines import evaluate

        u, v = _param_axis(new, 0, au.x), _param_axis(new, 1, av.x)
        surface = evaluate_grid(new, u, v)  # OCCT's evaluator on the real B-spline surface
        s_trend = evaluate(new, u, v, points=trend_pts)
        method = "occt"
        clamped, continued = _clamped_spans(new, au, av, u, v)
        if clamped.any():
            res = surface - s_trend
            res_uniform = continued(new.points - trend_pts)
            extra["uniform_match"] = float(np.abs(res - res_uniform)[~clamped].max(initial=0.0))
            extra["clamped_ends"] = "first/last p spans continued as the uniform spline for the band split"
            res_split = np.where(clamped[:, :, None], res_uniform, res)
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
    normal = None if component == "vector" else intent_normals(target, au.K)
    margin = border_margin(new, scheme)
    keep = region_mask(new.replace(uv_bounds=None),
                       ArtifactFields(x=au.x, y=av.x, surface=surface, intent=target), "interior", margin)
    key = "deviation" if include_signal_error else "total"
    if "clamped_ends" in extra:
        if key == "total":  # the deviation is pointwise: no split, nothing leaks
            raw = split_field(dev_res, au, av)["total"]
            extra["value_clamped"] = float(_stats({"total": project(raw, normal, component)}, keep)["total"]
                                           .get(metric))
        dev_res = res_split - (target - target_trend)
    bands = split_field(dev_res, au, av)
    bands["signal_error"] = bands["signal_error"] + (s_trend - target_trend)
    scalars = {name: project(bands[name], normal, component) for name in FIELD_NAMES}
    scalars["deviation"] = project(err, normal, component)
    stats = _stats(scalars, keep)
    out = {"method": method, "levels": levels, "value": float(stats[key].get(metric)),
           "stats": {k: {"peak": s.peak, "rms": s.rms} for k, s in stats.items()}}
    out.update(extra)
    return out


def _clamped_spans(net, au: Axis, av: Axis, u: np.ndarray, v: np.ndarray):
    """The first/last ``p`` spans of the clamped directions, and the net's surface continued uniformly there.

    Returns
    -------
    mask : (A, B) bool
        Fine-grid points in those spans. A direction of fewer than ``2p + 1`` points has no
        uniform span and is left clamped.
    continued : callable
        Control points ``(nu, nv, 3)`` -> surface on the fine grid whose clamped directions use the
        uniform cardinal basis on the net extended by even reflection (as the intent and
        :func:`cadartifact.measure._evaluator`); the other directions keep the real basis.
    """
    from .measure import cardinal_operator
    from .separable import sandwich
    from .splines import basis_matrix

    mask = np.zeros((au.fine_count, av.fine_count), bool)
    mats = []
    for axis, (ax, par) in enumerate(((au, u), (av, v))):
        p, n = net.degrees[axis], ax.n
        if net.periodic[axis] or n - 1 < 2 * p:
            mats.append(basis_matrix(net.knots[axis], p, par, n, net.periodic[axis]))
            continue
        inside = (ax.x >= p) & (ax.x <= n - 1 - p)
        mask |= ~inside[:, None] if axis == 0 else ~inside[None, :]
        mats.append(cardinal_operator(n, p, ax.x, False))
    return mask, lambda pts: sandwich(mats[0], np.asarray(pts, float), mats[1])
