"""A first day with the pictures (issue 12): GLB in metres with extras, maps options, noise, camera."""


import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("OCP")
pytest.importorskip("pyvista")
trimesh = pytest.importorskip("trimesh")

from cadartifact.cli.app import app  # noqa: E402
from cadartifact.exchange.load import read  # noqa: E402
from cadartifact.viz import view as V  # noqa: E402
from cadartifact.viz import facemaps as FM  # noqa: E402
from cadartifact.testing.paths import SAMPLES


def test_glb_is_in_metres_with_extras(tmp_path):
    path = SAMPLES / "hull_freeform.step"
    glb = tmp_path / "hull.glb"
    res = V.view(path, tol=0.05, out=False, glb=glb)
    scene = trimesh.load(glb)
    maps = FM.face_maps(read(path).nets, "total")
    size_mm = np.ptp(maps[0].points.reshape(-1, 3), axis=0)
    mesh = next(iter(scene.geometry.values()))
    np.testing.assert_allclose(np.ptp(mesh.vertices, axis=0), size_mm * 1e-3, rtol=1e-6)
    assert set(np.unique(mesh.faces)) == set(range(len(mesh.vertices)))  # no unused vertex
    extras = scene.metadata
    assert extras["field"] == "total" and extras["units"] == "mm" and extras["coordinates"] == "m"
    assert extras["tolerance"] == 0.05 and extras["peak"] == pytest.approx(res.peak)
    assert mesh.metadata["peak"] == pytest.approx(maps[0].peak)


def test_maps_grid_rejects_a_scheme(tmp_path):
    result = CliRunner().invoke(app, ["maps", "--grid", "-s", "4-8", "--out", str(tmp_path / "g.png")])
    assert result.exit_code == 2 and "--scheme" in result.stderr and "--grid" in result.stderr
    assert not (tmp_path / "g.png").exists()


def test_noise_floor_and_mean_normal():
    from cadartifact.net import ControlNet, clamped_uniform_knots, greville

    # a saddle sampled at its Greville abscissae: bilinear, reproduced exactly; its ripple is rounding
    ku, kv = clamped_uniform_knots(10, 3), clamped_uniform_knots(9, 3)
    gu, gv = greville(ku, 3, 10), greville(kv, 3, 9)
    X, Y = 100.0 * gu[:, None] + 0 * gv[None, :], 80.0 * gv[None, :] + 0 * gu[:, None]
    net = ControlNet(points=np.stack([X, Y, 0.001 * (X - 50) * (Y - 40) + 0.05 * X], axis=-1), degrees=(3, 3),
                     knots=(ku, kv))
    m = FM.face_maps([net], "total")[0]
    assert m.peak < V.noise_floor([m])  # 1e-13 mm of rounding is noise: drawn as 0
    n = V.mean_normal(m)
    assert n is not None and abs(np.linalg.norm(n) - 1) < 1e-12
    # the panel is nearly flat: its mean normal is the normal of its corner plane, by the net's corners
    p = np.asarray(net.points, float)
    corner = np.cross(p[-1, 0] - p[0, 0], p[0, -1] - p[0, 0])
    assert abs(np.dot(n, corner / np.linalg.norm(corner))) > 0.99


def test_over_tolerance_keeps_structure():
    values = np.array([0.0, 0.5, 1.0, 2.0, 5.0, 10.0])
    flat = FM.vertex_colours(values, (0.0, 1.0))
    assert len({tuple(c) for c in flat[values > 1]}) == 1  # the old scale: solid red
    graded = FM.vertex_colours(values, (0.0, 1.0), top=10.0)
    over = graded[values > 1, :3].astype(int)
    assert len({tuple(c) for c in over}) == 3 and np.all(np.diff(over[:, 0]) < 0)  # darker towards the peak
    assert tuple(graded[-1, :3]) == tuple(np.round(np.array(FM.PEAK_COLOUR) * 255).astype(int))
    np.testing.assert_array_equal(graded[values <= 1], flat[values <= 1])


def test_a_tile_says_why_it_shows_little_surface():
    """A face that curves all round, one mostly turned away, and one trimmed to a corner each say so."""
    import dataclasses

    from cadartifact.net import ControlNet

    t = np.linspace(0, 2 * np.pi, 12)
    tube = ControlNet.from_points(np.stack([np.cos(t)[:, None] * np.ones(6), np.sin(t)[:, None] * np.ones(6),
                                            np.ones(12)[:, None] * np.linspace(0, 5, 6)], axis=-1), degrees=(3, 3))
    assert "curved all round" in V.little_surface_reason(FM.face_maps([tube], "total")[0])
    half = np.linspace(0, 1.6 * np.pi, 12)  # mean normal exists, but little of the arch faces it
    arch = ControlNet.from_points(np.stack([np.cos(half)[:, None] * np.ones(6), np.sin(half)[:, None] * np.ones(6),
                                            np.ones(12)[:, None] * np.linspace(0, 5, 6)], axis=-1), degrees=(3, 3))
    assert "faces the viewer" in V.little_surface_reason(FM.face_maps([arch], "total")[0])
    gx, gy = np.meshgrid(np.arange(8.0), np.arange(8.0), indexing="ij")
    flat = ControlNet.from_points(np.stack([gx, gy, np.zeros((8, 8))], axis=-1), degrees=(3, 3))
    m = FM.face_maps([flat], "total")[0]
    assert V.little_surface_reason(m) == ""
    values = np.array(m.values, float)
    values[values.shape[0] // 3:, :] = np.nan
    assert "trimmed to" in V.little_surface_reason(dataclasses.replace(m, values=values))
