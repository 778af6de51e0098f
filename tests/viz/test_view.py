"""3-D heatmaps: off-screen PNGs, glb export, colours, the view command.

The models are STEP files written in tmp_path from nets of known ripple. What is drawn is checked
by numbers, not only pixels: the glb's vertex colours are decoded back to values and compared with
the budget the analysis reports for the loaded face.
"""

import io

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

pytest.importorskip("OCP")
pytest.importorskip("pyvista")
trimesh = pytest.importorskip("trimesh")

import cadartifact as ca  # noqa: E402
from cadartifact.cli.app import app  # noqa: E402
from cadartifact.errors import CadArtifactError, OptionError  # noqa: E402
from cadartifact.net import ControlNet, NetOrigin  # noqa: E402
from cadartifact.viz import view as V  # noqa: E402
from cadartifact.viz import facemaps as FM  # noqa: E402
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.paths import REALDATA

SIZE = (360, 260)


def ridge_points(nu=14, nv=10, amp=2.0, width=9.0, dy=0.0):
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    x, y = 100.0 * i / (nu - 1), 80.0 * j / (nv - 1) + dy
    d = x - 50.0
    z = amp * np.where(np.abs(d) < width, 0.5 * (1 + np.cos(np.pi * d / width)), 0.0) ** 2
    return np.stack([x, y, z], axis=-1)


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    from cadartifact.exchange.load import write_step

    root = tmp_path_factory.mktemp("view")
    ridge = ControlNet.from_points(ridge_points(), origin=NetOrigin(name="ridge", kind="bspline"))
    calm = ControlNet.from_points(ridge_points(amp=0.0, dy=100.0) + [0, 0, 1.0],
                                  origin=NetOrigin(name="flat", kind="bspline"))
    path = root / "pair.step"
    write_step([calm, ridge], path)
    nets = ca.load(path)
    budgets = {n.origin.face: ca.budget(n) for n in nets}
    return {"path": path, "nets": nets, "budgets": budgets}


def read_png(path_or_bytes):
    import matplotlib.image as mpimg

    src = io.BytesIO(path_or_bytes) if isinstance(path_or_bytes, bytes) else str(path_or_bytes)
    return mpimg.imread(src, format="png")


def test_face_maps_peak_is_the_budget_peak(model):
    for direction in ("total", "x1", "x2", "diagonal", "signal_error"):
        maps = FM.face_maps(model["nets"], direction)
        for m in maps:
            want = model["budgets"][m.net.origin.face].stats[direction].peak
            assert m.peak == pytest.approx(want, rel=1e-12, abs=1e-15)
            assert m.points.shape[:2] == m.values.shape


def test_view_writes_a_nonblank_png_of_the_right_size(model, tmp_path):
    out = tmp_path / "shot.png"
    res = V.view(model["path"], direction="x1", tol=0.05, out=out, window_size=SIZE)
    assert res.png == out and res.faces == (0, 1)
    img = read_png(out)
    assert img.shape[:2] == (SIZE[1], SIZE[0])
    assert img[..., :3].std() > 0.05  # not a blank canvas
    # the largest value shown is the largest per-face budget peak in that direction
    assert res.peak == pytest.approx(max(b.stats["x1"].peak for b in model["budgets"].values()))
    assert not list(tmp_path.glob(".*tmp"))


def test_tolerance_shows_red_where_the_ripple_exceeds_it(model, tmp_path):
    """Red (ABOVE_COLOUR) pixels appear only when the tolerance is below the peak."""
    ridge = [n for n in model["nets"] if n.origin.name == "ridge"]
    maps = FM.face_maps(ridge, "total")
    peak = maps[0].peak

    def red_share(tol):
        img = V.render_image(maps, tol=tol, window_size=SIZE, show_net=False).astype(int)
        red = (img[..., 0] > 150) & (img[..., 1] < 70) & (img[..., 2] < 70)
        return red.mean()

    assert red_share(peak / 4) > 0.01
    assert red_share(peak * 2) < 0.002  # only the colour bar's end triangle


