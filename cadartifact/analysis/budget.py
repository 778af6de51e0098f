"""The artifact budget of one control net: per-direction ripple against a tolerance (SPEC §4).

>>> import cadartifact as ca
>>> net = ca.load("samples/wavy_panel_diagonal.step")[0]          # doctest: +SKIP
>>> b = ca.budget(net, tolerance=0.05)                            # doctest: +SKIP
>>> b.stats["x1"].peak, b.share("total")                          # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import OptionError
from .clamped import reads_clamped_borders
from .fields import FIELD_NAMES, ArtifactFields, artifact_fields, intent_normals, project
from .intent import design_intent
from ..net import ControlNet, no_ripple_by_construction
from .pieces import gather_fields, split_net
from .settings import RunSettings, resolve_scheme
from .trim_region import cage_bounds, used_net

__all__ = ["Budget", "Stat", "budget", "budget_for", "total_ripple", "total_ripple_field"]


#: All statistics a budget carries: the ripple fields, the signal error and the whole deviation.
STAT_NAMES = FIELD_NAMES + ("deviation",)


@dataclass(frozen=True)
class Stat:
    """Peak ``max |f|`` and RMS ``sqrt(mean f^2)`` of one field, in model units."""

    peak: float
    rms: float

    def get(self, metric: str) -> float:
        return self.peak if metric == "peak" else self.rms


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
    intent : str
        The reading of the design intent: ``"surface"`` (the surface less its ripple; no signal
        error) or ``"net"`` (the shape the control points sample).
    undersampled : float
        Share of the net intent's RMS above 0.4 cycles per control point (above
        :data:`cadartifact.analysis.intent.UNDERSAMPLED_SHARE` the net under-samples its intent and
        :attr:`notes` says so).
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
    pieces : (int, int) or None
        A face split at its junctions (:mod:`cadartifact.analysis.pieces`): the grid of pieces analysed.
    caveats : tuple of str
        What the analysis could not do for this face (it is then in :attr:`notes`).
    options : (str, str)
        The ``method`` and ``region`` asked of :func:`budget` (``("auto", "auto")`` by default).
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
    intent: str = "surface"
    undersampled: float = 0.0
    fields: ArtifactFields | None = field(default=None, repr=False)
    scalar_fields: dict | None = field(default=None, repr=False)
    region: np.ndarray | None = field(default=None, repr=False)
    pieces: tuple | None = None
    caveats: tuple = ()
    options: tuple = ("auto", "auto")
    #: What of the surface's parameter range the trimmed face uses (:class:`~cadartifact.analysis.trim_region.UsedRegion`;
    #: None: untrimmed), and the net analysed: the surface cut down to those spans (``net`` when nothing is cut).
    used: object = None
    work: ControlNet | None = field(default=None, repr=False)

    @property
    def notes(self) -> list[str]:
        """Plain-language caveats about these numbers."""
        from .intent import UNDERSAMPLED_SHARE

        out = list(self.caveats)
        if self.undersampled > UNDERSAMPLED_SHARE:
            out.append(f"the net under-samples its intent: {self.undersampled:.0%} of its content lies above "
                       "0.4 cycles per control point, which no net of this density can tell from ripple")
        return out

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
            "intent": self.intent,
            "undersampled": _num(self.undersampled),
            "notes": self.notes,
            "pieces": list(self.pieces) if self.pieces else None,
            "outside_trim": None if self.used is None else self.used.to_dict(),
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
    """Spans from an open border that the *interior* leaves out.

    A clamped B-spline's first ``p`` spans have uneven Greville abscissae, and their effect on the
    surface decays by about ``2 - sqrt(3)`` per span (cubic): ``p + 1`` spans keep it below a few
    percent. Cages: the mask radius.
    """
    if net.is_bspline:
        return max(net.degrees) + 1
    return max(scheme.mask.shape) // 2


def trim_mask(net: ControlNet, frames, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Points of the grid ``x x y`` (analysis coordinates) inside the trimmed face's uv bounds."""
    keep = np.ones((len(x), len(y)), bool)
    if net.uv_bounds is None:  # a cage read from a trimmed face carries its bounds in pole indices
        return keep
    u0, u1, v0, v1 = net.uv_bounds
    masks = []
    for frame, pts, (lo, hi) in zip(frames, (x, y), ((u0, u1), (v0, v1))):
        par = frame.param(pts)
        if frame.periodic:
            per = frame.h * frame.spans
            par = lo + np.mod(par - lo, per)
        tol = 1e-9 * max(1.0, abs(hi - lo))
        masks.append((par >= lo - tol) & (par <= hi + tol))
    for axis, lo, hi in net.trim_gaps:  # a trim across a periodic opening: two ranges, the gap between left out
        par = frames[axis].param((x, y)[axis])
        tol = 1e-9 * max(1.0, abs(hi - lo))
        out = ~((par > lo + tol) & (par < hi - tol))
        masks[axis] = masks[axis] & out
    trim = masks[0][:, None] & masks[1][None, :]
    return trim if trim.any() else keep


