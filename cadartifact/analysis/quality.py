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
from . import face_checks
from .face_checks import distinct_spans as _spans
from .self_distance import self_distance
from .face_samples import (FaceSamples, Measured, NotEvaluated, curvatures, direction_range, inflections,
                           sample_face, trim_box)

__all__ = ["CRITERIA", "FACE_CRITERIA", "CriterionSpec", "Measured", "NotEvaluated", "FaceView", "Limit", "Profile",
           "Criterion",
           "DEFAULT_PROFILE", "default_profile", "criteria", "judge", "sample_face", "curvatures", "inflections",
           "trim_box"]

#: Curvature below 1 / (flat ratio * the face's size) counts as no sign: a bend of radius over this many face
#: sizes (a sagitta under 1/800 of the face) is flat for the face, whatever its unit or scale.
DEFAULT_FLAT_RATIO = 100.0
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
    flat_ratio : float
        Waviness: curvature ``|k| <= 1 / (flat_ratio * size)`` has no sign, ``size`` the diagonal of the face's
        bounding box (a radius over ``flat_ratio`` face sizes is flat for the face).
    flat_radius : float or None
        Waviness: an absolute flat radius in model units instead (``|k| <= 1 / flat_radius``); None: relative.
    knot_parameter : float or None
        Indistinct knots: None (the checkers' definition) judges a span by its length on the surface alone; a
        share asks it also to be shorter than that share of its direction's parameter range.
    sharp_angle : float
        Continuity between faces: an edge whose faces meet at a crease of at least this many degrees all along
        it is sharp by design (not judged on G1 or G2; :mod:`cadartifact.analysis.edges`).
    """

    name: str
    source: str | None = None
    limits: tuple = ()
    flat_ratio: float = DEFAULT_FLAT_RATIO
    flat_radius: float | None = None
    knot_parameter: float | None = None
    sharp_angle: float = DEFAULT_SHARP_ANGLE

    def __post_init__(self):
        keys = [k for k, _ in self.limits]
        if keys != list(CRITERIA):
            raise OptionError("limits", f"one entry per criterion in the order {', '.join(CRITERIA)}", keys)
        if not (self.flat_ratio > 0 and math.isfinite(self.flat_ratio)):
            raise OptionError("flat_ratio", "a positive number of face sizes", self.flat_ratio)
        if self.flat_radius is not None and not (self.flat_radius > 0 and math.isfinite(self.flat_radius)):
            raise OptionError("flat_radius", "a positive number of model units or None", self.flat_radius)
        if self.knot_parameter is not None and not (0 < self.knot_parameter < 1):
            raise OptionError("knot_parameter", "a share with 0 < s < 1 or None", self.knot_parameter)
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

    @cached_property
    def across_knots(self) -> dict:
        """Both sides of the knot lines where the face may break (:func:`.face_checks.across_knots`)."""
        return face_checks.across_knots(self)

    @cached_property
    def size(self) -> float:
        """The diagonal of the bounding box of the face's samples (model units)."""
        S = self.samples.S.reshape(-1, 3)
        return float(np.linalg.norm(S.max(axis=0) - S.min(axis=0)))

    @cached_property
    def near_collapsed(self) -> np.ndarray:
        """(a, b) bool: samples within the ``collapsed`` criterion's warn length of a collapsed edge of the trim
        box (shorter than that length and than half its opposite edge; a narrow face is not collapsed): there the
        curvature is the degenerate parametrisation's."""
        lim = self.profile.limit("collapsed")
        fs = self.samples
        out = np.zeros(fs.S.shape[:2], bool)
        short = None if lim is None else (lim.warn if lim.warn is not None else lim.fail)
        if short is None:
            return out
        edges = face_checks.boundary_edges(self)
        for e, (name, length, end) in enumerate(edges):
            if length < short and length < 0.5 * edges[e ^ 1][1]:  # shorter than its opposite: collapsed, not narrow
                edge = fs.S[:, end] if name.startswith("v") else fs.S[end, :]
                edge = edge[np.unique(np.linspace(0, len(edge) - 1, 9).round().astype(int))]  # all within `short`
                d = np.linalg.norm(fs.S[:, :, None, :] - edge[None, None, :, :], axis=-1).min(axis=-1)
                out |= d <= short
        return out

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
    near = face.near_collapsed
    kmax = np.where(near, np.nan, cv["kmax"])
    if not np.isfinite(kmax).any():
        return NotEvaluated("every sample with a normal is next to a collapsed edge (see the degenerate boundary)")
    i, j = np.unravel_index(int(np.nanargmax(kmax)), kmax.shape)
    note = _undefined_note(cv)
    if near.any():
        note += f"; {int(near.sum())} samples next to a collapsed edge left out (see collapsed)"
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
    pr = face.profile
    floor = 1.0 / pr.flat_radius if pr.flat_radius is not None else 1.0 / (pr.flat_ratio * max(face.size, 1e-300))
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
    box = float(fs.wu @ jac @ fs.wv)
    i, j = len(fs.u) // 2, len(fs.v) // 2
    if not face.net.trim_loops:
        return Measured(box, *face.at(i, j), detail=f"area {box:.4g} over the trim box (no trim loops read)")
    from .trim_area import inside, trimmed_area

    area, _ = trimmed_area(face.net, fs)
    on = np.argwhere(inside(face.net.trim_loops, fs.u, fs.v))
    if len(on):  # placed at the sample of the face nearest the box's middle
        i, j = on[np.argmin(np.abs(on - [i, j]).sum(axis=1))]
    return Measured(area, *face.at(i, j), detail=f"area {area:.4g} of the trimmed face ({len(face.net.trim_loops)} "
                                                 f"trim loop(s)); {box:.4g} over its uv box")


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
        settings=(Setting("flat_ratio", "flat_ratio", "a positive number", lambda x: x > 0),
                  Setting("flat_radius", "flat_radius", "a positive number", lambda x: x > 0))),
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
        "G-SU-IK", "shortest knot span, its length on the surface", "model units", "below",
        ("CA105", "pdq-indistinct-knots", "G-SU-IK: neighbouring knots closer on the surface than the profile's "
                                          "limit"),
        Limit(warn=0.02, fail=0.01), face_checks.indistinct_knots,
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
    "patch_gap": CriterionSpec(
        "G-SU-LG", "largest position gap across a knot line inside the face", "model units", "above",
        ("CA121", "pdq-large-patch-gap", "G-SU-LG: the face's patches are apart across a knot line"),
        Limit(warn=0.01, fail=0.02), face_checks.patch_gap),
    "patch_angle": CriterionSpec(
        "G-SU-NT", "largest normal angle across a knot line inside the face", "degrees", "above",
        ("CA122", "pdq-non-tangent-patches", "G-SU-NT: the face creases or folds across a knot line"),
        Limit(warn=2.0, fail=3.0), face_checks.patch_angle),
    "collapsed": CriterionSpec(
        "G-SU-DC", "shortest edge of the trim box on the surface", "model units", "below",
        ("CA123", "pdq-degenerate-boundary", "G-SU-DC: an edge of the face's surface is collapsed"),
        Limit(warn=0.02, fail=0.01), face_checks.collapsed_edge),
    "corner": CriterionSpec(
        "G-SU-DP", "smallest angle between S_u and S_v at a corner of the trim box", "degrees", "below",
        ("CA124", "pdq-degenerate-corner", "G-SU-DP: the face's surface has a corner angle near 0 or 180 "
                                           "degrees"),
        Limit(warn=None, fail=2.0), face_checks.corner_angle),
    "self_distance": CriterionSpec(
        "G-SU-IS", "smallest distance between two parts of the face far apart on it (0: self-intersecting)",
        "model units", "below",
        ("CA125", "pdq-self-intersecting", "G-SU-IS: the face intersects itself or comes closer to itself than "
                                           "the profile's limit"),
        Limit(warn=0.02, fail=0.01), self_distance),
    # continuity between faces (cadartifact.analysis.edges): judged per shared edge, not per face
    "edge_gap": CriterionSpec(
        "large face gap (G0)", "G0: largest distance between the two faces along their shared edge", "model units",
        "above",
        ("CA131", "pdq-edge-gap", "G0: the faces of a shared edge are further apart than the profile's limit"),
        Limit(warn=0.01, fail=0.02), None, needs="edges"),
    "edge_angle": CriterionSpec(
        "non-tangent faces (G1)", "G1: largest angle between the two faces' normals along their shared edge",
        "degrees", "above",
        ("CA132", "pdq-edge-angle", "G1: the faces of a shared edge meet at an angle above the profile's limit "
                                    "(and are not sharp by design)"),
        Limit(warn=0.5, fail=1.0), None, needs="edges",
        settings=(Setting("sharp_angle", "sharp_angle", "an angle in degrees with 0 < a <= 180",
                          lambda x: 0 < x <= 180),)),
    "edge_curvature": CriterionSpec(
        "non-smooth faces (G2)",
        "G2: largest relative jump |k1 - k2| / max(|k1|, |k2|) of the normal curvature across a shared edge", "share",
        "above",
        ("CA133", "pdq-edge-curvature", "G2: the normal curvature jumps across a shared edge by more than the "
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
