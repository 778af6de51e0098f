"""Two B-spline faces sharing an edge, with a join of known continuity (tests of continuity between faces).

Face A covers ``x in [-1, 0]``, face B ``x in [0, 1]``, both ``y in [0, 1]``, as graphs ``z = f(x, y)`` of cubic
polynomials, each one Bezier patch (exact). They are sewn (``BRepBuilderAPI_Sewing``) into a shell that shares the
edge ``x = 0``. With ``w(y) = 4 y (1 - y)`` (1 at ``y = 0.5``, 0 at the ends):

* ``smooth``: one cubic across both faces (G-infinity by construction);
* ``g1``: B is ``z = tan(size) x w(y)`` over a plane A: the normal angle is ``atan(tan(size) w(y))`` (``size`` in
  radians), largest (``size``) at ``y = 0.5``;
* ``g1_constant``: B is ``z = tan(size) x``: a crease of ``size`` radians all along the edge;
* ``g2``: A is ``z = a x^2 / 2`` and B ``z = b x^2 / 2`` (``size = (a, b)``): G1, the normal curvature across the
  edge jumps from ``a`` to ``b`` (relative ``|a - b| / max(|a|, |b|)``) all along it;
* ``g0``: B is shifted by ``size w(y)`` in z: a gap of ``size`` at ``y = 0.5``, none at the ends;
* ``g1_curved``: ``g1`` over a curved base shape common to both faces (docs/images/reflection-g1-break.png).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["bezier_face", "joined", "sew", "write_step_shape"]


def _bernstein(t: np.ndarray, p: int) -> np.ndarray:
    return np.stack([math.comb(p, k) * t ** k * (1 - t) ** (p - k) for k in range(p + 1)], axis=1)


def bezier_face(f, x0: float, x1: float, y0: float, y1: float, degree: int = 3):
    """The face of the Bezier patch interpolating ``z = f(x, y)`` (exact for polynomials of degree <= ``degree``
    in each variable) over ``[x0, x1] x [y0, y1]``."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_BezierSurface
    from OCP.gp import gp_Pnt
    from OCP.TColgp import TColgp_Array2OfPnt

    t = np.linspace(0.0, 1.0, degree + 1)
    B = np.linalg.inv(_bernstein(t, degree))
    X, Y = np.meshgrid(x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, indexing="ij")
    Z = np.vectorize(f)(X, Y)
    poles = [B @ C @ B.T for C in (X, Y, Z)]
    arr = TColgp_Array2OfPnt(1, degree + 1, 1, degree + 1)
    for i in range(degree + 1):
        for j in range(degree + 1):
            arr.SetValue(i + 1, j + 1, gp_Pnt(*(float(c[i, j]) for c in poles)))
    return BRepBuilderAPI_MakeFace(Geom_BezierSurface(arr), 1e-7).Face()


def sew(faces, tolerance: float = 1e-6):
    """The faces sewn into one shell (their common edges shared)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing

    sewing = BRepBuilderAPI_Sewing(tolerance)
    for face in faces:
        sewing.Add(face)
    sewing.Perform()
    return sewing.SewedShape()


def joined(kind: str, size=0.0):
    """The sewn shell of faces A and B (see the module's documentation)."""
    w = lambda y: 4 * y * (1 - y)  # noqa: E731
    fa, fb = (lambda x, y: 0.0), None
    tol = 1e-6
    if kind == "smooth":
        fa = fb = lambda x, y: 0.3 * x + 0.2 * x * x - 0.15 * x ** 3 + 0.1 * x * y + 0.05 * y * y
    elif kind == "g1":
        fb = lambda x, y: math.tan(size) * x * w(y)  # noqa: E731
    elif kind == "g1_constant":
        fb = lambda x, y: math.tan(size) * x  # noqa: E731
    elif kind == "g2":
        a, b = size
        fa, fb = (lambda x, y: a * x * x / 2), (lambda x, y: b * x * x / 2)
    elif kind == "g1_curved":
        fa = lambda x, y: 0.5 * (y - 0.5) ** 2 + 0.3 * x * x + 0.2 * x * y  # noqa: E731
        fb = lambda x, y: fa(x, y) + math.tan(size) * x * w(y)  # noqa: E731
    elif kind == "g0":
        fb = lambda x, y: size * w(y)  # noqa: E731
        tol = 2 * size
    else:
        raise ValueError(kind)
    return sew([bezier_face(fa, -1.0, 0.0, 0.0, 1.0), bezier_face(fb, 0.0, 1.0, 0.0, 1.0)], tol)


def write_step_shape(shape, path) -> str:
    """Write an OCCT shape to a STEP file as it stands (no conversion); returns the path."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    writer = STEPControl_Writer()
    writer.Transfer(shape, STEPControl_AsIs)
    if writer.Write(str(path)) != IFSelect_RetDone:
        raise OSError(f"{path}: STEP not written")
    return str(path)