def region_mask(net: ControlNet, frames, x: np.ndarray, y: np.ndarray, region: str, margin: int) -> np.ndarray:
    """Points that count: inside the trimmed face's uv bounds, and ``margin`` spans away from open
    borders for ``region="interior"``."""
    keep = trim_mask(net, frames, x, y)
    if region == "interior":
        for axis, (coord, frame) in enumerate(zip((x, y), frames)):
            if frame.periodic:
                continue
            inside = (coord >= margin) & (coord <= frame.spans - margin)
            if not inside.any():  # a net too small for the margin: its centre line
                inside = np.abs(coord - frame.spans / 2) <= 0.5
            keep = keep & (inside[:, None] if axis == 0 else inside[None, :])
    return keep


def _scalars(fields: ArtifactFields, component: str) -> dict:
    normal = None if component == "vector" else intent_normals(fields.intent, 2 ** fields.levels)
    has = None if normal is None else np.einsum("...k,...k->...", normal, normal) != 0.0
    linear = has is not None and bool(has.all())
    out = {name: project(fields.bands[name], normal, component, True if linear else has) for name in FIELD_NAMES}
    # the normal part is linear where every sample has a normal: the deviation is the sum of its parts (the total
    # is projected itself: :func:`total_ripple` reads it so, and the two must agree to the bit)
    out["deviation"] = (out["total"] + out["signal_error"] if linear else
                        project(fields.bands["total"] + fields.bands["signal_error"], normal, component, has))
    return out


def _stats(scalars: dict, keep: np.ndarray) -> dict:
    res = {}
    everywhere = bool(keep.all())
    for name, f in scalars.items():
        v = np.abs(f if everywhere else f[keep])
        res[name] = Stat(peak=float(v.max()) if v.size else 0.0, rms=float(np.sqrt(np.mean(v ** 2))) if v.size else 0.0)
    return res


def analysis_net(net: ControlNet, scheme, tolerance: float | None = None) -> ControlNet:
    """The net as the scheme reads it: a face under its own degrees keeps its knots and weights, cut down to the
    spans its trim uses (:func:`cadartifact.analysis.trim_region.used_net`; ``tolerance`` in model units: a
    trim past a join by less counts as stopping there); under another scheme its points are a cage (uniform
    parametrisation of that scheme)."""
    return used_region(net, scheme, tolerance)[0]


def used_region(net: ControlNet, scheme, tolerance: float | None = None):
    """``(analysis net, UsedRegion or None)``: :func:`analysis_net` and what of the surface's parameter range
    the trimmed face uses (:class:`cadartifact.analysis.trim_region.UsedRegion`)."""
    own = net.is_bspline and scheme.degrees is not None and tuple(scheme.degrees) == tuple(net.degrees)
    if not net.is_bspline:
        return net, None
    if own:
        return used_net(net, tolerance)
    # a cage of its poles under another scheme keeps the face's trim (mapped to pole indices)
    return ControlNet(points=net.points, periodic=net.periodic, unit=net.unit, origin=net.origin,
                      uv_bounds=cage_bounds(net)), None


def budget(net: ControlNet, scheme=None, tolerance: float | None = None, *, metric: str = "peak",
           method: str = "auto", levels: int = 3, component: str = "normal", region: str = "auto",
           intent: str = "surface", keep_fields: bool = False) -> Budget:
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
        ``auto``: measured (the real surface) for a face under its own degrees, predicted (the
        spectral road) for cages and other schemes; ``both``: the primary road's stats plus the
        other road's agreement on the interior in :attr:`Budget.check`.
    levels : int
        Fine grid ``K = 2**levels`` per control spacing (3: K = 8, close to the continuous surface;
        1: the paper's refined vertices).
    component : {"normal", "vector"}
        Report the displacement along the intent's normal (what a profile tolerance measures;
        tangential motion only re-parametrises) or its full length.
    region : {"auto", "face", "interior"}
        ``interior`` leaves out ``max(p, q) + 1`` spans at open borders; ``auto`` and ``face``: the
        whole (trimmed) face.
    intent : {"surface", "net"}
        The reading of the design intent (SPEC §4): the surface less its ripple (no signal error),
        or the shape the control points sample.
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
    settings = RunSettings(tolerance=tolerance, metric=metric, scheme=scheme, intent=intent, levels=levels,
                           component=component, method=method, region=region)
    return budget_for(net, settings, keep_fields=keep_fields)


