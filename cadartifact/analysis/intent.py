"""The design intent of a control net, faithful on finite nets (SPEC §4).

A net's control points are read as samples of the shape the designer meant (``reading="net"``,
the paper's premise). Per direction the intent is

* a low-degree Legendre **trend** fitted to the points by least squares (degree: what the scheme
  reproduces, capped at ``n - 1``; none beyond a constant in periodic directions), plus
* a **Fourier extension** of the residual: a Fourier series on a period ``T`` twice the net's
  span (``T = n`` when periodic), band-limited below ``F_MAX`` cycles per control point, that
  passes through the residual samples at their Greville abscissae and, among all such series,
  has the least Sobolev norm ``sum_k (1 + (f_k L)^2)^(s/2) |c_k|^2`` (``s = SOBOLEV``).

The even reflection used before puts a slope kink at every open border, and band-limited
interpolation rings from it across the whole face (11-41 % of the shape's amplitude on the
interior at 0.15-0.35 cycles per control point); the smooth extension has no kink. Measured on
600 random clamped faces sampling known shapes (cosines, sums of cosines, bumps; degrees 2-5,
nets of 14-40, content up to 0.35 cycles per control point): at most 1.0 % of the amplitude on
the interior (15-85 % of the parameter range) and 2.6 % on the whole face
(``tests/analysis/test_intent.py`` checks the same bounds on families it draws itself).

The residual's series is T-periodic with integer frequencies ``k / T``: its samples on the lattice
``x = j + offset`` (:class:`cadartifact.analysis.frames.AxisFrame`) have exactly the series' coefficients as
their DFT, so the spectral road (:mod:`cadartifact.analysis.fields`) applies the scheme's responses to it
with no truncation.

References
----------
J. P. Boyd, *A comparison of numerical algorithms for Fourier extension of the first, second, and
third kinds*, J. Comput. Phys. 178 (2002). B. Adcock, D. Huybrechs, *On the resolution power of
Fourier extensions for oscillatory functions*, J. Comput. Appl. Math. 260 (2014).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .frames import AxisFrame, axis_frames
from .settings import READINGS
from ..net import ControlNet, knot_multiplicities, lifted
from ..numerics.operator_cache import OperatorCache
from ..numerics.tensor import sandwich

__all__ = ["Intent", "AxisIntent", "design_intent", "axis_intent", "from_homogeneous", "READINGS", "F_MAX", "SOBOLEV",
           "UNDERSAMPLED_FREQUENCY"]

#: The two readings of the design intent (SPEC §4).

#: Band limit of the Fourier extension, cycles per control point (open directions). Content
#: between it and 1/2 cannot be told from ripple on a finite net.
F_MAX = 0.4

#: Sobolev order of the ridge's weights (high frequencies cost more).
SOBOLEV = 2.5

#: Weight of the Sobolev ridge against the energy outside the net (1e-3-1e-4 best on the test
#: families; below 1e-5 the system loses conditioning).
RIDGE = 1e-3

#: Content above this frequency (cycles per control point) is under-sampled by the net.
UNDERSAMPLED_FREQUENCY = 0.4

#: Share of the residual's RMS above :data:`UNDERSAMPLED_FREQUENCY` from which a net is said to
#: under-sample its intent (a cosine at 0.35 cycles per point reads up to 0.43 on 20-point nets, 0.02 on 40;
#: one at 0.43 at least 0.73; on smaller nets the window's resolution, 1/L, blurs the line).
UNDERSAMPLED_SHARE = 0.5


def _legendre(x: np.ndarray, spans: float, degree: int) -> np.ndarray:
    from numpy.polynomial import legendre as L

    return L.legvander(2.0 * np.asarray(x, float) / max(spans, 1e-300) - 1.0, degree)


class AxisIntent:
    """The per-direction operators of the intent (cached per frame and trend degree).

    Parameters
    ----------
    frame : AxisFrame
    degree : int
        Trend degree along this direction.
    fmax : float
        Band limit (cycles per control point, open directions; default :data:`F_MAX`).
    ridge : float
        Weight of the Sobolev ridge (default :data:`RIDGE`); other values give the admissible
        reconstructions of :mod:`cadartifact.analysis.uncertainty`.
    fourier : AxisIntent, optional
        An intent of the same frame, band limit and ridge: its Fourier part is reused (it does not depend on
        the trend degree).

    Attributes
    ----------
    freqs : (M,) float
        Frequency of each Fourier basis function (cycles per control point).
    coef : (M, n) float
        Residual samples -> Fourier coefficients (weighted minimum-norm interpolation).
    """

    def __init__(self, frame: AxisFrame, degree: int, fmax: float = F_MAX, ridge: float = RIDGE, fourier=None):
        self.frame, self.degree = frame, degree
        self.fmax, self.ridge = fmax, ridge
        self.T = frame.period
        n = frame.n
        if fourier is not None:  # another trend degree of the same extension (its Fourier part is the degree's own)
            self.k, self.nyquist, self.freqs, self.weights, self.coef = (fourier.k, fourier.nyquist, fourier.freqs,
                                                                        fourier.weights, fourier.coef)
        else:
            self._fourier(frame, fmax, ridge)
        self.V = _legendre(frame.xs, frame.spans, degree)  # (n, d+1)
        self.Vp = np.linalg.pinv(self.V)
        self.rest = np.eye(n) - self.V @ self.Vp  # samples -> what this direction's polynomial leaves
        self._lattice = None

    def _fourier(self, frame: AxisFrame, fmax: float, ridge: float) -> None:
        """The Fourier extension's frequencies, weights and coefficients (independent of the trend degree)."""
        self.T = frame.period
        if frame.periodic:
            kmax = (self.T - 1) // 2
            nyquist = self.T % 2 == 0
        else:
            kmax = max(int(np.ceil(fmax * self.T)) - 1, 0)
            nyquist = False
        self.k = np.arange(1, kmax + 1)
        self.nyquist = nyquist
        f = self.k / self.T
        self.freqs = np.concatenate([[0.0], f, f] + ([[0.5]] if nyquist else []))
        self.weights = (1.0 + (self.freqs * frame.spans) ** 2) ** (SOBOLEV / 2)
        A = self.basis(frame.xs)
        if frame.periodic:
            self.coef = np.linalg.pinv(A / self.weights, rcond=1e-12) / self.weights[:, None]
        else:
            # the interpolant with the least energy outside the net (plus a small Sobolev ridge):
            # min c' G c subject to A c = r, c = G^-1 A' (A G^-1 A')^-1 r
            outside = np.linspace(frame.spans, self.T, 8 * int(round(self.T - frame.spans)) + 1)[1:-1]
            Bo = self.basis(outside)
            G = Bo.T @ Bo / len(outside) + ridge * np.diag(self.weights ** 2)
            GiAt = np.linalg.solve(G, A.T)
            self.coef = GiAt @ np.linalg.pinv(A @ GiAt, rcond=1e-13)

    def basis(self, x: np.ndarray) -> np.ndarray:
        """``(len(x), M)``: ``[1, cos(2 pi k x / T), sin(2 pi k x / T), (cos pi x)]``."""
        x = np.asarray(x, float)
        ph = (2 * np.pi / self.T) * np.outer(x, self.k)
        cols = [np.ones((len(x), 1)), np.cos(ph), np.sin(ph)]
        if self.nyquist:
            cols.append(np.cos(np.pi * (x - self.frame.offset))[:, None])
        return np.hstack(cols)

    def at(self, x: np.ndarray) -> np.ndarray:
        """``(len(x), n)``: residual samples -> the residual's intent at ``x``."""
        return self.basis(x) @ self.coef

    def full_at(self, x: np.ndarray) -> np.ndarray:
        """``(len(x), n)``: samples -> this direction's intent at ``x``: its polynomial (degree
        :attr:`degree`, least squares) plus the Fourier extension of the rest. It interpolates the samples
        and reproduces every polynomial of that degree, outside the net too."""
        return self.trend_at(x) @ self.Vp + self.at(x) @ self.rest

    def lattice(self) -> np.ndarray:
        """``(T, n)``: residual samples -> the intent on the lattice ``x = j + offset``, ``j = 0..T-1`` (read-only)."""
        if self._lattice is None:
            self._lattice = self.at(np.arange(self.T) + self.frame.offset)
            self._lattice.flags.writeable = False
        return self._lattice

    def trend_at(self, x: np.ndarray) -> np.ndarray:
        return _legendre(x, self.frame.spans, self.degree)


