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

The face's sampling (the quadrature grid of its trim box, the curvatures) is :mod:`.face_samples`.

Every criterion is one :class:`CriterionSpec` in :data:`CRITERIA` (code, unit, sense, SARIF rule, the default
profile's thresholds, its measure): the default profile, the gate's profile files, its reports' rules and lines
(:mod:`cadartifact.gate.profiles`, :mod:`cadartifact.gate.reports`) are derived from it. Adding a criterion is one
entry there.

References: SASIG / VDA, *Product Data Quality Guideline for the Global Automotive Industry* (VDA 4955; ISO/PAS
26183:2006); PTC Creo ModelCHECK, *GeomIntegrityCHECK configuration options and their settings*; M. P. do Carmo,
*Differential Geometry of Curves and Surfaces*, 1976, ch. 3 (fundamental forms, principal and normal curvatures).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Callable, NamedTuple

import numpy as np

from ..errors import OptionError
from ..registry import LiveMapping
from .face_samples import FaceSamples, curvatures, direction_range, inflections, sample_face, trim_box

__all__ = ["CRITERIA", "FACE_CRITERIA", "CriterionSpec", "Measured", "NotEvaluated", "FaceView", "Limit", "Profile",
           "Criterion",
           "DEFAULT_PROFILE", "default_profile", "criteria", "judge", "sample_face", "curvatures", "inflections",
           "trim_box"]

#: Curvature below 1 / flat radius counts as no sign (a flat stretch, or numerical noise on a plane).
DEFAULT_FLAT_RADIUS = 1.0e5
#: Neighbouring knots closer than this share of the parameter range are close in parameter (G-SU-IK).
DEFAULT_KNOT_PARAMETER = 1.0e-3
#: Two faces meeting at a crease of at least this many degrees all along their edge are sharp by design.
DEFAULT_SHARP_ANGLE = 10.0


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
    sharp_angle : float
        Continuity between faces: an edge whose faces meet at a crease of at least this many degrees all along
        it is sharp by design (not judged on G1 or G2; :mod:`cadartifact.analysis.edges`).
    """

    name: str
    source: str | None = None
    limits: tuple = ()
    flat_radius: float = DEFAULT_FLAT_RADIUS
    knot_parameter: float = DEFAULT_KNOT_PARAMETER
    sharp_angle: float = DEFAULT_SHARP_ANGLE

    def __post_init__(self):
        keys = [k for k, _ in self.limits]
        if keys != list(CRITERIA):
            raise OptionError("limits", f"one entry per criterion in the order {', '.join(CRITERIA)}", keys)
        if not (self.flat_radius > 0 and math.isfinite(self.flat_radius)):
            raise OptionError("flat_radius", "a positive number of model units", self.flat_radius)
        if not (0 < self.knot_parameter < 1):
            raise OptionError("knot_parameter", "a share with 0 < s < 1", self.knot_parameter)
        if not (0 < self.sharp_angle <= 180):
            raise OptionError("sharp_angle", "an angle in degrees with 0 < a <= 180", self.sharp_angle)

    def limit(self, key: str) -> Limit | None:  # noqa: D102
        return dict(self.limits)[key]


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
        spec = CRITERIA[self.key]
        return {"criterion": self.key, "code": spec.code, "evaluated": self.evaluated, "value": _num(self.value),
                "unit": spec.unit, "verdict": self.verdict,
                "threshold": None if self.limit is None else {"warn": self.limit.warn, "fail": self.limit.fail,
                                                              "sense": spec.sense},
                "at": None if self.uv is None else {"uv": [_num(t) for t in self.uv],
                                                    "xyz": None if self.xyz is None else [_num(c) for c in self.xyz]},
                "detail": self.detail, "reason": self.reason}


def _num(x):
    return None if x is None or not math.isfinite(float(x)) else round(float(x), 9)


def _points(net, u, v) -> np.ndarray:
    from ..numerics.splines import evaluate

    return evaluate(net, u, v)


# ---------------------------------------------------------------- the measures
class Measured(NamedTuple):
    """What a measure found: the value, where the face is worst (or None), one line of supporting numbers, and a
    verdict when the measure decides it rather than the thresholds (None: judged against the profile)."""

    value: float
    uv: tuple | None = None
    xyz: tuple | None = None
    detail: str = ""
    verdict: str | None = None


class NotEvaluated(NamedTuple):
    """A measure that cannot be taken on this face, and why."""

    reason: str


class FaceView:
    """One face as the measures read it: the net, the profile, and its samples and curvatures (computed once, on
    first use, for every measure that reads them)."""

    def __init__(self, net, profile: Profile):
        self.net = net
        self.profile = profile

    @cached_property
    def samples(self) -> FaceSamples:
        """The face on the quadrature grid of its trim box (:func:`~cadartifact.analysis.face_samples.sample_face`)."""
        return sample_face(self.net)

    @cached_property
    def curvatures(self) -> dict:
        """:func:`~cadartifact.analysis.face_samples.curvatures` of the samples."""
        return curvatures(self.samples)

    def at(self, i: int, j: int) -> tuple:
        """``(uv, xyz)`` of the sample ``(i, j)``."""
        fs = self.samples
        return (fs.u[i], fs.v[j]), fs.S[i, j]


def _points_max(face: FaceView) -> Measured:
    nu, nv = face.net.shape
    return Measured(max(nu, nv), detail=f"{nu} x {nv} control points (u x v)")


def _points_total(face: FaceView) -> Measured:
    nu, nv = face.net.shape
    return Measured(nu * nv, detail=f"{nu} x {nv} control points")


def _degree(face: FaceView) -> Measured:
    p, q = face.net.degrees
    return Measured(max(p, q), detail=f"degrees {p} x {q} (u x v)" + (", rational" if face.net.rational else ""))


def _no_normal(face: FaceView):
    """The reason the curvature measures cannot be taken (the normal undefined everywhere), else None."""
    if not face.curvatures["valid"].any():
        return NotEvaluated("the normal is undefined at every sample (a degenerate face)")
    return None


def _undefined_note(cv: dict) -> str:
    bad = int((~cv["valid"]).sum())
    return f"; normal undefined at {bad} of {cv['valid'].size} samples" if bad else ""


def _radius(face: FaceView):
    """Smallest principal curvature radius, ``1 / max |k_i|``."""
    if _no_normal(face):
        return _no_normal(face)
    cv = face.curvatures
    kmax = cv["kmax"]
    i, j = np.unravel_index(int(np.nanargmax(kmax)), kmax.shape)
    note = _undefined_note(cv)
    radius = 1.0 / kmax[i, j] if kmax[i, j] > 0 else math.inf
    if math.isfinite(radius):
        return Measured(radius, *face.at(i, j), detail=f"max |principal curvature| {kmax[i, j]:.4g}{note}")
    return Measured(math.inf, *face.at(i, j), detail=f"flat everywhere (no curvature){note}")


def _waviness(face: FaceView):
    """Inflections of the normal curvature along the isoparametric lines (the line with the most, then the
    largest sign change)."""
    if _no_normal(face):
        return _no_normal(face)
    cv = face.curvatures
    floor = 1.0 / face.profile.flat_radius
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
        return Measured(n, *face.at(i, j), detail=f"{n} inflection(s) along a {along} line; largest sign change "
                                                 f"{amp:.3g} per model unit (|curvature| <= {floor:.3g} counts as "
                                                 "flat)")
    return Measured(0, detail=f"no inflection along any isoparametric line (|curvature| <= {floor:.3g} counts "
                              "as flat)" + _undefined_note(cv))


def _area(face: FaceView) -> Measured:
    """Area ``int int |S_u x S_v| du dv``, placed at the middle sample."""
    fs = face.samples
    jac = np.linalg.norm(np.cross(fs.Su, fs.Sv), axis=-1)
    area = float(fs.wu @ jac @ fs.wv)
    return Measured(area, *face.at(len(fs.u) // 2, len(fs.v) // 2), detail=f"area {area:.4g} over the trim box")


def _width(face: FaceView) -> Measured:
    """Width ``min(max_v int |S_u| du, max_u int |S_v| dv)``: at the middle of the longest line across."""
    fs = face.samples
    len_u = fs.wu @ np.linalg.norm(fs.Su, axis=-1)  # (b,): length of each u line
    len_v = np.linalg.norm(fs.Sv, axis=-1) @ fs.wv  # (a,): length of each v line
    ju, iv = int(np.argmax(len_u)), int(np.argmax(len_v))
    wu_, wv_ = float(len_u[ju]), float(len_v[iv])
    a, b = len(fs.u), len(fs.v)
    detail = f"longest u line {wu_:.4g}, longest v line {wv_:.4g}"
    if wu_ <= wv_:  # narrow across u: the widest u line, at its middle
        return Measured(wu_, *face.at(a // 2, ju), detail=detail)
    return Measured(wv_, *face.at(iv, b // 2), detail=detail)


def _spans(t: np.ndarray, p: int, n: int, periodic: bool) -> np.ndarray:
    """Distinct-knot spans ``(k, 2)`` of one direction's knot range (one period)."""
    a, b = direction_range(t, p, n, periodic)
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


def _unused(face: FaceView) -> Measured:
    """Share of the knot-span patches wholly outside the trim box, and of the parameter area."""
    net = face.net
    used, shares, cells = [], [], []
    box = trim_box(net)
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        t = np.asarray(t, float)
        a, b = direction_range(t, p, n, per)
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
        return Measured(share, uv, xyz, detail=detail)
    return Measured(0.0, detail=detail)


def _knots(face: FaceView):
    """Spans close in parameter (``< knot_parameter`` of the range) and their length on the surface."""
    net, fs, profile = face.net, face.samples, face.profile
    found = []  # (length, relative, direction, span)
    shortest = None
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        t = np.asarray(t, float)
        a, b = direction_range(t, p, n, per)
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
        return NotEvaluated("no knot span")
    if found:
        length, rel, d, span, uv, xyz = min(found, key=lambda f: f[0])
        return Measured(length, uv, xyz, detail=f"{len(found)} span(s) under {profile.knot_parameter:g} of the "
                                                f"parameter range; the shortest on the surface: {d} knots "
                                                f"{span[0]:.9g} and {span[1]:.9g} ({rel:.2g} of the range), "
                                                f"{length:.4g} long")
    length, rel, d, span, uv, xyz = shortest
    # not close in parameter: distinct whatever its length (G-SU-IK needs both)
    return Measured(length, uv, xyz, verdict="pass",
                    detail=f"no span under {profile.knot_parameter:g} of the parameter range (the shortest: {d} "
                           f"knots {span[0]:.9g} and {span[1]:.9g}, {rel:.2g} of the range, {length:.4g} long): "
                           "distinct")


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


# ---------------------------------------------------------------- the registry
class Setting(NamedTuple):
    """An extra key of a criterion's table in a profile file (:mod:`cadartifact.gate.profiles`): the key, the
    :class:`Profile` attribute it sets, what is expected, and the test a value must pass."""

    key: str
    attribute: str
    expected: str
    valid: Callable[[float], bool]


class CriterionSpec(NamedTuple):
    """One PDQ criterion: everything the analysis, the profiles and the reports know of it.

    Attributes
    ----------
    code : str
        The PDQ code (``G-SU-WV``) or the checker's name for it.
    what : str
        What is measured.
    unit : str
        The value's unit (``"model units"`` is replaced by the face's own unit in reports).
    sense : {"above", "below"}
        ``"above"``: a value above the threshold is bad; ``"below"``: a value below it is.
    rule : (str, str, str)
        The SARIF rule: id, name, description (level ``warning``; :mod:`cadartifact.gate.reports`).
    default : Limit or None
        The thresholds of the built-in ``default`` profile (None: off there).
    measure : callable ``(FaceView) -> Measured | NotEvaluated``
    needs : {"net", "knots", "trim", "edges"}
        What the face must have to be measured: any net (a subdivision cage too), knots and degrees, or also
        a non-empty trim box; ``"edges"``: not a face's criterion but one of the edges two faces share
        (:mod:`cadartifact.analysis.edges`, judged per edge by the gate; ``measure`` is then unused).
    settings : tuple of Setting
        Extra keys of its table in a profile file.
    """

    code: str
    what: str
    unit: str
    sense: str
    rule: tuple
    default: Limit | None
    measure: Callable
    needs: str = "trim"
    settings: tuple = ()


#: The criteria, in the order reports list them: id -> :class:`CriterionSpec`. Adding a criterion is one entry here.
CRITERIA: dict = {
    "waviness": CriterionSpec(
        "G-SU-WV", "inflections of the normal curvature along one isoparametric line", "inflections", "above",
        ("CA101", "pdq-wavy-surface", "G-SU-WV: too many inflections of the normal curvature along an "
                                      "isoparametric line"),
        Limit(warn=1, fail=3), _waviness,
        settings=(Setting("flat_radius", "flat_radius", "a positive number", lambda x: x > 0),)),
    "degree": CriterionSpec(
        "G-SU-HD", "highest polynomial degree", "degree", "above",
        ("CA102", "pdq-high-degree", "G-SU-HD: the face's polynomial degree is above the profile's limit"),
        Limit(warn=7, fail=11), _degree, needs="knots"),
    "points": CriterionSpec(
        "control points", "control points in one direction (the larger of u and v)", "points", "above",
        ("CA103", "pdq-control-points", "Too many control points in one direction"),
        Limit(warn=100, fail=500), _points_max, needs="net"),
    "points_total": CriterionSpec(
        "control points", "control points in total (nu * nv)", "points", "above",
        ("CA104", "pdq-control-points-total", "Too many control points in total"),
        Limit(warn=5000, fail=50000), _points_total, needs="net"),
    "knots": CriterionSpec(
        "G-SU-IK", "shortest knot span in model units among spans also shorter than the parameter threshold",
        "model units", "below",
        ("CA105", "pdq-indistinct-knots", "G-SU-IK: neighbouring knots closer than the profile's limit in "
                                          "parameter and in model units"),
        Limit(warn=0.02, fail=0.01), _knots,
        settings=(Setting("parameter", "knot_parameter", "a share with 0 < s < 1", lambda x: 0 < x < 1),)),
    "unused": CriterionSpec(
        "unused patches", "share of the surface's knot-span patches wholly outside the trimmed face", "share",
        "above",
        ("CA106", "pdq-unused-patches", "Knot-span patches of the surface lie wholly outside the trimmed face"),
        Limit(warn=0.0, fail=0.5), _unused),
    "area": CriterionSpec(
        "G-FA-TI", "area of the trimmed face", "model units^2", "below",
        ("CA107", "pdq-tiny-face", "G-FA-TI: the face's area is below the profile's limit"),
        Limit(warn=0.01, fail=0.0004), _area),
    "width": CriterionSpec(
        "narrow face", "width in the narrower direction (longest isoparametric line across it)", "model units",
        "below",
        ("CA108", "pdq-narrow-face", "The face is narrower than the profile's limit"),
        Limit(warn=0.02, fail=0.01), _width),
    "radius": CriterionSpec(
        "tiny curvature radius", "smallest principal curvature radius", "model units", "below",
        ("CA109", "pdq-tiny-curvature-radius", "The face's smallest principal curvature radius is below the "
                                               "profile's limit"),
        Limit(warn=None, fail=0.5), _radius),
    # continuity between faces (cadartifact.analysis.edges): judged per shared edge, not per face
    "edge_gap": CriterionSpec(
        "large face gap (G0)", "G0: largest distance between the two faces along their shared edge", "model units",
        "above",
        ("CA121", "pdq-edge-gap", "G0: the faces of a shared edge are further apart than the profile's limit"),
        Limit(warn=0.01, fail=0.02), None, needs="edges"),
    "edge_angle": CriterionSpec(
        "non-tangent faces (G1)", "G1: largest angle between the two faces' normals along their shared edge",
        "degrees", "above",
        ("CA122", "pdq-edge-angle", "G1: the faces of a shared edge meet at an angle above the profile's limit "
                                    "(and are not sharp by design)"),
        Limit(warn=0.5, fail=1.0), None, needs="edges",
        settings=(Setting("sharp_angle", "sharp_angle", "an angle in degrees with 0 < a <= 180",
                          lambda x: 0 < x <= 180),)),
    "edge_curvature": CriterionSpec(
        "non-smooth faces (G2)",
        "G2: largest relative jump |k1 - k2| / max(|k1|, |k2|) of the normal curvature across a shared edge", "share",
        "above",
        ("CA123", "pdq-edge-curvature", "G2: the normal curvature jumps across a shared edge by more than the "
                                        "profile's share"),
        None, None, needs="edges"),
}

#: The criteria of one face (:data:`CRITERIA` less those of the edges between faces), live.
FACE_CRITERIA = LiveMapping(lambda: {k: s for k, s in CRITERIA.items() if s.needs != "edges"})


def default_profile() -> Profile:
    """The built-in profile: each criterion's :attr:`CriterionSpec.default` (docs/quality-criteria.md justifies
    each figure and cites the checkers' defaults)."""
    return Profile(name="default", limits=tuple((k, spec.default) for k, spec in CRITERIA.items()))


#: The built-in profile, as :func:`default_profile` gives it for the criteria of this module.
DEFAULT_PROFILE = default_profile()


# ---------------------------------------------------------------- the criteria
def criteria(net, profile: Profile | None = None) -> list[Criterion]:
    """Every face criterion of :data:`CRITERIA` on one face, in that order (:data:`FACE_CRITERIA`).

    Parameters
    ----------
    net : ControlNet
    profile : Profile, optional
        Default: :func:`default_profile`.

    Returns
    -------
    list of Criterion
        One per criterion: evaluated with value, verdict and location, or not evaluated with the reason
        (a subdivision cage: only the control-point counts apply; the profile turns a criterion off).
    """
    profile = default_profile() if profile is None else profile
    out = {}
    off = {k for k, lim in profile.limits if lim is None}
    for k in off:
        if CRITERIA[k].needs != "edges":
            out[k] = Criterion(k, False, reason="off in this profile")
    why = {}  # what the face lacks, by the spec's needs
    if not net.is_bspline:
        why["knots"] = why["trim"] = ("a subdivision cage has no knots, degree or trim (its limit surface is not "
                                      "evaluated here)")
    else:
        u0, u1, v0, v1 = trim_box(net)
        if not (u1 > u0 and v1 > v0):
            why["trim"] = f"the trim box ({u0:g}..{u1:g}) x ({v0:g}..{v1:g}) is empty inside the knot range"
    face = FaceView(net, profile)
    for key, spec in CRITERIA.items():
        if key in off or spec.needs == "edges":
            continue
        lim = profile.limit(key)
        got = NotEvaluated(why[spec.needs]) if spec.needs in why else spec.measure(face)
        if isinstance(got, NotEvaluated):
            out[key] = Criterion(key, False, limit=lim, reason=got.reason)
            continue
        value = float(got.value)
        out[key] = Criterion(key, True, value=value, verdict=got.verdict or judge(value, lim, spec.sense),
                             limit=lim, uv=None if got.uv is None else tuple(float(t) for t in got.uv),
                             xyz=None if got.xyz is None else tuple(float(c) for c in got.xyz), detail=got.detail)
    return [out[k] for k in CRITERIA if k in out]
