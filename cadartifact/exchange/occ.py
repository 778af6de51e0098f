"""OCCT surfaces <-> control nets, and OCCT's own evaluator (the "measured" road).

This module is the only place that turns OCP geometry into :class:`ControlNet`
objects and back. It does no analysis.

Reading rules
-------------
- A face's surface is ``BRep_Tool.Surface_s(face)`` (location applied), with
  ``Geom_RectangularTrimmedSurface`` unwrapped to its basis surface.
- ``Geom_BSplineSurface`` -> kind ``"bspline"``; ``Geom_BezierSurface`` -> ``"bezier"``
  (clamped knots ``[0]*(p+1) + [1]*(p+1)``). Analytic faces (plane, cylinder, cone,
  sphere, torus) are counted in ``skipped``. Other freeform faces (revolution,
  extrusion, offset, ...) are counted too unless ``convert=True``: then the surface,
  trimmed to the face's UV rectangle, is converted with
  ``GeomConvert.SurfaceToBSplineSurface_s`` (kind ``"converted"``; the net covers the
  face's UV rectangle, and ``uv_bounds`` are the converted surface's own bounds).
- Poles, weights, knots and multiplicities are read one index at a time (the bulk
  ``Weights()`` accessor has crashed on rational surfaces).
- Every net's ``canonical`` and ``exact`` come from :func:`cadartifact.exchange.canonical.recognise`
  on the face's surface and UV rectangle (exact planes, cylinders, cones, spheres, tori; faces
  exactly straight or circular along a direction), unless ``recognise=False``.

Knot vectors
------------
``ControlNet.knots`` holds flat knot sequences in OCCT's convention: pole ``i``
(0-based) drives flat basis function ``i`` (and ``i + n`` when periodic).
Non-periodic: exactly OCCT's ``UKnotSequence`` (``n + p + 1`` knots).
Periodic: OCCT keeps the ``n`` distinct poles and a flat sequence of
``sum(mults) + 2 (p + 1 - m_first)`` knots, which is ``n + 2p + 1`` only when the
seam knot is simple. We keep OCCT's sequence as the prefix and continue it
periodically to ``n + 2p + 1`` knots, so every net has the same layout
(:func:`periodic_flat_knots`); :func:`occ_surface` folds it back exactly.
"""

from __future__ import annotations

import contextlib

import numpy as np

from ..dependencies import require
from ..errors import InvalidNetError, OptionError
from ..net import ControlNet, NetOrigin

require("OCP", "reading and evaluating CAD surfaces")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.Geom import (  # noqa: E402
    Geom_BezierSurface,
    Geom_BSplineSurface,
    Geom_RectangularTrimmedSurface,
)
from OCP.GeomConvert import GeomConvert  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.Message import Message  # noqa: E402
from OCP.Standard import Standard_Failure  # noqa: E402
from OCP.TColgp import TColgp_Array2OfPnt  # noqa: E402
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal, TColStd_Array2OfReal  # noqa: E402
from OCP.TopAbs import TopAbs_FACE  # noqa: E402
from OCP.TopExp import TopExp_Explorer  # noqa: E402
from OCP.TopoDS import TopoDS, TopoDS_Shape  # noqa: E402

__all__ = [
    "ANALYTIC_KINDS",
    "FREEFORM_KINDS",
    "quiet_occt",
    "surface_kind",
    "net_from_surface",
    "nets_from_shape",
    "periodic_flat_knots",
    "occ_surface",
    "make_face",
    "evaluate_grid",
]

#: Geom class name -> kind reported in ``LoadResult.skipped``.
_KIND_OF_CLASS = {
    "Geom_BSplineSurface": "bspline",
    "Geom_BezierSurface": "bezier",
    "Geom_Plane": "plane",
    "Geom_CylindricalSurface": "cylinder",
    "Geom_ConicalSurface": "cone",
    "Geom_SphericalSurface": "sphere",
    "Geom_ToroidalSurface": "torus",
    "Geom_SurfaceOfRevolution": "revolution",
    "Geom_SurfaceOfLinearExtrusion": "extrusion",
    "Geom_OffsetSurface": "offset",
}

#: Analytic kinds: always skipped (their "net" is not a design net).
ANALYTIC_KINDS = ("plane", "cylinder", "cone", "sphere", "torus")
#: Freeform kinds read directly.
FREEFORM_KINDS = ("bspline", "bezier")


@contextlib.contextmanager
def quiet_occt():
    """Silence OCCT's console printers (STEP parse errors, transfer statistics) for the block.

    The default messenger's printers are removed and put back afterwards, so other
    users of OCCT in the same process keep their output.
    """
    messenger = Message.DefaultMessenger_s()
    saved = list(messenger.Printers())
    for printer in saved:
        messenger.RemovePrinter(printer)
    try:
        yield
    finally:
        for printer in saved:
            messenger.AddPrinter(printer)


