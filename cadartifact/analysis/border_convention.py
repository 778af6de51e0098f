"""The ``surface`` reading's border convention and its uncertainty (SPEC §4 "The `surface` reading at borders").

Near an open border the band split of the measured road (:func:`cadartifact.analysis.fields.measured_fields`)
needs a continuation of the surface past it, and no continuation is the truth: the continuation is part of the
reading's definition, as a filter's end-effect treatment is part of a surface-texture parameter's
(ISO 16610-28). The convention (docs/model.md "The `surface` reading's border convention"):

* a tensor Legendre trend, degree per open direction ``max(p, min(L // 2, 6))`` (at most ``n - 1``), kept out
  of the split;
* the rest continued past each open border by one Hermite polynomial of degree 11 (value and five derivatives
  of the end span matched at both ends, :data:`cadartifact.analysis.fields.BRIDGE_ORDER`), from the far
  border back to the near one;
* one period of ``T`` lattice points per open direction: the domain's ``L`` spans plus a fixed gap of
  :data:`cadartifact.analysis.fields.MEASURED_GAP` = 32 spans (at least ``n + 4``), rounded up to a multiple of
  ``m`` (:attr:`~cadartifact.analysis.frames.AxisFrame.alignment`: 2, an even period, where the cut is half a cycle
  per span), so that a bin lies exactly at the cut; ``K T`` fine samples (``K = 2**levels``), transformed at that
  length (numpy's FFT takes any length: no other rounding); bands split at half a cycle per span
  (:data:`cadartifact.analysis.fields.SPLIT_CUT`). The gap was twice the face
  (``T = 3 L``) before 2026-12-05: on short faces the reading then moved by up to 50 % of itself with one
  lattice point of period (the bridge's shape scales with its length, and an odd period has no bin at half a
  cycle per span), and most faces above t/3 would have been undecided;
* the peak (or RMS) read on the fine grid of the face.

What it leaves open, and :func:`surface_uncertainty` covers:

* **the period**: an implementation may round ``T`` up to an FFT-friendly length among those with a bin at the
  cut; the convention admits the next two (:data:`PERIOD_LATITUDE`: ``T + m`` and ``T + 2 m``, i.e. ``T + 2`` and
  ``T + 4`` where ``m = 2``, are read, each direction alone and both) and the spread of the value is taken:
  ``D = max_j |v_j - v_0|``;
* **the grid**: the peak is read on samples ``1 / K`` span apart; between them the field can exceed them by
  up to ``h^2 max |f''| / 8`` (``h = 1 / K``), bounded from the field's second differences next to its peak;
* **rounding**: 4 ulp of noise in the poles move no band's peak by more than 1.3e-11 mm on the samples and
  real files (docs/model.md), far below either term; it is not estimated.

``U = D + G`` (``G`` the grid term): both are half-widths of intervals the convention admits, not standard
deviations, so ``U`` covers them by construction (the coverage factor ``k = 2`` is reported as the
``net`` reading's, to which ``U`` is comparable). Its per-direction shares (``u``, ``v``) are the spread of
the variants that move that direction's period alone.

**Cost.** The variants share one evaluation of the real surface and one trend fit, and their passes
(:func:`period_variants`: three ``u`` passes and seven ``v`` passes for the seven variants, the total band only).
They are read only where the decision could flip: a face first takes the bound ``U = RELATIVE_BOUND v + G``
(``G`` from today's reading's kept fields), which covers the variants' spread on every face of the samples and
real files and on 97.5 % of the border-free family (docs/uncertainty.md); where that bound decides (``v + U <= t``
or ``v - U > t``) the variants would decide the same there, and it is reported.
"""

from __future__ import annotations


import numpy as np

__all__ = ["PERIOD_LATITUDE", "RELATIVE_BOUND", "period_variants", "surface_uncertainty", "variant_values"]

#: Lattice points the convention lets the period grow by (an FFT-friendly rounding of ``T``), where a bin sits at half
#: a cycle per span (``m = 2``); ``j m / 2`` for a direction whose period is a multiple of ``m``: each is read.
PERIOD_LATITUDE = (2, 4)

#: The variants' spread over the value, bounded: ``D <= RELATIVE_BOUND v`` on 97.5 % of the border-free family's
#: faces (158 of 162 reading more than 1e-5; the others 0.14-0.31) and on every face of the samples and
#: ../shared/realdata (largest 0.036) (docs/uncertainty.md). Wider would cover those four and blunt every
#: decision and baseline comparison of the faces that take the bound.
RELATIVE_BOUND = 0.1