#: Per-axis operators kept (a density search revisits its sizes).
_CACHE = OperatorCache(1024)


def axis_intent(frame: AxisFrame, degree: int, fmax: float = F_MAX, ridge: float = RIDGE,
                like: AxisIntent | None = None) -> AxisIntent:
    """The cached :class:`AxisIntent` of a frame (keyed by its geometry, not its levels); ``like``: an intent of
    the same frame, band limit and ridge whose Fourier part is reused (another trend degree)."""
    key = (frame.n, frame.periodic, frame.spans, round(frame.offset, 12), frame.xs.round(12).tobytes(),
           frame.period, degree, fmax, ridge)
    same = like is not None and (like.T, like.fmax, like.ridge) == (frame.period, fmax, ridge) and like.frame is frame
    return _CACHE.get(key, lambda: AxisIntent(frame, degree, fmax, ridge, like if same else None))


def trend_terms(scheme, frames) -> tuple[list, tuple[int, int]]:
    """Legendre exponents ``(a, b)`` of the trend and the per-axis caps.

    Tensor-product schemes reproduce every ``x^a y^b`` with ``a, b <= d``; other schemes only total
    degree ``<= d``. Caps: ``min(d, n - 1)`` open, 0 periodic.
    """
    d = int(scheme.reproduction_degree)
    caps = tuple(0 if f.periodic else min(d, f.n - 1) for f in frames)
    tensor = bool(getattr(scheme, "tensor", False))
    terms = [(a, b) for a in range(caps[0] + 1) for b in range(caps[1] + 1) if tensor or a + b <= d]
    return terms, caps


