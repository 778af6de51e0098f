"""Design intent and artifact fields of a real control net (SPEC §4).

A net is analysed in index space (control point ``(i, j)`` at ``(i, j)``). Its
*design intent* is the polynomial part the scheme reproduces plus the
band-limited interpolant of the residual (even reflection at open borders,
wrap-around in periodic directions). Artifact fields are the surface minus the
intent on a grid ``K = 2**levels`` times finer than the net, split by frequency
(cycles per control point) into

* base band ``|fx|, |fy| < 1/2`` -> signal error (attenuation),
* ``|fx| >= 1/2`` only -> X1 ripple, ``|fy| >= 1/2`` only -> X2 ripple, both -> diagonal ripple,
* lateral: each ripple component weighted by the lateral factor of the frequency it aliases
  (SPEC §3: ``sin phi1 = |wy|/|W|`` for X1, ``sin phi2 = |wx|/|W|`` for X2,
  ``|wx^2 - wy^2| / (2|W|^2)`` for diagonal).

Two independent roads produce the surface: *predicted* (the residual's spectrum
times the scheme's transfer function, :meth:`Scheme.transfer`) and *measured*
(the real surface: exact NURBS evaluation of the face, or numerical subdivision
of the net, see :mod:`cadartifact.measure`). Their agreement is the product's
self-check.

References
----------
P. J. Augsdörfer, N. A. Dodgson, M. A. Sabin, *Artifact analysis on B-splines, box-splines and
other surfaces defined by quadrilateral polyhedra*, CAGD 2011.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import OptionError, check_option
from .net import ControlNet

__all__ = ["Axis", "Intent", "ArtifactFields", "FIELD_NAMES", "design_intent", "predicted_fields",
           "band_split", "legendre_terms", "poly_design",
           "predicted_surface", "ripple_only", "bandlimited_basis",
           "bandlimited_basis_real"]

#: The fields a budget reports, in report order.
FIELD_NAMES = ("x1", "x2", "diagonal", "lateral", "total", "signal_error")

COMPONENTS = ("normal", "vector")


@dataclass(frozen=True)
class Axis:
    """One direction of the analysis grid.

    Attributes
    ----------
    n : int
        Control points along the axis.
    periodic : bool
    levels : int
        ``K = 2**levels`` fine samples per control spacing.
    """

    n: int
    periodic: bool
    levels: int

    @property
    def K(self) -> int:
        return 2 ** self.levels

    @property
    def period(self) -> int:
        """Period of the extended data in control spacings: ``n`` (periodic) or ``2(n-1)`` (even reflection)."""
        return self.n if self.periodic else 2 * (self.n - 1)

    @property
    def fine_count(self) -> int:
        """Fine samples over the net's own domain (``[0, n)`` periodic, ``[0, n-1]`` open)."""
        return self.K * self.n if self.periodic else self.K * (self.n - 1) + 1

    @property
    def x(self) -> np.ndarray:
        """Index coordinates of the fine samples, ``(fine_count,)``."""
        return np.arange(self.fine_count) / self.K

    def extend(self, a: np.ndarray, axis: int) -> np.ndarray:
        """Extend samples on ``[0, n-1]`` to one period (whole-sample even reflection); identity if periodic."""
        return a if self.periodic else _reflect(a, axis)

    def freqs(self, fine: bool) -> np.ndarray:
        """Frequencies in cycles per control point of the FFT bins (fine: ``K*period`` bins)."""
        m = self.K * self.period if fine else self.period
        return np.fft.fftfreq(m, d=1.0 / (self.K if fine else 1))


def _reflect(a: np.ndarray, axis: int) -> np.ndarray:
    """Whole-sample symmetric extension ``a0 a1 .. a_{n-1} a_{n-2} .. a1`` along ``axis``."""
    n = a.shape[axis]
    if n < 2:
        return a
    back = np.flip(np.take(a, np.arange(1, n - 1), axis=axis), axis=axis)
    return np.concatenate([a, back], axis=axis)


# ---------------------------------------------------------------- polynomial trend
def legendre_terms(degree: int, caps: tuple[int, int], tensor: bool = False) -> list[tuple[int, int]]:
    """Exponent pairs ``(a, b)`` with ``a <= caps[0]``, ``b <= caps[1]`` and, unless ``tensor``, ``a + b <= degree``.

    A tensor-product scheme whose factors generate degree ``d`` generates every ``x^a y^b`` with
    ``a, b <= d``; other schemes are only known to generate total degree ``<= d``.
    """
    return [(a, b) for a in range(caps[0] + 1) for b in range(caps[1] + 1) if tensor or a + b <= degree]


