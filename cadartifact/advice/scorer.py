"""The scorer of a density search: candidate densities (and today's net) against one intent (SPEC §5).

A candidate ``a x b`` is the least-squares fit of the intent on a check grid (:mod:`cadartifact.analysis.fitting`);
its value is its error against the intent along the intent's normal, over the trimmed face. A face with
junctions (knots of multiplicity ``>= p``) is fitted by candidates that keep them (:mod:`.joins`).
"""

from __future__ import annotations

import numpy as np

from ..analysis.baseband import baseband_at
from ..analysis.budget import budget_for, total_ripple, total_ripple_field, trim_mask
from ..analysis.fields import intent_normals, project
from ..analysis.fitting import candidate_axis, candidate_net, curve_distance, error_planes, fit_error
from ..analysis.settings import RunSettings
from ..net import ControlNet
from ..numerics.operator_cache import OperatorCache
from ..numerics.tensor import sandwich, sandwich_left, sandwich_right
from .exact import kept_axis, kept_directions
from .joins import join_plan, jointed_axis

__all__ = ["_Scorer", "_make_scorer", "_ripple_of", "_own_claim", "_trimmed", "_real_on"]


class _Scorer:
    """Scores candidate densities (and today's net) against one intent on check grids (memoised)."""

    def __init__(self, net: ControlNet, work: ControlNet, scheme, fields, intent, settings: RunSettings):
        self.net, self.work, self.scheme = net, work, scheme
        # settings.intent is the reading candidates are scored against, settings.levels the check grid's
        self.fields, self.intent, self.reading = fields, intent, settings.intent
        self.K, self.metric, self.component = 2 ** settings.levels, settings.metric, settings.component
        self.frames = intent.frames
        self.degrees = work.degrees if work.is_bspline else tuple(
            min(d, n - 1) for d, n in zip(scheme.degrees or (3, 3), work.shape))
        self._targets: dict = {}
        self._scores: dict = {}
        self._errors: dict = {}
        self._trim = trim_mask
        self._borders: dict = {}
        self._planes: dict = {}  # grid -> the target's error_planes (fit_error)
        self._halves = OperatorCache(16, shared=False)  # (side, count, grid, fit) -> a half of the fit
        # directions kept as today's (exact lines and arcs, one Bezier piece: :mod:`.exact`) under the face's own
        # degrees; the face's joins, kept by every candidate in the others (a cage, or a face read under another
        # scheme, has none)
        own = work.is_bspline and tuple(self.degrees) == tuple(work.degrees) and (
            scheme.degrees is None or tuple(scheme.degrees) == tuple(work.degrees))
        self.kept = kept_directions(net, work) if own else (None, None)
        self.plans = tuple(join_plan(work, k) if work.is_bspline and not self.kept[k] else None
                           for k in (0, 1))

    def with_plans(self, plans) -> "_Scorer":
        """This scorer with other :class:`~.joins.JoinPlan` per direction (a per-piece candidate's): the intent
        and the check grids' targets are shared, its scores are its own."""
        return self._variant(plans=tuple(plans))

    def with_degrees(self, degrees) -> "_Scorer":
        """This scorer for candidates of other B-spline degrees (a named scheme's uniform B-splines: the scheme
        comparison's best net of a density), with no joins: the intent and the check grids' targets are shared."""
        return self._variant(degrees=tuple(int(d) for d in degrees), plans=(None, None), kept=(None, None))

    def _variant(self, **changes) -> "_Scorer":
        """A copy with other candidates (``changes``: their plans or degrees) sharing the intent and the targets;
        every cache keyed by the candidate's counts is its own (the same counts make other candidates)."""
        import copy

        other = copy.copy(self)
        for name, value in changes.items():
            setattr(other, name, value)
        other._scores, other._errors = {}, {}
        other._halves = OperatorCache(8, shared=False)
        return other

    def target(self, x: np.ndarray, y: np.ndarray):
        """The intent, its normals and the trim mask on the grid ``x x y`` (cached by grid size)."""
        key = _grid_key(x, y)
        if key not in self._targets:
            if self.reading == "surface":
                I = baseband_at(self.fields, x, y)
            else:
                I = self.intent.evaluate(x, y)
            normal = None if self.component == "vector" else intent_normals(I, spacing=(_spacing(x), _spacing(y)))
            keep = self._trim(self.work, self.frames, x, y)
            if len(self._targets) > 16:
                self._targets.clear()
            self._targets[key] = (I, normal, keep)
        return self._targets[key]

    def axes(self, a: int, b: int):
        """The candidate's two :class:`~cadartifact.analysis.fitting.CandidateAxis`: today's where a direction is
        kept (:mod:`.exact`), else keeping the face's joins where it has them (:mod:`.joins`)."""
        return tuple(kept_axis(self.work, f, k, n, self.K) if self.kept[k]
                     else candidate_axis(f, n, d, self.K) if plan is None else jointed_axis(f, n, d, self.K, plan)
                     for k, (f, n, d, plan) in enumerate(zip(self.frames, (a, b), self.degrees, self.plans)))

    def fit(self, a: int, b: int):
        """``(Q, surface, target, normal, keep, axes)`` of the candidate ``a x b`` (:func:`fit_points`)."""
        Q, I, normal, keep, (cu, cv) = self.points(a, b)
        return Q, sandwich(cu.B, Q, cv.B), I, normal, keep, (cu, cv)

    def points(self, a: int, b: int):
        """``(Q, target, normal, keep, axes)``: the candidate's control points ``Fu I Fv^T`` without its surface.
        The search pairs each ``a`` with many ``b`` and each ``b`` with many ``a``: the fit's ``u`` half
        ``Fu I`` is kept per ``a`` and grid, its ``v`` half ``I Fv^T`` per ``b``; a candidate with neither makes
        both (the same numbers in either order, to rounding)."""
        cu, cv = self.axes(a, b)
        I, normal, keep = self.target(cu.x, cv.x)
        grid = _grid_key(cu.x, cv.x)
        half = self._halves.peek(("u", a) + grid)
        if half is not None:
            return sandwich_right(half, cv.pinv), I, normal, keep, (cu, cv)
        other = self._halves.peek(("v", b) + grid)
        if other is None:
            other = self._halves.get(("v", b) + grid, lambda: np.ascontiguousarray(
                np.tensordot(I, cv.pinv, axes=(1, 1)).transpose(0, 2, 1)))
            self._halves.get(("u", a) + grid, lambda: sandwich_left(cu.pinv, I))
        return sandwich_left(cu.pinv, other), I, normal, keep, (cu, cv)

    def score(self, a: int, b: int) -> dict:
        """``{"peak", "rms", "boundary"}`` of the candidate's error (model units)."""
        if (a, b) not in self._scores:
            Q, I, normal, keep, (cu, cv) = self.points(a, b)
            self._scores[(a, b)] = dict(self.error(a, b), boundary=self.boundary(Q, cu, cv))
        return self._scores[(a, b)]

    def error(self, a: int, b: int) -> dict:
        """``{"peak", "rms"}`` of the candidate's error against the intent (what the search reads; the border
        curves' distance, :meth:`boundary`, is reported for the advised net only)."""
        if (a, b) not in self._errors:
            Q, I, normal, keep, (cu, cv) = self.points(a, b)
            key = _grid_key(cu.x, cv.x)
            if key not in self._planes:
                if len(self._planes) > 4:
                    self._planes.clear()
                self._planes[key] = error_planes(I, normal, self.component)
            self._errors[(a, b)] = fit_error(Q, cu, cv, self._planes[key], keep)
        return self._errors[(a, b)]

    def _measure(self, err, normal, keep) -> dict:
        f = np.abs(project(err, normal, self.component))
        v = f[keep] if not keep.all() else f
        return {"peak": float(v.max()) if v.size else 0.0, "rms": float(np.sqrt(np.mean(v ** 2))) if v.size else 0.0}

    def value(self, a: int, b: int) -> float:
        return self.error(a, b)[self.metric]

    def boundary(self, Q: np.ndarray, cu, cv) -> float:
        """Largest distance of the candidate's open border curves from today's real ones (untrimmed faces):
        each candidate border sample's distance to today's border curve (a polyline through its samples on
        the check grid), so a different parametrisation of the same curve costs nothing. The candidate's
        border curves are its surface's first and last rows and columns (``Bu[[0, -1]] Q Bv^T``, ...)."""
        if not self.work.is_bspline or _trimmed(self.work, self.frames):
            return 0.0
        from ..numerics.splines import evaluate

        x, y = cu.x, cv.x
        fu, fv = self.frames
        out = 0.0
        key = _grid_key(x, y)
        if key not in self._borders:
            lines = {}
            if not fu.periodic:
                lines["u"] = evaluate(self.work, fu.param(x[[0, -1]]), fv.param(y))
            if not fv.periodic:
                lines["v"] = evaluate(self.work, fu.param(x), fv.param(y[[0, -1]]))
            self._borders[key] = lines
        lines = self._borders[key]
        if "u" in lines:
            rows = sandwich(cu.B[[0, -1]], Q, cv.B)
            for k in (0, 1):
                out = max(out, curve_distance(rows[k], lines["u"][k]))
        if "v" in lines:
            cols = sandwich(cu.B, Q, cv.B[[0, -1]])
            for k in (0, 1):
                out = max(out, curve_distance(cols[:, k], lines["v"][:, k]))
        return out

    def today(self) -> dict:
        """Today's net scored by the same code: its real surface minus the intent on its own check grid."""
        cu, cv = self.axes(*self.work.shape)
        I, normal, keep = self.target(cu.x, cv.x)
        real = _real_on(self.work, self.scheme, self.intent, cu.x, cv.x, self.fields)
        out = self._measure(real - I, normal, keep)
        out["boundary"] = 0.0
        return out