def test_glb_round_trip_colours_decode_to_the_field(model, tmp_path):
    glb = tmp_path / "faces.glb"
    tol = 0.05
    res = V.view(model["path"], tol=tol, out=False, glb=glb)
    assert res.png is None and res.glb == glb
    scene = trimesh.load(glb)
    assert sorted(scene.geometry) == ["face_0", "face_1"]
    maps = {m.net.origin.face: m for m in FM.face_maps(model["nets"], "total")}
    import matplotlib

    lut = np.round(matplotlib.colormaps[FM.CMAP](np.linspace(0, 1, 513)) * 255)[:, :3]
    for name, mesh in scene.geometry.items():
        m = maps[int(name.split("_")[1])]
        a, b = m.values.shape
        assert len(mesh.vertices) == a * b and len(mesh.faces) == 2 * (a - 1) * (b - 1)
        # glTF is in metres: the mm faces are scaled by 1e-3
        np.testing.assert_allclose(np.asarray(mesh.vertices).reshape(a, b, 3) * 1e3, m.points, atol=1e-5)
        rgb = np.asarray(mesh.visual.vertex_colors)[:, :3].astype(float)
        values = m.values.ravel()
        # beyond the tolerance: the red segment, ABOVE_COLOUR at the tolerance to PEAK_COLOUR at the peak
        red = values > tol
        top = max(mm.peak for mm in maps.values())
        s = np.clip((values[red] - tol) / (top - tol), 0, 1)[:, None]
        want = np.round(((1 - s) * np.array(FM.ABOVE_COLOUR) + s * np.array(FM.PEAK_COLOUR)) * 255)
        np.testing.assert_allclose(rgb[red], want, atol=1)
        # the other vertices: nearest colormap entry gives the value back to within the 8-bit steps
        idx = np.argmin(((rgb[~red, None, :] - lut[None, :, :]) ** 2).sum(-1), axis=1)
        decoded = idx / 512 * tol
        assert np.max(np.abs(decoded - values[~red])) < 0.03 * tol


@settings(max_examples=50, deadline=None)
@given(values=st.lists(st.one_of(st.floats(0, 10), st.just(float("nan"))), min_size=1, max_size=40),
       hi=st.floats(0.01, 5))
def test_property_vertex_colours(values, hi):
    import matplotlib

    v = np.array(values)
    rgba = FM.vertex_colours(v, (0.0, hi))
    assert rgba.shape == (len(v), 4) and rgba.dtype == np.uint8 and np.all(rgba[:, 3] == 255)
    nan = np.isnan(v)
    over = ~nan & (v > hi)
    inside = ~nan & ~over
    assert np.all(rgba[nan, :3] == np.round(np.array(FM.OUTSIDE_COLOUR) * 255))
    assert np.all(rgba[over, :3] == np.round(np.array(FM.ABOVE_COLOUR) * 255))
    want = np.round(np.asarray(matplotlib.colormaps[FM.CMAP](v[inside] / hi))[:, :3] * 255)
    np.testing.assert_array_equal(rgba[inside, :3], want)


@settings(max_examples=30, deadline=None)
@given(a=st.integers(2, 12), b=st.integers(2, 12))
def test_property_grid_cells_cover_the_grid(a, b):
    quads = FM._quads(a, b)
    assert quads.shape == ((a - 1) * (b - 1), 4)
    assert quads.min() == 0 and quads.max() == a * b - 1
    i, j = np.divmod(quads, b)
    # each cell is a unit square in index space, corners in order
    np.testing.assert_array_equal(np.diff(i[:, [0, 1, 2, 3, 0]], axis=1) ** 2 + np.diff(j[:, [0, 1, 2, 3, 0]], axis=1) ** 2,
                                  np.ones((len(quads), 4)))


def test_layout_choice(model):
    maps = FM.face_maps(model["nets"], "total")
    assert V.choose_layout(maps[:1]) == "model"
    assert V.choose_layout(maps) == "model"  # two panels of similar size side by side
    tiny = FM.FaceMap(net=maps[0].net, points=maps[0].points * 1e-3, values=maps[0].values, peak=0.0, budget=None)
    assert V.choose_layout([maps[0], maps[1], tiny, tiny, tiny]) == "tiles"
    img = V.render_image(maps, layout="tiles", window_size=SIZE, title="tiles")
    assert img.shape == (SIZE[1], SIZE[0], 3) and img.std() > 10
    with pytest.raises(OptionError, match="layout"):
        V.choose_layout(maps, "grid")