def budget_for(net: ControlNet, settings: RunSettings, *, keep_fields: bool = False) -> Budget:
    """:func:`budget` under a run's settings (made and checked once, at the edge; see
    :mod:`cadartifact.analysis.settings`): ``settings.scheme``, ``tolerance``, ``metric``, ``method``,
    ``levels``, ``component``, ``region`` and ``intent`` as :func:`budget`'s arguments."""
    if not isinstance(net, ControlNet):
        raise OptionError("net", "a ControlNet", type(net).__name__)
    sch = resolve_scheme(net, settings.scheme)
    work, used = used_region(net, sch, settings.tolerance)
    b = None
    if work.is_bspline:
        pieces = split_net(work)
        if len(pieces) > 1 or pieces[0].net is not work:
            b = _piecewise_budget(net, work, pieces, sch, settings, keep_fields)
        elif pieces[0].note:
            b = _budget_of(net, work, sch, settings, keep_fields)
            b = dataclasses.replace(b, reason=f"{b.reason}; {pieces[0].note}", caveats=b.caveats + (pieces[0].note,))
    if b is None:
        b = _budget_of(net, work, sch, settings, keep_fields)
    options = (settings.method, settings.region)
    return dataclasses.replace(b, options=options, used=used, work=work)


def _budget_of(net, work, sch, settings: RunSettings, keep_fields, keep_scalars=False) -> Budget:
    """:func:`budget` of a net that needs no splitting."""
    method, levels, component, intent = settings.method, settings.levels, settings.component, settings.intent
    it = design_intent(work, sch, levels)
    face = work.is_bspline
    primary = _road(work, method)
    if primary == "measured":
        reason = ("the real surface (exact NURBS evaluation of the face)" if face else
                  "the real surface (numerical subdivision / uniform B-spline of the net)")
        why = []
        if face and not all(net.knots_uniform):
            why.append("knots are not uniform")
        if why:
            reason += "; " + " and ".join(why) + ": outside the uniform theory"
        construction = no_ripple_by_construction(work)
        if construction:
            reason += f"; no ripple by construction ({construction})"
    else:
        reason = "spectral prediction (the scheme's responses)"
    if it.homogeneous:
        reason += "; rational: analysed in homogeneous coordinates (w P, w)"
    main = artifact_fields(it, sch, primary, intent)
    frames = it.frames
    margin = border_margin(work, sch)
    region = "face" if settings.region == "auto" else settings.region
    scalars = _scalars(main, component)
    keep = region_mask(work, frames, main.x, main.y, region, margin)
    stats = _stats(scalars, keep)

    check = None
    if method == "both":
        other_name = "measured" if primary == "predicted" else "predicted"
        other = artifact_fields(it, sch, other_name, intent)
        interior = region_mask(work, frames, main.x, main.y, "interior", margin)
        diff = np.linalg.norm(main.bands["total"] - other.bands["total"], axis=-1)[interior]
        scale = np.linalg.norm(main.bands["total"], axis=-1)[interior]
        mad = float(diff.max()) if diff.size else 0.0
        peak = float(scale.max()) if scale.size else 0.0
        check = {"method": other_name, "max_abs_diff": mad, "relative": mad / peak if peak > 0 else 0.0}

    caveats = ()
    if (primary == "predicted" and face and it.homogeneous and not all(f.periodic for f in frames)
            and not reads_clamped_borders(it, sch)):
        # generated rational clamped faces, read as an infinite uniform net (2026-12-03): 1.6-258x the real
        # surface, median 11x; clamped uniform knots are read from their uniform-equivalent points instead
        caveats = ("the predicted road reads the uniform theory's infinite net: at the open borders of a rational "
                   "face whose knots are not clamped uniform (or of degree above 4) it can read up to a few hundred "
                   "times the real surface (method 'measured' reads the surface itself)",)
    return Budget(net=net, scheme=sch.name, method=primary, reason=reason, tolerance=settings.tolerance,
                  metric=settings.metric, component=component, levels=levels, stats=stats, check=check, intent=intent,
                  caveats=caveats,
                  undersampled=it.undersampled(),
                  fields=main if keep_fields else None,
                  scalar_fields=scalars if keep_fields or keep_scalars else None,
                  region=keep if keep_fields or keep_scalars else None)


def _road(work: ControlNet, method: str = "auto") -> str:
    """The primary road of a method: ``auto`` (and ``both``) measure a face's real surface and predict a cage's."""
    if method in ("auto", "both"):
        return "measured" if work.is_bspline else "predicted"
    return method


