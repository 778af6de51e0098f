"""The `surface` reading's border convention and its U (SPEC §4 "The `surface` reading at borders").

Known faces (clamped uniform B-splines sampling cosines and bumps; degrees 2-5, nets 7-20, three directions, a
rational one). The second road for every variant: the whole budget (:func:`cadartifact.analysis.budget.budget_for`,
lateral band, normals and statistics of its own) with the period of every open direction lengthened by
patching :class:`~cadartifact.analysis.frames.AxisFrame`, against
:func:`cadartifact.analysis.border_convention.variant_values`.
"""

from __future__ import annotations

import numpy as np
import pytest

from cadartifact.advice.decision import CONFORMS, NONCONFORMING, UNDECIDED, face_uncertainty
from cadartifact.analysis import frames
from cadartifact.analysis.border_convention import PERIOD_LATITUDE, RELATIVE_BOUND, surface_uncertainty, variant_values
from cadartifact.analysis.budget import budget_for
from cadartifact.analysis.settings import RunSettings
from cadartifact.net import ControlNet
from cadartifact.runs.records import estimated_u
from cadartifact.testing.known_shapes import known_face, shape_function

FACES = [((3, 3), (14, 12), ("cosine", 0.3, 0.5)), ((2, 4), (9, 16), ("bump", 0.35, 0.0)),
         ((5, 3), (12, 10), ("cosine", 0.4, 1.57)), ((3, 2), (7, 20), ("cosine", 0.25, 0.8))]


def _face(degrees, shape, spec, rational=False):
    kind, f, direction = spec
    net, _ = known_face(degrees, shape, shape_function(kind, f, direction, 0.3,
                                                       tuple(n - d for n, d in zip(shape, degrees))))
    if rational:
        w = np.exp(0.2 * np.cos(0.4 * np.arange(shape[0])[:, None] + 0.3 * np.arange(shape[1])[None, :]))
        net = ControlNet(points=net.points, degrees=net.degrees, knots=net.knots, weights=w)
    return net


