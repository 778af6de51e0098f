"""Canonical faces: B-spline faces that are exactly a plane, cylinder, cone, sphere or torus, or exactly
straight or circular along one direction (extrusions, revolutions), recognised with OCCT.

A face recognised here carries no artifact along its exact directions (SPEC §4): the reader sets
``ControlNet.canonical`` (a short label) and ``ControlNet.exact`` from :func:`recognise`, and the
analysis (:mod:`cadartifact.analysis.frames`) drops the ripple band of those directions.

How a face is recognised
------------------------
1. The whole surface: OCCT's ``GeomConvert_SurfToAnaSurf`` over the face's UV rectangle. Its answer
   is not trusted alone: the B-spline is sampled on a grid over the same rectangle (at least 9x9, two
   samples per pole and direction) and every sample's distance to the recognised analytic surface
   (closed-form distance to the plane, axis, centre, ...) must be within the tolerance.
2. Otherwise, per direction: isocurves running along it (both ends and 5 to 17 between: one per
   pole across, at the midpoints of equal parts, off the knots) (OCCT's ``VIso(v)`` runs along u,
   ``UIso(u)`` along v), restricted to the face's range, are tested with
   ``GeomConvert_CurveToAnaCurve.ComputeLine_s`` / ``ComputeCircle_s`` and confirmed the same way
   (samples' distances to the line or circle). A direction is exact only if every tested isocurve is
   the same kind; a degenerate isocurve (a pole collapsed to a point) is consistent with any kind.

Tolerance
---------
``RTOL * d`` with ``RTOL = 1e-6`` and ``d`` the diagonal of the sampled face's bounding box:
relative, so the answer does not depend on the file's unit (mm, inch, m); far above the round-off
of an exactly represented conic (rational quadratic circles and spheres sit within ~1e-14 of ``d``,
boxed_sphere's spheres within 4e-14) and far below any ripple a tolerance is set for (1 µm on a 1 m
face; a sphere patch whose poles move by 1e-3 of its radius is rejected).

This module reads geometry only (formats side); any OCCT exception means "not recognised".
"""

from __future__ import annotations

import math

import numpy as np

from ..dependencies import require

require("OCP", "recognising canonical faces")

from OCP.Geom import (  # noqa: E402
    Geom_Circle,
    Geom_ConicalSurface,
    Geom_CylindricalSurface,
    Geom_Line,
    Geom_Plane,
    Geom_SphericalSurface,
    Geom_ToroidalSurface,
)
from OCP.GeomConvert import GeomConvert_CurveToAnaCurve, GeomConvert_SurfToAnaSurf  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402

__all__ = ["RTOL", "ISOCURVES", "NOT_CANONICAL", "recognise", "surface_label"]

#: Tolerance relative to the face's bounding-box diagonal (see the module notes).
RTOL = 1e-6
#: Interior isocurves tested per direction (besides both ends): one per pole across, at least 5, at most 17.
ISOCURVES = (5, 17)
#: What :func:`recognise` returns for a face that is nothing canonical.
NOT_CANONICAL = (None, (None, None))

_MIN_SAMPLES = 9
_MAX_SAMPLES = 65
#: Angle (radians) within which lines count as parallel and circles' axes as one axis (labels only).
_ANGLE = 10 * RTOL


def _xyz(p) -> np.ndarray:
    return np.array(p.Coord(), dtype=float)


def _sample_surface(surface, us, vs) -> np.ndarray:
    """``(len(us), len(vs), 3)`` points of the surface (OCCT's D0)."""
    point = gp_Pnt()
    d0, coord = surface.D0, point.Coord
    out = []
    for u in us:
        for v in vs:
            d0(u, v, point)
            out.append(coord())
    return np.array(out, dtype=float).reshape(len(us), len(vs), 3)


def _sample_curve(curve, ts) -> np.ndarray:
    point = gp_Pnt()
    d0, coord = curve.D0, point.Coord
    out = []
    for t in ts:
        d0(t, point)
        out.append(coord())
    return np.array(out, dtype=float)


def _samples(n_poles: int) -> int:
    """Samples per direction for a confirmation: two per pole, at least 9, at most 65."""
    return int(min(_MAX_SAMPLES, max(_MIN_SAMPLES, 2 * n_poles + 1)))


def _bounds(surface, uv_bounds) -> tuple[float, float, float, float]:
    """The face's UV rectangle clipped to the surface's own range (non-periodic directions).

    Faces' UV bounds may reach round-off (1e-13) outside the knot range, and OCCT's recogniser
    then gives up (two of boxed_sphere's spheres).
    """
    su0, su1, sv0, sv1 = surface.Bounds()
    if uv_bounds is None:
        return su0, su1, sv0, sv1
    u0, u1, v0, v1 = (float(x) for x in uv_bounds)
    if not surface.IsUPeriodic():
        u0, u1 = max(u0, su0), min(u1, su1)
    if not surface.IsVPeriodic():
        v0, v1 = max(v0, sv0), min(v1, sv1)
    return u0, u1, v0, v1