def _pieces(work):
    """The nets the measured road reads: a B-spline face's pieces (split at its junctions), else the net."""
    from .pieces import split_net

    if not work.is_bspline:
        return [work]
    return [p.net for p in split_net(work)]


def variant_values(net, settings, pads=None, work=None) -> tuple[float, list, list, float]:
    """The ``surface`` reading's value under the convention's period variants.

    Parameters
    ----------
    net : ControlNet
        A B-rep face (``is_bspline``).
    settings : RunSettings
        The run's (``metric``, ``component``, ``levels``, ``scheme``, ``tolerance``, ``region``).
    pads : tuple of int, optional
        Default :data:`PERIOD_LATITUDE`. Lattice points added to each open direction's period, one variant each; every variant is read with
        both directions padded, and with each direction alone.
    work : ControlNet, optional
        The analysis net when the caller has it (:func:`cadartifact.analysis.budget.analysis_net`).

    Returns
    -------
    (v0, both, alone, grid) : (float, list of float, list of (float, float), float)
        The value at the convention's period (equal to the budget's, to rounding), per pad the value with
        both directions padded, per pad the values with only ``u`` / only ``v`` padded, and the grid term
        ``G`` (module docstring).
    """
    from .budget import analysis_net, border_margin, region_mask
    from .fields import _from_lifted, intent_normals, project, split_coordinates
    from .intent import design_intent
    from .measure import real_surface
    from .settings import resolve_scheme

    pads = PERIOD_LATITUDE if pads is None else pads
    sch = resolve_scheme(net, settings.scheme)
    work = work if work is not None else analysis_net(net, sch, settings.tolerance)
    region = "face" if settings.region == "auto" else settings.region
    combos = [(0, 0)] + [(j, j) for j in pads] + [c for j in pads for c in ((j, 0), (0, j))]
    per_combo = {c: [] for c in combos}
    grid = 0.0
    for piece in _pieces(work):
        it = design_intent(piece, sch, settings.levels)
        fu, fv = it.frames
        if fu.ripple_free and fv.ripple_free:  # nothing can alias: no ripple under any continuation
            continue
        real = split_coordinates(real_surface(it, sch), it.frames)  # as the road splits it
        keep = region_mask(piece, it.frames, fu.x, fv.x, region, border_margin(piece, sch))
        read = {}
        for c, total, smooth in period_variants(real, (fu, fv), sch, combos):
            if smooth.shape[-1] == 4:
                lifted, smooth, _ = _from_lifted({"total": total}, smooth, real)
                total = lifted["total"]
            # each variant is the whole reading at its period: its own smooth part orients it
            normal = None if settings.component == "vector" else intent_normals(smooth, fu.K)
            read[c] = project(total, normal, settings.component)
        for c in combos:
            f = read[_effective(c, (fu, fv))]
            per_combo[c].append(np.abs(f[keep]) if keep.any() else np.zeros(0))
        grid = max(grid, _grid_term(read[(0, 0)], keep))
    if not per_combo[(0, 0)]:
        return 0.0, [0.0] * len(pads), [(0.0, 0.0)] * len(pads), 0.0

    def value(c):
        v = np.concatenate(per_combo[c])
        if not v.size:
            return 0.0
        return float(v.max()) if settings.metric == "peak" else float(np.sqrt(np.mean(v ** 2)))

    v0 = value((0, 0))
    return (v0, [value((j, j)) for j in pads], [(value((j, 0)), value((0, j))) for j in pads], grid)


def _effective(pads, frames) -> tuple:
    """The pads a variant reads: a periodic direction has no period latitude (its pad is 0)."""
    return tuple(0 if f.periodic else p for p, f in zip(pads, frames))