@dataclass(frozen=True, eq=False)
class Intent:
    """The design intent of a net under a scheme, reading ``net`` (SPEC §4).

    Attributes
    ----------
    net : ControlNet
    frames : (AxisFrame, AxisFrame)
    axes : (AxisIntent, AxisIntent)
    terms : list of (int, int)
        Legendre exponents of the trend.
    coef : (len(terms), c) float
        Trend coefficients.
    residual : (nu, nv, c) float
        Control points minus trend.
    spectrum : (Tu, Tv, c) complex
        DFT of the residual's intent on the lattice (one period of the extended data).
    points : (nu, nv, c) float
        What the intent was built from: the control points (``c = 3``), or for a rational net with
        varying weights its homogeneous points ``(w P, w)`` (``c = 4``, SPEC §4 "Rational faces").
    """

    net: ControlNet
    frames: tuple
    axes: tuple
    terms: list
    coef: np.ndarray
    residual: np.ndarray
    points: np.ndarray | None = None

    @cached_property
    def spectrum(self) -> np.ndarray:
        """``(Tu, Tv, c)`` complex: the DFT of the residual's intent on the lattice (computed when first
        asked: the separable road never needs it)."""
        ext = sandwich(self.axes[0].lattice(), self.residual, self.axes[1].lattice())
        return np.fft.fft2(ext, axes=(0, 1))

    @property
    def homogeneous(self) -> bool:
        """Whether the analysis runs in homogeneous coordinates (4 components)."""
        return self.points is not None and self.points.shape[-1] == 4

    @property
    def levels(self) -> int:
        return self.frames[0].levels

    def trend(self, x: np.ndarray, y: np.ndarray, coef: np.ndarray | None = None) -> np.ndarray:
        """The trend (or another polynomial on the same terms) on the outer grid ``x x y`` -> ``(a, b, 3)``."""
        c = self.coef if coef is None else coef
        fu, fv = self.frames
        du = max(t[0] for t in self.terms)
        dv = max(t[1] for t in self.terms)
        M = np.zeros((du + 1, dv + 1, c.shape[-1]))
        for k, (a, b) in enumerate(self.terms):
            M[a, b] = c[k]
        return sandwich(_legendre(x, fu.spans, du), M, _legendre(y, fv.spans, dv))

    def evaluate(self, x: np.ndarray | None = None, y: np.ndarray | None = None) -> np.ndarray:
        """The intent on the outer grid ``x x y`` (analysis coordinates; default: the fine grid) -> ``(a, b, 3)``."""
        return from_homogeneous(self.evaluate_lifted(x, y))

    def evaluate_lifted(self, x: np.ndarray | None = None, y: np.ndarray | None = None) -> np.ndarray:
        """:meth:`evaluate` before the projection: ``(a, b, 4)`` homogeneous for a rational net."""
        x = self.frames[0].x if x is None else np.asarray(x, float)
        y = self.frames[1].x if y is None else np.asarray(y, float)
        # per direction: polynomial plus extension of the rest, so a shape straight (or polynomial) along
        # one direction stays so past the net's borders too (AxisIntent.full_at)
        return sandwich(self.axes[0].full_at(x), self.lifted_points, self.axes[1].full_at(y))

    @property
    def lifted_points(self) -> np.ndarray:
        """The points the intent interpolates: ``points``, or the net's control points."""
        return np.asarray(self.net.points if self.points is None else self.points, float)

    def undersampled(self) -> float:
        """Share of the intent's residual content above :data:`UNDERSAMPLED_FREQUENCY` cycles per point.

        Per direction, the residual's intent on the fine grid, Hann-windowed, by FFT (resolution
        ``1/L``); the share of the larger direction's energy (a direction with no content has only
        rounding to compare). 0 for a net that is its trend (to 1e-6 of its spread). Content there
        cannot be told from ripple, nor reconstructed between the points: the report says so above
        :data:`UNDERSAMPLED_SHARE`. Directions of fewer than 10 spans are not judged (a Bezier or
        few-span direction has no frequency resolution to speak of), nor directions with multiple knots
        (their control points are not samples of the shape: a C1 arc's points zigzag on and off it).
        """
        if self.homogeneous:  # judge the shape's content, not the weights' (the projection of the intent)
            return design_intent(self.net.replace(weights=None), _Reproduces(self), self.levels).undersampled()
        P = self.net.points.reshape(-1, 3)
        spread = float(np.sqrt(np.mean(np.sum((P - P.mean(axis=0)) ** 2, axis=1))))
        if float(np.sqrt(np.mean(np.sum(self.residual ** 2, axis=-1)))) <= 1e-6 * spread:
            return 0.0
        # The fine-grid intent is R = Au E Av^T (E the residual): the windowed transform along u of its
        # centred columns is G E Av^T with G = rfft(diag(win) (I - 11^T/L) Au), and its power summed over
        # the columns and components is diag(G Q G^H), Q = sum_c E_c Av^T Av E_c^T: no fine-grid array
        # (the same numbers to rounding as transforming R, in a hundredth of the time on 100 x 100 nets).
        fu, fv = self.frames
        ops = (self.axes[0].at(fu.x), self.axes[1].at(fv.x))
        E = np.asarray(self.residual, float)
        E = E.reshape(E.shape[:2] + (-1,))
        his, tots = [0.0], [0.0]
        for axis, frame in enumerate(self.frames):
            if frame.spans < 10:  # the window cannot tell 0.35 from 0.4 cycles (resolution 1/L)
                continue
            if _multiple_knots(self.net, axis):  # its points are not samples (a C1 arc's zigzag): nothing to judge
                continue
            A, other = ops[axis], ops[1 - axis]
            Ea = np.moveaxis(E, axis, 0)  # (n_axis, n_other, c)
            M = other.T @ other
            Q = sum(Ea[:, :, c] @ M @ Ea[:, :, c].T for c in range(Ea.shape[2]))
            win = np.ones(len(A)) if frame.periodic else np.hanning(len(A))
            G = np.fft.rfft((A - A.mean(axis=0)) * win[:, None], axis=0)
            power = np.maximum(np.sum((G @ Q) * G.conj(), axis=1).real, 0.0)
            f = np.fft.rfftfreq(len(A), d=1.0 / frame.K)
            his.append(float(power[f >= UNDERSAMPLED_FREQUENCY].sum()))
            tots.append(float(power.sum()))
        return float(np.sqrt(max(his) / max(tots))) if max(tots) > 0 else 0.0  # 0: no direction could tell