def _fmt(x: float) -> str:
    return f"{x:.4g}"


# ---------------------------------------------------------------- distances to analytic surfaces
def _frame(ax) -> tuple[np.ndarray, np.ndarray]:
    """Origin and unit axis of a gp_Ax1/gp_Ax2/gp_Ax3."""
    return _xyz(ax.Location()), np.array(ax.Direction().Coord(), dtype=float)


def _axial(points: np.ndarray, origin: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Height along the axis and distance from it, per point."""
    d = points - origin
    h = d @ axis
    rho = np.linalg.norm(d - h[..., None] * axis, axis=-1)
    return h, rho


def surface_label(analytic) -> tuple[str, object] | None:
    """Label and distance function ``points (..., 3) -> (...)`` of an OCCT analytic surface, or None.

    Labels: ``"plane"``, ``"cylinder r=4"``, ``"cone half-angle 30°"``, ``"sphere r=12.5"``,
    ``"torus R=10 r=2"`` (4 significant digits, no unit).
    """
    if isinstance(analytic, Geom_Plane):
        o, n = _frame(analytic.Pln().Position())
        return "plane", lambda p: np.abs((p - o) @ n)
    if isinstance(analytic, Geom_CylindricalSurface):
        cyl = analytic.Cylinder()
        o, a = _frame(cyl.Position())
        r = cyl.Radius()
        return f"cylinder r={_fmt(r)}", lambda p: np.abs(_axial(p, o, a)[1] - r)
    if isinstance(analytic, Geom_ConicalSurface):
        cone = analytic.Cone()
        o, a = _frame(cone.Position())
        r, alpha = cone.RefRadius(), cone.SemiAngle()
        # OCCT's cone: radius r + z tan(alpha) at height z; distance to the generator in the meridian plane
        c, s = math.cos(alpha), math.sin(alpha)

        def dist(p):
            h, rho = _axial(p, o, a)
            return np.abs((rho - r) * c - h * s)

        return f"cone half-angle {_fmt(math.degrees(abs(alpha)))}°", dist
    if isinstance(analytic, Geom_SphericalSurface):
        sph = analytic.Sphere()
        centre, r = _xyz(sph.Location()), sph.Radius()
        return f"sphere r={_fmt(r)}", lambda p: np.abs(np.linalg.norm(p - centre, axis=-1) - r)
    if isinstance(analytic, Geom_ToroidalSurface):
        tor = analytic.Torus()
        o, a = _frame(tor.Position())
        big, small = tor.MajorRadius(), tor.MinorRadius()

        def dist(p):
            h, rho = _axial(p, o, a)
            return np.abs(np.hypot(rho - big, h) - small)

        return f"torus R={_fmt(big)} r={_fmt(small)}", dist
    return None


def _whole_surface(surface, bounds, tol: float) -> str | None:
    """The analytic surface's label when OCCT recognises the face and the samples confirm it."""
    u0, u1, v0, v1 = bounds
    analytic = GeomConvert_SurfToAnaSurf(surface).ConvertToAnalytical(tol, u0, u1, v0, v1)
    if analytic is None:
        return None
    known = surface_label(analytic)
    if known is None:
        return None
    label, dist = known
    grid = _sample_surface(surface, np.linspace(u0, u1, _samples(surface.NbUPoles())),
                           np.linspace(v0, v1, _samples(surface.NbVPoles())))
    return label if float(dist(grid).max()) <= tol else None


# ---------------------------------------------------------------- isocurves
def _line_or_circle(curve, t0: float, t1: float, tol: float, n_poles: int):
    """``("line", (origin, direction))``, ``("circle", (centre, normal, radius))``, ``("point", None)`` or None.

    OCCT proposes a line or a circle; samples of the curve over ``[t0, t1]`` must lie within ``tol`` of it.
    """
    pts = _sample_curve(curve, np.linspace(t0, t1, _samples(n_poles)))
    if float(np.linalg.norm(np.ptp(pts, axis=0))) <= tol:
        return "point", None
    line = GeomConvert_CurveToAnaCurve.ComputeLine_s(curve, tol, t0, t1, 0.0, 0.0, 0.0)
    if isinstance(line, Geom_Line):
        o, d = _frame(line.Lin().Position())
        off = np.linalg.norm(np.cross(pts - o, d), axis=-1)
        return ("line", (o, d)) if float(off.max()) <= tol else None
    circle = GeomConvert_CurveToAnaCurve.ComputeCircle_s(curve, tol, t0, t1, 0.0, 0.0, 0.0)
    if isinstance(circle, Geom_Circle):
        circ = circle.Circ()
        c, n = _frame(circ.Axis())
        r = circ.Radius()
        h, rho = _axial(pts, c, n)
        off = np.hypot(rho - r, h)
        return ("circle", (c, n, r)) if float(off.max()) <= tol else None
    return None


def _across(k: int) -> np.ndarray:
    """Where isocurves are tested across a direction, as fractions: both ends and ``k`` midpoints.

    Midpoints of ``k`` equal parts rather than ``linspace``: on uniform knots, equally spaced
    isocurves sit on knots, where an approximated sweep is often exact (NIST CTC-02 has such faces,
    circular to 1e-15 at the knots and 2e-5 off between them).
    """
    return np.concatenate([[0.0], (np.arange(k) + 0.5) / k, [1.0]])


def _direction(surface, bounds, direction: int, tol: float) -> tuple[str | None, str | None]:
    """``(kind, how)`` of one direction: kind "line"/"circle" when every tested isocurve along it is one;
    ``how`` is "extruded"/"ruled" (parallel or not) or "revolved"/"swept" (coaxial or not)."""
    u0, u1, v0, v1 = bounds
    poles = (surface.NbUPoles(), surface.NbVPoles())
    if direction == 0:  # along u: curves at fixed v
        iso, (t0, t1), (s0, s1), n_poles, n_across = surface.VIso, (u0, u1), (v0, v1), *poles
    else:
        iso, (t0, t1), (s0, s1), n_poles, n_across = surface.UIso, (v0, v1), (u0, u1), *poles[::-1]
    kind, shapes = None, []
    for s in s0 + (s1 - s0) * _across(int(np.clip(n_across, *ISOCURVES))):
        found = _line_or_circle(iso(float(s)), t0, t1, tol, n_poles)
        if found is None:
            return None, None
        k, shape = found
        if k == "point":
            continue
        if kind is None:
            kind = k
        elif k != kind:
            return None, None
        shapes.append(shape)
    if kind is None or len(shapes) < 3:
        return None, None
    if kind == "line":
        d0 = shapes[0][1]
        parallel = all(np.linalg.norm(np.cross(d0, d)) <= _ANGLE for _, d in shapes)
        return "line", "extruded" if parallel else "ruled"
    c0, n0, _ = shapes[0]
    scale = max(r for _, _, r in shapes)
    coaxial = all(np.linalg.norm(np.cross(n0, n)) <= _ANGLE
                  and np.linalg.norm(np.cross(c - c0, n0)) <= tol + _ANGLE * scale for c, n, _ in shapes)
    return "circle", "revolved" if coaxial else "swept"


def _direction_label(kinds, hows) -> str:
    names = ("u", "v")
    parts = []
    for k, how, name in zip(kinds, hows, names):
        if k is not None:
            parts.append(f"{how}: {'straight' if k == 'line' else 'circular'} in {name}")
    if len(parts) == 2 and kinds[0] == kinds[1] == "line":
        return "ruled: straight in u and v"
    return "; ".join(parts)


def recognise(surface, uv_bounds=None) -> tuple[str | None, tuple]:
    """What a B-spline (or Bézier) face exactly is, if anything canonical.

    Parameters
    ----------
    surface : Geom_BSplineSurface or Geom_BezierSurface
    uv_bounds : (u0, u1, v0, v1), optional
        The face's parameter rectangle (default: the surface's own bounds); clipped to the
        surface's range in non-periodic directions.

    Returns
    -------
    label : str or None
        ``"sphere r=12.5"``, ``"cylinder r=4"``, ``"plane"``, ``"torus R=10 r=2"``,
        ``"cone half-angle 30°"``, ``"revolved: circular in u"``, ``"extruded: straight in v"``,
        ``"ruled: straight in v"`` (lines not parallel), ``"swept: circular in u"`` (circles not
        coaxial), or None.
    exact : (str or None, str or None)
        ``("surface", "surface")`` for a canonical surface; per direction ``"line"``/``"circle"``
        otherwise (entries of :data:`cadartifact.net.EXACT_KINDS`); ``(None, None)`` when nothing is
        recognised or OCCT fails on the face.
    """
    try:
        bounds = _bounds(surface, uv_bounds)
        u0, u1, v0, v1 = bounds
        if not (u1 > u0 and v1 > v0) or not all(math.isfinite(x) for x in bounds):
            return NOT_CANONICAL
        coarse = _sample_surface(surface, np.linspace(u0, u1, _MIN_SAMPLES), np.linspace(v0, v1, _MIN_SAMPLES))
        size = float(np.linalg.norm(np.ptp(coarse.reshape(-1, 3), axis=0)))
        if not size > 0 or not math.isfinite(size):
            return NOT_CANONICAL
        tol = RTOL * size
        label = _whole_surface(surface, bounds, tol)
        if label is not None:
            return label, ("surface", "surface")
        found = [_direction(surface, bounds, d, tol) for d in (0, 1)]
    except Exception:  # noqa: BLE001 - any OCCT failure (Standard_Failure and its kin) means "not recognised"
        return NOT_CANONICAL
    kinds = tuple(k for k, _ in found)
    if kinds == (None, None):
        return NOT_CANONICAL
    return _direction_label(kinds, [h for _, h in found]), kinds