def _spacing(x: np.ndarray):
    """A check grid's spacing for the normals: one step when even, else the coordinates (a grid keeping joins is
    even within each piece only; ``numpy.gradient`` then takes the coordinates)."""
    step = (x[-1] - x[0]) / max(len(x) - 1, 1)
    if len(x) < 3 or np.allclose(np.diff(x), step, rtol=1e-9, atol=0.0):
        return step
    return np.asarray(x, float)


def _grid_key(x: np.ndarray, y: np.ndarray) -> tuple:
    """A check grid's key: sizes and sums (a candidate keeping joins adds them to its grid: same size, other
    points)."""
    return (len(x), float(np.sum(x)), len(y), float(np.sum(y)))


def _trimmed(net: ControlNet, frames) -> bool:
    """Whether a face is trimmed inside its surface's parameter range (its borders are then trim curves)."""
    if net.uv_bounds is None:
        return False
    (u0, u1, v0, v1), (fu, fv) = net.uv_bounds, frames
    full = (fu.u0, fu.u0 + fu.h * fu.spans, fv.u0, fv.u0 + fv.h * fv.spans)
    scale = max(1.0, *(abs(a) for a in full))
    return any(abs(a - b) > 1e-9 * scale for a, b in zip((u0, u1, v0, v1), full))


