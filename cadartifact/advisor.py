"""Resampling and density advice (SPEC §5).

The intent of a net (trend + band-limited residual, :mod:`cadartifact.fields`) is
resampled at ``n'u x n'v`` control points; the artifact of the resampled net is
the part of ``surface(n') - intent`` in the alias bands of the ``n'`` net, which
also counts the intent lost above the new Nyquist limit. The advice is the
density with the fewest points whose artifact stays within the tolerance,
verified on the real surface (OCCT) of the advised net.

>>> import cadartifact as ca
>>> a = ca.advise(net, tolerance=0.05)                 # doctest: +SKIP
>>> a.shape, a.meets_tolerance, a.comparison           # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .budget import METRICS, Budget, Stat, _stats, budget, default_scheme
from .errors import OptionError, check_option
from .fields import (FIELD_NAMES, Intent, band_split, design_intent, intent_normals, predicted_surface, project,
                     ripple_only)  # noqa: F401
from .net import ControlNet, clamped_uniform_knots
from .splines import param_range

__all__ = ["Advice", "advise", "resample", "artifact_at", "carried_intent", "NAMED_SCHEMES"]

NAMED_SCHEMES = ("bilinear", "bicubic", "4-3", "4-8", "kobbelt")

#: Largest advised density per direction, as a multiple of today's (and an absolute cap).
GROWTH, MAX_POINTS = 8, 2000

#: The frontier walk looks this many times beyond the first feasible corner in each direction (2 found
#: no better answer on the real files, at 1.8x the search time).
WALK_REACH = 1

#: Nets above this many control points skip the scheme comparison unless asked for.
COMPARE_MAX_POINTS = 2000

#: Fine grid of the density search (K = 2, the refined vertices); the answer is then confirmed and walked at the
#: requested levels. K = 4 gave the same answers on the real files but for one face (9x8 instead of 8x10) at
#: about 1.8x the time.
COARSE_LEVELS = 1


def _new_positions(n_old: int, n_new: int, periodic: bool) -> np.ndarray:
    """Index coordinates (old net) of the new control points spanning the same domain."""
    if periodic:
        return np.arange(n_new) * (n_old / n_new)
    return np.linspace(0.0, n_old - 1.0, n_new)


def _scale(n_old: int, n_new: int, periodic: bool) -> float:
    """Old index units per new control spacing."""
    return n_old / n_new if periodic else (n_old - 1.0) / max(n_new - 1, 1)


def _uniform_knots(n: int, degree: int, lo: float, hi: float, periodic: bool) -> np.ndarray:
    if periodic:
        h = (hi - lo) / n
        return lo + h * (np.arange(n + 2 * degree + 1) - degree)
    return clamped_uniform_knots(n, degree, lo, hi)


def resample(net: ControlNet, shape: tuple[int, int], scheme=None, *, intent: Intent | None = None) -> ControlNet:
    """The net's design intent resampled at a new density, with new uniform knots.

    Parameters
    ----------
    net : ControlNet
    shape : (int, int)
        New ``(n'u, n'v)``.
    scheme : str or Scheme, optional
        Defines the intent's polynomial trend and, for a cage, the degrees of the result
        (default as :func:`cadartifact.budget`).
    intent : Intent, optional
        Reuse an intent already computed for ``net`` and ``scheme``.

    Returns
    -------
    ControlNet
        ``points[i', j'] = intent(x_i', y_j')`` with ``x_i' = i' (nu-1)/(n'u-1)`` (periodic:
        ``i' nu/n'u``); same degrees (clipped to ``n' - 1``) over the same parameter range, uniform
        clamped (or periodic) knots, no weights. A cage stays a cage.
    """
    from .schemes import Scheme, scheme as get_scheme

    sch = default_scheme(net) if scheme is None else (scheme if isinstance(scheme, Scheme) else get_scheme(scheme))
    try:
        a, b = (int(s) for s in shape)
    except (TypeError, ValueError):
        raise OptionError("shape", "two integers (n'u, n'v)", shape) from None
    degrees = net.degrees
    low = [2, 2] if degrees is None else [d + 1 for d in degrees]
    if a < low[0] or b < low[1]:
        raise OptionError("shape", f"at least {low[0]}x{low[1]} control points", (a, b))
    it = intent if intent is not None else design_intent(net, sch, 1)
    x = _new_positions(net.shape[0], a, net.periodic[0])
    y = _new_positions(net.shape[1], b, net.periodic[1])
    pts = it.evaluate(x, y)
    if degrees is None:
        return ControlNet(points=pts, periodic=net.periodic, unit=net.unit, origin=net.origin)
    knots = []
    for n_new, deg, k, per in zip((a, b), degrees, net.knots, net.periodic):
        lo, hi = param_range(k, deg)
        knots.append(_uniform_knots(n_new, deg, lo, hi, per))
    return ControlNet(points=pts, degrees=degrees, knots=tuple(knots), periodic=net.periodic,
                      unit=net.unit, origin=net.origin)


def artifact_at(intent: Intent, scheme, shape: tuple[int, int], *, levels: int = 3, component: str = "normal",
                region: str = "face", only: str | None = None, fast: bool = True) -> dict:
    """Statistics of ``surface(n') - intent`` split in the bands of the ``n'`` net.

    Parameters
    ----------
    intent : Intent
        Today's intent.
    scheme : Scheme
    shape : (int, int)
        Candidate density.
    levels : int
        Fine grid of the candidate net.

    only : {"total", "deviation"}, optional
        Compute just that statistic (the search's objective), skipping the other bands.
    fast : bool
        Tensor-product schemes: per-axis operators (:func:`cadartifact.separable.resampled_error`);
        False forces the 2-D FFT path (the reference).

    Returns
    -------
    dict str -> Stat
        As :attr:`Budget.stats`.
    """
    net = intent.net
    if fast and getattr(scheme, "tensor", False):
        return _artifact_at_tensor(intent, scheme, shape, levels, component, only, region)
    new = resample(net, shape, scheme, intent=intent)
    it2 = carried_intent(intent, new, levels)
    au, av = it2.axes
    surface = predicted_surface(it2, scheme)
    su = _scale(net.shape[0], shape[0], net.periodic[0])
    sv = _scale(net.shape[1], shape[1], net.periodic[1])
    x_old, y_old = au.x * su, av.x * sv
    target = intent.evaluate(x_old, y_old)
    err = surface - target
    normal = None if component == "vector" else intent_normals(target, au.K)
    scalars = {}
    if only is None and fast:
        from .separable import split_field

        bands = split_field(err, au, av)
        scalars = {name: project(bands[name], normal, component) for name in FIELD_NAMES}
    elif only != "deviation":
        spec = np.fft.fft2(av.extend(au.extend(err, 0), 1), axes=(0, 1))
        fu, fv, shp = au.freqs(fine=True), av.freqs(fine=True), (au.fine_count, av.fine_count)
        if only == "total":
            scalars["total"] = project(ripple_only(spec, fu, fv, shp), normal, component)
        else:
            bands = band_split(spec, fu, fv, shp)
            scalars = {name: project(bands[name], normal, component) for name in FIELD_NAMES}
    if only in (None, "deviation"):
        scalars["deviation"] = project(err, normal, component)
    keep = np.ones(err.shape[:2], bool)
    if region == "interior":
        from .budget import border_margin, region_mask
        from .fields import ArtifactFields

        margin = border_margin(new, scheme)
        keep = region_mask(new.replace(uv_bounds=None), ArtifactFields(x=au.x, y=av.x, surface=err,
                                                                        intent=target), "interior", margin)
    return _stats(scalars, keep)


def carried_intent(intent: Intent, new: ControlNet, levels: int) -> Intent:
    """The intent of a resampled net as today's trend plus its band-limited residual (no refit).

    Refitting a trend to the resampled points would move part of the band-limited residual into a
    polynomial whose even reflection kinks at the borders: spurious ripple. Today's Legendre
    coefficients apply unchanged, because both nets scale index space to the same ``[-1, 1]``.
    """
    from .fields import Axis

    axes = (Axis(new.shape[0], new.periodic[0], levels), Axis(new.shape[1], new.periodic[1], levels))
    tmp = Intent(net=new, axes=axes, terms=intent.terms, coef=intent.coef, residual=None, spectrum=None)
    residual = new.points - tmp.trend(np.arange(new.shape[0]), np.arange(new.shape[1]))
    spectrum = np.fft.fft2(axes[1].extend(axes[0].extend(residual, 0), 1), axes=(0, 1))
    return Intent(net=new, axes=axes, terms=intent.terms, coef=intent.coef, residual=residual, spectrum=spectrum)


def _artifact_at_tensor(intent: Intent, scheme, shape, levels, component, only, region) -> dict:
    """:func:`artifact_at` for tensor-product schemes by per-axis operators (same numbers, much faster)."""
    from .fields import Axis, trend_caps
    from .separable import axis_model, resampled_error, ripple_and_intent

    net = intent.net
    d = int(scheme.reproduction_degree)
    old_axes = intent.axes
    new_axes = (Axis(shape[0], net.periodic[0], levels), Axis(shape[1], net.periodic[1], levels))
    caps = trend_caps(d, old_axes)  # the resampled net carries today's trend (SPEC §5)
    old = tuple(axis_model(scheme, k, a.n, a.periodic, c) for k, (a, c) in enumerate(zip(old_axes, caps)))
    new = tuple(axis_model(scheme, k, a.n, a.periodic, c) for k, (a, c) in enumerate(zip(new_axes, caps)))
    scales = [_scale(n, m, per) for n, m, per in zip(net.shape, shape, net.periodic)]
    x_new = tuple(_new_positions(n, m, per) for n, m, per in zip(net.shape, shape, net.periodic))
    x_fine = tuple(a.x * s for a, s in zip(new_axes, scales))
    if only == "total":
        ripple, target = ripple_and_intent(net.points, old, new, x_new, x_fine, levels)
        bands = {"total": ripple}
    else:
        bands, target = resampled_error(net.points, old, new, x_new, x_fine, levels, only=only)
    normal = None if component == "vector" else intent_normals(target, new_axes[0].K)
    scalars = {name: project(f, normal, component) for name, f in bands.items()}
    keep = _candidate_region(net, scheme, shape, new_axes, target, region)
    return _stats(scalars, keep)


def _candidate_region(net, scheme, shape, axes, target, region) -> np.ndarray:
    au, av = axes
    if region != "interior":
        return np.ones((au.fine_count, av.fine_count), bool)
    from .budget import border_margin, region_mask
    from .fields import ArtifactFields

    new = _resample_shell(net, shape)
    margin = border_margin(new, scheme)
    return region_mask(new, ArtifactFields(x=au.x, y=av.x, surface=target, intent=target), "interior", margin)


def _resample_shell(net: ControlNet, shape) -> ControlNet:
    """A net of the candidate's shape, degrees and periodicity (its points do not matter): for region masks."""
    degrees = net.degrees
    pts = np.zeros(tuple(shape) + (3,))
    pts[..., 0] = np.arange(shape[0])[:, None]  # not degenerate; positions do not matter for the mask
    pts[..., 1] = np.arange(shape[1])[None, :]
    if degrees is None:
        return ControlNet(points=pts, periodic=net.periodic, unit=net.unit)
    knots = tuple(_uniform_knots(n, p, 0.0, 1.0, per) for n, p, per in zip(shape, degrees, net.periodic))
    return ControlNet(points=pts, degrees=degrees, knots=knots, periodic=net.periodic, unit=net.unit)


@dataclass(frozen=True, eq=False)
class Advice:
    """Density advice for one net.

    Attributes
    ----------
    net : ControlNet
        Today's net.
    scheme : str
    tolerance : float
    metric : str
    include_signal_error : bool
    current : Budget
        Today's budget.
    shape : (int, int)
        Advised ``(n'u, n'v)`` (fewest points within tolerance).
    stats : dict str -> Stat
        The budget at the advice (artifact of the resampled net against today's intent).
    meets_tolerance : bool
        Whether the advice's value stays within the tolerance (False when no density up to the
        search limit does).
    binding : str or None
        ``"u"`` or ``"v"``: the direction in which one step coarser breaks the tolerance.
    verification : dict
        The advised net built as a real surface and measured: ``{"method", "value", "meets",
        "coarser": {"shape", "value", "meets"}}``.
    comparison : dict str -> dict
        The same advice for the other named schemes: ``{"net": [n'u, n'v], "points", "meets_tolerance"}``.
    comparison_note : str or None
        Why the comparison was skipped (large nets, ``compare="auto"``).
    """

    net: ControlNet
    scheme: str
    tolerance: float
    metric: str
    include_signal_error: bool
    current: Budget
    shape: tuple
    stats: dict
    meets_tolerance: bool
    binding: str | None = None
    verification: dict | None = None
    comparison: dict = field(default_factory=dict)
    comparison_note: str | None = None

    @property
    def value(self) -> float:
        return self.stats["deviation" if self.include_signal_error else "total"].get(self.metric)

    @property
    def points(self) -> int:
        return int(self.shape[0] * self.shape[1])

    def resampled(self) -> ControlNet:
        """The advised net (today's intent at the advised density)."""
        return resample(self.net, self.shape, self.scheme)

    def to_dict(self) -> dict:
        """JSON-ready summary (the ``advice`` object of the advise schema)."""
        t = self.tolerance
        d = {
            "net": list(self.shape),
            "points": self.points,
            "budget": {k: {"peak": _f(s.peak), "rms": _f(s.rms)} for k, s in self.stats.items()},
            "share": {k: _f(s.get(self.metric) / t) for k, s in self.stats.items()},
            "meets_tolerance": bool(self.meets_tolerance),
            "binding": self.binding,
            "verification": self.verification,
            "comparison": self.comparison,
        }
        if self.comparison_note:
            d["comparison_note"] = self.comparison_note
        return d


def _f(x):
    return None if x is None or not math.isfinite(x) else float(x)


class _Search:
    """Memoised artifact evaluations over candidate densities."""

    def __init__(self, intent, scheme, tolerance, metric, include_signal_error, levels, component, region):
        self.intent, self.scheme, self.t = intent, scheme, tolerance
        self.metric, self.key = metric, "deviation" if include_signal_error else "total"
        self.levels, self.component, self.region = levels, component, region
        self.cache: dict = {}
        self.full: dict = {}

    def stats(self, a: int, b: int) -> dict:
        """All statistics at a density (computed once)."""
        if (a, b) not in self.full:
            self.full[(a, b)] = artifact_at(self.intent, self.scheme, (a, b), levels=self.levels,
                                            component=self.component, region=self.region)
        return self.full[(a, b)]

    def value(self, a: int, b: int) -> float:
        """The objective at a density (only what the search compares)."""
        if (a, b) not in self.cache:
            st = self.full.get((a, b)) or artifact_at(self.intent, self.scheme, (a, b), levels=self.levels,
                                                      component=self.component, region=self.region, only=self.key)
            self.cache[(a, b)] = st[self.key].get(self.metric)
        return self.cache[(a, b)]

    def ok(self, a: int, b: int) -> bool:
        return self.value(a, b) <= self.t


def _first_true(lo: int, hi: int, pred) -> int:
    """Smallest n in [lo, hi] with pred(n) (pred monotone, pred(hi) True)."""
    while lo < hi:
        mid = (lo + hi) // 2
        if pred(mid):
            hi = mid
        else:
            lo = mid + 1
    return lo


def _gallop(pred, lo: int, hi: int, hint: int) -> int:
    """Smallest x in [lo, hi] with pred(x) (pred monotone, pred(hi) True), searched from a hint.

    Steps of 1, 2, 4... away from ``hint`` (down if pred(hint), else up), then bisection: about
    ``2 log2 |answer - hint|`` evaluations, so an answer near today's density costs two or three.
    """
    h = min(hi, max(lo, hint))
    if pred(h):
        top, step = h, 1
        while top - step >= lo and pred(top - step):
            top, step = top - step, 2 * step
        return _first_true(max(lo, top - step + 1), top, pred)
    bottom, step = h, 1
    while True:
        nxt = min(hi, bottom + step)
        if nxt == hi or pred(nxt):
            return _first_true(bottom + 1, nxt, pred)
        bottom, step = nxt, 2 * step


def _frontier(search: _Search, lo: tuple[int, int], hi: tuple[int, int],
              start: tuple[int, int]) -> tuple[tuple[int, int], bool]:
    """Fewest-points feasible density by walking the whole frontier ``n'v(n'u)``; ``(shape, reachable)``.

    A feasible corner is found by doubling from ``start`` (today's density). The frontier's ends are
    the smallest ``n'u`` feasible with ``n'v`` at its maximum and the smallest ``n'v`` feasible with
    ``n'u`` at its maximum; from the first, each step adds one ``u`` point and lowers ``n'v`` while the
    tolerance holds (galloping, then bisecting), until ``n'u`` times the smallest ``n'v`` cannot beat
    the best so far. Exact, when the predicate is monotone in both directions, within
    :data:`WALK_REACH` times the first feasible corner.
    """
    a, b = (max(l, min(h, s)) for l, h, s in zip(lo, hi, start))
    while not search.ok(a, b):
        if a >= hi[0] and b >= hi[1]:
            return (a, b), False
        a, b = min(hi[0], 2 * a), min(hi[1], 2 * b)
    best = (a, b)
    # past the feasible corner a direction would have to shrink in proportion to save points: the
    # walk stays in the box WALK_REACH times the corner (far corners cost large candidates)
    hi = (min(hi[0], WALK_REACH * a), min(hi[1], WALK_REACH * b))
    # the frontier's ends, searched from today's density (the answer is often near it)
    a_min = _gallop(lambda x: search.ok(x, hi[1]), lo[0], a, start[0])
    b_floor = _gallop(lambda y: search.ok(hi[0], y), lo[1], b, start[1])
    # the first frontier point: up from the smallest n'v (often just above it), then small steps
    a, b = a_min, _gallop(lambda y: search.ok(a_min, y), b_floor, hi[1], b_floor)
    while True:
        if b > b_floor and search.ok(a, b - 1):
            b = _gallop(lambda y, x=a: search.ok(x, y), b_floor, b - 1, b - 1)
        if a * b < best[0] * best[1]:
            best = (a, b)
        if a >= hi[0] or (a + 1) * b_floor >= best[0] * best[1]:
            return best, True
        a += 1


def advise(net: ControlNet, tolerance: float, scheme=None, *, metric: str = "peak",
           include_signal_error: bool = False, levels: int = 3, component: str = "normal",
           compare: bool | str = "auto", verify: bool = True) -> Advice:
    """Advise the control-point density that keeps the artifact within ``tolerance``.

    Parameters
    ----------
    net : ControlNet
    tolerance : float
        Model units.
    scheme : str or Scheme, optional
        Default: the net's own B-spline degrees; Catmull-Clark for cages.
    metric : {"peak", "rms"}
    include_signal_error : bool
        Make the tolerance cover the whole deviation from intent (attenuation too), not only ripple.
    levels : int
        Fine grid ``2**levels`` per control spacing for the final numbers (the search runs at the
        paper's refined vertices, ``levels=1``, then confirms at ``levels``).
    component : {"normal", "vector"}
    compare : bool or "auto"
        Also advise the other named schemes (search only, no verification); ``"auto"``: for nets of
        up to :data:`COMPARE_MAX_POINTS` control points (a long sweep would take seconds per scheme).
    verify : bool
        Build the advised net as a real surface (OCCT B-spline; subdivision for other schemes),
        evaluate and measure it on its interior, and the same one step coarser in the binding
        direction.

    Returns
    -------
    Advice

    Notes
    -----
    The search assumes the artifact falls as density rises in each direction (true for the band
    structure; resonances are caught by verification). On the refined vertices (K = 2) it finds each
    direction's smallest feasible count with the other at its maximum (galloping from today's
    density), then walks the whole frontier ``n'v(n'u)`` to the fewest points ``n'u n'v``; at
    ``levels`` it confirms the answer, and where the finer grid finds higher peaks it lowers the
    coarse tolerance by the ratio of the two grids, walks again, and steps to the nearest density
    the finer grid accepts.
    """
    from .schemes import Scheme, scheme as get_scheme

    check_option("metric", metric, METRICS)
    try:
        tolerance = float(tolerance)
    except (TypeError, ValueError):
        raise OptionError("tolerance", "a positive number of model units", tolerance) from None
    if not math.isfinite(tolerance) or tolerance <= 0:
        raise OptionError("tolerance", "a positive number of model units", tolerance)
    sch = default_scheme(net) if scheme is None else (scheme if isinstance(scheme, Scheme) else get_scheme(scheme))
    current = budget(net, sch, tolerance, metric=metric, levels=levels, component=component)

    shape, reachable, search_fine = _advise_shape(net, sch, tolerance, metric, include_signal_error, levels, component)
    stats = search_fine.stats(*shape)
    meets = stats["deviation" if include_signal_error else "total"].get(metric) <= tolerance
    binding = _binding(search_fine, shape, net)

    verification = None
    if verify:
        verification = _verify(net, sch, shape, binding, search_fine, tolerance, metric, include_signal_error,
                               component)
    comparison, comparison_note = {}, None
    if compare == "auto":
        compare = net.size <= COMPARE_MAX_POINTS
        if not compare:
            comparison_note = f"skipped: net of {net.size} points (> {COMPARE_MAX_POINTS}); pass compare=True"
    if compare:
        for name in NAMED_SCHEMES:
            other = get_scheme(name)
            if other.name == sch.name:
                comparison[other.name] = {"net": list(shape), "points": int(shape[0] * shape[1]),
                                          "meets_tolerance": bool(meets)}
                continue
            s2, ok2, _ = _advise_shape(net, other, tolerance, metric, include_signal_error, 1, component,
                                       confirm=False)
            comparison[other.name] = {"net": list(s2), "points": int(s2[0] * s2[1]), "meets_tolerance": bool(ok2)}
    return Advice(net=net, scheme=sch.name, tolerance=tolerance, metric=metric,
                  include_signal_error=include_signal_error, current=current, shape=tuple(shape), stats=stats,
                  meets_tolerance=bool(meets), binding=binding, verification=verification, comparison=comparison,
                  comparison_note=comparison_note)


def _limits(net: ControlNet) -> tuple[tuple[int, int], tuple[int, int]]:
    low = (2, 2) if net.degrees is None else tuple(d + 1 for d in net.degrees)
    high = tuple(max(l + 1, min(MAX_POINTS, GROWTH * n)) for l, n in zip(low, net.shape))
    return low, high


def _advise_shape(net, sch, tolerance, metric, include_signal_error, levels, component, confirm=True):
    """Search at levels=1, then confirm (and walk) at ``levels``. Returns (shape, reachable, fine search)."""
    low, high = _limits(net)
    it1 = design_intent(net, sch, COARSE_LEVELS)
    coarse = _Search(it1, sch, tolerance, metric, include_signal_error, COARSE_LEVELS, component, "face")
    shape, reachable = _frontier(coarse, low, high, net.shape)
    if not confirm or levels == 1:
        return shape, reachable, coarse
    it = design_intent(net, sch, levels)
    fine = _Search(it, sch, tolerance, metric, include_signal_error, levels, component, "face")
    if not reachable:
        return shape, fine.ok(*shape), fine
    a, b = shape
    # the refined-vertex search misses peaks between vertices: lower its tolerance by the ratio of the
    # two grids at its answer and walk its frontier again (its values are cached), so that the fine
    # walk below starts next to the fine frontier
    for _ in range(2):
        if fine.ok(a, b) or coarse.value(a, b) <= 0.0:
            break
        coarse.t = tolerance * min(1.0, coarse.value(a, b) / fine.value(a, b)) * (1 - 1e-6)
        (a2, b2), ok2 = _frontier(coarse, low, high, (a, b))
        if not ok2 or (a2, b2) == (a, b):
            break
        a, b = a2, b2
    # grow until the fine grid agrees
    while not fine.ok(a, b) and (a < high[0] or b < high[1]):
        grow_u = a < high[0] and (b >= high[1] or fine.value(a + 1, b) <= fine.value(a, min(b + 1, high[1])))
        a, b = (a + 1, b) if grow_u else (a, b + 1)
    # and it may be pessimistic: per direction, the fewest points the fine grid still accepts
    # (galloping, not single steps: the two grids can disagree by tens of points)
    changed = fine.ok(a, b)
    while changed:
        changed = False
        if a > low[0] and fine.ok(a - 1, b):
            a, changed = _gallop(lambda x, y=b: fine.ok(x, y), low[0], a - 1, a - 1), True
        if b > low[1] and fine.ok(a, b - 1):
            b, changed = _gallop(lambda y, x=a: fine.ok(x, y), low[1], b - 1, b - 1), True
    return (a, b), fine.ok(a, b), fine


def _binding(search: _Search, shape, net) -> str | None:
    low, _ = _limits(net)
    a, b = shape
    worse = {}
    if a - 1 >= low[0]:
        worse["u"] = search.value(a - 1, b)
    if b - 1 >= low[1]:
        worse["v"] = search.value(a, b - 1)
    failing = {k: v for k, v in worse.items() if v > search.t}
    if not failing:
        return None
    return max(failing, key=failing.get)


def _verify(net, sch, shape, binding, search, tolerance, metric, include_signal_error, component) -> dict:
    """Measure the advised net as a real surface on its interior; and one step coarser in the binding direction."""
    from .budget import border_margin
    from .verify import measure_resampled

    out = measure_resampled(net, sch, shape, search.intent, metric=metric,
                            include_signal_error=include_signal_error, component=component)
    out["meets"] = bool(out["value"] <= tolerance)
    if binding is not None:
        coarser = (shape[0] - 1, shape[1]) if binding == "u" else (shape[0], shape[1] - 1)
        c = measure_resampled(net, sch, coarser, search.intent, metric=metric,
                              include_signal_error=include_signal_error, component=component)
        out["coarser"] = {"shape": list(coarser), "value": c["value"], "meets": bool(c["value"] <= tolerance)}
        if out["coarser"]["meets"]:
            # the search sees the whole face; verification the interior: what binds lies near a border
            out["note"] = (f"one step coarser ({coarser[0]}x{coarser[1]}) also meets the tolerance on the interior: "
                           f"what binds the advice lies within {border_margin(_resample_shell(net, coarser), sch)} "
                           "spans of a clamped border, which the interior leaves out")
    return out