def _multiple_knots(net: ControlNet, axis: int) -> bool:
    """Whether a direction of a face has an interior knot of multiplicity > 1."""
    if not net.is_bspline:
        return False
    return any(m > 1 for _, m in knot_multiplicities(net.knots[axis], net.degrees[axis], net.shape[axis],
                                                      net.periodic[axis]))


class _Reproduces:
    """The trend degree of an intent, as a scheme (for :meth:`Intent.undersampled`)."""

    def __init__(self, intent: Intent):
        self.reproduction_degree = max(max(t) for t in intent.terms) if intent.terms else 0
        self.tensor = True


def from_homogeneous(H: np.ndarray) -> np.ndarray:
    """``(a, b, 3)``: the projection ``H_xyz / H_w`` of homogeneous points (3-component input passes)."""
    if H.shape[-1] != 4:
        return H
    return H[..., :3] / H[..., 3:4]


def design_intent(net: ControlNet, scheme, levels: int = 3) -> Intent:
    """The ``net`` reading of a net's design intent (trend + smooth Fourier extension).

    Parameters
    ----------
    net : ControlNet
    scheme : Scheme
        Its ``reproduction_degree`` sets the trend.
    levels : int
        Fine grid ``K = 2**levels`` samples per control spacing.

    Returns
    -------
    Intent
        ``intent.evaluate(x, y)`` is the intent anywhere; the ``surface`` reading is built from it by
        :func:`cadartifact.analysis.fields.artifact_fields`.
    """
    return intent_on_frames(net, lifted(net), axis_frames(net, levels), scheme)


