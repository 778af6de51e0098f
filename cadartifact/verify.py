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
    from .advisor import _scale, resample
    from .budget import region_mask
    from .fields import design_intent
    from .measure import _evaluator, _param_axis, measurement_road

    new = resample(net, shape, scheme, intent=intent)
    au = Axis(new.shape[0], new.periodic[0], levels)
    av = Axis(new.shape[1], new.periodic[1], levels)
    road, _ = measurement_road(new, scheme)
    if road == "face":
        from .exchange import evaluate_grid

        surface = evaluate_grid(new, _param_axis(new, 0, au.x), _param_axis(new, 1, av.x))
        method = "occt"
    else:
        it_new = design_intent(new, scheme, levels)
        surface = _evaluator(it_new, scheme, road)(new.points)
        method = road
    su = _scale(net.shape[0], shape[0], net.periodic[0])
    sv = _scale(net.shape[1], shape[1], net.periodic[1])
    target = intent.evaluate(au.x * su, av.x * sv)
    err = surface - target
    spec = np.fft.fft2(av.extend(au.extend(err, 0), 1), axes=(0, 1))
    bands = band_split(spec, au.freqs(fine=True), av.freqs(fine=True), (au.fine_count, av.fine_count))
    normal = None if component == "vector" else intent_normals(target, au.K)
    scalars = {name: project(bands[name], normal, component) for name in FIELD_NAMES}
    scalars["deviation"] = project(err, normal, component)
    margin = max(new.degrees) if new.degrees else max(scheme.mask.shape) // 2
    keep = region_mask(new.replace(uv_bounds=None),
                       ArtifactFields(x=au.x, y=av.x, surface=surface, intent=target), "interior", margin)
    stats = _stats(scalars, keep)
    key = "deviation" if include_signal_error else "total"
    return {"method": method, "levels": levels, "value": float(stats[key].get(metric)),
            "stats": {k: {"peak": s.peak, "rms": s.rms} for k, s in stats.items()}}