def total_ripple(net: ControlNet, settings: RunSettings) -> float:
    """``budget_for(net, settings).stats["total"][settings.metric]`` computed for that number only (the default
    road and the whole face, the surface reading): the same fields less the lateral one, the same projection
    and mask, no other band's statistics. The advice asks this of hundreds of candidates per face (the scheme
    comparison's cages, the confirmed candidates' own ripple). A face that needs splitting takes the full budget.
    """
    return _total_ripple(net, settings, keep_field=False)[0]


def total_ripple_field(net: ControlNet, settings: RunSettings) -> tuple:
    """:func:`total_ripple` with what its uncertainty is read on: ``(value, field, mask)``, the projected total
    ripple ``(a, b)`` on the fine grid and the face's mask, as the budget's ``scalar_fields["total"]`` and
    ``region`` (for a split face, the pieces' gathered field, as :func:`budget_for` keeps it)."""
    return _total_ripple(net, settings, keep_field=True)


def _total_ripple(net: ControlNet, settings: RunSettings, keep_field: bool) -> tuple:
    """``(value, field, mask)`` of :func:`total_ripple_field`; a split face's field and mask only if kept."""
    sch = resolve_scheme(net, settings.scheme)
    work = analysis_net(net, sch, settings.tolerance)
    if work.is_bspline:
        pieces = split_net(work)
        if len(pieces) > 1 or pieces[0].net is not work or pieces[0].note:
            whole = settings.replace(tolerance=None, scheme=sch, intent="surface", method="auto", region="auto")
            b = budget_for(net, whole, keep_fields=keep_field)  # the pieces' gathered field, as the gate keeps it
            value = b.stats["total"].get(settings.metric)
            return (value, b.scalar_fields["total"], b.region) if keep_field else (value, None, None)
    it = design_intent(work, sch, settings.levels)
    main = artifact_fields(it, sch, _road(work), "surface", lateral=False)
    normal = None if settings.component == "vector" else intent_normals(main.intent, 2 ** main.levels)
    total = project(main.bands["total"], normal, settings.component)
    keep = region_mask(work, it.frames, main.x, main.y, "face", border_margin(work, sch))
    return _stats({"total": total}, keep)["total"].get(settings.metric), total, keep


def _after_junction(a: np.ndarray, piece) -> np.ndarray:
    """A piece's fine-grid array without its first row/column where it repeats the previous piece's last."""
    return a[(1 if piece.index[0] > 0 else 0):, (1 if piece.index[1] > 0 else 0):]


def _piecewise_budget(net, work, pieces, sch, settings: RunSettings, keep_fields) -> Budget:
    """The budget of a face split at its junctions (:mod:`cadartifact.analysis.pieces`): each piece analysed as a
    net of its own; peaks over all pieces, RMS over all their fine-grid samples."""
    levels = settings.levels
    each = settings.replace(tolerance=None)
    parts = [_budget_of(p.net, p.net, sch, each, keep_fields, keep_scalars=True) for p in pieces]
    scalars = [dict(b.scalar_fields, __region__=b.region) for b in parts]
    fields = None
    if keep_fields:
        fields, gathered = gather_fields(work, pieces, [b.fields for b in parts], scalars, levels)
        keep = gathered.pop("__region__")
    else:  # the same samples as the gathered grid (a junction's row once), without building it
        gathered = {name: np.concatenate([_after_junction(s[name], p)[_after_junction(s["__region__"], p)].ravel()
                                          for s, p in zip(scalars, pieces)])
                    for name in scalars[0] if name != "__region__"}
        keep = np.ones(next(iter(gathered.values())).shape, bool)
    stats = _stats(gathered, keep)
    rows = len({p.index[0] for p in pieces})
    cols = len({p.index[1] for p in pieces})
    first = parts[0]
    reason = (f"{first.reason}; split at its junctions (knots of multiplicity >= the degree) into {rows}x{cols} "
              f"pieces analysed separately")
    # method "both": the pieces' worst agreement between the roads
    check = max((b.check for b in parts if b.check), key=lambda c: c["max_abs_diff"], default=None)
    return Budget(net=net, scheme=sch.name, method=first.method, reason=reason, tolerance=settings.tolerance,
                  metric=settings.metric, component=settings.component, levels=levels, stats=stats, check=check,
                  intent=settings.intent,
                  undersampled=max(b.undersampled for b in parts), pieces=(rows, cols),
                  fields=fields, scalar_fields=gathered if keep_fields else None,
                  region=keep if keep_fields else None)