def _budget_value(net, settings, pad, monkeypatch):
    """The whole budget's value with every open direction's period lengthened by ``pad`` (the second road)."""
    plain = frames.AxisFrame.period.fget
    with monkeypatch.context() as m:
        m.setattr(frames.AxisFrame, "period",
                  property(lambda f: plain(f) + (0 if f.periodic else pad * max(f.alignment, 2) // 2)))
        return budget_for(net, settings).value()


@pytest.mark.parametrize("degrees, shape, spec", FACES)
def test_the_variants_are_the_budget_read_at_the_admissible_periods(degrees, shape, spec, monkeypatch):
    net = _face(degrees, shape, spec)
    s = RunSettings()
    v0, both, _, grid = variant_values(net, s)
    assert v0 == pytest.approx(budget_for(net, s).value(), rel=1e-12)
    for pad, v in zip(PERIOD_LATITUDE, both):
        assert v == pytest.approx(_budget_value(net, s, pad, monkeypatch), rel=1e-9, abs=1e-15)
    assert 0 <= grid < 0.2 * v0


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("degrees, shape, spec", FACES)
def test_U_covers_the_convention_s_latitude_on_every_face(degrees, shape, spec, rational, monkeypatch):
    """Estimated on every B-rep face, k = 2; covers every admissible period's reading (read by the second road)
    and the grid's (the same face read on a grid twice as fine)."""
    net = _face(degrees, shape, spec, rational)
    s = RunSettings()
    unc = surface_uncertainty(net, s)
    assert unc.estimated and unc.reading == "surface" and unc.factor == 2.0
    v0 = budget_for(net, s).value()
    for pad in PERIOD_LATITUDE:
        assert abs(_budget_value(net, s, pad, monkeypatch) - v0) <= unc.peak * (1 + 1e-9)
    assert abs(budget_for(net, s.replace(levels=4)).value() - v0) <= unc.peak


@pytest.mark.parametrize("degrees, shape, spec", FACES)
def test_far_from_the_tolerance_the_bound_decides_as_the_variants_would(degrees, shape, spec):
    net = _face(degrees, shape, spec)
    b = budget_for(net, RunSettings(), keep_fields=True)
    v = b.value()
    full = surface_uncertainty(net, RunSettings())
    v0, both, alone, _ = variant_values(net, RunSettings())
    assert max(abs(x - v0) for x in both + [y for pair in alone for y in pair]) <= RELATIVE_BOUND * v
    for t, expected in ((4 * v, CONFORMS), (v / 8, NONCONFORMING)):
        s = RunSettings(tolerance=t)
        cheap = surface_uncertainty(net, s, v, b.work, b.scalar_fields, b.region)
        assert cheap.peak >= full.peak  # the bound is no narrower than the variants' spread
        assert (CONFORMS if v + cheap.peak <= t else NONCONFORMING if v - cheap.peak > t else UNDECIDED) == expected


def test_the_decision_uses_it_and_the_doors_say_where_none_is_estimated():
    """A face just under the tolerance is undecided once its latitude is counted; a cage (its continuation is its
    intent's) has none: its record says so and the doors print "-"."""
    net = _face(*FACES[0])
    v = budget_for(net, RunSettings()).value()
    s = RunSettings(tolerance=v * 1.01)
    current = budget_for(net, s, keep_fields=True)
    unc = face_uncertainty(net, s, current)
    assert unc.estimated and unc.peak > 0.01 * v
    cage = ControlNet(points=np.asarray(net.points))
    none = face_uncertainty(cage, RunSettings(tolerance=1.0), budget_for(cage, RunSettings(tolerance=1.0)))
    assert not none.estimated
    assert estimated_u({"uncertainty": none.to_dict()}) is None
    assert estimated_u({"uncertainty": unc.to_dict()}) == unc.peak
    assert estimated_u({"uncertainty": {"peak": 0.0, "estimated": True}}) == 0.0


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("degrees, shape, spec", FACES + [((3, 3), (10, 9), ("cosine", 0.3, 0.5))])
def test_the_shared_passes_equal_the_whole_split_at_every_period(degrees, shape, spec, rational):
    """:func:`period_variants` (the ``u`` pass once per ``u`` pad, one ``v`` pass, no base band) against the whole
    split (:func:`cadartifact.analysis.fields._bridged_bands`) at each admissible period, each direction alone
    and both: the total band and the smooth part agree to rounding, rational faces (homogeneous) and a face
    closed along ``u`` (no latitude there) included."""
    from cadartifact.analysis.border_convention import period_variants
    from cadartifact.analysis.fields import _bridged_bands, measured_frames, split_coordinates
    from cadartifact.analysis.intent import design_intent
    from cadartifact.analysis.measure import real_surface
    from cadartifact.net import periodic_uniform_knots
    from cadartifact.theory.catalogue import bspline

    net = _face(degrees, shape, spec, rational)
    if shape == (10, 9):  # the same poles closed along u (periodic knots)
        net = ControlNet(points=net.points, degrees=net.degrees, weights=net.weights, periodic=(True, False),
                         knots=(periodic_uniform_knots(shape[0], degrees[0]), net.knots[1]))
    sch = bspline(*net.degrees)
    it = design_intent(net, sch, 3)
    real = split_coordinates(real_surface(it, sch), it.frames)
    combos = [(0, 0)] + [(j, j) for j in PERIOD_LATITUDE] + [c for j in PERIOD_LATITUDE for c in ((j, 0), (0, j))]
    got = {c: (total, smooth) for c, total, smooth in period_variants(real, it.frames, sch, combos)}
    size = float(np.ptp(real[..., :3]))
    for c in combos:
        key = tuple(0 if f.periodic else j for j, f in zip(c, it.frames))
        bands, smooth, _ = _bridged_bands(real, measured_frames(it.frames, c), sch, lateral=False)
        assert np.abs(got[key][0] - bands["total"]).max() <= 1e-12 * size, c
        assert np.abs(got[key][1] - smooth).max() <= 1e-12 * size, c
    assert len(got) == (3 if net.periodic[0] else 7)