def surface_kind(surface) -> tuple[str, object]:
    """Classify a Geom surface.

    Returns
    -------
    kind : str
        ``"bspline"``, ``"bezier"``, one of :data:`ANALYTIC_KINDS`, ``"revolution"``,
        ``"extrusion"``, ``"offset"``, or the lower-case class name without ``Geom_``
        for anything else (e.g. ``"geomplate_surface"``); ``"none"`` for a face without surface.
    basis : Geom_Surface or None
        The surface with rectangular trims unwrapped.
    """
    if surface is None:
        return "none", None
    while isinstance(surface, Geom_RectangularTrimmedSurface):
        surface = surface.BasisSurface()
    name = surface.DynamicType().Name()
    kind = _KIND_OF_CLASS.get(name)
    if kind is None:
        kind = name.removeprefix("Geom_").lower()
    return kind, surface


# ---------------------------------------------------------------- knots
def periodic_flat_knots(knots: np.ndarray, mults: np.ndarray, degree: int) -> np.ndarray:
    """OCCT's periodic flat knot sequence, continued to ``n + 2p + 1`` knots.

    Parameters
    ----------
    knots : (k,) float
        Distinct knots of one period, first to last (OCCT's ``UKnot(1..k)``).
    mults : (k,) int
        Their multiplicities (``mults[0] == mults[-1]`` for a periodic spline).
    degree : int
        Degree ``p``.

    Returns
    -------
    flat : (n + 2p + 1,) float
        ``t_{j + m_0 - 1 - p}`` for ``j = 0 .. n + 2p``, where ``t_0 .. t_{n-1}`` are one
        period's knots with multiplicity (the last knot excluded), ``t_{j+n} = t_j + T``,
        ``T = knots[-1] - knots[0]`` and ``n = sum(mults) - mults[-1]`` poles.
        The first ``sum(mults) + 2 (p + 1 - m_0)`` entries equal OCCT's ``UKnotSequence``.
    """
    knots = np.asarray(knots, dtype=float)
    mults = np.asarray(mults, dtype=int)
    base = np.repeat(knots[:-1], mults[:-1])
    n = len(base)
    period = knots[-1] - knots[0]
    j = np.arange(n + 2 * degree + 1) + int(mults[0]) - 1 - degree
    wraps = np.floor_divide(j, n)
    flat = base[np.mod(j, n)] + wraps * period
    # the seam knot one period on is the last knot itself (no rounding from adding T)
    flat[(np.mod(j, n) < mults[0]) & (wraps == 1)] = knots[-1]
    return flat


