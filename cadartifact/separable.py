"""Per-axis (separable) computation of artifact fields: today's budget and every candidate density.

For a tensor-product scheme every step of the analysis is linear and acts on each axis
separately: the (tensor-degree) trend fit, the band-limited interpolant of the residual (even
reflection / wrap), resampling, the limit surface (trend through the limit stencil, residual
through the 1-D transfer function; or a face's own B-spline basis on the measured road) and the
band split, whose masks are products of per-axis masks. So a field is a short sum of ``A M B^T``
products of small real matrices, and its bands come from filtering the factors
(:func:`split_terms`), computed with BLAS instead of large complex FFTs. Only the lateral field
is not separable: on the predicted road it comes from the residual spectrum pre-weighted by the
lateral factors, otherwise from one 2-D FFT. The FFT paths (:func:`cadartifact.fields.band_split`,
``fast=False``) are the reference; tests keep them equal (1e-10).
"""

from __future__ import annotations

import numpy as np

from .fields import Axis, bandlimited_basis_real

__all__ = ["AxisModel", "axis_model", "sandwich", "resampled_error", "ripple_and_intent", "lowpass", "split_terms",
           "lateral_field", "tensor_fields", "split_field", "clear_caches"]


def sandwich(A: np.ndarray, P: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A P B^T`` for each coordinate: ``A (a, n)``, ``P (n, m, c)``, ``B (b, m)`` -> ``(a, b, c)``."""
    n, m, c = P.shape
    tmp = (A @ P.reshape(n, m * c)).reshape(A.shape[0], m, c)  # (a, m, c)
    return np.tensordot(tmp, B, axes=(1, 1)).transpose(0, 2, 1)  # (a, b, c)


def _legvander(x: np.ndarray, span: float, degree: int) -> np.ndarray:
    from numpy.polynomial import legendre as L

    return L.legvander(2 * np.asarray(x, float) / max(span, 1e-300) - 1, degree)


class AxisModel:
    """One axis of a net under a 1-D scheme factor: trend, band-limited interpolation, synthesis.

    Parameters
    ----------
    n : int
        Control points.
    periodic : bool
    degree : int
        Trend degree along this axis (0 when periodic).
    transfer : callable
        ``transfer(xi, levels)``: the 1-D factor of the scheme's transfer function.
    stencil : (s,) float
        The 1-D limit stencil (odd size), or None for no polynomial signal error (dual axes).
    """

    def __init__(self, n, periodic, degree, transfer, stencil):
        self.n, self.periodic, self.degree = n, periodic, degree
        self.transfer, self.stencil = transfer, stencil
        self._memo: dict = {}
        self.span = float(max(n - 1, 1))
        self.N = n if periodic else 2 * (n - 1)
        self.Vn = _legvander(np.arange(n), self.span, degree)
        self.Vp = np.linalg.pinv(self.Vn)
        self.f = np.fft.fftfreq(self.N)

    @property
    def F(self) -> np.ndarray:
        """``(N, n)`` complex: DFT of the extended unit vectors (built on first use: large for long axes)."""
        if "F" not in self._memo:
            ext = self._extend(np.eye(self.n))
            self._memo["F"] = np.fft.fft(ext, axis=0)
        return self._memo["F"]

    @property
    def Fr(self) -> np.ndarray:
        if "Fr" not in self._memo:
            self._memo["Fr"] = np.ascontiguousarray(self.F.real)
        return self._memo["Fr"]

    @property
    def Fi(self) -> np.ndarray:
        if "Fi" not in self._memo:
            self._memo["Fi"] = np.ascontiguousarray(self.F.imag)
        return self._memo["Fi"]

    def _extend(self, X: np.ndarray) -> np.ndarray:
        """Rows ``0..n-1`` extended to one period: wrap (periodic) or whole-sample even reflection."""
        if self.periodic or self.n < 3:
            return X
        return np.concatenate([X, X[1:self.n - 1][::-1]], axis=0)

    def bandlimited(self, x) -> np.ndarray:
        """``(len(x), n)``: residual samples -> their band-limited interpolant at ``x``."""
        C, S = bandlimited_basis_real(x, self.f)
        return C @ self.Fr - S @ self.Fi

    def bandlimited_fine(self, levels: int) -> np.ndarray:
        """``(fine, n)``: :meth:`bandlimited` on this axis's own fine grid (cached)."""
        key = ("blf", levels)
        if key not in self._memo:
            self._memo[key] = self.bandlimited(Axis(self.n, self.periodic, levels).x)
        return self._memo[key]

    def limit_coef(self) -> np.ndarray:
        """``(m, m)``: Legendre coefficients of a trend -> those of its limit surface (exact: degree kept).

        The limit at integer ``J`` is ``sum_a s[a] trend(J + r - a)`` (the trend extends as a
        polynomial past the net); it is sampled on enough integers to fit exactly.
        """
        if "lc" in self._memo:
            return self._memo["lc"]
        m = self.degree + 1
        if self.stencil is None or m == 1:
            coef = np.eye(m)
        else:
            s = np.asarray(self.stencil, float)
            r = len(s) // 2
            M = max(self.n, m + 1)
            pad = _legvander(np.arange(-r, M + r), self.span, self.degree)  # (M+2r, m)
            # lim[J] = sum_a s[a] trend(J + r - a), as fields._trend_limit_coef
            lim = np.stack([np.convolve(pad[:, j], s, mode="valid") for j in range(m)], axis=1)  # (M, m)
            coef = np.linalg.pinv(_legvander(np.arange(M), self.span, self.degree)) @ lim
        self._memo["lc"] = coef
        return coef

    def fine_vander(self, levels: int) -> np.ndarray:
        """``(fine, m)``: the Legendre basis (this axis's scaling) on the fine grid."""
        return _legvander(Axis(self.n, self.periodic, levels).x, self.span, self.degree)

    def synthesis(self, levels: int) -> np.ndarray:
        """``(fine, n)``: residual samples -> predicted limit surface (1-D transfer) on the fine grid."""
        if ("syn", levels) in self._memo:
            return self._memo[("syn", levels)]
        out = self._memo[("syn", levels)] = self.synthesize(np.eye(self.n), levels)
        return out

    def synthesize(self, X: np.ndarray, levels: int) -> np.ndarray:
        """``synthesis(levels) @ X`` without forming the matrix: ``(n, m)`` samples -> ``(fine, m)``.

        One FFT of the extended columns, the spectrum repeated ``K`` times and weighted by
        ``K T(xi)``, one inverse FFT: ``O(K N m log)`` instead of ``O(K N n m)``.
        """
        ax = Axis(self.n, self.periodic, levels)
        K = ax.K
        spec = np.fft.fft(self._extend(np.asarray(X, float)), axis=0)
        w = K * self.transfer(ax.freqs(fine=True), levels)
        return np.fft.ifft(np.tile(spec, (K, 1)) * w[:, None], axis=0).real[: ax.fine_count]



_MODELS: dict = {}


#: Cached axis models are dropped when their arrays exceed this many bytes (a long axis's
#: synthesis and DFT matrices reach tens of MB at K = 8).
MODEL_CACHE_BYTES = 256 * 2 ** 20


def _models_bytes() -> int:
    return sum(v.nbytes for m in _MODELS.values() for v in m._memo.values() if isinstance(v, np.ndarray))


def axis_model(scheme, axis: int, n: int, periodic: bool, degree: int) -> AxisModel:
    """The (cached) :class:`AxisModel` of one axis of a tensor-product scheme."""
    # the mask too: two user schemes may share a name
    key = (scheme.name, hash(np.asarray(scheme.mask, float).tobytes()), axis, n, periodic, degree)
    model = _MODELS.get(key)
    if model is None:
        st = np.asarray(scheme.limit_stencil, float).sum(axis=1 - axis)
        stencil = st if len(st) % 2 == 1 else None
        if axis == 0:
            transfer = lambda xi, L: np.asarray(scheme.transfer(xi, np.zeros_like(xi), L), float)  # noqa: E731
        else:
            transfer = lambda xi, L: np.asarray(scheme.transfer(np.zeros_like(xi), xi, L), float)  # noqa: E731
        if len(_MODELS) > 512 or (len(_MODELS) % 16 == 0 and _models_bytes() > MODEL_CACHE_BYTES):
            _MODELS.clear()
        model = _MODELS[key] = AxisModel(n, periodic, degree, transfer, stencil)
    return model


# ---------------------------------------------------------------- band split on per-axis factors
def lowpass(X: np.ndarray, ax: Axis) -> np.ndarray:
    """The base band (``|f| < 1/2`` cycles per control point) of each column of a fine-grid factor.

    Parameters
    ----------
    X : (ax.fine_count, m) float
    ax : Axis

    Returns
    -------
    (ax.fine_count, m) float
        What the band split's low-pass does to a field along this axis (same extension: even
        reflection or wrap), applied to the factor instead of the field: the low-pass of
        ``A M B^T`` along u is ``(lowpass(A)) M B^T``.
    """
    ext = ax.extend(X, 0)
    f = np.fft.rfftfreq(ext.shape[0], d=1.0 / ax.K)
    keep = (np.abs(f) < 0.5 - 1e-12)[:, None]
    return np.fft.irfft(np.fft.rfft(ext, axis=0) * keep, n=ext.shape[0], axis=0)[: X.shape[0]]


def _right(lefts: list, rights: list) -> np.ndarray:
    """``sum_k lefts[k] @ rights[k]^T`` over the middle axis: ``(a, m_k, c)`` and ``(b, m_k)`` -> ``(a, b, c)``."""
    XM = lefts[0] if len(lefts) == 1 else np.concatenate(lefts, axis=1)
    Y = rights[0] if len(rights) == 1 else np.concatenate(rights, axis=1)
    a, m, c = XM.shape
    out = np.ascontiguousarray(XM.transpose(0, 2, 1)).reshape(a * c, m) @ Y.T
    return out.reshape(a, c, -1).transpose(0, 2, 1)


def split_terms(terms: list, au: Axis, av: Axis, only: str | None = None, lateral: list | None = None,
                lows: list | None = None) -> dict:
    """Band split of a field given as a sum of separable terms ``sum_k A_k M_k B_k^T``.

    Parameters
    ----------
    terms : list of (A (a, n_k) float, M (n_k, m_k, c) float, B (b, m_k) float)
        ``a = au.fine_count``, ``b = av.fine_count``.
    au, av : Axis
    only : {"total"}, optional
        Just the whole ripple.
    lateral : list of (M1, M2, Md), optional
        Per term, the middle matrices pre-weighted by the lateral factors of the X1, X2 and diagonal
        bands (possible when every fine frequency comes from one coarse bin, as in the predicted
        road): the lateral field is then ``X1(M1) + X2(M2) + diagonal(Md)`` with no 2-D FFT.
        Without it, the lateral field is one FFT of the ripple.
    lows : list of (LA, LB), optional
        Per term, :func:`lowpass` of its factors when already known (cached operators).

    Returns
    -------
    dict str -> (a, b, c) float
        ``signal_error`` (base band), ``x1``, ``x2``, ``diagonal``, ``total`` and ``lateral``: equal to
        :func:`cadartifact.fields.band_split` of the field (the band masks are products of per-axis
        masks; lateral is not).
    """
    LA, HA, LB, HB = [], [], [], []
    for k, (A, M, B) in enumerate(terms):
        la, lb = (lowpass(A, au), lowpass(B, av)) if lows is None else lows[k]
        LA.append(la), HA.append(A - la), LB.append(lb), HB.append(B - lb)

    def left(X, M):
        return np.tensordot(X, M, axes=(1, 0))

    if only == "total":
        full = [left(A, M) for A, M, _ in terms]
        low = [left(la, M) for la, (_, M, _) in zip(LA, terms)]
        return {"total": _right(full, [B for _, _, B in terms]) - _right(low, LB)}
    lo_left = [left(la, M) for la, (_, M, _) in zip(LA, terms)]
    hi_left = [left(ha, M) for ha, (_, M, _) in zip(HA, terms)]
    out = {
        "signal_error": _right(lo_left, LB),
        "x1": _right(hi_left, LB),
        "x2": _right(lo_left, HB),
        "diagonal": _right(hi_left, HB),
    }
    out["total"] = out["x1"] + out["x2"] + out["diagonal"]
    if lateral is None:
        out["lateral"] = lateral_field(out["total"], au, av)
    else:
        out["lateral"] = (_right([left(h, m[0]) for h, m in zip(HA, lateral)], LB)
                          + _right([left(la, m[1]) for la, m in zip(LA, lateral)], HB)
                          + _right([left(h, m[2]) for h, m in zip(HA, lateral)], HB))
    return out


def split_field(field: np.ndarray, au: Axis, av: Axis) -> dict:
    """:func:`cadartifact.fields.band_split` of a fine-grid field, by three 1-D low-pass passes.

    The band masks are products of per-axis masks: ``base = Lu Lv F``, ``x1 = (1 - Lu) Lv F``,
    ``x2 = Lu (1 - Lv) F``, ``diagonal = (1 - Lu)(1 - Lv) F``; only the lateral field needs a 2-D FFT.

    Parameters
    ----------
    field : (au.fine_count, av.fine_count, c) float

    Returns
    -------
    dict str -> (a, b, c) float
    """
    A, B, c = field.shape
    Lu = lowpass(field.reshape(A, B * c), au).reshape(A, B, c)
    Lv = lowpass(field.transpose(1, 0, 2).reshape(B, A * c), av).reshape(B, A, c).transpose(1, 0, 2)
    LL = lowpass(np.ascontiguousarray(Lv).reshape(A, B * c), au).reshape(A, B, c)
    out = {"signal_error": LL, "x1": Lv - LL, "x2": Lu - LL, "diagonal": field - Lu - Lv + LL}
    out["total"] = out["x1"] + out["x2"] + out["diagonal"]
    out["lateral"] = lateral_field(out["total"], au, av)
    return out


def lateral_field(ripple: np.ndarray, au: Axis, av: Axis) -> np.ndarray:
    """The lateral part of a ripple field (SPEC §3 weights per alias band), by one 2-D FFT."""
    from .fields import _band_masks

    ext = av.extend(au.extend(ripple, 0), 1)
    A, B = ext.shape[:2]
    fu = np.fft.fftfreq(A, d=1.0 / au.K)
    fv = np.fft.rfftfreq(B, d=1.0 / av.K)
    w = _band_masks(fu, fv)["lateral"]
    spec = np.fft.rfft2(ext, axes=(0, 1)) * w[:, :, None]
    return np.fft.irfft2(spec, s=(A, B), axes=(0, 1))[: ripple.shape[0], : ripple.shape[1]]


def _road_operators(intent, scheme, road: str):
    """Per-axis ``(fine, n)`` matrices mapping control points to the surface, or None if not separable."""
    from .fields import trend_caps
    from .measure import _param_axis
    from .splines import basis_matrix

    net = intent.net
    axes = intent.axes
    models = None
    if getattr(scheme, "tensor", False):
        caps = trend_caps(int(scheme.reproduction_degree), axes)
        models = [axis_model(scheme, k, a.n, a.periodic, c) for k, (a, c) in enumerate(zip(axes, caps))]
    if road == "predicted":
        if models is None:
            return None
        return [m.synthesis(a.levels) for m, a in zip(models, axes)], models
    if road == "face":
        if net.weights_vary:
            return None  # the rational quotient is not a sum of products
        ops = [basis_matrix(net.knots[k], net.degrees[k], _param_axis(net, k, a.x), a.n, net.periodic[k])
               for k, a in enumerate(axes)]
    elif road == "uniform-bspline":
        from .measure import cardinal_operator

        ops = [cardinal_operator(a.n, deg, a.x, a.periodic) for a, deg in zip(axes, scheme.degrees)]
    else:
        return None
    return ops, models


def tensor_fields(intent, scheme, road: str):
    """:func:`~cadartifact.fields.predicted_fields` / :func:`~cadartifact.measure.measured_fields` by per-axis
    factors, when the surface is separable (tensor scheme predicted; a non-rational or constant-weight face;
    a uniform B-spline of a cage). Same numbers (tests keep them equal), far less work: no 2-D FFT except
    one for the lateral field.

    Parameters
    ----------
    intent : Intent
    scheme : Scheme
    road : {"predicted", "face", "uniform-bspline", "subdivision"}

    Returns
    -------
    ArtifactFields or None
        None when the road is not separable (the caller uses the FFT path).
    """
    from .fields import ArtifactFields, _trend_limit_coef

    got = _road_operators(intent, scheme, road)
    if got is None:
        return None
    ops, models = got
    au, av = intent.axes
    if models is None:  # the intent's interpolant needs no scheme: a bare model of each axis
        models = [AxisModel(a.n, a.periodic, 0, None, None) for a in intent.axes]
    G = [m.bandlimited_fine(a.levels) for m, a in zip(models, intent.axes)]
    R = intent.residual
    lateral = None
    if road == "predicted":
        # every fine bin of the predicted surface comes from one coarse bin of the residual: weight
        # the residual's spectrum by the lateral factors instead of filtering the fine field
        from .fields import lateral_factors

        nu, nv = R.shape[:2]
        w = lateral_factors(au.freqs(fine=False), av.freqs(fine=False))
        Rw = tuple(np.fft.ifft2(intent.spectrum * f[:, :, None], axes=(0, 1)).real[:nu, :nv] for f in w)
        lateral = [Rw, Rw]
    bands = split_terms([(ops[0], R, ops[1]), (-G[0], R, G[1])], au, av, lateral=lateral)
    trend_fine = intent.trend(au.x, av.x)
    intent_fine = trend_fine + sandwich(G[0], R, G[1])
    if road == "predicted":
        bands["signal_error"] = bands["signal_error"] + intent.trend(au.x, av.x,
                                                                     _trend_limit_coef(intent, scheme) - intent.coef)
    else:
        nu, nv = intent.net.shape
        s_trend = sandwich(ops[0], intent.trend(np.arange(nu), np.arange(nv)), ops[1])
        bands["signal_error"] = bands["signal_error"] + (s_trend - trend_fine)
    surface = intent_fine + bands["signal_error"] + bands["total"]
    return ArtifactFields(x=au.x, y=av.x, surface=surface, intent=intent_fine, bands=bands,
                          method="predicted" if road == "predicted" else "measured", levels=au.levels)


def candidate_operators(old: AxisModel, new: AxisModel, x_new: np.ndarray, x_fine: np.ndarray, levels: int,
                        side: str) -> dict:
    """Per-axis matrices of a resampled net (cached per axis, density and positions).

    The four factors are ``tl`` ``(A', m)``: trend coefficients -> the candidate's limit of the carried
    trend; ``v`` ``(A', m)``: trend coefficients -> the trend at ``x_fine``; ``res`` ``(A', n)``: today's
    residual samples -> the candidate's limit surface (band-limited resampling at ``x_new``, then the
    scheme's synthesis); ``bl`` ``(A', n)``: today's residual -> its band-limited interpolant at
    ``x_fine``; each also low-passed (``L``) on the candidate's fine axis. They are stored once, in the
    layout their side multiplies with, and read as views:

    * ``side="u"``: rows ``uC = [tl; -v; -L tl; L v]`` and ``uR = [res; -bl; -L res; L bl]`` (the error's
      signed terms, then minus their low-pass: the ripple's eight terms);
    * ``side="v"``: columns ``vCR = [tl, v, L tl, L v, res, bl, L res, L bl]``.

    Returns
    -------
    dict
        ``uC``, ``uR`` (side u) or ``vCR`` (side v), and ``A``, ``m``, ``n``.
    """
    key = (id(old), side, new.n, levels, hash(x_new.tobytes()), hash(x_fine.tobytes()))
    got = _CANDIDATES.get(key)
    if got is None:
        ax = Axis(new.n, new.periodic, levels)
        tl = new.fine_vander(levels) @ new.limit_coef()
        v = _legvander(x_fine, old.span, old.degree)
        res = new.synthesize(old.bandlimited(x_new), levels)
        bl = old.bandlimited(x_fine)
        got = {"A": len(x_fine), "m": v.shape[1], "n": bl.shape[1]}
        if side == "u":
            got["uC"] = np.concatenate([tl, -v, -lowpass(tl, ax), lowpass(v, ax)], axis=0)
            got["uR"] = np.concatenate([res, -bl, -lowpass(res, ax), lowpass(bl, ax)], axis=0)
        else:
            got["vCR"] = np.concatenate([tl, v, lowpass(tl, ax), lowpass(v, ax),
                                         res, bl, lowpass(res, ax), lowpass(bl, ax)], axis=1)
        _CANDIDATES.put(key, got, old)
    return got


def _u_factors(cu: dict) -> tuple[list, list]:
    """Side u: the error's four signed factors ``[tl, -v, res, -bl]`` and their low-passes."""
    A = cu["A"]
    C, R = cu["uC"], cu["uR"]
    err = [C[:A], C[A:2 * A], R[:A], R[A:2 * A]]
    low = [-C[2 * A:3 * A], -C[3 * A:], -R[2 * A:3 * A], -R[3 * A:]]
    return err, low


def _v_factors(cv: dict) -> tuple[list, list]:
    """Side v: the four factors ``[tl, v, res, bl]`` and their low-passes (column views)."""
    m, n, M = cv["m"], cv["n"], cv["vCR"]
    err = [M[:, :m], M[:, m:2 * m], M[:, 4 * m:4 * m + n], M[:, 4 * m + n:4 * m + 2 * n]]
    low = [M[:, 2 * m:3 * m], M[:, 3 * m:4 * m], M[:, 4 * m + 2 * n:4 * m + 3 * n], M[:, 4 * m + 3 * n:]]
    return err, low


class _ByteLRU:
    """Least-recently-used cache bounded by the bytes of the arrays it holds.

    Long axes make large operators (a 2000-point candidate on a 286-point axis: ~40 MB with its
    low-passes), so a count bound is not enough; entries also keep their axis model alive so that
    ``id(model)`` keys stay unique.
    """

    def __init__(self, max_bytes: int):
        from collections import OrderedDict

        self.max_bytes, self.bytes, self.items = max_bytes, 0, OrderedDict()

    def get(self, key):
        item = self.items.get(key)
        if item is None:
            return None
        self.items.move_to_end(key)
        return item[0]

    def put(self, key, value: dict, owner) -> None:
        size = sum(v.nbytes for v in value.values() if isinstance(v, np.ndarray))
        self.items[key] = (value, owner, size)
        self.bytes += size
        while self.bytes > self.max_bytes and len(self.items) > 1:
            _, (_, _, old_size) = self.items.popitem(last=False)
            self.bytes -= old_size

    def clear(self) -> None:
        self.items.clear()
        self.bytes = 0


#: Cached candidate operators (all axes), at most this many bytes.
CANDIDATE_CACHE_BYTES = 256 * 2 ** 20
_CANDIDATES = _ByteLRU(CANDIDATE_CACHE_BYTES)


def _trend_split(P: np.ndarray, ou: AxisModel, ov: AxisModel) -> tuple[np.ndarray, np.ndarray]:
    """Today's tensor trend coefficients ``C (mu, mv, 3)`` and residual ``R (nu, nv, 3)``."""
    C = sandwich(ou.Vp, P, ov.Vp)
    return C, P - sandwich(ou.Vn, C, ov.Vn)


def ripple_and_intent(P: np.ndarray, old: tuple, new: tuple, x_new: tuple, x_fine: tuple,
                      levels: int) -> tuple[np.ndarray, np.ndarray]:
    """The search objective's fields: the whole ripple of ``surface(n') - intent`` and the intent.

    Same numbers as ``resampled_error(..., only="total")``, in four matrix products: the eight
    signed terms (four of the error, four of its low-pass) are stacked per axis (cached per
    density), so a candidate costs two left and two right products whatever its size.

    Returns
    -------
    (ripple, target) : ((A, B, 3) float, (A, B, 3) float)
    """
    ou, ov = old
    C, R = _trend_split(P, ou, ov)
    cu = candidate_operators(ou, new[0], x_new[0], x_fine[0], levels, "u")
    cv = candidate_operators(ov, new[1], x_new[1], x_fine[1], levels, "v")
    A, B, M = cu["A"], cv["A"], cv["vCR"]
    mc, nc = C.shape[1], R.shape[1]
    XC = (cu["uC"] @ C.reshape(C.shape[0], -1)).reshape(4, A, mc, 3)
    XR = (cu["uR"] @ R.reshape(R.shape[0], -1)).reshape(4, A, nc, 3)
    # (A, 3, 4 mc + 4 nc): the eight signed blocks side by side, in vCR's column order
    left = np.concatenate([XC.transpose(1, 3, 0, 2).reshape(A, 3, 4 * mc),
                           XR.transpose(1, 3, 0, 2).reshape(A, 3, 4 * nc)], axis=2)
    ripple = (left.reshape(A * 3, -1) @ M.T).reshape(A, 3, B).transpose(0, 2, 1)
    # the intent: trend (v C v^T) + band-limited residual (bl R bl^T); the u blocks hold -v and -bl
    _, v_v, _, bl_v = _v_factors(cv)[0]
    target = -(_right([XC[1]], [v_v]) + _right([XR[1]], [bl_v]))
    return ripple, target


def resampled_error(P: np.ndarray, old: tuple, new: tuple, x_new: tuple, x_fine: tuple, levels: int,
                    only: str | None = None) -> tuple[dict, np.ndarray]:
    """Bands of ``surface(n') - intent`` on a candidate's fine grid, and the intent there.

    The resampled net is today's trend (coefficients carried unchanged) plus today's band-limited
    residual at the new positions (SPEC §5); its surface is the trend's limit polynomial plus the
    residual synthesised through the scheme's transfer function. Every step acts per axis, so the
    error is four separable terms and its band split filters the factors.

    Parameters
    ----------
    P : (nu, nv, 3) float
        Today's control points.
    old, new : (AxisModel, AxisModel)
        Today's axes, and the candidate's axes built with TODAY's trend degrees.
    x_new : ((a,) float, (b,) float)
        The new control points' positions in today's index space.
    x_fine : ((A,) float, (B,) float)
        The new fine grid's positions in today's index space.
    only : {"total", "deviation"}, optional
        Just that field.

    Returns
    -------
    (bands, target) : (dict str -> (A, B, 3) float, (A, B, 3) float)
        ``bands`` as :func:`split_terms` plus ``deviation`` (the whole error).
    """
    ou, ov = old
    C, R = _trend_split(P, ou, ov)
    cu = candidate_operators(ou, new[0], x_new[0], x_fine[0], levels, "u")
    cv = candidate_operators(ov, new[1], x_new[1], x_fine[1], levels, "v")
    au, av = Axis(new[0].n, new[0].periodic, levels), Axis(new[1].n, new[1].periodic, levels)
    (eu, lu), (ev, lv) = _u_factors(cu), _v_factors(cv)
    mids = (C, C, R, R)
    terms = list(zip(eu, mids, ev))
    # the u factors of v and bl carry the error's minus sign
    target = -_right([np.tensordot(eu[1], C, axes=(1, 0)), np.tensordot(eu[3], R, axes=(1, 0))], [ev[1], ev[3]])
    if only == "deviation":
        err = _right([np.tensordot(A, M, axes=(1, 0)) for A, M, _ in terms], [B for _, _, B in terms])
        return {"deviation": err}, target
    bands = split_terms(terms, au, av, only=only, lows=list(zip(lu, lv)))
    if only is None:
        bands["deviation"] = bands["signal_error"] + bands["total"]
    return bands, target


def clear_caches() -> None:
    """Forget every cached axis model and candidate operator (benchmarks measure cold runs with it)."""
    _MODELS.clear()
    _CANDIDATES.clear()
