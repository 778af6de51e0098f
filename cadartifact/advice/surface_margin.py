"""The advised net's own uncertainty under the ``surface`` reading (SPEC §4 "The `surface` reading at borders", §5).

Under the ``surface`` reading a candidate's value is its distance from the intent, today's surface less its ripple
as the border convention reads it (:mod:`cadartifact.analysis.border_convention`). The convention leaves the
period open by a few lattice points (:data:`~cadartifact.analysis.border_convention.PERIOD_LATITUDE`), and under
each admitted period the intent field itself moves. Let ``F`` be the largest pointwise change of the intent
(model units, Euclidean) over the trimmed face between the convention's period and its variants (``T + 2``,
``T + 4`` per open direction, each direction alone and both, as the face's own ``U`` reads them), and ``G_F`` the
grid term of reading that change on samples ``1 / K`` span apart (``h^2 max |d''| / 8`` per direction, summed).
For any candidate surface ``S`` and intents ``I``, ``I'`` of two variants,

    ``| |S - I'| - |S - I| | <= |I' - I| <= F + G_F``

pointwise, hence for the peak and the RMS over any grid of the face: every candidate's value moves by at most
``U_c = F + G_F`` under the convention's latitude. ``U_c`` is the candidates' margin (a candidate conforms at
``value + U_c <= t``, ISO 14253-1) and the ``advised_uncertainty`` of the advice's record.

Along the intent's normal the normal itself tilts with the intent by ``|n' - n|`` (of order
``|grad (I' - I)| / |grad I|``); the value then also moves by up to that tilt times the candidate's tangential error,
a second-order term (about 1e-4 of the value on the retry family) that the bound leaves out and the tests measure
with the rest (tests/advice/test_surface_margin.py reads each variant's advised value by the measurement itself).

**Cost.** One band split per variant of the real surface (evaluated once per piece), at most seven per piece and
read only for a B-spline face of the ``surface`` reading with a ripple band, before the search (the margin enters
every candidate's value, and whether any net can conform at all).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CONSTRUCTION", "KEPT", "CandidateUncertainty", "candidate_uncertainty", "kept_uncertainty", "intent_change"]

#: How ``U_c`` is built, as the record names it.
CONSTRUCTION = "intent change over the border convention's period variants (F + G_F)"
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
        base = _intent_field(real, (fu, fv), (0, 0), sch)
        for c in combos:
            if (c[0] and fu.periodic) or (c[1] and fv.periodic):  # a periodic direction has no period latitude
                c = (0 if fu.periodic else c[0], 0 if fv.periodic else c[1])
                if c == (0, 0):
                    continue
            d = _intent_field(real, (fu, fv), c, sch) - base
            if keep.any():
                F = max(F, float(np.linalg.norm(d, axis=-1)[keep].max()))
                G = max(G, _grid_term(d, keep))
    return F, G


def _intent_field(real: np.ndarray, frames, pads, scheme) -> np.ndarray:
    """The intent (the smooth part, Cartesian) on the fine grid under the convention with ``pads`` added."""
    from ..analysis.fields import _bridged_bands, measured_frames

    _, smooth, _ = _bridged_bands(real, measured_frames(frames, pads), scheme, lateral=False)
    return smooth[..., :3] / smooth[..., 3:4] if smooth.shape[-1] == 4 else smooth


def _grid_term(d: np.ndarray, keep: np.ndarray) -> float:
    """``sum_axes max ||second difference of d|| / 8`` over the kept samples (``h`` the grid step: the
    differences are in grid steps already): how far ``|d|`` can rise between samples of the fine grid."""
    out = 0.0
    for axis in (0, 1):
        if d.shape[axis] < 3:
            continue
        dd = np.linalg.norm(np.diff(d, 2, axis=axis), axis=-1)
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