def _real_on(work, scheme, intent, x, y, fields) -> np.ndarray:
    """Today's real surface on a grid of analysis coordinates."""
    if work.is_bspline and scheme.degrees is not None and tuple(scheme.degrees) == tuple(work.degrees):
        from ..numerics.splines import evaluate

        fu, fv = intent.frames
        return evaluate(work, fu.param(x), fv.param(y))
    # cages: the fine grid of the fields (the check grid at today's density is that grid)
    return fields.surface


def _make_scorer(net, work, sch, settings: RunSettings, current=None) -> _Scorer:
    """A scorer of candidates against the intent (``settings.intent``: the reading, ``settings.levels``: the
    check grid): the surface reading's fields (today's budget's when it kept them), and the intent object (a
    split face's :class:`cadartifact.analysis.pieces.PiecewiseIntent`)."""
    from ..analysis.intent import design_intent

    fields = current.fields if current is not None else None
    if fields is None or fields.baseband is None:  # a net-reading budget keeps no base band: the surface reading
        lv = current.levels if current is not None else settings.levels
        surface = RunSettings(scheme=sch, levels=lv, component=settings.component)
        fields = budget_for(work, surface, keep_fields=True).fields
    it = fields.baseband.get("intent") or design_intent(work, sch, fields.levels)
    return _Scorer(net, work, sch, fields, it, settings)


def _ripple_of(sc: _Scorer, a, b, settings: RunSettings) -> float:
    """The ripple-only objective: the fitted candidate's own ripple budget (under its own degrees, on the
    scorer's check grid)."""
    key = ("ripple", a, b)
    if key not in sc._scores:
        Q, S, I, normal, keep, (cu, cv) = sc.fit(a, b)
        cand = candidate_net(sc.net, Q, cu, cv)
        sc._scores[key] = total_ripple(cand, settings.replace(scheme=None, levels=int(np.log2(sc.K))))
    return sc._scores[key]


def _own_claim(sc: _Scorer, a, b, settings: RunSettings) -> float:
    """``own + U_own``: the candidate's own ripple (:func:`_ripple_of`) plus the ``U`` the gate will decide that
    net by (:func:`~cadartifact.analysis.border_convention.surface_uncertainty`, SPEC §4 decisions): its bound
    ``RELATIVE_BOUND own + G`` where that decides against ``settings.tolerance``, else the period variants (read
    only then). A claim on the net at ``own + U_own <= t`` is one the gate confirms, not leaves undecided."""
    from ..analysis.border_convention import surface_uncertainty

    if not sc.net.is_bspline:  # a cage's candidate is written as a cage, whose reading has no border convention:
        return _ripple_of(sc, a, b, settings)  # the gate decides it with U not estimated (zero)
    key = ("claim", a, b)
    if key not in sc._scores:
        Q, S, I, normal, keep, (cu, cv) = sc.fit(a, b)
        cand = candidate_net(sc.net, Q, cu, cv)
        own_settings = settings.replace(scheme=None, levels=int(np.log2(sc.K)))
        own, total, region = total_ripple_field(cand, own_settings)
        sc._scores[("ripple", a, b)] = own
        u = surface_uncertainty(cand, own_settings, own, scalars={"total": total}, region=region)
        sc._scores[key] = own + float(u.peak)
    return sc._scores[key]


