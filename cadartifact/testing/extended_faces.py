"""Generated faces extended beyond their trim (issue 23): a clamped face sampling a smooth shape, its surface
extended by a few per cent along its end tangents on some sides, the extension bent a little (a crease at the
join) and joined with a knot of multiplicity ``p`` or ``p - 1``, the face trimmed back to ``[0, 1]``, past it
by rounding, or a third of the way into the extension. Shared by the tests (not a test module itself)."""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots
from cadartifact.numerics.splines import basis_matrix

SIDES = ("u0", "u1", "v0", "v1")
TRIMS = ("back", "rounding", "third")


def smooth_face(n=(9, 8), degree=3, size=100.0, amplitude=4.0, seed=0) -> ControlNet:
    """A clamped uniform face whose poles sample a smooth bump at their Greville abscissae."""
    rng = np.random.default_rng(seed)
    kx, ky = rng.uniform(0.6, 1.4, 2)
    px, py = rng.uniform(0, np.pi, 2)
    tu, tv = (clamped_uniform_knots(m, degree) for m in n)
    gu = np.array([tu[i + 1: i + degree + 1].mean() for i in range(n[0])])
    gv = np.array([tv[i + 1: i + degree + 1].mean() for i in range(n[1])])
    X, Y = np.meshgrid(gu, gv, indexing="ij")
    Z = amplitude * np.sin(kx * np.pi * X + px) * np.cos(ky * np.pi * Y + py)
    return ControlNet(points=np.stack([size * X, size * Y, Z], -1), degrees=(degree, degree), knots=(tu, tv))


def bordered_bump_face(n=(10, 9), degree=3, size=100.0, amplitude=2.0, where=0.06, width=0.06, seed=0) -> ControlNet:
    """:func:`smooth_face` (amplitude 1) with a Gaussian bump of ``amplitude`` and ``width`` (of the face's side)
    centred ``where`` from its ``u = 0`` border, half way along it: content near an open border."""
    face = smooth_face(n, degree, size, 1.0, seed)
    P = np.array(face.points, float)
    X, Y = P[..., 0] / size, P[..., 1] / size
    P[..., 2] += amplitude * np.exp(-((X - where) ** 2 + (Y - 0.5) ** 2) / (2.0 * width ** 2))
    return face.replace(points=P)


def _extend_axis(P, t, p, ext, sides, bend, normal_sign):
    """Extend one direction (axis 0 of ``P``) at its start/end by ``ext`` of the range with a Bezier span joined
    at multiplicity ``p`` (C1 along the tangent, then bent by ``bend`` of the extension's length)."""
    n = len(P)
    spans = n - p
    lo, hi = t[p], t[n]
    L = hi - lo
    if sides[0]:
        d = P[1] - P[0]
        E = [P[0] - k * (ext * spans) * d for k in range(p, 0, -1)]
        nrm = np.cross(d, P[0] - P[0][::-1] if False else np.gradient(P[0], axis=0))
        nrm /= np.maximum(np.linalg.norm(nrm, axis=-1, keepdims=True), 1e-300)
        E = [e + normal_sign * bend * (p - j) / p * ext * L * 100 * nrm for j, e in enumerate(E)]
        P = np.concatenate([np.array(E), P])
        t = np.r_[[lo - ext * L] * (p + 1), [lo] * p, t[p + 1:]]
    if sides[1]:
        n = len(P)
        d = P[-1] - P[-2]
        E = [P[-1] + k * (ext * spans) * d for k in range(1, p + 1)]
        nrm = np.cross(d, np.gradient(P[-1], axis=0))
        nrm /= np.maximum(np.linalg.norm(nrm, axis=-1, keepdims=True), 1e-300)
        E = [e + normal_sign * bend * (j + 1) / p * ext * L * 100 * nrm for j, e in enumerate(E)]
        P = np.concatenate([P, np.array(E)])
        t = np.r_[t[: len(t) - p - 1], [hi] * p, [hi + ext * L] * (p + 1)]
    return P, t