def _fold_knots(flat: np.ndarray, degree: int, n: int, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Distinct knots and multiplicities from a flat sequence (inverse of the flat layouts)."""
    flat = np.asarray(flat, dtype=float)
    if periodic:
        # one period t_p .. t_{n+p}; a seam knot's copies reach just outside it, so count in the whole sequence
        values = np.unique(flat[degree:n + degree + 1])
        return values, np.array([np.count_nonzero(flat == x) for x in values])
    values, mults = np.unique(flat, return_counts=True)
    return values, mults


# ---------------------------------------------------------------- surface -> net
def _read_knots(surface, direction: str, degree: int, n: int, periodic: bool) -> np.ndarray:
    count = getattr(surface, f"Nb{direction}Knots")()
    knot = getattr(surface, f"{direction}Knot")
    mult = getattr(surface, f"{direction}Multiplicity")
    values = np.array([knot(i) for i in range(1, count + 1)], dtype=float)
    mults = np.array([mult(i) for i in range(1, count + 1)], dtype=int)
    if periodic:
        return periodic_flat_knots(values, mults, degree)
    return np.repeat(values, mults)


def net_from_surface(surface, *, origin: NetOrigin, uv_bounds=None, canonical: str | None = None,
                     exact=(None, None), trim_loops: tuple = ()) -> ControlNet:
    """Build a :class:`ControlNet` from a ``Geom_BSplineSurface`` or ``Geom_BezierSurface``.

    Parameters
    ----------
    surface : Geom_BSplineSurface or Geom_BezierSurface
    origin : NetOrigin
        Where the face came from (its ``kind`` is kept).
    uv_bounds : (u0, u1, v0, v1), optional
        The face's parameter bounds.
    canonical, exact
        What the face exactly is (:func:`cadartifact.exchange.canonical.recognise`), stored on the net.
    trim_loops : tuple of (k, 2) float
        The face's wires in the surface's parameters (:func:`cadartifact.exchange.trim_loops.face_loops`).

    Returns
    -------
    ControlNet
        Points ``(nu, nv, 3)`` in OCCT's units, weights ``(nu, nv)`` when the surface is
        rational in either direction, OCCT's flat knots (see the module notes).

    Raises
    ------
    InvalidNetError
        Non-finite or all-coincident poles.
    """
    nu, nv = surface.NbUPoles(), surface.NbVPoles()
    pole = surface.Pole
    points = np.array([[pole(i, j).Coord() for j in range(1, nv + 1)] for i in range(1, nu + 1)], dtype=float)
    weights = None
    if surface.IsURational() or surface.IsVRational():
        weight = surface.Weight
        weights = np.array([[weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)], dtype=float)
    p, q = surface.UDegree(), surface.VDegree()
    if isinstance(surface, Geom_BezierSurface):
        knots = (np.repeat([0.0, 1.0], p + 1), np.repeat([0.0, 1.0], q + 1))
        periodic = (False, False)
    else:
        periodic = (bool(surface.IsUPeriodic()), bool(surface.IsVPeriodic()))
        knots = (_read_knots(surface, "U", p, nu, periodic[0]), _read_knots(surface, "V", q, nv, periodic[1]))
    return ControlNet(points=points, weights=weights, degrees=(p, q), knots=knots, periodic=periodic,
                      uv_bounds=uv_bounds, unit="mm", origin=origin, canonical=canonical, exact=exact,
                      trim_loops=trim_loops)


def _convert(surface, face) -> Geom_BSplineSurface:
    """Convert a freeform surface, trimmed to the face's UV rectangle, to a B-spline (OCCT)."""
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    trimmed = Geom_RectangularTrimmedSurface(surface, u0, u1, v0, v1)
    return GeomConvert.SurfaceToBSplineSurface_s(trimmed)


def iter_faces(shape: TopoDS_Shape):
    """Yield ``(index, face)`` in ``TopExp_Explorer`` order (every face counted)."""
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    index = 0
    while explorer.More():
        yield index, TopoDS.Face_s(explorer.Current())
        index += 1
        explorer.Next()


def nets_from_shape(shape: TopoDS_Shape, *, file: str | None = None, convert: bool = False,
                    face_name=None, recognise: bool = True) -> tuple[list[ControlNet], int, dict[str, int], list[str]]:
    """Extract the control nets of every analysable face of a shape.

    Parameters
    ----------
    shape : TopoDS_Shape
    file : str, optional
        Label recorded in each net's origin (file path, or a name for in-memory shapes).
    convert : bool
        Convert revolution/extrusion/offset/other freeform faces to B-splines.
    face_name : callable(face) -> str or None, optional
        Name lookup (e.g. from the STEP entity).
    recognise : bool
        Recognise canonical faces (:func:`cadartifact.exchange.canonical.recognise`: exact planes,
        cylinders, cones, spheres, tori, and faces exactly straight or circular along a direction)
        and set each net's ``canonical`` and ``exact``; False leaves them None.

    Returns
    -------
    nets : list of ControlNet
        In face order; ``origin.face`` is the face index over *all* faces.
    faces_total : int
    skipped : dict str -> int
        Faces not analysed, by kind (plus ``"degenerate"`` for nets whose poles all
        coincide or are not finite, and ``"conversion failed"``).
    messages : list of str
        One line per skipped degenerate/failed face.
    """
    nets: list[ControlNet] = []
    skipped: dict[str, int] = {}
    messages: list[str] = []
    where = file or "<shape>"
    from .canonical import recognise as recognise_face
    from .trim_loops import face_loops
    total = 0
    for index, face in iter_faces(shape):
        total += 1
        surface = BRep_Tool.Surface_s(face)
        kind, basis = surface_kind(surface)
        if kind not in FREEFORM_KINDS:
            if kind in ANALYTIC_KINDS or kind == "none" or not convert:
                skipped[kind] = skipped.get(kind, 0) + 1
                continue
            try:
                basis = _convert(surface, face)
            except Standard_Failure as exc:
                skipped["conversion failed"] = skipped.get("conversion failed", 0) + 1
                messages.append(f"{where}: face {index} ({kind}) could not be converted to a B-spline: {exc}")
                continue
            uv = basis.Bounds()
            kind = "converted"
            loops = ()  # the converted surface's parameters are not the pcurves'
        else:
            uv = BRepTools.UVBounds_s(face)
            loops = face_loops(face)
        name = face_name(face) if face_name is not None else None
        entity_of = getattr(face_name, "entity", None)  # STEP: the face's #id in the file
        entity = entity_of(face) if entity_of is not None else None
        canonical, exact = recognise_face(basis, uv) if recognise else (None, (None, None))
        try:
            nets.append(net_from_surface(basis, origin=NetOrigin(file=file, face=index, name=name, kind=kind,
                                                                 entity=entity),
                                         uv_bounds=uv, canonical=canonical, exact=exact, trim_loops=loops))
        except InvalidNetError as exc:
            skipped["degenerate"] = skipped.get("degenerate", 0) + 1
            messages.append(f"skipped face: {exc}")
    return nets, total, skipped, messages


# ---------------------------------------------------------------- net -> surface
def _array1(values, kind=float):
    arr = TColStd_Array1OfReal(1, len(values)) if kind is float else TColStd_Array1OfInteger(1, len(values))
    for i, x in enumerate(values, start=1):
        arr.SetValue(i, kind(x))
    return arr


def occ_surface(net: ControlNet) -> Geom_BSplineSurface:
    """Rebuild the exact OCCT surface of a B-spline net.

    Parameters
    ----------
    net : ControlNet
        With degrees and knots (periodic and rational nets are handled).

    Returns
    -------
    Geom_BSplineSurface
        Same poles, weights, distinct knots, multiplicities, degrees and periodic flags
        as the surface the net was read from.

    Raises
    ------
    OptionError
        For a cage (no degrees/knots).
    """
    if not net.is_bspline:
        raise OptionError("net", "a B-spline net with degrees and knots", f"a {net.origin.kind} cage {net.origin.label()}")
    nu, nv = net.shape
    (p, q), (pu, pv) = net.degrees, net.periodic
    ku, mu = _fold_knots(net.knots[0], p, nu, pu)
    kv, mv = _fold_knots(net.knots[1], q, nv, pv)
    poles = TColgp_Array2OfPnt(1, nu, 1, nv)
    pts = net.points
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*pts[i, j]))
    args = [poles]
    if net.weights is not None:
        weights = TColStd_Array2OfReal(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv):
                weights.SetValue(i + 1, j + 1, float(net.weights[i, j]))
        args.append(weights)
    try:
        return Geom_BSplineSurface(*args, _array1(ku), _array1(kv), _array1(mu, int), _array1(mv, int),
                                   p, q, pu, pv)
    except Standard_Failure as exc:
        raise InvalidNetError(f"{net.origin.label()}: OCCT rejects the B-spline data: {exc}") from None