def intent_on_frames(net: ControlNet, points: np.ndarray, frames, scheme) -> Intent:
    """:func:`design_intent` of ``points`` sitting where ``frames`` put them (``frames[k].xs``)."""
    terms, caps = trend_terms(scheme, frames)
    axes = tuple(axis_intent(f, c) for f, c in zip(frames, caps))
    P = np.asarray(points, float)
    full = terms == [(a, b) for a in range(caps[0] + 1) for b in range(caps[1] + 1)]
    if full:  # separable least squares: pinv(Vu (x) Vv) = pinv(Vu) (x) pinv(Vv)
        C = sandwich(axes[0].Vp, P, axes[1].Vp)
        coef = C.reshape(-1, P.shape[-1])
        residual = P - sandwich(axes[0].V, C, axes[1].V)
    else:
        Vu, Vv = axes[0].V, axes[1].V
        A = np.stack([Vu[:, a][:, None] * Vv[:, b][None, :] for a, b in terms], axis=-1).reshape(-1, len(terms))
        coef, *_ = np.linalg.lstsq(A, P.reshape(-1, P.shape[-1]), rcond=None)
        residual = (P.reshape(-1, P.shape[-1]) - A @ coef).reshape(P.shape)
    return Intent(net=net, frames=tuple(frames), axes=axes, terms=terms, coef=coef, residual=residual,
                  points=P if P.shape[-1] == 4 else None)
