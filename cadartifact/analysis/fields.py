"""Artifact fields of a control net: its surface minus its intent, split by frequency (SPEC §4).

On a grid ``K = 2**levels`` times finer than the net, the deviation of the surface from the
intent of the ``net`` reading (:mod:`cadartifact.analysis.intent`) is split by frequency in cycles per
control point into

* base band ``|fx|, |fy| < 1/2`` -> signal error (attenuation),
* ``|fx| >= 1/2`` only -> X1 ripple, ``|fy| >= 1/2`` only -> X2 ripple, both -> diagonal ripple,
* lateral: each ripple component weighted by the lateral factor of the frequency it aliases
  (SPEC §3).

The ``surface`` reading (the default for CAD work) takes the surface less its ripple as the
intent: the same ripple fields, no signal error.

Two independent roads produce the surface:

* *predicted*: the residual's lattice spectrum (one period ``T`` of the smoothly extended
  intent) times the scheme's transfer function to the fine grid, ``Scheme.transfer``: exact, no
  alias truncation; the trend goes through the limit stencil (a polynomial of the same degree);
* *measured*: the real surface (:mod:`cadartifact.analysis.measure`: exact NURBS evaluation of the face,
  a uniform B-spline, or numerical subdivision). Outside the net's domain the predicted deviation
  continues it, plus the measured-minus-predicted difference mirrored evenly at each border (so
  the split sees no jump): equal to the predicted road where the real surface is the uniform one.

References
----------
P. J. Augsdörfer, N. A. Dodgson, M. A. Sabin, *Artifact analysis on B-splines, box-splines and
other surfaces defined by quadrilateral polyhedra*, CAGD 2011.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..errors import check_option
from .frames import AxisFrame, index_space_cut
from .bands import _baseband, _fine_freqs, _one_piece, baseband_bins, band_split, lateral_factors, lateral_of
from .baseband import baseband_at
from .clamped import clamped_syntheses
from .settings import COMPONENTS, READINGS
from .intent import Intent, _legendre, design_intent, from_homogeneous
from ..numerics.hermite import end_derivatives, gap_basis, hermite_to_bezier
from ..numerics.operator_cache import OperatorCache
from ..numerics.tensor import sandwich

__all__ = ["ArtifactFields", "FIELD_NAMES", "COMPONENTS", "design_intent", "predicted_fields", "measured_fields",
           "artifact_fields", "split_coordinates", "band_split", "lateral_factors", "project", "intent_normals",
           "trend_image_coef", "baseband_at"]

#: The fields a budget reports, in report order.
FIELD_NAMES = ("x1", "x2", "diagonal", "lateral", "total", "signal_error")


@dataclass(frozen=True, eq=False)
class ArtifactFields:
    """Surface, intent and band-split deviation fields on the fine grid.

    Attributes
    ----------
    x : (a,) float, y : (b,) float
        Analysis coordinates of the fine grid (span units).
    surface, intent : (a, b, 3) float
        The surface and the intent of the fields' reading.
    bands : dict str -> (a, b, 3) float
        ``signal_error``, ``x1``, ``x2``, ``diagonal``, ``lateral``, ``total`` (= x1 + x2 + diagonal).
    method : str
        ``"predicted"`` or ``"measured"``.
    reading : str
        ``"surface"`` or ``"net"``.
    baseband : dict or None
        ``surface`` reading: the signal error's base-band bins and polynomial part, so that the
        intent can be evaluated anywhere (:func:`baseband_at`).
    """

    x: np.ndarray
    y: np.ndarray
    surface: np.ndarray
    intent: np.ndarray
    bands: dict = field(default_factory=dict)
    method: str = "predicted"
    levels: int = 3
    reading: str = "surface"
    baseband: object = None


def _coef_matrix(intent: Intent, coef: np.ndarray) -> np.ndarray:
    """Trend-term coefficients ``(terms, 3)`` as a tensor Legendre array ``(du+1, dv+1, 3)``."""
    du = max(t[0] for t in intent.terms)
    dv = max(t[1] for t in intent.terms)
    M = np.zeros((du + 1, dv + 1, coef.shape[-1]))
    for k, (a, b) in enumerate(intent.terms):
        M[a, b] = coef[k]
    return M


# ---------------------------------------------------------------- the trend through the scheme
def trend_image_coef(intent: Intent, scheme) -> np.ndarray:
    """Coefficients (same Legendre terms) of the scheme's limit surface of the intent's trend.

    The limit of a net sampling a polynomial of degree <= the scheme's reproduction degree is a
    polynomial of the same degree; at the lattice points it is the limit stencil applied to the
    polynomial's lattice samples, which determine it.
    """
    L = np.asarray(scheme.limit_stencil, float)
    if not intent.terms or intent.terms == [(0, 0)] or L.shape[0] % 2 == 0 or L.shape[1] % 2 == 0:
        return intent.coef.copy()
    fu, fv = intent.frames
    ru, rv = L.shape[0] // 2, L.shape[1] // 2
    mu = max(fu.spans + 1, max(t[0] for t in intent.terms) + 2)
    mv = max(fv.spans + 1, max(t[1] for t in intent.terms) + 2)
    xs = np.arange(-ru, mu + ru) + fu.offset
    ys = np.arange(-rv, mv + rv) + fv.offset
    padded = intent.trend(xs, ys)
    lim = np.zeros((mu, mv, padded.shape[-1]))
    for a in range(L.shape[0]):
        for b in range(L.shape[1]):
            if L[a, b] != 0.0:
                lim += L[a, b] * padded[2 * ru - a: 2 * ru - a + mu, 2 * rv - b: 2 * rv - b + mv]
    from numpy.polynomial import legendre as Lg

    Vx = Lg.legvander(2 * (np.arange(mu) + fu.offset) / fu.spans - 1, max(t[0] for t in intent.terms))
    Vy = Lg.legvander(2 * (np.arange(mv) + fv.offset) / fv.spans - 1, max(t[1] for t in intent.terms))
    A = np.stack([Vx[:, a][:, None] * Vy[:, b][None, :] for a, b in intent.terms], axis=-1).reshape(mu * mv, -1)
    coef, *_ = np.linalg.lstsq(A, lim.reshape(mu * mv, -1), rcond=None)
    return coef


# ---------------------------------------------------------------- the two roads
def _fine_spectrum(intent: Intent) -> np.ndarray:
    """The lattice spectrum repeated to the fine grid's half spectrum, scaled by ``K^2``."""
    fu, fv = intent.frames
    pu, pv = intent.spectrum.shape[:2]
    B = fv.K * pv
    rows = np.arange(fu.K * pu) % pu
    cols = np.arange(B // 2 + 1) % pv
    return intent.spectrum[np.ix_(rows, cols)] * (fu.K * fv.K)


def predicted_fields(intent: Intent, scheme, reading: str = "net", lateral: bool = True) -> ArtifactFields:
    """Artifact fields from the scheme's spectral response (the *predicted* road).

    Fine spectrum of the residual's limit surface: ``S(xi) = K^2 T_L(xi) R(xi mod 1)``, ``T_L`` the
    scheme's transfer to the ``K = 2^L`` grid (SPEC §4), ``R`` the lattice spectrum of the residual's
    intent; the trend's limit is a polynomial (:func:`trend_image_coef`). Ripple: the limit's bins
    above 1/2; the surface less its ripple: the base band plus the trend's limit.

    Parameters
    ----------
    intent : Intent
    scheme : Scheme
    reading : {"net", "surface"}
    lateral : bool
        Also the lateral field (one more pair of FFTs); False leaves ``bands["lateral"]`` out, for
        callers that need the other bands only (the scheme comparison's predicate).

    Returns
    -------
    ArtifactFields
    """
    synth = clamped_syntheses(intent, scheme)  # a rational face's clamped directions (issue 23 item 5)
    if synth is not None:
        return _predicted_separable(intent, scheme, reading, lateral, synth)
    if getattr(scheme, "tensor", False) and not any(getattr(scheme, "dual", (False, False))):
        return _predicted_separable(intent, scheme, reading, lateral)
    fu, fv = intent.frames
    B = fv.K * fv.period
    h = B // 2 + 1
    T = np.asarray(scheme.transfer(_fine_freqs(fu)[:, None], np.abs(_fine_freqs(fv)[:h])[None, :], fu.levels))
    limit_spec = _fine_spectrum(intent) * T[:, :, None]
    poly = _coef_matrix(intent, trend_image_coef(intent, scheme))
    return _finish(intent, limit_spec, poly, None, "predicted", reading, lateral)


#: One direction's synthesis operators per (direction intent, levels, period, scheme, axis): the scheme
#: comparison builds hundreds of cages of a few sizes per face.
_SYNTHESES = OperatorCache(256)


def _axis_synthesis(intent: Intent, scheme, axis: int):
    """One direction of a tensor scheme's limit surface: ``(low, high, low_at)`` (cached; read-only).

    ``low``, ``high`` : ``(fine, n)`` samples -> the base band / the ripple band of the limit along this
    direction on the fine grid; ``low_at(x)`` the base band anywhere. The direction's polynomial goes
    through the 1-D limit stencil (a polynomial of the same degree, base band); the rest through the
    lattice spectrum of its Fourier extension times the scheme's 1-D transfer function. They depend on
    the direction's geometry and the scheme only, never on the points.
    """
    frame, ax = intent.frames[axis], intent.axes[axis]
    key = (ax, frame.levels, frame.period, frame.shift, frame.fine_count, scheme, axis)
    return _SYNTHESES.get(key, lambda: _build_axis_synthesis(frame, ax, scheme, axis))


def _build_axis_synthesis(frame: AxisFrame, ax, scheme, axis: int):
    K, T, n = frame.K, frame.period, frame.n
    d = ax.degree
    st = np.asarray(scheme.limit_stencil, float).sum(axis=1 - axis)
    if d == 0 or len(st) % 2 == 0:
        lam = np.eye(d + 1)
    else:
        r = len(st) // 2
        M = max(n, d + 2)
        J = np.arange(M) + frame.offset
        pad = _legendre(np.arange(-r, M + r) + frame.offset, frame.spans, d)
        lim = np.stack([np.convolve(pad[:, k], st, mode="valid") for k in range(d + 1)], axis=1)
        lam = np.linalg.pinv(_legendre(J, frame.spans, d)) @ lim
    poly = lambda x: _legendre(x, frame.spans, d) @ lam @ ax.Vp  # noqa: E731
    X = np.fft.fft(ax.lattice() @ ax.rest, axis=0)  # (T, n)
    xi = _fine_freqs(frame)
    zeros = np.zeros_like(xi)
    T1 = np.asarray(scheme.transfer(xi, zeros, frame.levels) if axis == 0 else scheme.transfer(zeros, xi, frame.levels),
                    float)
    spec = np.tile(X, (K, 1)) * (K * T1)[:, None]
    low_bins = np.abs(xi) < 0.5 - 1e-12
    idx = (frame.shift + np.arange(frame.fine_count)) % (K * T)
    low = np.fft.ifft(spec * low_bins[:, None], axis=0).real[idx]
    high = np.fft.ifft(spec * ~low_bins[:, None], axis=0).real[idx]
    Xl, fl = spec[low_bins], xi[low_bins]

    def low_at(x):
        z = np.asarray(x, float) + frame.shift / K
        ph = 2 * np.pi * np.outer(z, fl)
        return poly(x) + (np.cos(ph) @ Xl.real - np.sin(ph) @ Xl.imag) / (K * T)

    low = poly(frame.x) + low
    low.flags.writeable = high.flags.writeable = False  # shared by every net of this size
    return low, high, low_at


def _predicted_separable(intent: Intent, scheme, reading: str, lateral: bool = True,
                         synth: tuple | None = None) -> ArtifactFields:
    """:func:`predicted_fields` of a tensor scheme, direction by direction (each reproduces its polynomials).

    ``synth``: per direction ``(low, high, low_at)`` to use instead of :func:`_axis_synthesis` (None: that one),
    as :func:`cadartifact.analysis.clamped.clamped_syntheses` gives for a rational face's clamped directions.
    """
    fu, fv = intent.frames
    synth = synth or (None, None)
    (Lu, Hu, lu), (Lv, Hv, lv) = (synth[k] or _axis_synthesis(intent, scheme, k) for k in (0, 1))
    P = intent.lifted_points
    smooth = sandwich(Lu, P, Lv)
    bands = {"x1": sandwich(Hu, P, Lv), "x2": sandwich(Lu, P, Hv), "diagonal": sandwich(Hu, P, Hv)}
    bands["total"] = bands["x1"] + bands["x2"] + bands["diagonal"]
    if lateral:
        bands["lateral"] = lateral_of(bands["total"], fu, fv, (P, (Hu, Lv + Hv), (Lu, Hv)))
    return _assemble(intent, bands, smooth, smooth + bands["total"], "predicted", reading,
                     {"separable": (lu, lv), "points": P})


#: The measured road's period before its border convention had a fixed gap, in multiples of the spans (kept for
#: the benchmarks that compare with it; the measured road reads :data:`MEASURED_GAP`).
MEASURED_EXTENSION = 3

#: The measured road's continuation past the open borders, in spans: one period is the domain plus this gap, with
#: a lattice bin exactly at the cut (:attr:`~.frames.AxisFrame.alignment`). A fixed gap keeps the reading within a
#: few per cent when the period grows by a few lattice points, where a gap of twice the face moved it by up to half
#: of itself (the `surface` reading's border convention: docs/model.md, analysis.border_convention).
MEASURED_GAP = 32


def measured_fields(intent: Intent, scheme, reading: str = "net", lateral: bool = True) -> ArtifactFields:
    """Artifact fields of the real surface (the *measured* road).

    The real surface (:func:`cadartifact.analysis.measure.real_surface`: exact NURBS evaluation of a face,
    numerical subdivision or the uniform B-spline of a cage) less a polynomial fit is continued past
    each open border by a Hermite bridge (:func:`_bridge`: value and five derivatives continuous,
    exact for a B-spline's end span) and band-split by FFT (:func:`_bridged_bands`).
    The net's points never enter the split, so how they sit near a clamped border cannot leak into
    the ripple; periodic directions wrap, and there the road equals the predicted one to rounding.
    """
    from .measure import measurement_road, real_surface

    fu, fv = intent.frames
    real = real_surface(intent, scheme)
    if fu.ripple_free and fv.ripple_free and measurement_road(intent.net, scheme)[0] == "face":
        # nothing along either direction can alias (canonical, Bezier or degree-1 both ways): no ripple at all,
        # the surface is its own intent (no split needed)
        return _assemble(intent, {k: np.zeros_like(real) for k in ("x1", "x2", "diagonal", "lateral", "total")},
                         real, real, "measured", reading, {"evaluate": _surface_of(intent)})
    real = split_coordinates(real, intent.frames)
    wide = measured_frames(intent.frames)
    bands, smooth, baseband = _bridged_bands(real, wide, scheme, lateral)
    return _assemble(intent, bands, smooth, real, "measured", reading, baseband)


def measured_frames(frames, pads=(0, 0)) -> tuple:
    """The measured road's frames: cut as :data:`SPLIT_CUT` says, each open direction's period the domain plus
    :data:`MEASURED_GAP` spans (a bin at the cut: :attr:`~.frames.AxisFrame.alignment`), lengthened by ``pads``."""
    cut = index_space_cut if SPLIT_CUT == "index" else (lambda f: 0.5)
    return tuple(dataclasses.replace(f, gap=MEASURED_GAP, pad=p, cut=cut(f)) for f, p in zip(frames, pads))


#: Where the measured road cuts an open direction: ``"span"``, half a cycle per span, or ``"index"``, half a cycle
#: per control point counted in index space (:func:`cadartifact.analysis.frames.index_space_cut`), measured and
#: not adopted: it breaks the advice's fixed point (docs/model.md, "Where the split cuts").
SPLIT_CUT = "span"

#: How the measured road splits a rational face with an open direction: ``"homogeneous"`` (the non-rational
#: B-spline of ``(w P, w)``, each band projected to first order, SPEC §4) or ``"cartesian"`` (the surface as it
#: stands, like a non-rational face). Measured both ways on faces cut from longer ones (docs/model.md, "Rational
#: faces"): the Cartesian split is more local but not as local as a non-rational face's, and reads short faces
#: with strongly varying weights up to 3x more; the homogeneous split stays.
RATIONAL_SPLIT = "homogeneous"


def split_coordinates(real: np.ndarray, frames, rational_split: str | None = None) -> np.ndarray:
    """The field the measured road splits.

    Parameters
    ----------
    real : (a, b, 3) or (a, b, 4) float
        The real surface on the fine grid; 4 components: homogeneous ``(w S, w)``.
    frames : (AxisFrame, AxisFrame)
    rational_split : {"homogeneous", "cartesian"}, optional
        Default :data:`RATIONAL_SPLIT`.

    Returns
    -------
    (a, b, 3) or (a, b, 4) float
        ``S = H_xyz / H_w`` for ``"cartesian"`` when ``real`` is homogeneous and a direction is open; ``real``
        otherwise (both directions periodic: no border, the homogeneous split is the uniform theory's exactly).

    Notes
    -----
    The band split's high-pass kernel decays like ``1/d`` with the distance ``d``. Split in homogeneous
    coordinates and projected to first order, ``dS = (dH_xyz - S dH_w) / H_w``, a rational face's ripple holds
    the commutator ``L(w S) - S L(w)`` (``L`` the split), whose kernel is ``(S(y) - S(x)) k(x - y)``: about ``d``
    times the split's, so it does not decay, and a border's continuation reaches across the whole face.
    """
    how = RATIONAL_SPLIT if rational_split is None else rational_split
    check_option("rational_split", how, ("homogeneous", "cartesian"))
    fu, fv = frames
    if how == "cartesian" and real.shape[-1] == 4 and not (fu.periodic and fv.periodic):
        return from_homogeneous(real)
    return real


def _surface_of(intent: Intent):
    """The face's own surface at analysis coordinates (the intent of a face with no ripple band)."""
    from ..numerics.splines import evaluate

    fu, fv = intent.frames

    def at(x, y):
        return from_homogeneous(evaluate(intent.net, fu.param(x), fv.param(y), points=intent.lifted_points,
                                         homogeneous=intent.homogeneous))

    return at


def split_degrees(scheme) -> tuple[int, int]:
    """The degrees the measured road's split takes per direction (its trend's least degree and the bridge's
    derivative fit): the scheme's B-spline degrees, else its reproduction degree both ways."""
    return tuple(scheme.degrees or (int(scheme.reproduction_degree),) * 2)


def _bridged_bands(field: np.ndarray, frames, scheme, lateral: bool = True) -> tuple[dict, np.ndarray, dict]:
    """Bands of a field on the domain, split after a polynomial fit and a smooth periodic bridge.

    A tensor Legendre polynomial (:func:`_poly_fit`) is fitted and kept out of the split; the rest is
    continued past each open border by :func:`_bridge` and band-split by FFT.

    The bridge, the band masks and the crop to the domain are each a tensor product of one operator per
    direction, so the split is done one direction at a time: along ``u`` on the bridged columns, keeping
    the domain's rows, then along ``v`` on those rows only. The numbers are those of one 2-D transform of
    the bridged period (to rounding); the work is about a third, and no ``K Tu x K Tv`` array is made.

    Returns
    -------
    (bands, smooth, baseband) : (dict, (a, b, 3) float, dict)
        The ripple bands (``signal_error`` zero), the smooth part (base band plus polynomial), and
        the smooth part in the form :func:`baseband_at` evaluates anywhere.
    """
    fu, fv = frames
    own = split_degrees(scheme)
    V, poly = _poly_fit(field, frames, own)
    rest = field - sandwich(V[0], poly, V[1])
    one = _one_piece(fu, fv)
    # along u: the bridged period's half spectrum per column (x = 0 at fine index `shift`), kept for the base band
    hi_u, Su = above_half_cycle(rest, fu, 0, own[0], one[0], spectrum=True)
    lo_u = rest - hi_u

    def v_high(X: np.ndarray) -> np.ndarray:
        """The part of domain rows above half a cycle per span along ``v`` (bridged the same way)."""
        return above_half_cycle(X, fv, 1, own[1], one[1])[0]

    diagonal, x2 = v_high(hi_u), v_high(lo_u)
    bands = {"x1": hi_u - diagonal, "x2": x2, "diagonal": diagonal}
    bands["total"] = bands["x1"] + bands["x2"] + bands["diagonal"]
    # the lateral weights are not a band: they would weigh what the continuation leaves far outside the
    # face; weigh the face's own ripple instead, extended by even reflection (it has no smooth part)
    if lateral:
        bands["lateral"] = lateral_of(bands["total"], fu, fv)
    smooth = (lo_u - x2) + sandwich(V[0], poly, V[1])
    bands["signal_error"] = np.zeros_like(smooth)
    return bands, smooth, _baseband_of_rows(Su, fu, fv, own[1], poly)


def above_half_cycle(X: np.ndarray, frame: AxisFrame, axis: int, degree: int, one_piece: bool,
                     spectrum: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """One direction's pass of the measured road's split: the part of a domain field above half a cycle per span.

    Parameters
    ----------
    X : (a, b, c) float
        Samples on the domain's fine grid.
    frame : AxisFrame
        The direction's (its period, bridged by :func:`_bridge` past an open border).
    axis : {0, 1}
    degree : int
        The direction's degree (the bridge's derivative fit).
    one_piece : bool
        The direction is one polynomial piece: nothing is above (:func:`cadartifact.analysis.bands._one_piece`).
    spectrum : bool
        Return the bridged period's half spectrum along ``axis`` even where nothing is above.

    Returns
    -------
    (high, S) : ((a, b, c) float, complex array or None)
        ``high`` the part above half a cycle per span on the domain (zeros where the mask is empty); ``S`` the
        half spectrum (x = 0 at fine index ``frame.shift``), None where neither it nor ``high`` needed it.
    """
    E = np.roll(_bridge(X, frame, axis, degree), frame.shift, axis=axis)
    N = E.shape[axis]
    mask = (np.fft.rfftfreq(N, d=1.0 / frame.K) >= frame.cut - 1e-12) & (not one_piece)
    S = np.fft.rfft(E, axis=axis) if spectrum or mask.any() else None
    if not mask.any():
        return np.zeros_like(X), S
    index = (frame.shift + np.arange(frame.fine_count)) % N
    along = mask[:, None, None] if axis == 0 else mask[None, :, None]
    return np.take(np.fft.irfft(S * along, n=N, axis=axis), index, axis=axis), S


def _baseband_of_rows(Su: np.ndarray, fu: AxisFrame, fv: AxisFrame, degree_v: int, poly: np.ndarray) -> dict:
    """:func:`_baseband` from the ``u`` half spectrum of the ``u``-bridged columns: the base-band rows
    (full spectrum, ``X[-k] = conj(X[k])`` for real columns), bridged and transformed along ``v``."""
    A = fu.K * fu.period
    (ku, kv), freqs = baseband_bins(fu, fv)
    direct = ku <= A // 2
    rows = np.empty((len(ku),) + Su.shape[1:], complex)
    rows[direct] = Su[ku[direct]]
    rows[~direct] = np.conj(Su[(A - ku[~direct]) % A])
    Ev = np.roll(_bridge(rows, fv, 1, degree_v), fv.shift, axis=1)
    spec = np.fft.fft(Ev, axis=1)[:, kv]
    return {"spec": spec, "freqs": freqs, "frames": (fu, fv), "poly": poly}


def _poly_fit(field: np.ndarray, frames, degrees) -> tuple[list, np.ndarray]:
    """Least-squares tensor Legendre fit of a fine-grid field: ``(V, coefficients)``.

    Degree per open direction: the scheme's (polynomials it reproduces are intent by definition),
    or up to half the spans (at most 6: well below 1/2 cycle per span); 0 when periodic.
    """
    degrees = degrees or (3, 3)
    degs = [0 if f.periodic else int(min(f.n - 1, max(d, min(f.spans // 2, 6)))) for f, d in zip(frames, degrees)]
    V = [_legendre(f.x, f.spans, d) for f, d in zip(frames, degs)]
    return V, sandwich(np.linalg.pinv(V[0]), field, np.linalg.pinv(V[1]))


#: Derivatives the measured road's bridge matches at each open border (value and 1..BRIDGE_ORDER): a
#: Hermite polynomial of degree ``2 BRIDGE_ORDER + 1``. Five keeps a smooth shape's fourth and fifth
#: derivatives across the border, where a third-order bridge leaked a short net's curvature into the ripple
#: band; four reads less on short faces but lets a knot insertion raise a 2-span face's lateral ripple
#: (issue 23 item 5, docs/model.md).
BRIDGE_ORDER = 5


def _bridge(a: np.ndarray, frame: AxisFrame, axis: int, degree: int = 3) -> np.ndarray:
    """A domain field extended to one period: wrapped (periodic), or bridged across the gap from its
    end back to its start by a Hermite polynomial of degree ``2 M + 1`` (``M =`` :data:`BRIDGE_ORDER`)
    matching value and first ``M`` derivatives at both borders, evaluated in Bezier form
    (:func:`cadartifact.numerics.hermite.hermite_to_bezier`).

    The derivatives come from a least-squares polynomial of degree ``min(max(degree + 1, M), K, 7)``
    over the first (last) span's ``K + 1`` samples: exact for a B-spline face of degree up to 6 (at the
    default ``K = 8``), whose end span is one polynomial piece (its derivatives above ``degree`` are
    zero). The extension is then as smooth at the border as the surface is inside an end span, so the
    split sees no border beyond the surface's own knots.
    """
    if frame.periodic:
        return a
    M = BRIDGE_ORDER
    m, N, K = a.shape[axis], frame.K * frame.period, frame.K
    G = N - m
    a0 = np.moveaxis(a, axis, 0)
    flat = a0.reshape(m, -1)
    w = min(m, K + 1)
    d = int(min(max(degree + 1, M), w - 1, 7))
    Pq = end_derivatives(w, d, M)  # value and derivatives 1..M (per fine step)
    start = Pq @ flat[:w]
    end = Pq @ flat[::-1][:w]
    end[1::2] *= -1.0  # odd derivatives along +index at the end
    scale = float(G + 1) ** np.arange(M + 1)
    to_bezier = hermite_to_bezier(M)  # (M + 1, M + 1): derivatives at an end -> the Bezier points near it
    near_end = to_bezier @ (end * scale[:, None])
    near_start = to_bezier @ (start * (scale * (-1.0) ** np.arange(M + 1))[:, None])
    coeffs = np.concatenate([near_end, near_start[::-1]], axis=0)  # (2 M + 2, cols)
    out = np.empty((N,) + flat.shape[1:], np.result_type(flat, coeffs))
    out[:m] = flat
    np.matmul(gap_basis(G, 2 * M + 1).T, coeffs, out=out[m:])
    return np.moveaxis(out.reshape((N,) + a0.shape[1:]), 0, axis)


def _from_lifted(bands: dict, smooth: np.ndarray, surface: np.ndarray) -> tuple[dict, np.ndarray, np.ndarray]:
    """Homogeneous fields -> the surface (SPEC §4): the smooth part and the surface projected, each band
    by the first-order projection about the smooth part, ``dS = (dH_xyz - S dH_w) / H_w``."""
    w = smooth[..., 3:4]
    S = smooth[..., :3] / w
    return ({k: (v[..., :3] - S * v[..., 3:4]) / w for k, v in bands.items()}, S, from_homogeneous(surface))


def _assemble(intent: Intent, bands: dict, smooth: np.ndarray, surface, method, reading, baseband) -> ArtifactFields:
    check_option("intent", reading, READINGS)
    fu, fv = intent.frames
    if smooth.shape[-1] == 4:
        bands, smooth, surface = _from_lifted(bands, smooth, surface)
        if baseband is not None:
            baseband["homogeneous"] = True
    if reading == "surface":
        bands["signal_error"] = np.zeros_like(smooth)
        intent_out = smooth
    else:
        intent_out = intent.evaluate()
        bands["signal_error"] = smooth - intent_out
        baseband = None
    return ArtifactFields(x=fu.x, y=fv.x, surface=surface, intent=intent_out, bands=bands, method=method,
                          levels=fu.levels, reading=reading, baseband=baseband)


def _finish(intent: Intent, spec, poly, surface, method: str, reading: str, lateral: bool = True) -> ArtifactFields:
    """Fields from the half spectrum of a surface's non-polynomial part and its polynomial part."""
    fu, fv = intent.frames
    bands = band_split(spec, fu, fv, lateral=lateral)
    smooth = bands["signal_error"] + sandwich(_legendre(fu.x, fu.spans, poly.shape[0] - 1), poly,
                                              _legendre(fv.x, fv.spans, poly.shape[1] - 1))
    if surface is None:
        surface = smooth + bands["total"]
    return _assemble(intent, bands, smooth, surface, method, reading, _baseband(spec, fu, fv, poly))


def artifact_fields(intent: Intent, scheme, method: str = "predicted", reading: str = "surface",
                    lateral: bool = True) -> ArtifactFields:
    """:func:`predicted_fields` or :func:`measured_fields` by name (``lateral``: see there)."""
    check_option("method", method, ("predicted", "measured"))
    return (predicted_fields if method == "predicted" else measured_fields)(intent, scheme, reading, lateral)


# ---------------------------------------------------------------- scalars
def project(vec: np.ndarray, normal: np.ndarray | None, component: str, has: np.ndarray | None = None) -> np.ndarray:
    """Reduce a vector field ``(a, b, 3)`` to the reported scalar: signed normal part or Euclidean norm.

    ``has`` : (a, b) bool, optional
        Where ``normal`` is non-zero (computed when not given; ``None`` and ``normal`` everywhere
        non-zero are the same). Where the intent has no normal (collapsed edge, pole) the whole
        displacement counts.
    """
    check_option("component", component, COMPONENTS)
    if component == "vector" or normal is None:
        return np.sqrt(np.einsum("...k,...k->...", vec, vec))
    # einsum reads the (a, b, 3) layout in one pass: a third of the time of per-component products
    dot = np.einsum("...k,...k->...", vec, normal)
    if has is None:
        has = np.einsum("...k,...k->...", normal, normal) != 0.0
    if has is True or has.all():
        return dot
    return np.where(has, dot, np.sqrt(np.einsum("...k,...k->...", vec, vec)))


def intent_normals(intent_fine: np.ndarray, K: float = 1.0, spacing: tuple[float, float] | None = None) -> np.ndarray:
    """Unit normals ``(a, b, 3)`` of a surface sampled on a grid (zeros where degenerate).

    ``n = du x dv / |du x dv|`` with central differences (``numpy.gradient``; grid spacing
    ``1/K`` or ``spacing``); points where ``|du x dv| <= 1e-9 |du| |dv|`` (a collapsed edge or
    pole) get ``0``. The cross product and the norms are written out per component (``np.cross``
    and ``np.linalg.norm`` cost three times as much on these shapes).
    """
    su, sv = spacing if spacing is not None else (1.0 / K, 1.0 / K)
    du = np.gradient(intent_fine, su, axis=0) if intent_fine.shape[0] > 1 else np.zeros_like(intent_fine)
    dv = np.gradient(intent_fine, sv, axis=1) if intent_fine.shape[1] > 1 else np.zeros_like(intent_fine)
    ux, uy, uz = du[..., 0], du[..., 1], du[..., 2]
    vx, vy, vz = dv[..., 0], dv[..., 1], dv[..., 2]
    n = np.empty(np.broadcast_shapes(du.shape, dv.shape))
    n[..., 0] = uy * vz - uz * vy
    n[..., 1] = uz * vx - ux * vz
    n[..., 2] = ux * vy - uy * vx
    norm = np.sqrt(np.einsum("...k,...k->...", n, n))
    scale = np.sqrt(np.einsum("...k,...k->...", du, du) * np.einsum("...k,...k->...", dv, dv))
    ok = norm > 1e-9 * np.maximum(scale, 1e-300)
    if ok.all():
        n /= norm[..., None]
        return n
    return np.where(ok[..., None], n / np.where(ok, norm, 1.0)[..., None], 0.0)