def test_bad_arguments_write_nothing(model, tmp_path):
    out = tmp_path / "x.png"
    for kwargs, parameter in (({"direction": "x3"}, "direction"), ({"tol": 0}, "tol"), ({"faces": [7]}, "face"),
                              ({"window_size": (10, 10)}, "window_size"), ({"scheme": "nope"}, "scheme")):
        with pytest.raises(OptionError) as info:
            V.view(model["path"], out=out, **kwargs)
        assert info.value.parameter == parameter
    with pytest.raises(OptionError, match="out"):
        V.view(model["path"], out=tmp_path / "x.jpg")
    with pytest.raises(OptionError, match="glb"):
        V.view(model["path"], out=out, glb=tmp_path / "missing" / "x.glb")
    with pytest.raises(CadArtifactError, match="file not found"):
        V.view(tmp_path / "none.step", out=out)
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------- the view command
def invoke(*args):
    result = CliRunner().invoke(app, ["view", *map(str, args)])
    no_traceback(result)
    return result


def test_view_command_default_output_and_glb(model, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = invoke(model["path"], "--direction", "x2", "--face", 1, "--glb", "m.glb", "--size", "320x240")
    assert result.exit_code == 0, result.output
    png = tmp_path / "pair_x2.png"
    assert read_png(png).shape[:2] == (240, 320)
    assert "wrote pair_x2.png (1 face," in result.stdout
    assert list(trimesh.load(tmp_path / "m.glb").geometry) == ["face_1"]


def test_view_marks_the_policy_tolerance_without_tol(model, tmp_path, monkeypatch):
    """Without --tol, ``view`` marks the tolerance the gate's policy gives the file: the same picture as with
    --tol that value; with no policy it says there is no mark and how to get one."""
    monkeypatch.chdir(tmp_path)
    args = (model["path"], "--face", 1, "--size", "320x240")
    plain = invoke(*args, "--out", "plain.png")
    assert plain.exit_code == 0 and "no tolerance mark: pass --tol" in plain.stdout
    (tmp_path / "cadartifact.toml").write_text("tolerance = 0.02\n")
    marked = invoke(*args, "--out", "policy.png")
    assert marked.exit_code == 0 and "tolerance mark: 0.02 (policy " in marked.stdout, marked.stdout
    given = invoke(*args, "--out", "given.png", "--tol", "0.02")
    assert "tolerance mark: 0.02 (--tol)" in given.stdout
    assert np.array_equal(read_png(tmp_path / "policy.png"), read_png(tmp_path / "given.png"))
    assert not np.array_equal(read_png(tmp_path / "plain.png"), read_png(tmp_path / "given.png"))


@pytest.mark.parametrize("args, needle", [
    (["--direction", "sideways"], "--direction: expected one of 'total', 'x1'"),
    (["--face", "9"], "--face: expected an analysable face index of pair.step (0, 1), received 9"),
    (["--tol", "-1"], "--tol: expected a positive number"),
    (["--size", "big"], "--size: expected WIDTHxHEIGHT"),
    (["--out", "shot.jpg"], "--out: expected a .png file"),
    (["--scheme", "nope"], "--scheme: expected one of"),
    (["--layout", "grid"], "--layout: expected one of"),
])
def test_view_command_usage_errors_are_one_line(model, tmp_path, monkeypatch, args, needle):
    monkeypatch.chdir(tmp_path)
    result = invoke(model["path"], *args)
    assert result.exit_code == 2
    assert needle in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_view_command_bad_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    bad = tmp_path / "bad.step"
    bad.write_text("ISO-10303-21;\nnot really\n")
    result = invoke(bad)
    assert result.exit_code == 2 and "bad.step" in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.step"]


@pytest.mark.realdata
def test_real_file_heatmap(tmp_path):
    """CATIA degree-5 faces (MAINBODY_BACK): one picture of all faces, peak equals their budgets."""
    path = REALDATA / "step" / "MAINBODY_BACK.stp"
    res = V.view(path, tol=0.05, out=tmp_path / "mb.png", window_size=SIZE)
    assert res.peak == pytest.approx(max(ca.budget(n).stats["total"].peak for n in ca.load(path)))
    assert read_png(res.png)[..., :3].std() > 0.05
