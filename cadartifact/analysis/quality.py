"""The product-data-quality (PDQ) criteria of one face, beside the ripple: waviness, high degree, control-point
counts, indistinct knots, unused patches, tiny and narrow faces, tiny curvature radius.

Teams gate CAD data with checkers whose criteria come from the SASIG PDQ guideline / VDA 4955 (ISO/PAS 26183):
G-SU-WV (wavy surface), G-SU-HD (high degree), G-SU-IK (indistinct knots), tiny faces (G-FA-TI), narrow faces,
unoccupied patch rows, minimum curvature radius. Each criterion here is a pure function of a face's net, knots,
weights and trim box (``uv_bounds``) with a threshold in a :class:`Profile`; each gives a value, a verdict
(``pass`` / ``warn`` / ``fail``) and where the face is worst (``uv`` and ``xyz``). A criterion that cannot be
evaluated on a face (a subdivision cage has no knots; a face whose normal is undefined everywhere has no
curvature) says so with a reason: none is skipped silently. docs/quality-criteria.md gives the default profile
and where its figures come from.

The surface is evaluated here in numpy (B-spline basis functions and their derivatives from
:func:`cadartifact.numerics.splines.basis_derivatives`, rational faces through their homogeneous form), never with OCCT: the tests
check every number against OCCT's ``GeomLProp_SLProps`` / ``Geom_BSplineSurface.D2`` / ``BRepGProp``.

Sampling (per direction): the trim box ``[lo, hi]`` is cut at the distinct knots into pieces; each piece gets
``m`` Gauss-Legendre nodes (``m = clip(240 // pieces, 2, 6)``) and the box's ends are added with weight 0, so
that ``sum_i w_i f(u_i)`` integrates a function of the parameter and curvature is seen in every span.

References: SASIG / VDA, *Product Data Quality Guideline for the Global Automotive Industry* (VDA 4955; ISO/PAS
26183:2006); PTC Creo ModelCHECK, *GeomIntegrityCHECK configuration options and their settings*; M. P. do Carmo,
*Differential Geometry of Curves and Surfaces*, 1976, ch. 3 (fundamental forms, principal and normal curvatures).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import OptionError

__all__ = ["CRITERIA", "Limit", "Profile", "Criterion", "DEFAULT_PROFILE", "criteria", "judge", "sample_face"]

#: The criteria: id -> (PDQ code or the checker's name for it, what is measured, unit, sense). ``sense`` is
#: ``"above"`` when a value above the threshold is bad, ``"below"`` when a value below it is.
CRITERIA = {
    "waviness": ("G-SU-WV", "inflections of the normal curvature along one isoparametric line", "inflections",
                 "above"),
    "degree": ("G-SU-HD", "highest polynomial degree", "degree", "above"),
    "points": ("control points", "control points in one direction (the larger of u and v)", "points", "above"),
    "points_total": ("control points", "control points in total (nu * nv)", "points", "above"),
    "knots": ("G-SU-IK", "shortest knot span in model units among spans also shorter than the parameter "
                         "threshold", "model units", "below"),
    "unused": ("unused patches", "share of the surface's knot-span patches wholly outside the trimmed face",
               "share", "above"),
    "area": ("G-FA-TI", "area of the trimmed face", "model units^2", "below"),
    "width": ("narrow face", "width in the narrower direction (longest isoparametric line across it)",
              "model units", "below"),
    "radius": ("tiny curvature radius", "smallest principal curvature radius", "model units", "below"),
}

#: Curvature below 1 / flat radius counts as no sign (a flat stretch, or numerical noise on a plane).
DEFAULT_FLAT_RADIUS = 1.0e5
#: Neighbouring knots closer than this share of the parameter range are close in parameter (G-SU-IK).
DEFAULT_KNOT_PARAMETER = 1.0e-3


@dataclass(frozen=True)
class Limit:
    """The thresholds of one criterion: ``warn`` and ``fail`` (either None: that level is off).

    With sense ``"above"`` a value ``> fail`` fails and ``> warn`` warns; with ``"below"`` a value ``< fail``
    fails and ``< warn`` warns; a value equal to a threshold is on the good side of it.
    """

    warn: float | None = None
    fail: float | None = None

    def __post_init__(self):
        for name in ("warn", "fail"):
            x = getattr(self, name)
            if x is not None and (isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x)):
                raise OptionError(name, "a finite number or None", x)


@dataclass(frozen=True)
class Profile:
    """A set of thresholds, one :class:`Limit` per criterion of :data:`CRITERIA` (None: the criterion is off).

    Attributes
    ----------
    name : str
        ``"default"`` or the profile file's stem.
    source : str or None
        The file it was read from (None: built in).
    limits : tuple of (str, Limit or None)
        In the order of :data:`CRITERIA`.
    flat_radius : float
        Waviness: curvature ``|k| <= 1 / flat_radius`` has no sign (model units).
    knot_parameter : float
        Indistinct knots: spans shorter than this share of their direction's parameter range are close in
        parameter; they are indistinct when also shorter than the ``knots`` limit in model units.
    """

    name: str
    source: str | None = None
    limits: tuple = ()
    flat_radius: float = DEFAULT_FLAT_RADIUS
    knot_parameter: float = DEFAULT_KNOT_PARAMETER

    def __post_init__(self):
        keys = [k for k, _ in self.limits]
        if keys != list(CRITERIA):
            raise OptionError("limits", f"one entry per criterion in the order {', '.join(CRITERIA)}", keys)
        if not (self.flat_radius > 0 and math.isfinite(self.flat_radius)):
            raise OptionError("flat_radius", "a positive number of model units", self.flat_radius)
        if not (0 < self.knot_parameter < 1):
            raise OptionError("knot_parameter", "a share with 0 < s < 1", self.knot_parameter)

    def limit(self, key: str) -> Limit | None:  # noqa: D102
        return dict(self.limits)[key]


#: The built-in profile (docs/quality-criteria.md justifies each figure and cites the checkers' defaults).
DEFAULT_PROFILE = Profile(name="default", limits=(
    ("waviness", Limit(warn=1, fail=3)),
    ("degree", Limit(warn=7, fail=11)),
    ("points", Limit(warn=100, fail=500)),
    ("points_total", Limit(warn=5000, fail=50000)),
    ("knots", Limit(warn=0.02, fail=0.01)),
    ("unused", Limit(warn=0.0, fail=0.5)),
    ("area", Limit(warn=0.01, fail=0.0004)),
    ("width", Limit(warn=0.02, fail=0.01)),
    ("radius", Limit(warn=None, fail=0.5)),
))


def judge(value: float, limit: Limit, sense: str) -> str:
    """``"fail"``, ``"warn"`` or ``"pass"`` of a value against a :class:`Limit` (strict inequalities)."""
    bad = (lambda x, t: x > t) if sense == "above" else (lambda x, t: x < t)
    if limit.fail is not None and bad(value, limit.fail):
        return "fail"
    if limit.warn is not None and bad(value, limit.warn):
        return "warn"
    return "pass"


@dataclass(frozen=True)
class Criterion:
    """One criterion on one face.

    Attributes
    ----------
    key : str
        A key of :data:`CRITERIA`.
    evaluated : bool
        False: ``reason`` says why it could not be (or that the profile turns it off); ``verdict`` is then None.
    value, verdict, limit
        The number, ``"pass"`` / ``"warn"`` / ``"fail"`` and the thresholds it was judged against.
    uv, xyz : tuple or None
        Where the face is worst (parameters, and the surface point there); None where the criterion has no
        place (degree, counts).
    detail : str
        One line with the supporting numbers.
    reason : str or None
    """

    key: str
    evaluated: bool
    value: float | None = None
    verdict: str | None = None
    limit: Limit | None = None
    uv: tuple | None = None
    xyz: tuple | None = None
    detail: str = ""
    reason: str | None = None

    def to_dict(self) -> dict:
        code, what, unit, sense = CRITERIA[self.key]
        return {"criterion": self.key, "code": code, "evaluated": self.evaluated, "value": _num(self.value),
                "unit": unit, "verdict": self.verdict,
                "threshold": None if self.limit is None else {"warn": self.limit.warn, "fail": self.limit.fail,
                                                              "sense": sense},
                "at": None if self.uv is None else {"uv": [_num(t) for t in self.uv],
                                                    "xyz": None if self.xyz is None else [_num(c) for c in self.xyz]},
                "detail": self.detail, "reason": self.reason}


def _num(x):
    return None if x is None or not math.isfinite(float(x)) else round(float(x), 9)


# ---------------------------------------------------------------- evaluation
@dataclass(frozen=True)
class FaceSamples:
    """A face sampled on the grid ``u x v`` (:func:`sample_face`).

    Attributes
    ----------
    u, v : (a,), (b,) float
        Parameters (increasing; the trim box's ends included).
    wu, wv : (a,), (b,) float
        Quadrature weights: ``sum_i wu_i f(u_i) ~ int f du`` over the box.
    S, Su, Sv, Suu, Suv, Svv : (a, b, 3) float
        The point and its partial derivatives.
    """

    u: np.ndarray
    v: np.ndarray
    wu: np.ndarray
    wv: np.ndarray
    S: np.ndarray
    Su: np.ndarray
    Sv: np.ndarray
    Suu: np.ndarray
    Suv: np.ndarray
    Svv: np.ndarray


def _direction_range(t, p: int, n: int, periodic: bool) -> tuple[float, float]:
    return float(t[p]), float(t[n if not periodic else p + n])


def _breaks(t: np.ndarray, p: int, n: int, periodic: bool, lo: float, hi: float) -> np.ndarray:
    """Distinct knots strictly inside ``(lo, hi)`` (a periodic direction: the period's knots repeated)."""
    a, b = _direction_range(t, p, n, periodic)
    distinct = np.unique(t[p:(n if not periodic else p + n) + 1])
    if periodic:
        period = b - a
        k0, k1 = math.floor((lo - a) / period) - 1, math.ceil((hi - a) / period) + 1
        distinct = np.unique(np.concatenate([distinct + k * period for k in range(k0, k1 + 1)]))
    tol = 1e-12 * max(1.0, abs(hi - lo), abs(lo), abs(hi))
    return distinct[(distinct > lo + tol) & (distinct < hi - tol)]


_GAUSS = {m: np.polynomial.legendre.leggauss(m) for m in range(2, 7)}


def _nodes(lo: float, hi: float, inner: np.ndarray, cap: int = 240) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights per piece of ``[lo, hi]`` cut at ``inner``, with the ends (weight 0)."""
    edges = np.concatenate([[lo], inner, [hi]])
    g, w = _GAUSS[int(np.clip(cap // (len(edges) - 1), 2, 6))]
    a, b = edges[:-1, None], edges[1:, None]
    x = (a + (b - a) * (g[None, :] + 1) / 2).ravel()
    wx = ((b - a) / 2 * w[None, :]).ravel()
    return np.concatenate([[lo], x, [hi]]), np.concatenate([[0.0], wx, [0.0]])


def trim_box(net) -> tuple[float, float, float, float]:
    """``uv_bounds`` clipped to the knot range (periodic: not clipped), or the knot range of an untrimmed net."""
    box = []
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        a, b = _direction_range(np.asarray(t, float), p, n, per)
        if net.uv_bounds is None:
            box += [a, b]
            continue
        lo, hi = net.uv_bounds[2 * k], net.uv_bounds[2 * k + 1]
        if not per:
            lo, hi = max(lo, a), min(hi, b)
        box += [lo, hi]
    return tuple(box)


def sample_face(net, u: np.ndarray | None = None, v: np.ndarray | None = None) -> FaceSamples:
    """Evaluate a B-spline/NURBS face and its first and second partial derivatives on a grid.

    Parameters
    ----------
    net : ControlNet
        With knots and degrees.
    u, v : (a,), (b,) float, optional
        Parameters (default: the quadrature grid of the trim box, see the module's notes; weights are then
        those of the quadrature, else zero).

    Notes
    -----
    Returns :class:`FaceSamples`. With homogeneous points ``H = (w P, w)`` and ``A = sum_ij N_i(u) N_j(v) H_ij`` (and its derivatives, by
    the derivatives of the basis), ``S = A_xyz / A_w`` and, by the quotient rule (The NURBS Book, eq. 4.8),
    ``S_u = (A_u - w_u S) / w``, ``S_uu = (A_uu - 2 w_u S_u - w_uu S) / w``,
    ``S_uv = (A_uv - w_u S_v - w_v S_u - w_uv S) / w``.
    """
    (ku, kv), (p, q), (pu, pv), (nu, nv) = net.knots, net.degrees, net.periodic, net.shape
    u0, u1, v0, v1 = trim_box(net)
    wu = wv = None
    if u is None:
        u, wu = _nodes(u0, u1, _breaks(np.asarray(ku, float), p, nu, pu, u0, u1))
    if v is None:
        v, wv = _nodes(v0, v1, _breaks(np.asarray(kv, float), q, nv, pv, v0, v1))
    from ..numerics.splines import basis_derivatives

    u, v = np.asarray(u, float), np.asarray(v, float)
    Bu = basis_derivatives(ku, p, u, nu, pu)
    Bv = basis_derivatives(kv, q, v, nv, pv)
    P = np.asarray(net.points, float)
    w = np.ones(P.shape[:2]) if net.weights is None else np.asarray(net.weights, float)
    H = np.concatenate([P * w[:, :, None], w[:, :, None]], axis=-1).reshape(nu, nv * 4)  # (w P, w)
    T = [(Bu[a] @ H).reshape(len(u), nv, 4).transpose(0, 2, 1) for a in range(3)]  # (a, 4, nv)
    A = {(a, b): (T[a] @ Bv[b].T).transpose(0, 2, 1) for a, b in ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))}
    W = {ab: A[ab][..., 3:] for ab in A}
    X = {ab: A[ab][..., :3] for ab in A}
    w0 = W[0, 0]
    S = X[0, 0] / w0
    Su = (X[1, 0] - W[1, 0] * S) / w0
    Sv = (X[0, 1] - W[0, 1] * S) / w0
    Suu = (X[2, 0] - 2 * W[1, 0] * Su - W[2, 0] * S) / w0
    Svv = (X[0, 2] - 2 * W[0, 1] * Sv - W[0, 2] * S) / w0
    Suv = (X[1, 1] - W[1, 0] * Sv - W[0, 1] * Su - W[1, 1] * S) / w0
    zero_u, zero_v = np.zeros(len(u)), np.zeros(len(v))
    return FaceSamples(u=u, v=v, wu=zero_u if wu is None else wu, wv=zero_v if wv is None else wv, S=S, Su=Su,
                       Sv=Sv, Suu=Suu, Suv=Suv, Svv=Svv)


def curvatures(fs: FaceSamples) -> dict:
    """Normals, principal and isoparametric normal curvatures on the samples.

    Returns
    -------
    dict
        ``"valid"`` (a, b) bool (the normal is defined: ``|S_u x S_v| > 1e-10 |S_u| |S_v|`` and neither
        derivative below 1e-6 of its median over the face: a collapsed edge, such as a sphere's pole),
        ``"kmax"`` (a, b): ``max |k_i| = |H| + sqrt(max(H^2 - K, 0))``, ``"ku"``, ``"kv"`` (a, b): the normal
        curvature along the u and v lines, ``L / E`` and ``N / G``; NaN where not valid.

    Notes
    -----
    First fundamental form ``E = S_u.S_u, F = S_u.S_v, G = S_v.S_v``, second ``L = S_uu.n, M = S_uv.n,
    N = S_vv.n`` with ``n = S_u x S_v / |S_u x S_v|``; ``K = (LN - M^2) / (EG - F^2)``,
    ``H = (EN - 2FM + GL) / (2 (EG - F^2))`` (do Carmo §3.3).
    """
    cross = np.cross(fs.Su, fs.Sv)
    norm = np.linalg.norm(cross, axis=-1)
    lu, lv = np.linalg.norm(fs.Su, axis=-1), np.linalg.norm(fs.Sv, axis=-1)
    # a collapsed edge (a sphere's pole) has one derivative zero up to rounding, and the fundamental forms
    # there are rounding noise: a derivative below 1e-6 of the face's typical one counts as zero
    typical_u = float(np.median(lu)) if lu.size else 0.0
    typical_v = float(np.median(lv)) if lv.size else 0.0
    valid = (lu > 1e-6 * typical_u) & (lv > 1e-6 * typical_v) & (lu > 0) & (lv > 0) & (norm > 1e-10 * lu * lv)
    with np.errstate(divide="ignore", invalid="ignore"):
        n = cross / norm[..., None]
        E, F, G = lu ** 2, np.einsum("abk,abk->ab", fs.Su, fs.Sv), lv ** 2
        L = np.einsum("abk,abk->ab", fs.Suu, n)
        M = np.einsum("abk,abk->ab", fs.Suv, n)
        N = np.einsum("abk,abk->ab", fs.Svv, n)
        det = E * G - F ** 2
        K = (L * N - M ** 2) / det
        H = (E * N - 2 * F * M + G * L) / (2 * det)
        kmax = np.abs(H) + np.sqrt(np.maximum(H ** 2 - K, 0.0))
        ku, kv = L / E, N / G
    nan = np.full(valid.shape, np.nan)
    return {"valid": valid, "kmax": np.where(valid, kmax, nan), "ku": np.where(valid, ku, nan),
            "kv": np.where(valid, kv, nan)}


def inflections(k: np.ndarray, floor: float) -> tuple[int, float, int]:
    """Sign changes of a curvature sequence along one line, ignoring ``|k| <= floor`` (and NaN).

    Returns
    -------
    count : int
        Lobes of one sign minus one (a lobe: consecutive samples of the same sign with ``|k| > floor``).
    amplitude : float
        Largest ``min(peak |k| of the lobe before, peak |k| of the lobe after)`` over the sign changes (0 without).
    at : int
        Index of the first sample after the largest sign change (-1 without).
    """
    k = np.asarray(k, float)
    idx = np.flatnonzero(np.isfinite(k) & (np.abs(k) > floor))
    if len(idx) < 2:
        return 0, 0.0, -1
    s = np.sign(k[idx])
    starts = np.concatenate([[0], np.flatnonzero(np.diff(s) != 0) + 1])
    if len(starts) < 2:
        return 0, 0.0, -1
    peaks = np.maximum.reduceat(np.abs(k[idx]), starts)
    amps = np.minimum(peaks[:-1], peaks[1:])
    best = int(np.argmax(amps))
    return len(starts) - 1, float(amps[best]), int(idx[starts[best + 1]])


# ---------------------------------------------------------------- the criteria
def criteria(net, profile: Profile = DEFAULT_PROFILE) -> list[Criterion]:
    """Every criterion of :data:`CRITERIA` on one face, in that order.

    Parameters
    ----------
    net : ControlNet
    profile : Profile

    Returns
    -------
    list of Criterion
        One per criterion: evaluated with value, verdict and location, or not evaluated with the reason
        (a subdivision cage: only the control-point counts apply; the profile turns a criterion off).
    """
    out = {}
    off = {k for k, lim in profile.limits if lim is None}
    for k in off:
        out[k] = Criterion(k, False, reason="off in this profile")

    def put(key, value, uv=None, xyz=None, detail="", verdict=None):
        if key in off:
            return
        lim = profile.limit(key)
        verdict = verdict or judge(float(value), lim, CRITERIA[key][3])
        out[key] = Criterion(key, True, value=float(value), verdict=verdict,
                             limit=lim, uv=None if uv is None else tuple(float(t) for t in uv),
                             xyz=None if xyz is None else tuple(float(c) for c in xyz), detail=detail)

    def skip(key, reason):
        if key not in off:
            out[key] = Criterion(key, False, limit=profile.limit(key), reason=reason)

    nu, nv = net.shape
    put("points", max(nu, nv), detail=f"{nu} x {nv} control points (u x v)")
    put("points_total", nu * nv, detail=f"{nu} x {nv} control points")
    if not net.is_bspline:
        why = "a subdivision cage has no knots, degree or trim (its limit surface is not evaluated here)"
        for key in CRITERIA:
            if key not in out:
                skip(key, why)
        return [out[k] for k in CRITERIA]
    p, q = net.degrees
    put("degree", max(p, q), detail=f"degrees {p} x {q} (u x v)" + (", rational" if net.rational else ""))
    u0, u1, v0, v1 = trim_box(net)
    if not (u1 > u0 and v1 > v0):
        for key in ("waviness", "knots", "unused", "area", "width", "radius"):
            skip(key, f"the trim box ({u0:g}..{u1:g}) x ({v0:g}..{v1:g}) is empty inside the knot range")
        return [out[k] for k in CRITERIA]
    fs = sample_face(net)
    _unused(net, put)
    _size(fs, put)
    wanted = {"waviness", "radius"} - off
    if wanted:
        cv = curvatures(fs)
        if not cv["valid"].any():
            for key in wanted:
                skip(key, "the normal is undefined at every sample (a degenerate face)")
        else:
            _curvature(fs, cv, profile, put)
    if "knots" not in off:
        _knots(net, fs, profile, put, skip)
    return [out[k] for k in CRITERIA]


def _points(net, u, v) -> np.ndarray:
    from ..numerics.splines import evaluate

    return evaluate(net, u, v)


def _at(fs: FaceSamples, i: int, j: int) -> tuple:
    return (fs.u[i], fs.v[j]), fs.S[i, j]

def _curvature(fs: FaceSamples, cv: dict, profile: Profile, put) -> None:
    kmax = cv["kmax"]
    i, j = np.unravel_index(int(np.nanargmax(kmax)), kmax.shape)
    bad = int((~cv["valid"]).sum())
    note = f"; normal undefined at {bad} of {cv['valid'].size} samples" if bad else ""
    radius = 1.0 / kmax[i, j] if kmax[i, j] > 0 else math.inf
    if math.isfinite(radius):
        put("radius", radius, *_at(fs, i, j), detail=f"max |principal curvature| {kmax[i, j]:.4g}{note}")
    else:
        put("radius", math.inf, *_at(fs, i, j), detail=f"flat everywhere (no curvature){note}")
    floor = 1.0 / profile.flat_radius
    best = (0, 0.0, 0, 0, "u")  # count, amplitude, i, j, along
    ku, kv = cv["ku"], cv["kv"]
    with np.errstate(invalid="ignore"):  # only lines with both signs can inflect
        both_u = ((ku > floor).any(axis=0) & (ku < -floor).any(axis=0))
        both_v = ((kv > floor).any(axis=1) & (kv < -floor).any(axis=1))
    for j in np.flatnonzero(both_u):  # u lines (v fixed)
        n, amp, at = inflections(ku[:, j], floor)
        if (n, amp) > best[:2]:
            best = (n, amp, at, j, "u")
    for i in np.flatnonzero(both_v):  # v lines (u fixed)
        n, amp, at = inflections(kv[i, :], floor)
        if (n, amp) > best[:2]:
            best = (n, amp, i, at, "v")
    n, amp, i, j, along = best
    if n:
        uv, xyz = _at(fs, i, j)
        put("waviness", n, uv, xyz, detail=f"{n} inflection(s) along a {along} line; largest sign change "
                                          f"{amp:.3g} per model unit (|curvature| <= {floor:.3g} counts as flat)")
    else:
        put("waviness", 0, detail=f"no inflection along any isoparametric line (|curvature| <= {floor:.3g} counts "
                                  "as flat)" + note)


def _size(fs: FaceSamples, put) -> None:
    """Area ``int int |S_u x S_v| du dv`` and width ``min(max_v int |S_u| du, max_u int |S_v| dv)``."""
    jac = np.linalg.norm(np.cross(fs.Su, fs.Sv), axis=-1)
    area = float(fs.wu @ jac @ fs.wv)
    len_u = fs.wu @ np.linalg.norm(fs.Su, axis=-1)  # (b,): length of each u line
    len_v = np.linalg.norm(fs.Sv, axis=-1) @ fs.wv  # (a,): length of each v line
    ju, iv = int(np.argmax(len_u)), int(np.argmax(len_v))
    wu_, wv_ = float(len_u[ju]), float(len_v[iv])
    a, b = len(fs.u), len(fs.v)
    put("area", area, *_at(fs, a // 2, b // 2), detail=f"area {area:.4g} over the trim box")
    if wu_ <= wv_:  # narrow across u: the widest u line, at its middle
        put("width", wu_, *_at(fs, a // 2, ju), detail=f"longest u line {wu_:.4g}, longest v line {wv_:.4g}")
    else:
        put("width", wv_, *_at(fs, iv, b // 2), detail=f"longest u line {wu_:.4g}, longest v line {wv_:.4g}")


def _spans(t: np.ndarray, p: int, n: int, periodic: bool) -> np.ndarray:
    """Distinct-knot spans ``(k, 2)`` of one direction's knot range (one period)."""
    a, b = _direction_range(t, p, n, periodic)
    d = np.unique(t[(t >= a) & (t <= b)])
    keep = np.concatenate([[True], np.diff(d) > 1e-12 * max(1.0, abs(b - a))])
    d = d[keep]
    return np.stack([d[:-1], d[1:]], axis=1)


def _overlaps(spans: np.ndarray, lo: float, hi: float, periodic: bool, period: float) -> np.ndarray:
    tol = 1e-9 * max(1.0, hi - lo)
    shifts = (-period, 0.0, period) if periodic else (0.0,)
    hit = np.zeros(len(spans), bool)
    for s in shifts:
        hit |= (spans[:, 1] > lo + s + tol) & (spans[:, 0] < hi + s - tol)
    return hit


def _unused(net, put) -> None:
    """Share of the knot-span patches wholly outside the trim box, and of the parameter area."""
    used, shares, cells = [], [], []
    box = trim_box(net)
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        t = np.asarray(t, float)
        a, b = _direction_range(t, p, n, per)
        spans = _spans(t, p, n, per)
        lo, hi = box[2 * k], box[2 * k + 1]
        used.append(_overlaps(spans, lo, hi, per, b - a))
        shares.append(min(1.0, (hi - lo) / (b - a)))
        cells.append(spans)
    inside = used[0][:, None] & used[1][None, :]
    share = 1.0 - inside.mean()
    param = 1.0 - shares[0] * shares[1]
    detail = (f"{int((~inside).sum())} of {inside.size} patches outside the trim box; {100 * param:.1f} % of the "
              "parameter range" + ("" if net.uv_bounds is not None else " (untrimmed)"))
    if share > 0:  # where: the centre of the first unused patch
        i, j = np.argwhere(~inside)[0]
        uv = (cells[0][i].mean(), cells[1][j].mean())
        xyz = _points(net, np.array([uv[0]]), np.array([uv[1]]))[0, 0]
        put("unused", share, uv, xyz, detail=detail)
    else:
        put("unused", 0.0, detail=detail)


def _knots(net, fs: FaceSamples, profile: Profile, put, skip) -> None:
    """Spans close in parameter (``< knot_parameter`` of the range) and their length on the surface."""
    found = []  # (length, relative, direction, span)
    shortest = None
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        t = np.asarray(t, float)
        a, b = _direction_range(t, p, n, per)
        spans = _spans(t, p, n, per)
        rel = (spans[:, 1] - spans[:, 0]) / (b - a)
        order = np.argsort(rel)
        for s in order[: max(1, int((rel < profile.knot_parameter).sum()))]:
            length, uv, xyz = _span_length(net, fs, k, spans[s])
            item = (length, float(rel[s]), "uv"[k], spans[s], uv, xyz)
            if rel[s] < profile.knot_parameter:
                found.append(item)
            if shortest is None or rel[s] < shortest[1]:
                shortest = item
    if shortest is None:
        skip("knots", "no knot span")
        return
    if found:
        length, rel, d, span, uv, xyz = min(found, key=lambda f: f[0])
        put("knots", length, uv, xyz, detail=f"{len(found)} span(s) under {profile.knot_parameter:g} of the "
                                            f"parameter range; the shortest on the surface: {d} knots {span[0]:.9g} "
                                            f"and {span[1]:.9g} ({rel:.2g} of the range), {length:.4g} long")
        return
    length, rel, d, span, uv, xyz = shortest
    # not close in parameter: distinct whatever its length (G-SU-IK needs both)
    put("knots", length, uv, xyz, verdict="pass",
        detail=f"no span under {profile.knot_parameter:g} of the parameter range (the shortest: {d} knots "
               f"{span[0]:.9g} and {span[1]:.9g}, {rel:.2g} of the range, {length:.4g} long): distinct")


def _span_length(net, fs: FaceSamples, k: int, span) -> tuple[float, tuple, np.ndarray]:
    """Longest polyline length (5 points) of a knot span across the face's other direction's samples."""
    x = np.linspace(span[0], span[1], 5)
    other = fs.v if k == 0 else fs.u
    if len(other) > 25:
        other = other[np.linspace(0, len(other) - 1, 25).round().astype(int)]
    S = _points(net, x, other) if k == 0 else np.swapaxes(_points(net, other, x), 0, 1)  # (5, m, 3)
    lengths = np.linalg.norm(np.diff(S, axis=0), axis=-1).sum(axis=0)
    j = int(np.argmax(lengths))
    uv = (x[2], other[j]) if k == 0 else (other[j], x[2])
    return float(lengths[j]), uv, S[2, j]
