"""Response maps (cadartifact.viz.maps) and the ``cadartifact maps`` command.

The plotted arrays are checked against closed forms computed here by hand (second road); the
pictures are checked for size, layout and non-blankness; the CLI for exit codes and one-line errors.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("matplotlib")

from matplotlib.image import imread  # noqa: E402

from cadartifact.errors import CadArtifactError, OptionError  # noqa: E402
from cadartifact.viz import maps as M  # noqa: E402
from cadartifact.testing.outcomes import no_traceback  # noqa: E402

LOW = 24  # resolution of the quick pictures


# ------------------------------------------------------------------ closed forms (second road)
def bicubic_limit_factor(t):
    """One axis of the bicubic limit response at refined vertices: M̂/4 · L̂ = cos⁴(πt/2)·(2 + cos πt)/3.

    Mask [1 4 6 4 1]/16 per axis has symbol 4cos⁴(πt/2) (per axis 2cos⁴); the limit stencil [1 4 1]/6
    has symbol (4 + 2cos πt)/6 (SPEC §2-3).
    """
    return np.cos(np.pi * t / 2) ** 4 * (2 + np.cos(np.pi * t)) / 3


def bicubic_limit(wx, wy):
    f = bicubic_limit_factor
    a, b, c, d = f(wx) * f(wy), f(wx + 1) * f(wy), f(wx) * f(wy + 1), f(wx + 1) * f(wy + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        r2 = wx * wx + wy * wy
        s1 = np.where(r2 > 0, np.abs(wy) / np.sqrt(r2), 0.0)
        s2 = np.where(r2 > 0, np.abs(wx) / np.sqrt(r2), 0.0)
        sd = np.where(r2 > 0, np.abs(wx * wx - wy * wy) / (2 * r2), 0.0)
    percent = 100 * np.sqrt((b * b + c * c + d * d) / 3) / np.abs(a)
    lateral = np.sqrt(((b * s1) ** 2 + (c * s2) ** 2 + (d * sd) ** 2) / 3)
    return np.abs(a), percent, lateral


def png_pixels(path):
    img = imread(path)
    assert img.ndim == 3 and img.shape[2] in (3, 4), img.shape
    return img


def assert_not_blank(img):
    grey = img[..., :3].mean(axis=2)
    assert grey.std() > 0.05, "picture looks blank"
    assert (grey < 0.2).mean() > 0.01 and (grey > 0.8).mean() > 0.05, "picture lacks dark or bright areas"


def expected_pixels(size_inches):
    w, h = size_inches
    return round(h * M.DPI), round(w * M.DPI)


# ------------------------------------------------------------------ data
def test_bicubic_limit_percent_at_sample_point_matches_hand_value():
    m = M.response_map("bicubic", stage="limit", resolution=26)  # step 0.02: (0.1, 0.2) is a grid point
    j, i = 5, 10
    assert (m.wx[j], m.wy[i]) == pytest.approx((0.1, 0.2))
    assert m.percent[i, j] == pytest.approx(0.273, abs=5e-4)
    assert m.percent[i, j] == pytest.approx(0.2731371053209, rel=1e-9)


def test_bicubic_limit_map_equals_closed_form_everywhere():
    m = M.response_map("bicubic", stage="limit", resolution=33)
    signal, percent, lateral = bicubic_limit(m.wx[None, :], m.wy[:, None])
    np.testing.assert_allclose(m.signal, signal, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(m.percent, percent, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(m.lateral, lateral, rtol=1e-9, atol=1e-14)


@pytest.mark.parametrize("name, value", [("bilinear", 6.27), ("4-3", 0.211), ("4-8", 0.00917), ("kobbelt", 1.52)])
def test_sample_limit_percents_from_spec(name, value):
    m = M.response_map(name, stage="limit", resolution=26)
    assert m.percent[10, 5] == pytest.approx(value, rel=3e-3)


def test_plotted_signal_image_holds_the_closed_form():
    fig = M.maps_figure(["bicubic"], stage="limit", resolution=LOW)
    w = np.linspace(0, 0.5, LOW)
    drawn = np.asarray(fig.axes[0].images[0].get_array())
    np.testing.assert_allclose(drawn, bicubic_limit(w[None, :], w[:, None])[0], rtol=1e-10)
    assert "bicubic" in fig.axes[0].get_title() and "4,4,0,0" in fig.axes[0].get_title()
    assert "limit" in fig.get_suptitle()


def test_square_domain_is_symmetric_for_symmetric_masks():
    m = M.response_map("4-3", stage="limit", resolution=17, domain="square")
    assert m.wx[0] == -0.5 and m.wx[-1] == 0.5
    for field in (m.signal, m.lateral):
        np.testing.assert_allclose(field, field[:, ::-1], atol=1e-12)
        np.testing.assert_allclose(field, field[::-1, :], atol=1e-12)
        np.testing.assert_allclose(field, field.T, atol=1e-12)


def test_lateral_is_zero_on_the_diagonal_for_4_3_and_4_8_but_not_bicubic():
    k = np.arange(1, 20)
    for name in ("4-3", "4-8"):
        m = M.response_map(name, stage="limit", resolution=20)
        assert np.all(np.abs(m.lateral[k, k]) < 1e-12), name
    m = M.response_map("bicubic", stage="limit", resolution=20)
    assert np.all(m.lateral[k, k] > 1e-8)


def test_pure_sampling_one_step_energy_is_one():
    w = np.linspace(-0.5, 0.5, 7)
    np.testing.assert_allclose(M.box_one_step_energy((0, 0, 0, 0), w[None, :], w[:, None]), 1.0)


@settings(max_examples=30, deadline=None)
@given(g=st.integers(2, 3), d=st.integers(0, 3),
       wx=st.floats(-0.5, 0.5), wy=st.floats(-0.5, 0.5))
def test_closed_form_box_energy_equals_catalogue_one_step(g, d, wx, wy):
    from cadartifact.theory.catalogue import box

    expected = box(g, g, d, d).response(wx, wy, stage="one_step").energy
    assert M.box_one_step_energy((g, g, d, d), wx, wy) == pytest.approx(float(expected), rel=1e-9, abs=1e-13)


def test_grid_energies_cover_all_sixteen_panels_in_one_step():
    w, energies = M.grid_energies("one_step", resolution=16)
    assert sorted(energies) == [(d, g) for d in range(4) for g in range(4)]
    assert all(e is not None and e.shape == (16, 16) for e in energies.values())
    np.testing.assert_allclose(energies[0, 0], 1.0)
    # Figure 8's story: diagonal smoothing alone leaves artifacts at low frequencies ...
    assert energies[3, 0][0, 1] > 0.5
    # ... and more smoothing of both kinds lowers them.
    assert energies[3, 3].max() < energies[0, 2].max()


# ------------------------------------------------------------------ pictures
@pytest.mark.parametrize("names", [["bicubic"], ["bicubic", "4-8", "kobbelt"]])
def test_plot_maps_writes_a_png_of_the_layout_size(tmp_path, names):
    out = tmp_path / "deep" / "maps.png"
    assert M.plot_maps(names, out, stage="limit", resolution=LOW) == out
    img = png_pixels(out)
    assert img.shape[:2] == expected_pixels(M.maps_figure_size(len(names)))
    assert_not_blank(img)


def test_plot_maps_accepts_scheme_objects_and_other_stages(tmp_path):
    from cadartifact.theory.catalogue import scheme

    for stage in ("one_step", "continuous"):
        out = M.plot_maps([scheme("4-3"), "bilinear"], tmp_path / f"{stage}.png", stage=stage, resolution=16)
        assert_not_blank(png_pixels(out))


@pytest.mark.parametrize("stage", ["one_step", "limit"])
def test_plot_grid_writes_a_png_of_the_layout_size(tmp_path, stage):
    out = M.plot_grid(tmp_path / "grid.png", stage=stage, resolution=16)
    img = png_pixels(out)
    assert img.shape[:2] == expected_pixels(M.grid_figure_size())
    assert_not_blank(img)


@pytest.mark.parametrize("kwargs, parameter", [
    (dict(schemes=[]), "schemes"),
    (dict(stage="final"), "stage"),
    (dict(resolution=8), "resolution"),
    (dict(resolution=20.5), "resolution"),
    (dict(resolution=True), "resolution"),
    (dict(domain="disc"), "domain"),
    (dict(out="maps.txt"), "out suffix"),
])
def test_bad_arguments_raise_option_error_and_write_nothing(tmp_path, kwargs, parameter):
    args = dict(schemes=["bicubic"], out=tmp_path / "x.png", stage="limit", resolution=16)
    args.update(kwargs)
    if not str(args["out"]).startswith(str(tmp_path)):
        args["out"] = tmp_path / args["out"]
    with pytest.raises(OptionError) as info:
        M.plot_maps(**args)
    assert info.value.parameter == parameter
    assert "\n" not in str(info.value)
    assert list(tmp_path.iterdir()) == []


def test_unknown_scheme_raises_and_writes_nothing(tmp_path):
    with pytest.raises(CadArtifactError):
        M.plot_maps(["bicubic", "no-such-scheme"], tmp_path / "x.png", resolution=16)
    assert list(tmp_path.iterdir()) == []


def test_unwritable_output_is_an_input_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(CadArtifactError, match="file"):
        M.plot_maps(["bicubic"], blocker / "x.png", resolution=16)


def test_importing_maps_does_not_load_matplotlib():
    code = "import sys, cadartifact.viz.maps; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# ------------------------------------------------------------------ CLI
def run_cli(*args):
    from typer.testing import CliRunner

    from cadartifact.cli.app import app

    return CliRunner().invoke(app, ["maps", *args])


def test_cli_maps_compares_schemes(tmp_path):
    out = tmp_path / "tmp" / "x.png"
    result = run_cli("--scheme", "bicubic", "--scheme", "4-8", "--out", str(out), "--resolution", str(LOW))
    assert result.exit_code == 0, result.output
    assert out.exists()
    assert png_pixels(out).shape[:2] == expected_pixels(M.maps_figure_size(2))


def test_cli_maps_grid(tmp_path):
    out = tmp_path / "grid.png"
    result = run_cli("--grid", "--stage", "one-step", "--out", str(out), "--resolution", "16")
    assert result.exit_code == 0, result.output
    assert png_pixels(out).shape[:2] == expected_pixels(M.grid_figure_size())


@pytest.mark.parametrize("args, needle", [
    (["--stage", "final"], "--stage"),
    (["--scheme", "no-such-scheme"], "no-such-scheme"),
    (["--resolution", "4"], "resolution"),
    (["--domain", "disc"], "domain"),
])
def test_cli_bad_input_is_one_line_exit_2_and_no_file(tmp_path, args, needle):
    out = tmp_path / "x.png"
    result = run_cli(*args, "--out", str(out), "--resolution", "16") if "--resolution" not in args \
        else run_cli(*args, "--out", str(out))
    assert result.exit_code == 2, result.output
    no_traceback(result)
    message = result.stderr.strip()
    assert len(message.splitlines()) == 1, message
    assert needle in message
    assert not out.exists()