def period_variants(field: np.ndarray, frames, scheme, combos):
    """Per period variant ``(pads, total, smooth)``: the total ripple band and the smooth part of the measured
    road's split (:func:`cadartifact.analysis.fields._bridged_bands`) with each open direction's period padded
    by ``pads`` lattice points (:func:`cadartifact.analysis.fields.measured_frames`), first ``combos[0]``.

    The same steps as the split (the tensor Legendre trend kept out, then one pass per direction,
    :func:`cadartifact.analysis.fields.above_half_cycle`), the ``u`` pass made once per ``u`` pad and one ``v``
    pass per variant: the split's total ``x1 + x2 + diagonal`` is the ``u`` pass's high part plus the ``v`` pass's
    high part of the rest (to rounding), and no base band is made. Three ``u`` and seven ``v`` passes for the
    convention's seven variants, where a whole split per variant made seven and fourteen (and seven base bands).
    A periodic direction has no period latitude: variants that differ only in its pad are read once.

    Parameters
    ----------
    field : (a, b, c) float
        The field the road splits (:func:`cadartifact.analysis.fields.split_coordinates`), on the domain's fine
        grid; ``c = 4`` for a rational face split in homogeneous coordinates (the caller projects).
    frames : (AxisFrame, AxisFrame)
        The intent's.
    scheme : Scheme
    combos : list of (int, int)

    Yields
    ------
    (pads, total, smooth) : ((int, int), (a, b, c) float, (a, b, c) float)
    """
    from ..numerics.tensor import sandwich
    from .bands import _one_piece
    from .fields import _poly_fit, above_half_cycle, measured_frames, split_degrees

    fu, fv = frames
    own = split_degrees(scheme)
    V, poly = _poly_fit(field, measured_frames(frames), own)
    trend = sandwich(V[0], poly, V[1])
    rest = field - trend
    one = _one_piece(fu, fv)
    passes = {}
    for c in dict.fromkeys(_effective(c, frames) for c in combos):
        wu, wv = measured_frames(frames, c)
        if c[0] not in passes:  # along u: the domain's columns above and below half a cycle per span
            high_u = above_half_cycle(rest, wu, 0, own[0], one[0])[0]
            passes[c[0]] = (high_u, rest - high_u)
        high_u, low_u = passes[c[0]]
        x2 = above_half_cycle(low_u, wv, 1, own[1], one[1])[0]  # along v: the low columns' part above it
        yield c, high_u + x2, low_u - x2 + trend


def _grid_term(f: np.ndarray, keep: np.ndarray) -> float:
    """``h^2 max |f''| / 8`` next to the peak of ``|f|`` on the kept samples (``h`` the grid step: the second
    differences are in grid steps already): how far the field can rise between the samples around its peak."""
    if not keep.any():
        return 0.0
    a = np.where(keep, np.abs(f), -np.inf)
    i, j = np.unravel_index(int(np.argmax(a)), a.shape)
    out = 0.0
    for axis, k in ((0, i), (1, j)):
        line = f[:, j] if axis == 0 else f[i, :]
        lo, hi = max(k - 2, 0), min(k + 3, len(line))
        seg = line[lo:hi]
        if seg.size >= 3:
            out = max(out, float(np.abs(np.diff(seg, 2)).max()) / 8.0)
    return out


def surface_uncertainty(net, settings, value: float | None = None, work=None, scalars=None, region=None):
    """The ``surface`` reading's expanded uncertainty ``U`` (model units) under its border convention.

    Parameters
    ----------
    net : ControlNet
    settings : RunSettings
        The run's; ``tolerance`` decides whether the variants are read (module docstring "Cost").
    value : float, optional
        Today's value under the convention (the budget's), when the caller has it.
    work : ControlNet, optional
        The analysis net, when the caller has it.
    scalars, region : dict, (a, b) bool, optional
        Today's budget's scalar fields and region (``keep_fields``): the grid term is read on them.

    Returns
    -------
    Uncertainty
        ``U = D + G`` (module docstring); a cage (no B-rep face: its continuation is its intent's, the
        ``net`` reading's) is not estimated (``estimated = False``).

    References
    ----------
    ISO 16610-28:2016, *Filtration - Part 28: Profile filters: End effects*; ISO 14253-1:2017.
    """
    from .uncertainty import COVERAGE_FACTOR, Uncertainty

    if not net.is_bspline:
        return Uncertainty.zero("surface")
    t = settings.tolerance
    if value is not None and t is not None:
        # the bound and the grid term of today's reading; where they decide, the variants would decide the same
        if scalars is not None and region is not None and np.shape(scalars["total"]) == np.shape(region):
            grid = _grid_term(scalars["total"], region)
        else:
            grid = variant_values(net, settings, pads=(), work=work)[3]
        bound = RELATIVE_BOUND * value + grid
        if value + bound <= t or value - bound > t:
            return Uncertainty(bound, bound, bound, "surface", COVERAGE_FACTOR)
    v0, both, alone, grid = variant_values(net, settings, work=work)
    D = max((abs(v - v0) for v in both), default=0.0)
    Du = max((abs(a - v0) for a, _ in alone), default=0.0)
    Dv = max((abs(b - v0) for _, b in alone), default=0.0)
    D = max(D, Du, Dv)
    return Uncertainty(D + grid, Du + grid, Dv + grid, "surface", COVERAGE_FACTOR)