def make_face(net: ControlNet, tolerance: float = 1e-7):
    """A ``TopoDS_Face`` on :func:`occ_surface`, bounded by ``net.uv_bounds`` when given."""
    surface = occ_surface(net)
    if net.uv_bounds is not None:
        u0, u1, v0, v1 = net.uv_bounds
        builder = BRepBuilderAPI_MakeFace(surface, u0, u1, v0, v1, tolerance)
    else:
        builder = BRepBuilderAPI_MakeFace(surface, tolerance)
    if not builder.IsDone():
        raise InvalidNetError(f"{net.origin.label()}: OCCT cannot build a face on this net")
    return builder.Face()


def evaluate_grid(net: ControlNet, u, v) -> np.ndarray:
    """Evaluate the real surface with OCCT on the outer grid ``u x v``.

    Parameters
    ----------
    net : ControlNet
        A B-spline net (see :func:`occ_surface`).
    u : (a,) float
        Parameters in the net's u range ``[t_p, t_{m-p-1}]`` (any value when u is periodic).
    v : (b,) float
        Same in v.

    Returns
    -------
    S : (a, b, 3) float
        ``S[i, j] = surface(u[i], v[j])`` from ``Geom_BSplineSurface.D0``
        (OCCT's span-cached evaluator, per point from Python: about 1.5 microseconds per
        point for bicubic nets, about 2.2 for rational degree 6x10 ones, on an idle core).

    Raises
    ------
    OptionError
        For a cage, or parameters outside a non-periodic range.
    """
    surface = occ_surface(net)
    u = np.asarray(u, dtype=float).ravel()
    v = np.asarray(v, dtype=float).ravel()
    bounds = surface.Bounds()
    for name, x, (lo, hi), periodic in (("u", u, bounds[:2], net.periodic[0]), ("v", v, bounds[2:], net.periodic[1])):
        if not np.all(np.isfinite(x)):
            raise OptionError(name, "finite parameter values", "NaN or infinite values")
        slack = 1e-9 * max(1.0, hi - lo)
        if not periodic and len(x) and (x.min() < lo - slack or x.max() > hi + slack):
            raise OptionError(name, f"parameters within [{lo:g}, {hi:g}]", f"[{x.min():g}, {x.max():g}]")
    out = []
    append = out.append
    point = gp_Pnt()
    d0 = surface.D0
    coord = point.Coord
    vs = v.tolist()
    for uu in u.tolist():
        for vv in vs:
            d0(uu, vv, point)
            append(coord())
    return np.array(out, dtype=float).reshape(len(u), len(v), 3)
