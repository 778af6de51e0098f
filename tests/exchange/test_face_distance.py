"""The distance of two trimmed faces by projection, both ways, on faces of known answer: parallel flat faces
offset by ``dz`` (one cut shorter: the other's points beyond it are as far as its border), and a cylinder's
quarter against a coaxial one (the radial gap, whatever either's parametrisation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("OCP")

from cadartifact.exchange.face_distance import distance_to_face, edge_tolerance, face_distance, face_samples, \
    face_valid  # noqa: E402
from cadartifact.exchange.occ import make_face  # noqa: E402
from cadartifact.net import ControlNet, clamped_uniform_knots  # noqa: E402


def flat(x1, y1, z, n=(5, 4), degree=2, reverse=False):
    """A flat B-spline face over [0, x1] x [0, y1] at height z (u reversed: another parametrisation)."""
    x = np.linspace(0.0, x1, n[0])[:: -1 if reverse else 1]
    y = np.linspace(0.0, y1, n[1])
    X, Y = np.meshgrid(x, y, indexing="ij")
    points = np.stack([X, Y, np.full_like(X, z)], -1)
    knots = tuple(clamped_uniform_knots(m, degree) for m in n)
    return make_face(ControlNet(points=points, degrees=(degree, degree), knots=knots))


@pytest.mark.parametrize("dz, short, reverse", [(0.01, 1.0, False), (0.3, 0.5, False), (2.0, 0.8, True),
                                                (0.05, 0.25, True)])
def test_parallel_faces_one_cut_shorter(dz, short, reverse):
    a = flat(100.0, 60.0, 0.0)
    b = flat(100.0 * short, 60.0, dz, n=(7, 5), degree=3, reverse=reverse)
    ab, ba = face_distance(a, b)
    assert ba == pytest.approx(dz, abs=1e-9)  # every point of b lies dz above a
    assert ab == pytest.approx(math.hypot(100.0 * (1 - short), dz), abs=1e-6)  # a's far border to b's
    assert edge_tolerance(a) <= 1e-6 and face_valid(a) and face_valid(b)


@pytest.mark.parametrize("r, gap", [(10.0, 0.02), (50.0, 0.5), (5.0, 1.0)])
def test_coaxial_cylinder_pieces(r, gap):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_CylindricalSurface
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

    def piece(radius, start):
        surface = Geom_CylindricalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), radius)
        return BRepBuilderAPI_MakeFace(surface, start, start + math.pi / 2, 0.0, 20.0, 1e-7).Face()

    a, b = piece(r, 0.0), piece(r + gap, 0.0)
    ab, ba = face_distance(a, b)
    assert ab == pytest.approx(gap, abs=1e-7) and ba == pytest.approx(gap, abs=1e-7)
    d = distance_to_face(face_samples(b), a)
    assert np.all(d <= gap + 1e-7) and np.all(d >= gap - 1e-7)
