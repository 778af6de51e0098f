"""How local the `surface` reading of a rational face is (SPEC §4, "The `surface` reading at borders"; docs/model.md,
"Rational faces": the measured road's split of rational faces).

The measured road splits a rational face in homogeneous coordinates and projects each band to first order; the
alternative is to split the surface as it stands (Cartesian), like a non-rational face
(:func:`cadartifact.analysis.fields.split_coordinates`). Both are measured here on faces cut exactly from faces 12
spans longer (:mod:`cadartifact.testing.border_free`): the difference from the longer face's reading two spans or
more from every border, over its largest (``E>2 / E``), median over the family's rational faces; the family's
non-rational faces and the rational draws without weights are the control.

* Non-rational faces are local (median 0.38 on seed 2; the rational draws' unweighted copies 0.52), and the
  Cartesian split is more local than the homogeneous one.
* The target, rational faces as local as the control (median <= 0.5), is reached by neither split (0.83 and 0.97
  on seed 2): a strict xfail keeps it.
* A second road to the Cartesian reading: the surface evaluated by scipy's B-spline basis and projected by hand,
  split by one 2-D transform of the whole bridged period, equals the measured road's fields.
* Both directions periodic: no border, the homogeneous split stays under either choice.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from cadartifact.analysis import fields as F
from cadartifact.analysis.bands import band_split
from cadartifact.analysis.frames import AxisFrame
from cadartifact.analysis.intent import design_intent
from cadartifact.analysis.measure import real_surface
from cadartifact.net import ControlNet
from cadartifact.testing.border_free import compare, homogeneous, long_face
from cadartifact.testing.rational_faces import rational_face
from cadartifact.theory.catalogue import bspline

MARGIN = 12


def _locality(seed: int, cases: int, rational_split: str) -> dict:
    """``E beyond 2 spans / E`` per face of one seed's draws: ``rational`` (the rational draws), ``unweighted``
    (the same draws without weights) and ``plain`` (the seed's non-rational draws; the split choice does not touch
    them, so they are read once, under ``"homogeneous"``)."""
    out = {"rational": [], "unweighted": [], "plain": []}
    rng = np.random.default_rng(seed)
    for _ in range(cases):
        state = rng.bit_generator.state
        whole, face, info = long_face(rng, MARGIN)
        pairs = []
        if info["rational"]:
            after = rng.bit_generator.state
            rng.bit_generator.state = state
            plain_whole, plain_face, _ = long_face(rng, MARGIN, rational=False)
            rng.bit_generator.state = after
            pairs = [(whole, face, "rational"), (plain_whole, plain_face, "unweighted")]
        elif rational_split == "homogeneous":
            pairs = [(whole, face, "plain")]
        for net_whole, net_face, key in pairs:
            row = compare(net_whole, net_face, MARGIN, rational_split=rational_split)
            if row["true"] > 1e-5 and np.isfinite(row["E>2"]):
                out[key].append(row["E>2"] / row["E"])
    return {k: np.array(v) for k, v in out.items()}


@functools.lru_cache(maxsize=1)
def _seed_two() -> dict:
    return {how: _locality(2, 100, how) for how in ("homogeneous", "cartesian")}


@pytest.fixture
def seed_two():
    """Seed 2, 100 draws: 30 rational (27 with ripple above 1e-5 of the amplitude and more than four spans each
    way, 20 of their unweighted copies), 70 non-rational (34). Its tests share an xdist group, so the readings
    (minutes) are made by one worker (they were made on both while pytest 9.2 made xdist ignore the groups)."""
    return _seed_two()


@pytest.mark.slow
@pytest.mark.xdist_group("border_free_seed_two")
def test_the_cartesian_split_is_more_local_and_non_rational_faces_are_local(seed_two):
    """Medians of ``E>2 / E`` on seed 2 (2026-12-05): rational faces 0.97 split in homogeneous coordinates, 0.83
    split as they stand; their unweighted copies 0.52, the seed's non-rational faces 0.38."""
    lifted, cartesian = seed_two["homogeneous"]["rational"], seed_two["cartesian"]["rational"]
    plain, unweighted = seed_two["homogeneous"]["plain"], seed_two["cartesian"]["unweighted"]
    assert len(cartesian) >= 15 and len(unweighted) >= 10 and len(plain) >= 25
    assert np.median(plain) <= 0.5, np.round(np.sort(plain), 2)
    assert np.median(unweighted) <= 0.6, np.round(np.sort(unweighted), 2)
    assert np.median(cartesian) < np.median(lifted) - 0.05