def _lower(t, P, p, axis, value):
    """The same surface with one copy of the join knot ``value`` removed (exact where it is C1 there): least
    squares on dense samples along ``axis``."""
    t2 = list(t)
    t2.remove(value)
    t2 = np.asarray(t2)
    n2 = len(t2) - p - 1
    s = np.linspace(t[p], t[len(t) - p - 1], 12 * len(t))
    A = basis_matrix(np.asarray(t), p, s, len(t) - p - 1, False)
    B = basis_matrix(t2, p, s, n2, False)
    Pm = np.moveaxis(P, axis, 0)
    rows = np.tensordot(A, Pm, axes=(1, 0))
    Q = np.linalg.lstsq(B, rows.reshape(len(s), -1), rcond=None)[0].reshape((n2,) + Pm.shape[1:])
    return t2, np.moveaxis(Q, 0, axis)


def extended_face(face: ControlNet, sides=("u0",), ext=0.02, bend=0.0, mult=None, trim="back") -> ControlNet:
    """``face`` extended by ``ext`` of its range on ``sides`` (of :data:`SIDES`), bent by ``bend`` (0: smooth),
    joined at multiplicity ``mult`` (default the degree; ``p - 1`` only when smooth), trimmed (:data:`TRIMS`)."""
    p = face.degrees[0]
    mult = p if mult is None else mult
    P = np.asarray(face.points, float)
    tu, tv = (np.asarray(k, float) for k in face.knots)
    P, tu = _extend_axis(P, tu, p, ext, ("u0" in sides, "u1" in sides), bend, 1.0)
    Pv, tv = _extend_axis(np.swapaxes(P, 0, 1), tv, p, ext, ("v0" in sides, "v1" in sides), bend, -1.0)
    P = np.swapaxes(Pv, 0, 1)
    if mult < p:
        for axis, t, ends in ((0, tu, ("u0", "u1")), (1, tv, ("v0", "v1"))):
            for side, value in zip(ends, (0.0, 1.0)):
                if side in sides:
                    t, P = _lower(t, P, p, axis, value)
            tu, tv = (t, tv) if axis == 0 else (tu, t)
    past = {"back": 0.0, "rounding": 1e-9, "third": ext / 3}[trim]
    b = [0.0 - past * ("u0" in sides), 1.0 + past * ("u1" in sides),
         0.0 - past * ("v0" in sides), 1.0 + past * ("v1" in sides)]
    return ControlNet(points=P, degrees=face.degrees, knots=(tu, tv), uv_bounds=tuple(b), unit=face.unit)


def jointed_face(pieces=2, direction=0, kind="C0", degree=3, spans=4, size=100.0, seed=0, amps=None) -> ControlNet:
    """A face of ``pieces`` smooth pieces along ``direction`` (each ``spans`` uniform spans sampling its own bump)
    joined at knots of multiplicity ``degree``: a crease (``"C0"``: the pieces' tangents differ across the join)
    or a G1 join (``"G1"``: the poles either side of the join collinear, at different distances). ``amps``: each
    piece's bump amplitude and frequency factor (0: a flat piece, its slope only), instead of random ones."""
    rng = np.random.default_rng(seed)
    p = degree
    m = spans + p  # poles per piece along the direction
    other = 6 + int(rng.integers(0, 3))
    tv = clamped_uniform_knots(other, p)
    gv = np.array([tv[i + 1: i + p + 1].mean() for i in range(other)])
    rows, knots = [], [0.0] * (p + 1)
    x0 = 0.0
    for k in range(pieces):
        gu = np.array([clamped_uniform_knots(m, p)[i + 1: i + p + 1].mean() for i in range(m)])
        X = x0 + gu
        amp, freq = rng.uniform(1.0, 3.0), rng.uniform(0.5, 1.2)
        if amps is not None:
            amp, freq = float(amps[k]), 2.5 * freq
        Z = amp * np.sin(freq * np.pi * (X[:, None] - x0)) * np.cos(np.pi * gv[None, :])
        Z += 6.0 * (-1) ** k * (X[:, None] - x0)  # each piece its own slope: the join is a crease
        pts = np.stack([size * np.broadcast_to(X[:, None], Z.shape), size * np.broadcast_to(gv[None, :], Z.shape),
                        Z], -1)
        if k:
            pts = pts - pts[0] + rows[-1][-1]  # share the join's row of poles
            if kind == "G1":  # the first inner pole on the line through the previous piece's last two
                d = rows[-1][-1] - rows[-1][-2]
                pts[1] = pts[0] + 1.3 * d
            pts = pts[1:]
        rows.append(pts)
        x0 = x0 + 1.0
        inner = list(np.linspace(k, k + 1, spans + 1)[1:-1])
        knots += inner + ([float(k + 1)] * (p if k < pieces - 1 else p + 1))
    P = np.concatenate(rows)
    tu = np.asarray(knots) / pieces
    net = ControlNet(points=P, degrees=(p, p), knots=(tu, tv))
    if direction == 1:
        net = ControlNet(points=np.swapaxes(P, 0, 1), degrees=(p, p), knots=(tv, tu))
    return net