def poly_design(x: np.ndarray, y: np.ndarray, spans: tuple[float, float],
                terms: list[tuple[int, int]]) -> np.ndarray:
    """Tensor Legendre design matrix on the outer grid ``x x y``.

    Parameters
    ----------
    x : (a,) float, y : (b,) float
        Index coordinates.
    spans : (float, float)
        Domain lengths; coordinates are scaled to ``[-1, 1]`` for conditioning.
    terms : list of (int, int)

    Returns
    -------
    A : (a, b, len(terms)) float
    """
    from numpy.polynomial import legendre as L

    sx = 2 * np.asarray(x, float) / max(spans[0], 1e-300) - 1
    sy = 2 * np.asarray(y, float) / max(spans[1], 1e-300) - 1
    da = max((t[0] for t in terms), default=0)
    db = max((t[1] for t in terms), default=0)
    Vx = L.legvander(sx, da)
    Vy = L.legvander(sy, db)
    return np.stack([Vx[:, a][:, None] * Vy[:, b][None, :] for a, b in terms], axis=-1)


# ---------------------------------------------------------------- intent
@dataclass(frozen=True, eq=False)
class Intent:
    """The design intent of a net under a scheme (SPEC §4).

    Attributes
    ----------
    axes : (Axis, Axis)
    terms : list of (int, int)
        Legendre exponents of the polynomial trend (total degree <= the scheme's reproduction degree).
    coef : (len(terms), 3) float
        Trend coefficients (least squares on the control points).
    residual : (nu, nv, 3) float
        Control points minus trend.
    spectrum : (Pu, Pv, 3) complex
        FFT of the residual extended to one period (even reflection / wrap).
    """

    net: ControlNet
    axes: tuple[Axis, Axis]
    terms: list
    coef: np.ndarray
    residual: np.ndarray
    spectrum: np.ndarray

    @property
    def spans(self) -> tuple[float, float]:
        return tuple(float(max(a.n - 1, 1)) for a in self.axes)

    def trend(self, x: np.ndarray, y: np.ndarray, coef: np.ndarray | None = None) -> np.ndarray:
        """The polynomial trend on the outer grid ``x x y`` -> ``(a, b, 3)``.

        Evaluated as ``Vx M Vy^T`` with ``M[a, b] = coef[(a, b)]`` (per-axis Legendre matrices, no
        ``(a, b, terms)`` design array).
        """
        from numpy.polynomial import legendre as L

        c = self.coef if coef is None else coef
        if not self.terms:
            return np.zeros((len(x), len(y), c.shape[-1]))
        da = max(t[0] for t in self.terms)
        db = max(t[1] for t in self.terms)
        M = np.zeros((da + 1, db + 1, c.shape[-1]))
        for k, (a, b) in enumerate(self.terms):
            M[a, b] = c[k]
        su, sv = self.spans
        Vx = L.legvander(2 * np.asarray(x, float) / max(su, 1e-300) - 1, da)
        Vy = L.legvander(2 * np.asarray(y, float) / max(sv, 1e-300) - 1, db)
        tmp = np.tensordot(Vx, M, axes=(1, 0)).transpose(0, 2, 1)  # (a, 3, db+1)
        return (tmp @ Vy.T).transpose(0, 2, 1)

    def fine_spectrum(self, half: bool = False) -> np.ndarray:
        """The residual spectrum repeated to the fine grid's ``(K Pu, K Pv)`` bins, scaled by ``K^2``.

        ``half``: only the ``K Pv // 2 + 1`` non-negative bins of the last axis (for ``irfft2``).
        """
        (au, av) = self.axes
        pu, pv = self.spectrum.shape[:2]
        B = av.K * pv
        rows = np.arange(au.K * pu) % pu
        cols = np.arange(B // 2 + 1 if half else B) % pv
        return self.spectrum[np.ix_(rows, cols)] * (au.K * av.K)

    def baseband_weight(self) -> np.ndarray:
        """``(K Pu, K Pv)`` weights of the band-limited interpolant: 1 inside, 1/2 on a Nyquist line, 0 outside."""
        w = [np.where(np.abs(f) < 0.5, 1.0, np.where(np.isclose(np.abs(f), 0.5), 0.5, 0.0))
             for f in (a.freqs(fine=True) for a in self.axes)]
        return w[0][:, None] * w[1][None, :]

    def evaluate(self, x: np.ndarray | None = None, y: np.ndarray | None = None) -> np.ndarray:
        """The intent surface on the fine grid (default) or at arbitrary index coordinates.

        Returns
        -------
        I : (a, b, 3) float
            Trend plus band-limited interpolant of the residual.
        """
        au, av = self.axes
        if x is None and y is None:
            A, B = au.K * au.period, av.K * av.period
            spec = self.fine_spectrum(half=True) * self.baseband_weight()[:, : B // 2 + 1, None]
            bl = np.fft.irfft2(spec, s=(A, B), axes=(0, 1))[: au.fine_count, : av.fine_count]
            return self.trend(au.x, av.x) + bl
        x = au.x if x is None else np.asarray(x, float)
        y = av.x if y is None else np.asarray(y, float)
        return self.trend(x, y) + _bandlimited_at(self.spectrum, au, av, x, y)


def _bandlimited_at(spectrum: np.ndarray, au: Axis, av: Axis, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Band-limited interpolant of a periodic spectrum at arbitrary outer-grid points (direct DFT sums)."""
    from .separable import sandwich

    (Cu, Su), (Cv, Sv) = (bandlimited_basis_real(pts, ax.freqs(fine=False)) for ax, pts in ((au, x), (av, y)))
    # real part of (Cu + i Su) X (Cv + i Sv)^T with X = Xr + i Xi
    Xr, Xi = np.ascontiguousarray(spectrum.real), np.ascontiguousarray(spectrum.imag)
    return (sandwich(Cu, Xr, Cv) - sandwich(Su, Xr, Sv) - sandwich(Cu, Xi, Sv) - sandwich(Su, Xi, Cv))


def bandlimited_basis(x: np.ndarray, f: np.ndarray) -> np.ndarray:
    """``(len(x), N)`` synthesis matrix of the band-limited interpolant from an N-bin DFT.

    Bins with ``|f| < 1/2`` contribute ``exp(2 pi i f x) / N``; the single Nyquist bin of an even
    N stands for the pair ``+-1/2`` and contributes ``cos(pi x) / N`` (the even split the zero-padded
    fine spectrum makes), so the interpolant is real and passes through the samples.
    """
    C, S = bandlimited_basis_real(x, f)
    return C + 1j * S


def bandlimited_basis_real(x: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Real and imaginary parts ``(C, S)`` of :func:`bandlimited_basis` (for real matrix products)."""
    f = np.asarray(f, float)
    inside = np.abs(f) < 0.5
    nyq = np.abs(np.abs(f) - 0.5) < 1e-12
    ph = (2 * np.pi) * np.outer(np.asarray(x, float), f)
    C = np.cos(ph) * (inside | nyq)  # the Nyquist bin: cos(pi x), full weight
    S = np.sin(ph) * inside
    return C / len(f), S / len(f)


def trend_caps(degree: int, axes) -> tuple[int, int]:
    """Trend degree per axis: ``min(d, n-1)`` on open axes, 0 on periodic ones."""
    return tuple(0 if a.periodic else min(degree, a.n - 1) for a in axes)


def design_intent(net: ControlNet, scheme, levels: int = 3) -> Intent:
    """Split a net into its polynomial trend and the spectrum of the residual.

    Parameters
    ----------
    net : ControlNet
    scheme : Scheme
        Its ``reproduction_degree`` d sets the trend: total degree <= d in the open directions
        (capped at ``n - 1``), none in periodic ones.
    levels : int
        Fine grid ``K = 2**levels`` samples per control spacing.

    Returns
    -------
    Intent

    Notes
    -----
    The trend is fitted by least squares in a Legendre basis; the residual is extended by
    whole-sample even reflection (period ``2(n-1)``) at open borders so that borders add no jumps,
    and taken as periodic (period ``n``) in periodic directions (SPEC §4).
    """
    if levels < 1 or levels > 6:
        raise OptionError("levels", "an integer from 1 to 6 (K = 2..64)", levels)
    nu, nv = net.shape
    axes = (Axis(nu, net.periodic[0], levels), Axis(nv, net.periodic[1], levels))
    d = int(scheme.reproduction_degree)
    caps = trend_caps(d, axes)
    terms = legendre_terms(d, caps, tensor=bool(getattr(scheme, "tensor", False)))
    spans = tuple(float(max(a.n - 1, 1)) for a in axes)
    if terms == legendre_terms(d, caps, tensor=True):
        # a full tensor basis: the least-squares fit is separable, pinv(Vu (x) Vv) = pinv(Vu) (x) pinv(Vv)
        from numpy.polynomial import legendre as L

        from .separable import sandwich

        V = [L.legvander(2 * np.arange(a.n) / s - 1, c) for a, s, c in zip(axes, spans, caps)]
        C = sandwich(np.linalg.pinv(V[0]), net.points, np.linalg.pinv(V[1]))
        coef = C.reshape(-1, C.shape[-1])  # row-major (a, b): the order of legendre_terms
        residual = net.points - sandwich(V[0], C, V[1])
    else:
        A = poly_design(np.arange(nu), np.arange(nv), spans, terms).reshape(nu * nv, len(terms))
        P = net.points.reshape(nu * nv, 3)
        coef, *_ = np.linalg.lstsq(A, P, rcond=None)
        residual = (P - A @ coef).reshape(nu, nv, 3)
    ext = axes[1].extend(axes[0].extend(residual, 0), 1)
    spectrum = np.fft.fft2(ext, axes=(0, 1))
    return Intent(net=net, axes=axes, terms=terms, coef=coef, residual=residual, spectrum=spectrum)


# ---------------------------------------------------------------- fields
@dataclass(frozen=True, eq=False)
class ArtifactFields:
    """Surface, intent and band-split deviation fields on the fine grid.

    Attributes
    ----------
    x : (a,) float, y : (b,) float
        Index coordinates of the fine grid.
    surface, intent : (a, b, 3) float
        The limit surface and the design intent.
    bands : dict str -> (a, b, 3) float
        Vector deviation per band: ``signal_error``, ``x1``, ``x2``, ``diagonal``, ``lateral``, ``total``
        (``total`` = x1 + x2 + diagonal, the whole ripple).
    method : str
        ``"predicted"`` or ``"measured"``.
    """

    x: np.ndarray
    y: np.ndarray
    surface: np.ndarray
    intent: np.ndarray
    bands: dict = field(default_factory=dict)
    method: str = "predicted"
    levels: int = 3


def _band_masks(fu: np.ndarray, fv: np.ndarray) -> dict:
    """Boolean masks and lateral weights over a grid of frequencies ``fu (a,)``, ``fv (b,)``."""
    hu = (np.abs(fu) >= 0.5 - 1e-12)[:, None]
    hv = (np.abs(fv) >= 0.5 - 1e-12)[None, :]
    x1 = hu & ~hv
    x2 = ~hu & hv
    dg = hu & hv
    s1, s2, sd = lateral_factors(fu, fv)
    lateral = x1 * s1 + x2 * s2 + dg * sd
    return {"signal_error": ~hu & ~hv, "x1": x1, "x2": x2, "diagonal": dg, "lateral": lateral}


def lateral_factors(fu: np.ndarray, fv: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SPEC §3 lateral factors ``(sin phi1, sin phi2, sin phid1 sin phid2)``, each ``(a, b)``, of the
    frequency each bin aliases (folded into the base band: ``w = f - round(f)``)."""
    wu = (fu - np.round(fu))[:, None]
    wv = (fv - np.round(fv))[None, :]
    r2 = wu ** 2 + wv ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        s1 = np.where(r2 > 0, np.abs(wv) / np.sqrt(r2), 0.0)
        s2 = np.where(r2 > 0, np.abs(wu) / np.sqrt(r2), 0.0)
        sd = np.where(r2 > 0, np.abs(wu ** 2 - wv ** 2) / (2 * r2), 0.0)
    return s1, s2, sd


def band_split(spectrum: np.ndarray, fu: np.ndarray, fv: np.ndarray, shape: tuple[int, int]) -> dict:
    """Split a deviation field, given by its fine-grid spectrum, into bands.

    Parameters
    ----------
    spectrum : (A, B, 3) complex
        FFT of the (extended) deviation on the fine grid.
    fu : (A,) float, fv : (B,) float
        Bin frequencies in cycles per control point.
    shape : (a, b)
        The domain part of the fine grid to return.

    Returns
    -------
    dict str -> (a, b, 3) float
        ``signal_error, x1, x2, diagonal, lateral, total``.
    """
    a, b = shape
    A, B = len(fu), len(fv)
    # the field is real and every mask is even in (fx, fy): the half spectrum and irfft2 suffice
    half = spectrum[:, : B // 2 + 1]  # a no-op when given the half already
    masks = _band_masks(fu, np.abs(fv[: B // 2 + 1]))
    out = {}
    for name, m in masks.items():
        out[name] = np.fft.irfft2(half * m[:, :, None], s=(A, B), axes=(0, 1))[:a, :b]
    out["total"] = out["x1"] + out["x2"] + out["diagonal"]
    return out


def predicted_fields(intent: Intent, scheme, fast: bool = True) -> ArtifactFields:
    """Artifact fields from the scheme's spectral response (the *predicted* road).

    Fine spectrum of the residual's limit surface: ``S(xi) = K^2 T_L(xi) R(xi mod 1)`` with
    ``T_L`` the scheme's transfer to the ``K = 2^L`` grid (SPEC §4: L steps of the symbol followed by
    the limit stencil, exact without alias truncation). The trend's limit is a polynomial of the same
    degree (sum rules), obtained exactly from the limit stencil at the integers; its difference from
    the trend is signal error.

    Parameters
    ----------
    intent : Intent
    scheme : Scheme
    fast : bool
        For tensor-product schemes, compute the same fields by per-axis factors
        (:func:`cadartifact.separable.tensor_fields`); False forces the 2-D FFT path (the reference).

    Returns
    -------
    ArtifactFields
    """
    if fast:
        from .separable import tensor_fields

        out = tensor_fields(intent, scheme, "predicted")
        if out is not None:
            return out
    au, av = intent.axes
    fu, fv = au.freqs(fine=True), av.freqs(fine=True)
    h = len(fv) // 2 + 1  # real fields: the non-negative bins of the last axis suffice
    T = np.asarray(scheme.transfer(fu[:, None], np.abs(fv[None, :h]), levels=au.levels))
    fine = intent.fine_spectrum(half=True)
    base_w = intent.baseband_weight()[:, :h]
    dev_spec = fine * (T - base_w)[:, :, None]
    shape = (au.fine_count, av.fine_count)
    bands = band_split(dev_spec, fu, fv, shape)
    trend_limit_coef = _trend_limit_coef(intent, scheme)
    x, y = au.x, av.x
    poly_err = intent.trend(x, y, trend_limit_coef - intent.coef)
    bands["signal_error"] = bands["signal_error"] + poly_err
    intent_fine = intent.evaluate()
    surface = intent_fine + bands["signal_error"] + bands["total"]
    return ArtifactFields(x=x, y=y, surface=surface, intent=intent_fine, bands=bands,
                          method="predicted", levels=au.levels)


def predicted_surface(intent: Intent, scheme) -> np.ndarray:
    """Only the predicted limit surface on the fine grid, ``(a, b, 3)`` (one inverse FFT)."""
    au, av = intent.axes
    fu, fv = au.freqs(fine=True), av.freqs(fine=True)
    h = len(fv) // 2 + 1
    T = np.asarray(scheme.transfer(fu[:, None], np.abs(fv[None, :h]), levels=au.levels))
    res = np.fft.irfft2(intent.fine_spectrum(half=True) * T[:, :, None], s=(len(fu), len(fv)),
                        axes=(0, 1))[: au.fine_count, : av.fine_count]
    return res + intent.trend(au.x, av.x, _trend_limit_coef(intent, scheme))


def ripple_only(spectrum: np.ndarray, fu: np.ndarray, fv: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """The whole ripple (x1 + x2 + diagonal) of a fine-grid spectrum, one inverse FFT."""
    base = (np.abs(fu) < 0.5 - 1e-12)[:, None] & (np.abs(fv) < 0.5 - 1e-12)[None, :]
    a, b = shape
    return np.fft.ifft2(spectrum * (~base)[:, :, None], axes=(0, 1)).real[:a, :b]


def _trend_limit_coef(intent: Intent, scheme) -> np.ndarray:
    """Coefficients of the limit surface of the polynomial trend (a polynomial of the same degree).

    The limit at the integers is the limit stencil applied to the trend extended as a polynomial
    beyond the net; a polynomial of degree <= d is determined by those samples.
    """
    if not intent.terms or intent.terms == [(0, 0)]:
        return intent.coef.copy()
    L = np.asarray(scheme.limit_stencil, float)
    ru, rv = (L.shape[0] - 1) / 2, (L.shape[1] - 1) / 2
    nu, nv = intent.net.shape
    if ru != int(ru) or rv != int(rv):
        # an even-size stencil (dual scheme) has no vertex at the integers: evaluate through the
        # transfer function's polynomial behaviour instead (the trend is reproduced up to the
        # stencil's moments); fall back to the trend itself, i.e. no polynomial signal error.
        return intent.coef.copy()
    ru, rv = int(ru), int(rv)
    # sample on enough integers to determine the limit polynomial (the trend extends past the net)
    nu = max(nu, max(t[0] for t in intent.terms) + 2)
    nv = max(nv, max(t[1] for t in intent.terms) + 2)
    xs = np.arange(-ru, nu + ru)
    ys = np.arange(-rv, nv + rv)
    padded = intent.trend(xs, ys)
    lim = np.zeros((nu, nv, 3))
    # the limit point at J is sum_n L_n P_{J-n}; L is symmetric for the catalogue, kept general here
    for a in range(L.shape[0]):
        for b in range(L.shape[1]):
            if L[a, b] != 0.0:
                lim += L[a, b] * padded[2 * ru - a: 2 * ru - a + nu, 2 * rv - b: 2 * rv - b + nv]
    A = poly_design(np.arange(nu), np.arange(nv), intent.spans, intent.terms).reshape(nu * nv, -1)
    coef, *_ = np.linalg.lstsq(A, lim.reshape(nu * nv, 3), rcond=None)
    return coef


def project(vec: np.ndarray, normal: np.ndarray | None, component: str) -> np.ndarray:
    """Reduce a vector field ``(a, b, 3)`` to the reported scalar: signed normal part or Euclidean norm."""
    check_option("component", component, COMPONENTS)
    x, y, z = vec[..., 0], vec[..., 1], vec[..., 2]
    if component == "vector" or normal is None:
        return np.sqrt(x * x + y * y + z * z)
    dot = x * normal[..., 0] + y * normal[..., 1] + z * normal[..., 2]
    # where the intent has no normal (collapsed edge, pole) the whole displacement counts
    has_normal = _has_normal(normal)
    if has_normal is True:
        return dot
    return np.where(has_normal, dot, np.sqrt(x * x + y * y + z * z))


def _has_normal(normal: np.ndarray):
    """``True`` when every point has a normal, else the ``(a, b)`` mask of those that do."""
    mask = (normal[..., 0] != 0.0) | (normal[..., 1] != 0.0) | (normal[..., 2] != 0.0)
    return True if mask.all() else mask


def intent_normals(intent_fine: np.ndarray, K: int) -> np.ndarray:
    """Unit normals ``(a, b, 3)`` of the intent surface on the fine grid (zeros where degenerate).

    ``n = du x dv / |du x dv|`` with ``du, dv`` the central differences of ``numpy.gradient``;
    points where ``|du x dv| <= 1e-9 |du| |dv|`` (a collapsed edge or pole) get ``0``.
    """
    du = np.gradient(intent_fine, 1.0 / K, axis=0)
    dv = np.gradient(intent_fine, 1.0 / K, axis=1)
    a0, a1, a2 = du[..., 0], du[..., 1], du[..., 2]
    b0, b1, b2 = dv[..., 0], dv[..., 1], dv[..., 2]
    n = np.empty_like(du)
    n[..., 0] = a1 * b2 - a2 * b1
    n[..., 1] = a2 * b0 - a0 * b2
    n[..., 2] = a0 * b1 - a1 * b0
    norm = np.sqrt(n[..., 0] ** 2 + n[..., 1] ** 2 + n[..., 2] ** 2)
    scale = np.sqrt((a0 * a0 + a1 * a1 + a2 * a2) * (b0 * b0 + b1 * b1 + b2 * b2))
    ok = norm > 1e-9 * np.maximum(scale, 1e-300)
    if ok.all():
        n /= norm[..., None]
        return n
    return np.where(ok[..., None], n / np.where(ok, norm, 1.0)[..., None], 0.0)