@pytest.mark.slow
@pytest.mark.xdist_group("border_free_seed_two")
@pytest.mark.xfail(strict=True, reason="rational readings are not yet as local as non-rational ones: median E>2/E "
                   "0.97 (homogeneous split) and 0.83 (Cartesian) on seed 2, non-rational faces 0.38")
@pytest.mark.parametrize("how", ["homogeneous", "cartesian"])
def test_a_rational_reading_is_as_local_as_a_non_rational_one(seed_two, how):
    rational = seed_two[how]["rational"]
    assert np.median(rational) <= 0.5, np.round(np.sort(rational), 2)


def _scipy_surface(net: ControlNet, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The rational surface by scipy's B-spline basis, projected by hand: ``(len(u), len(v), 3)``."""
    from scipy.interpolate import BSpline

    Bu = BSpline.design_matrix(np.clip(u, net.knots[0][0], net.knots[0][-1]), np.asarray(net.knots[0], float),
                               net.degrees[0]).toarray()
    Bv = BSpline.design_matrix(np.clip(v, net.knots[1][0], net.knots[1][-1]), np.asarray(net.knots[1], float),
                               net.degrees[1]).toarray()
    H = np.einsum("ia,abc,jb->ijc", Bu, homogeneous(net), Bv)
    return H[..., :3] / H[..., 3:]


def _whole_period_split(field, frames, scheme):
    """The split as one 2-D transform of the whole bridged period."""
    fu, fv = frames
    V, poly = F._poly_fit(field, frames, scheme.degrees)
    rest = field - F.sandwich(V[0], poly, V[1])
    ext = np.roll(F._bridge(F._bridge(rest, fu, 0, scheme.degrees[0]), fv, 1, scheme.degrees[1]),
                  (fu.shift, fv.shift), axis=(0, 1))
    return band_split(np.fft.rfft2(ext, axes=(0, 1)), fu, fv, lateral=False)


@pytest.mark.parametrize("seed", [0, 3, 7, 10, 21])
def test_the_cartesian_split_by_a_second_road(seed, monkeypatch):
    monkeypatch.setattr(F, "RATIONAL_SPLIT", "cartesian")
    net = rational_face(seed)
    sch = bspline(*net.degrees)
    it = design_intent(net, sch, 3)
    fu, fv = it.frames
    fields = F.measured_fields(it, sch, "surface")
    surface = _scipy_surface(net, fu.param(fu.x), fv.param(fv.x))
    size = float(np.ptp(net.points))
    assert np.abs(fields.surface - surface).max() <= 1e-9 * size
    wide = F.measured_frames((fu, fv))
    total = _whole_period_split(surface, wide, sch)["total"]
    peak = float(np.abs(fields.bands["total"]).max())
    assert peak > 1e-6 * size
    assert np.abs(fields.bands["total"] - total).max() <= 1e-6 * peak
    assert np.abs(fields.intent + fields.bands["total"] - surface).max() <= 1e-9 * size


def _frame(n: int, periodic: bool, degree: int = 3) -> AxisFrame:
    spans = n if periodic else n - degree
    return AxisFrame(n, periodic, spans, 0.0 if periodic else ((degree - 1) / 2) % 1.0, np.arange(n, dtype=float), 3)


def test_which_faces_the_cartesian_split_projects():
    H = np.random.default_rng(5).uniform(0.5, 2.0, size=(9, 7, 4))
    assert F.split_coordinates(H, (_frame(8, True), _frame(6, True)), "cartesian") is H
    for frames in ((_frame(8, True), _frame(6, False)), (_frame(8, False), _frame(6, False))):
        assert np.array_equal(F.split_coordinates(H, frames, "cartesian"), H[..., :3] / H[..., 3:])
        assert F.split_coordinates(H, frames, "homogeneous") is H
        assert F.split_coordinates(H, frames) is H  # the road's own (docs/model.md: the homogeneous split stays)
    S = H[..., :3]
    assert F.split_coordinates(S, (_frame(8, False), _frame(6, False)), "cartesian") is S
