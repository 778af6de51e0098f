"""Reflection lines (cadartifact.viz.reflection): each defect shows in the stripes' phase at its known place.

A crease inside a face and a G1 break between two faces make the phase *jump* by the amount the reflection law
gives for the two faces' exact normals (the independent road: the formula on the normals of the generating
shape, against the phase read from the drawn fine grid); ripple makes it *oscillate* with the ripple's period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("pyvista")

from cadartifact.cli.app import app  # noqa: E402
from cadartifact.net import ControlNet, NetOrigin  # noqa: E402
from cadartifact.testing.outcomes import no_traceback  # noqa: E402
from cadartifact.viz.facemaps import face_maps  # noqa: E402
from cadartifact.viz.reflection import centred, face_phase, reflection_phase, stripe_count, stripes  # noqa: E402
from cadartifact.viz.view import camera  # noqa: E402


def _net(f, x0, x1, nx=12, ny=10, degrees=(3, 3), face=0):
    """Poles ``(x, y, f(x, y))`` on a grid: exact for f linear in x and y (linear precision)."""
    x, y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(0.0, 1.0, ny), indexing="ij")
    return ControlNet.from_points(np.stack([x, y, f(x, y)], -1), degrees=degrees,
                                  origin=NetOrigin(face=face, kind="bspline"))


def _tilted(theta):
    return np.array([-math.sin(theta), 0.0, math.cos(theta)])


def _jump(theta, towards, up):
    """The reflection law on the exact normals: |phase(tilted by theta) - phase(flat)|, wrapped."""
    d = reflection_phase(_tilted(theta), towards, up) - reflection_phase(np.array([0, 0, 1.0]), towards, up)
    return abs(float(np.angle(np.exp(1j * d))))


def _line(m, phase):
    """The phase along the face's middle v line (x from low to high), with its x."""
    j = m.points.shape[1] // 2
    return m.points[:, j, 0], phase[:, j]


@pytest.mark.parametrize("degrees", [2.0, 5.0, 10.0])
def test_g1_break_between_faces_jumps_the_phase_at_the_edge(degrees):
    theta = math.radians(degrees)
    a = _net(lambda x, y: 0 * x, -1.0, 0.0, face=0)
    b = _net(lambda x, y: math.tan(theta) * x, 0.0, 1.0, face=1)
    maps = face_maps([a, b])
    towards, up = camera(maps)
    phases = centred([face_phase(m, towards, up) for m in maps])  # as the picture draws them
    xa, pa = _line(maps[0], phases[0])
    xb, pb = _line(maps[1], phases[1])
    x, p = np.concatenate([xa, xb]), np.concatenate([pa, pb])
    steps = np.abs(np.diff(p))
    k = int(np.argmax(steps))
    assert x[k] == pytest.approx(0.0, abs=1e-9) and x[k + 1] == pytest.approx(0.0, abs=1e-9)  # at the edge
    expected = _jump(theta, towards, up)
    assert steps[k] == pytest.approx(expected, rel=0.05)
    assert np.ptp(pa) < 1e-6 and np.ptp(pb) < 1e-6  # planes: one phase each, the stripes only break at the edge
    # the stripes, as drawn, change there when there are enough of them per turn
    count = stripe_count([pa, pb])
    changes = (stripes(np.array([pa[-1]]), count) != stripes(np.array([pb[0]]), count)).all()
    assert changes or expected * count < 2 * np.pi


@pytest.mark.parametrize("degrees", [3.0, 8.0])
def test_crease_inside_a_face_jumps_the_phase_at_the_crease(degrees):
    theta = math.radians(degrees)
    x = np.array([-1.0, 0.0, 1.0])  # degree 1 along x: a crease at the middle pole
    X, Y = np.meshgrid(x, np.linspace(0, 1, 8), indexing="ij")
    Z = np.where(X > 0, math.tan(theta) * X, 0.0)
    net = ControlNet.from_points(np.stack([X, Y, Z], -1), degrees=(1, 3), origin=NetOrigin(face=0, kind="bspline"))
    (m,) = face_maps([net])
    towards, up = camera([m])
    xs, p = _line(m, centred([face_phase(m, towards, up)])[0])
    expected = _jump(theta, towards, up)
    steps = np.abs(np.diff(p))
    k = int(np.argmax(steps))
    h = float(np.max(np.diff(xs)))
    assert abs(0.5 * (xs[k] + xs[k + 1])) <= h  # at the crease
    assert abs(p[-1] - p[0]) == pytest.approx(expected, rel=0.05)  # the whole jump ...
    assert abs(p[min(k + 2, len(p) - 1)] - p[max(k - 1, 0)]) == pytest.approx(expected, rel=0.05)  # ... there
    away = np.abs(xs - xs[k]) > 2 * h
    assert np.ptp(p[away & (xs < 0)]) < 1e-6 and np.ptp(p[away & (xs > 0)]) < 1e-6


@pytest.mark.parametrize("periods", [2, 3])
def test_ripple_makes_the_phase_oscillate_with_its_period(periods):
    n = 40
    net = _net(lambda x, y: 0.004 * np.sin(2 * np.pi * periods * x), 0.0, 1.0, nx=n, ny=8)
    (m,) = face_maps([net])
    towards, up = camera([m])
    xs, p = _line(m, centred([face_phase(m, towards, up)])[0])
    inner = (xs > 0.05) & (xs < 0.95)
    d = p[inner] - np.mean(p[inner])
    crossings = np.flatnonzero(np.sign(d[1:]) != np.sign(d[:-1]))
    # the phase follows the slope, cos(2 pi k x): a zero every half period
    assert len(crossings) == pytest.approx(2 * periods * 0.9, abs=1.5)
    gaps = np.diff(xs[inner][crossings])
    assert np.median(gaps) == pytest.approx(1 / (2 * periods), rel=0.1)


def test_view_reflection_writes_both_pictures_from_one_camera(tmp_path, samples):
    src = samples / "wavy_panel_diagonal.step"
    result = CliRunner().invoke(app, ["view", str(src), "--out", str(tmp_path / "w.png"), "--reflection",
                                      "--size", "400x300"])
    no_traceback(result)
    assert result.exit_code == 0 and "reflection lines" in result.stdout
    import matplotlib.image as mpimg

    heat, zebra = mpimg.imread(tmp_path / "w.png"), mpimg.imread(tmp_path / "w_reflection.png")
    assert heat.shape == zebra.shape
    grey = zebra[..., :3].mean(axis=-1)
    assert (grey < 0.1).mean() > 0.1 and (grey > 0.9).mean() > 0.1  # black and white stripes
    # on a ground of neither colour, so that the white stripes keep the face's outline
    from cadartifact.viz.view import REFLECTION_GROUND

    ground = np.all(np.abs(zebra[..., :3] - np.array(REFLECTION_GROUND)) < 0.02, axis=-1)
    assert ground.mean() > 0.05
