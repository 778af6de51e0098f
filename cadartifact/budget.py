"""The artifact budget of one control net: per-direction ripple against a tolerance (SPEC §4).

>>> import cadartifact as ca
>>> net = ca.load("samples/wavy_panel_diagonal.step")[0]          # doctest: +SKIP
>>> b = ca.budget(net, tolerance=0.05)                            # doctest: +SKIP
>>> b.stats["x1"].peak, b.share("total")                          # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import OptionError, check_option
from .fields import COMPONENTS, FIELD_NAMES, ArtifactFields, design_intent, intent_normals, predicted_fields, project
from .net import ControlNet

__all__ = ["Budget", "Stat", "budget", "default_scheme", "METHODS", "METRICS", "REGIONS"]

METHODS = ("auto", "predicted", "measured", "both")
METRICS = ("peak", "rms")
REGIONS = ("auto", "face", "interior")

#: All statistics a budget carries: the ripple fields, the signal error and the whole deviation.
STAT_NAMES = FIELD_NAMES + ("deviation",)


@dataclass(frozen=True)
class Stat:
    """Peak ``max |f|`` and RMS ``sqrt(mean f^2)`` of one field, in model units."""

    peak: float
    rms: float

    def get(self, metric: str) -> float:
        return self.peak if metric == "peak" else self.rms


def default_scheme(net: ControlNet):
    """The scheme a net is analysed with by default: its own B-spline degrees, Catmull-Clark for cages."""
    from .schemes import bspline, scheme

    if net.degrees is not None:
        return bspline(*net.degrees)
    return scheme("catmull-clark")


@dataclass(frozen=True, eq=False)
class Budget:
    """Artifact budget of one net.

    Attributes
    ----------
    net : ControlNet
    scheme : str
        Name of the scheme analysed.
    method : str
        ``"predicted"`` (spectral) or ``"measured"`` (real surface), the road the stats come from.
    reason : str
        Why that road (e.g. non-uniform knots are measured).
    tolerance : float or None
        In model units.
    metric : str
        ``"peak"`` or ``"rms"``: what :meth:`share` divides by the tolerance.
    component : str
        ``"normal"`` (signed displacement along the intent's normal) or ``"vector"`` (its length).
    levels : int
        The fine grid has ``2**levels`` samples per control spacing.
    stats : dict str -> Stat
        ``x1, x2, diagonal, lateral, total`` (all ripple), ``signal_error`` and ``deviation``
        (surface minus intent, everything).
    check : dict or None
        Agreement of the other road on the interior, when both were computed:
        ``{"method", "max_abs_diff", "relative"}``.
    fields : ArtifactFields or None
        The fine-grid fields (kept on request, for pictures).
    scalar_fields : dict str -> (a, b) float or None
        The reported scalar of each field on the fine grid (kept on request).
    region : (a, b) bool or None
        The fine-grid points the stats were taken over (kept on request).
    """

    net: ControlNet
    scheme: str
    method: str
    reason: str
    tolerance: float | None
    metric: str
    component: str
    levels: int
    stats: dict
    check: dict | None = None
    fields: ArtifactFields | None = field(default=None, repr=False)
    scalar_fields: dict | None = field(default=None, repr=False)
    region: np.ndarray | None = field(default=None, repr=False)

    def share(self, name: str) -> float | None:
        """``stats[name].<metric> / tolerance`` (None without a tolerance)."""
        if self.tolerance is None:
            return None
        return self.stats[name].get(self.metric) / self.tolerance

    def value(self, include_signal_error: bool = False) -> float:
        """The number compared with the tolerance: the ripple (or whole deviation) under the metric."""
        return self.stats["deviation" if include_signal_error else "total"].get(self.metric)

    def meets(self, include_signal_error: bool = False) -> bool | None:
        """Whether the value stays within the tolerance (None without a tolerance)."""
        if self.tolerance is None:
            return None
        return bool(self.value(include_signal_error) <= self.tolerance)

    def to_dict(self) -> dict:
        """JSON-ready summary (no arrays)."""
        d = {
            "scheme": self.scheme,
            "method": self.method,
            "reason": self.reason,
            "metric": self.metric,
            "component": self.component,
            "levels": self.levels,
        }
        d.update({name: {"peak": _num(s.peak), "rms": _num(s.rms)} for name, s in self.stats.items()})
        if self.tolerance is not None:
            d["share"] = {name: _num(self.share(name)) for name in self.stats}
        if self.check is not None:
            d["check"] = {k: (_num(v) if isinstance(v, float) else v) for k, v in self.check.items()}
        return d


def _num(x):
    return None if x is None or not math.isfinite(x) else float(x)


def border_margin(net: ControlNet, scheme) -> int:
    """Control spacings from an open border that the *interior* leaves out.

    A clamped B-spline's first ``p`` spans have uneven Greville abscissae, and their effect on the
    surface decays by about ``2 - sqrt(3)`` per span (cubic): ``p + 1`` spans keep it below a few
    percent. Cages: the mask radius.
    """
    if net.degrees is not None:
        return max(net.degrees) + 1
    return max(scheme.mask.shape) // 2


def region_mask(net: ControlNet, fields: ArtifactFields, region: str, margin: int) -> np.ndarray:
    """Fine-grid points that count: inside the trimmed face's uv bounds, and away from open borders
    by ``margin`` control spacings for ``region="interior"``."""
    x, y = fields.x, fields.y
    keep = np.ones((len(x), len(y)), bool)
    if region == "interior":
        for axis, (coord, n) in enumerate(((x, net.shape[0]), (y, net.shape[1]))):
            if net.periodic[axis]:
                continue
            inside = (coord >= margin) & (coord <= n - 1 - margin)
            if not inside.any():  # a net too small for the margin: use its centre line
                inside = np.abs(coord - (n - 1) / 2) <= 0.5
            keep &= inside[:, None] if axis == 0 else inside[None, :]
    if net.uv_bounds is not None and net.knots is not None:
        from .measure import _param_axis

        u0, u1, v0, v1 = net.uv_bounds
        u = _param_axis(net, 0, x)
        v = _param_axis(net, 1, y)
        if net.periodic[0]:
            per = net.knots[0][len(net.knots[0]) - net.degrees[0] - 1] - net.knots[0][net.degrees[0]]
            u = u0 + np.mod(u - u0, per)
        if net.periodic[1]:
            per = net.knots[1][len(net.knots[1]) - net.degrees[1] - 1] - net.knots[1][net.degrees[1]]
            v = v0 + np.mod(v - v0, per)
        tol_u, tol_v = 1e-9 * max(1.0, abs(u1 - u0)), 1e-9 * max(1.0, abs(v1 - v0))
        trim = ((u >= u0 - tol_u) & (u <= u1 + tol_u))[:, None] & ((v >= v0 - tol_v) & (v <= v1 + tol_v))[None, :]
        if (keep & trim).any():
            keep &= trim
    return keep


def _scalars(fields: ArtifactFields, component: str) -> dict:
    normal = None if component == "vector" else intent_normals(fields.intent, 2 ** fields.levels)
    out = {name: project(fields.bands[name], normal, component) for name in FIELD_NAMES}
    out["deviation"] = project(fields.bands["total"] + fields.bands["signal_error"], normal, component)
    return out


def _stats(scalars: dict, keep: np.ndarray) -> dict:
    res = {}
    everywhere = bool(keep.all())
    for name, f in scalars.items():
        v = np.abs(f if everywhere else f[keep])
        res[name] = Stat(peak=float(v.max()) if v.size else 0.0, rms=float(np.sqrt(np.mean(v ** 2))) if v.size else 0.0)
    return res


def budget(net: ControlNet, scheme=None, tolerance: float | None = None, *, metric: str = "peak",
           method: str = "auto", levels: int = 3, component: str = "normal", region: str = "auto",
           keep_fields: bool = False) -> Budget:
    """Per-direction artifact budget of a control net.

    Parameters
    ----------
    net : ControlNet
    scheme : str or Scheme, optional
        Default: the net's own B-spline degrees ``bspline(p, q)``; Catmull-Clark for cages.
    tolerance : float, optional
        Model units (mm for STEP). Must be positive.
    metric : {"peak", "rms"}
        What shares and :meth:`Budget.meets` use.
    method : {"auto", "predicted", "measured", "both"}
        ``auto``: predicted where the uniform theory applies (uniform knots, constant weights, or a
        cage), measured otherwise; ``both``: predicted stats (measured for non-uniform faces) plus the
        other road's agreement in :attr:`Budget.check`.
    levels : int
        Fine grid ``K = 2**levels`` per control spacing (3: K = 8, close to the continuous surface;
        1: the paper's refined vertices).
    component : {"normal", "vector"}
        Report the displacement along the intent's normal (what a profile tolerance measures;
        tangential motion only re-parametrises) or its full length.
    region : {"auto", "face", "interior"}
        ``interior`` leaves out ``max(p, q) + 1`` control spacings at open borders (clamped ends are
        outside the uniform model); ``auto``: the whole face when predicted, the interior when a face
        is measured.
    keep_fields : bool
        Keep the fine-grid fields for pictures.

    Returns
    -------
    Budget

    Notes
    -----
    For one sinusoid ``A cos(2 pi W.J)`` on a periodic net, the ripple fields have RMS
    ``A r / sqrt(2)`` with ``r`` the continuous (or, at ``levels=1``, refined-vertex) response
    of SPEC §3 per direction; ``total`` RMS is ``A sqrt(3) energy / sqrt(2)``.
    """
    from .schemes import Scheme, scheme as get_scheme

    check_option("metric", metric, METRICS)
    check_option("method", method, METHODS)
    check_option("component", component, COMPONENTS)
    check_option("region", region, REGIONS)
    if tolerance is not None:
        tolerance = float(tolerance)
        if not math.isfinite(tolerance) or tolerance <= 0:
            raise OptionError("tolerance", "a positive number of model units", tolerance)
    if not isinstance(net, ControlNet):
        raise OptionError("net", "a ControlNet", type(net).__name__)
    sch = default_scheme(net) if scheme is None else (scheme if isinstance(scheme, Scheme) else get_scheme(scheme))

    intent = design_intent(net, sch, levels)
    own = net.knots is not None and sch.degrees is not None and tuple(sch.degrees) == tuple(net.degrees)
    uniform = net.uniform or not own
    if not uniform:
        why = []
        if not all(net.knots_uniform):
            why.append("knots are not uniform")
        if net.weights_vary:
            why.append("weights vary")
        primary, reason = "measured", " and ".join(why) + ": outside the uniform theory, measured on the real surface"
    elif method == "measured":
        primary, reason = "measured", "measured on request"
    else:
        primary, reason = "predicted", "uniform: spectral prediction"
    if method == "predicted" and not uniform:
        primary, reason = "predicted", "predicted on request although " + reason.split(":")[0]

    main = _road(primary, intent, sch)
    margin = border_margin(net, sch)
    if region == "auto":
        region = "interior" if primary == "measured" and net.knots is not None else "face"
        if region == "interior":
            reason += f"; stats leave out {margin} spans at clamped borders (outside the uniform model)"
    scalars = _scalars(main, component)
    keep = region_mask(net, main, region, margin)
    stats = _stats(scalars, keep)

    check = None
    if method == "both":
        other_name = "measured" if primary == "predicted" else "predicted"
        other = _road(other_name, intent, sch)
        interior = region_mask(net, main, "interior", margin)
        diff = np.linalg.norm(main.bands["total"] - other.bands["total"], axis=-1)[interior]
        scale = np.linalg.norm(main.bands["total"], axis=-1)[interior]
        mad = float(diff.max()) if diff.size else 0.0
        peak = float(scale.max()) if scale.size else 0.0
        check = {"method": other_name, "max_abs_diff": mad, "relative": mad / peak if peak > 0 else 0.0}

    return Budget(net=net, scheme=sch.name, method=primary, reason=reason, tolerance=tolerance, metric=metric,
                  component=component, levels=levels, stats=stats, check=check,
                  fields=main if keep_fields else None, scalar_fields=scalars if keep_fields else None,
                  region=keep if keep_fields else None)


def _road(name: str, intent, scheme) -> ArtifactFields:
    if name == "predicted":
        return predicted_fields(intent, scheme)
    from .measure import measured_fields

    return measured_fields(intent, scheme)
