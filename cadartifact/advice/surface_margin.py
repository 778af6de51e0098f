"""The advised net's own uncertainty under the ``surface`` reading (SPEC §4 "The `surface` reading at borders", §5).

Under the ``surface`` reading a candidate's value is its distance from the intent, today's surface less its ripple
as the border convention reads it (:mod:`cadartifact.analysis.border_convention`). The convention leaves the
period open by a few lattice points (:data:`~cadartifact.analysis.border_convention.PERIOD_LATITUDE`), and under
each admitted period the intent field itself moves. Let ``F`` be the largest pointwise change of the intent
(model units, Euclidean) over the trimmed face between the convention's period and its variants (``T + m``,
``T + 2 m`` per open direction, ``m = 2`` where the cut is half a cycle per span, each direction alone and both,
as the face's own ``U`` reads them), and ``G_F`` the grid term of reading that change on samples ``1 / K`` span
apart (``h^2 max |d''| / 8`` per direction, summed).
For any candidate surface ``S`` and intents ``I``, ``I'`` of two variants,

    ``| |S - I'| - |S - I| | <= |I' - I| <= F + G_F``

pointwise, hence for the peak and the RMS over any grid of the face: every candidate's value moves by at most
``U_c = F + G_F`` under the convention's latitude. ``U_c`` is the candidates' margin (a candidate conforms at
``value + U_c <= t``, ISO 14253-1) and the ``advised_uncertainty`` of the advice's record.

Along the intent's normal the normal itself tilts with the intent by ``|n' - n|`` (of order
``|grad (I' - I)| / |grad I|``); the value then also moves by up to that tilt times the candidate's tangential error,
a second-order term (about 1e-4 of the value on the retry family) that the bound leaves out and the tests measure
with the rest (tests/advice/test_surface_margin.py reads each variant's advised value by the measurement itself).

**Cost.** The variants' intents share their ``u`` passes (:func:`_intent_fields`): on the 100x100 face of
``benchmarks/bench_advise.py`` about 1.1 s, as much as the rest of its advice. So they are read only where a
decision depends on them (:class:`LazyMargin`). First the triangle inequality: the intent is the surface less its ripple ``r``, so
``|I' - I| = |r' - r| <= |r'| + |r|``, and with the variants' ripple no larger than ``(1 + RELATIVE_BOUND)``
today's (what the face's own ``U`` assumes, :data:`~cadartifact.analysis.border_convention.RELATIVE_BOUND`),
``U_c <= B = (2 + RELATIVE_BOUND) (max |r| + G_r)`` (``G_r`` today's ripple's grid term). A candidate with
``value > t`` fails and one with ``value + B <= t`` conforms whatever ``U_c`` is; ``F`` is read the first time a
candidate lies between, or where ``B`` alone would leave no net verifiable. Measured (2026-12-06) on the retry
family, 40 border-free faces and 8 rational faces: ``(F + G_F) / B`` median 0.005, max 0.20 (``F / max |r|`` at
most 0.43): ``B`` is wide, so it decides only faces whose ripple is well within the tolerance (most faces of a
real file), and a claim decided by it reports ``U = B``. ``B`` is a bound under the assumption it shares with the
face's own ``U`` (the variants' ripple within ``1 + RELATIVE_BOUND`` of today's, which holds on 97.5 % of the
border-free family, worst 1.31; for a rational face ``|I' - I| = |r' - r|`` to first order), not unconditionally:
its measured width (``U_c`` at most 0.2 ``B``) is what makes a claim it decides safe.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CONSTRUCTION", "BOUND", "KEPT", "CandidateUncertainty", "LazyMargin", "candidate_uncertainty",
           "kept_uncertainty", "intent_change", "ripple_bound"]

#: How ``U_c`` is built, as the record names it.
CONSTRUCTION = "intent change over the border convention's period variants (F + G_F)"
#: The construction named when the triangle bound ``B`` decided the claim (module docstring, "Cost").
BOUND = "bound: (2 + RELATIVE_BOUND) x today's ripple peak and its grid term (the variants not read)"
#: The construction named when today's net is kept: its claim is today's decision, under the face's own ``U``.
KEPT = "today's net kept: the face's own U under the border convention"


@dataclass(frozen=True)
class CandidateUncertainty:
    """The expanded uncertainty a claim on the advised net used (model units).

    Attributes
    ----------
    peak : float
        ``U_c = F + G_F``.
    reading : str
        ``"surface"``.
    factor : float
        The coverage factor reported with it (the face's ``U``'s: both are half-widths of admitted intervals).
    estimated : bool
        False where no estimate exists (a cage: its continuation is its intent's), ``U_c`` 0.
    construction : str
        :data:`CONSTRUCTION`.
    change, grid : float
        ``F`` and ``G_F``.
    """

    peak: float
    reading: str
    factor: float
    estimated: bool
    construction: str
    change: float = 0.0
    grid: float = 0.0

    def to_dict(self) -> dict:
        """``{"peak", "reading", "coverage_factor", "estimated", "construction"}``."""
        return {"peak": float(self.peak), "reading": self.reading, "coverage_factor": float(self.factor),
                "estimated": bool(self.estimated), "construction": self.construction}


def intent_change(net, settings, work=None, pads=None) -> tuple[float, float]:
    """``(F, G_F)``: the largest pointwise change of the ``surface`` reading's intent over the trimmed face
    across the border convention's period variants, and its grid term.

    Parameters
    ----------
    net : ControlNet
        A B-rep face (``is_bspline``).
    settings : RunSettings
        The run's (``scheme``, ``levels``).
    work : ControlNet, optional
        The analysis net when the caller has it.
    pads : tuple of int, optional
        Default :data:`~cadartifact.analysis.border_convention.PERIOD_LATITUDE`.

    Returns
    -------
    (float, float)
        Model units; ``(0, 0)`` for a face whose pieces carry no ripple band.
    """
    from ..analysis.border_convention import PERIOD_LATITUDE, _pieces
    from ..analysis.budget import analysis_net, trim_mask
    from ..analysis.fields import split_coordinates
    from ..analysis.intent import design_intent
    from ..analysis.measure import real_surface
    from ..analysis.settings import resolve_scheme

    pads = PERIOD_LATITUDE if pads is None else pads
    sch = resolve_scheme(net, settings.scheme)
    work = work if work is not None else analysis_net(net, sch, settings.tolerance)
    combos = [(j, j) for j in pads] + [c for j in pads for c in ((j, 0), (0, j))]
    F = G = 0.0
    for piece in _pieces(work):
        it = design_intent(piece, sch, settings.levels)
        fu, fv = it.frames
        if fu.ripple_free and fv.ripple_free:  # the surface is its own intent under any continuation
            continue
        real = split_coordinates(real_surface(it, sch), it.frames)  # as the road splits it
        keep = trim_mask(piece, it.frames, fu.x, fv.x)  # the scorer's mask (the trimmed face, borders included)
        if not keep.any():
            continue
        base = None
        for c, smooth in _intent_fields(real, (fu, fv), sch, [(0, 0)] + combos):
            if base is None:
                base = smooth
                continue
            d = smooth - base
            F = max(F, float(np.sqrt(np.einsum("abk,abk->ab", d, d))[keep].max()))
            G = max(G, _grid_term(d, keep))
    return F, G


def _intent_fields(real: np.ndarray, frames, scheme, combos):
    """``(pads, intent)`` per period variant, first ``combos[0]``: the smooth part (Cartesian, on the fine grid) of
    the measured road's split with its periods padded by ``pads``
    (:func:`cadartifact.analysis.border_convention.period_variants`: each ``u`` pass made once per ``u`` pad)."""
    from ..analysis.border_convention import period_variants

    for c, _, smooth in period_variants(real, frames, scheme, combos):
        yield c, smooth[..., :3] / smooth[..., 3:4] if smooth.shape[-1] == 4 else smooth


def _grid_term(d: np.ndarray, keep: np.ndarray) -> float:
    """``sum_axes max ||second difference of d|| / 8`` over the kept samples (``h`` the grid step: the
    differences are in grid steps already): how far ``|d|`` can rise between samples of the fine grid."""
    out = 0.0
    for axis in (0, 1):
        if d.shape[axis] < 3:
            continue
        dd = np.diff(d, 2, axis=axis)
        dd = np.sqrt(np.einsum("abk,abk->ab", dd, dd))
        k = keep[1:-1, :] if axis == 0 else keep[:, 1:-1]
        if k.any():
            out += float(dd[k].max()) / 8.0
    return out


def candidate_uncertainty(net, settings, work=None) -> CandidateUncertainty:
    """``U_c`` of every candidate of a density search under the ``surface`` reading (module docstring).

    Parameters
    ----------
    net : ControlNet
    settings : RunSettings
        The run's (``intent`` must be ``"surface"``).
    work : ControlNet, optional
        The analysis net when the caller has it.

    Returns
    -------
    CandidateUncertainty
        Not estimated (``U_c = 0``) for a cage, as the face's own ``U`` of this reading.
    """
    from ..analysis.uncertainty import COVERAGE_FACTOR

    if not net.is_bspline:
        return CandidateUncertainty(0.0, "surface", 0.0, False, CONSTRUCTION)
    F, G = intent_change(net, settings, work)
    return CandidateUncertainty(F + G, "surface", COVERAGE_FACTOR, True, CONSTRUCTION, F, G)


def kept_uncertainty(unc) -> CandidateUncertainty:
    """The ``U`` of a claim on today's net kept as the advice: the face's own
    (:func:`~cadartifact.analysis.border_convention.surface_uncertainty`), which decided it."""
    return CandidateUncertainty(float(unc.peak), unc.reading, float(unc.factor), bool(unc.estimated), KEPT)


def ripple_bound(fields) -> float:
    """``B = (2 + RELATIVE_BOUND) (max |r| + G_r)`` of today's fields (module docstring, "Cost"): ``r`` the total
    ripple band over the whole fine grid (a superset of the trimmed face), Euclidean."""
    from ..analysis.border_convention import RELATIVE_BOUND

    r = np.asarray(fields.bands["total"], float)
    if not r.size:
        return 0.0
    peak = float(np.linalg.norm(r, axis=-1).max())
    return (2.0 + RELATIVE_BOUND) * (peak + _grid_term(r, np.ones(r.shape[:2], bool)))


class LazyMargin:
    """``U_c`` read only where a decision depends on it (module docstring, "Cost").

    Parameters
    ----------
    net, settings, work
        As :func:`candidate_uncertainty`.
    fields : ArtifactFields
        Today's budget's (the ``surface`` reading's total ripple band).
    tolerance : float
    """

    def __init__(self, net, settings, work, fields, tolerance: float):
        self._args, self.t = (net, settings, work), float(tolerance)
        self.bound = ripple_bound(fields) if net.is_bspline else 0.0
        self._exact = None if net.is_bspline else candidate_uncertainty(net, settings, work)
        self._settled = None

    @property
    def known(self) -> bool:
        """Whether ``F`` has been read."""
        return self._exact is not None

    def exact(self) -> float:
        """``U_c`` (reads the variants once), unless :meth:`settle` fixed the margin already."""
        if self._settled is not None:
            return self._settled
        if self._exact is None:
            self._exact = candidate_uncertainty(*self._args)
        return self._exact.peak

    def margin(self, value: float) -> float:
        """The margin that decides ``value`` against the tolerance as ``U_c`` would: ``B`` where that decides."""
        if self._settled is not None:
            return self._settled
        if self._exact is not None:
            return self._exact.peak
        return self.bound if value > self.t or value + self.bound <= self.t else self.exact()

    def settle(self) -> float:
        """Fix the margin from here on (the claim's ``U``): ``U_c`` when read, else ``B``."""
        if self._settled is None:
            self._settled = self._exact.peak if self._exact is not None else self.bound
        return self._settled

    def record(self) -> CandidateUncertainty:
        """What the claim used: ``U_c`` when read, else ``B``."""
        if self._exact is not None:
            return self._exact
        from ..analysis.uncertainty import COVERAGE_FACTOR

        return CandidateUncertainty(self.bound, "surface", COVERAGE_FACTOR, True, BOUND)