def graded_face(n=(10, 9), degree=3, size=100.0, amplitude=3.0, grade=0.5, seed=0) -> ControlNet:
    """:func:`smooth_face` with graded (non-uniform) interior knots: span ``k`` of ``m`` grows as ``1 + grade k /
    m``; the poles sample the same bump at their Greville abscissae, so the surface's parametrisation is not its
    intent's (the advice's refit is parametrised otherwise: the old pcurves no longer address the trim)."""
    base = smooth_face(n, degree, size, amplitude, seed)
    knots = []
    for m in n:
        spans = m - degree
        widths = 1.0 + grade * np.arange(spans) / spans
        inner = np.cumsum(widths)[:-1] / widths.sum()
        knots.append(np.r_[[0.0] * (degree + 1), inner, [1.0] * (degree + 1)])
    return base.replace(knots=tuple(knots))


def extended_shell(path, *, pieces=2, sides=("u0", "u1", "v0", "v1"), ext=0.02, mult=None, unit="MM", seed=0,
                   grade=0.5, circle=False):
    """A STEP shell of ``pieces`` faces side by side along u, sharing their edges, each on a surface extended
    ``ext`` past its trim on ``sides`` (:func:`extended_face`, joined at multiplicity ``mult``) over graded knots
    (:func:`graded_face`); ``circle``: the first face is a disc cut from its surface by a circle of the uv square (a
    trim that is no iso-line; then it stands alone). Written in ``unit`` (``write.step.unit``). Returns ``path``."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire, \
        BRepBuilderAPI_Sewing
    from OCP.BRep import BRep_Builder
    from OCP.BRepLib import BRepLib
    from OCP.Geom2d import Geom2d_Circle
    from OCP.gp import gp_Ax2d, gp_Dir2d, gp_Pnt2d
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopoDS import TopoDS_Compound

    from cadartifact.exchange.occ import net_from_surface, occ_surface, quiet_occt
    from cadartifact.exchange.step import write_settings
    from cadartifact.net import NetOrigin

    whole = graded_face(n=(6 * pieces + 4, 9), size=100.0, grade=grade, seed=seed)
    sewing = BRepBuilderAPI_Sewing(1e-2)  # a join lowered to p - 1 moves the border by up to ~0.006
    extra = []
    for k in range(pieces):
        piece = occ_surface(whole)
        piece.Segment(k / pieces, (k + 1) / pieces, 0.0, 1.0)
        net = net_from_surface(piece, origin=NetOrigin(file=None, face=k))
        tu = (np.asarray(net.knots[0]) - k / pieces) * pieces  # each piece over [0, 1]
        net = net.replace(knots=(tu, np.asarray(net.knots[1])), uv_bounds=None)
        net = extended_face(net, sides=sides, ext=ext, mult=mult)
        surface = occ_surface(net)
        if circle and k == 0:
            edge = BRepBuilderAPI_MakeEdge(Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.5, 0.5), gp_Dir2d(1.0, 0.0)), 0.42),
                                           surface).Edge()
            BRepLib.BuildCurves3d_s(edge)
            face = BRepBuilderAPI_MakeFace(surface, BRepBuilderAPI_MakeWire(edge).Wire()).Face()
            extra.append(face)
            continue
        sewing.Add(BRepBuilderAPI_MakeFace(surface, 0.0, 1.0, 0.0, 1.0, 1e-7).Face())
    sewing.Perform()
    compound = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(compound)
    for face in extra:
        builder.Add(compound, face)
    builder.Add(compound, sewing.SewedShape())
    writer = STEPControl_Writer()
    with quiet_occt(), write_settings(unit, None):
        if writer.Transfer(compound, STEPControl_AsIs) != IFSelect_RetDone:
            raise RuntimeError("OCCT could not translate the shell")
        if writer.Write(str(path)) != IFSelect_RetDone:
            raise RuntimeError(f"cannot write {path}")
    return path
