"""The per-axis operator caches: bounded, least recently used first out, and invisible in the results."""

import numpy as np
import pytest

import cadartifact as ca
from cadartifact.advice.advise import clear_caches
from cadartifact.numerics.operator_cache import OperatorCache


def test_lru_order_and_bound():
    c = OperatorCache(2)
    built = []

    def make(k):
        built.append(k)
        return k * 10

    assert c.get(1, lambda: make(1)) == 10
    assert c.get(2, lambda: make(2)) == 20
    assert c.get(1, lambda: make(1)) == 10  # 1 is now the most recent
    c.get(3, lambda: make(3))  # evicts 2
    assert len(c) == 2
    c.get(1, lambda: make(1))
    c.get(2, lambda: make(2))
    assert built == [1, 2, 3, 2]
    c.clear()
    assert len(c) == 0


@pytest.mark.parametrize("scheme", ["bicubic", "bilinear", "kobbelt", "4-3"])
def test_cold_and_warm_caches_give_the_same_bits(scheme):
    """Cached syntheses, lattices and bases are shared across nets: a second net of the same size must not
    see anything of the first, and a warm run equals a cold one to the bit."""
    rng = np.random.default_rng(3)
    i, j = np.meshgrid(np.arange(9.0), np.arange(7.0), indexing="ij")
    nets = [ca.ControlNet(points=np.stack([i, j, np.cos(0.9 * i + s * j) + 0.1 * rng.standard_normal(i.shape)], -1))
            for s in (0.3, 0.7)]
    clear_caches()
    cold = [ca.budget(n, scheme, 0.05).stats["total"].peak for n in nets]
    warm = [ca.budget(n, scheme, 0.05).stats["total"].peak for n in nets]
    clear_caches()
    again = [ca.budget(nets[1], scheme, 0.05).stats["total"].peak, ca.budget(nets[0], scheme, 0.05).stats["total"].peak]
    assert cold == warm == again[::-1]
    assert cold[0] != cold[1]


def test_cached_synthesis_is_read_only():
    from cadartifact.analysis.fields import _axis_synthesis
    from cadartifact.theory.catalogue import scheme
    from cadartifact.analysis.intent import design_intent

    net = ca.ControlNet(points=np.random.default_rng(0).standard_normal((6, 5, 3)))
    it = design_intent(net, scheme("bicubic"), 2)
    low, high, _ = _axis_synthesis(it, scheme("bicubic"), 0)
    with pytest.raises(ValueError):
        low[0, 0] = 1.0
    assert _axis_synthesis(it, scheme("bicubic"), 0)[0] is low


def test_scorer_fit_with_kept_halves_equals_fit_points():
    """The search keeps the fit's u half per ``a`` and its v half per ``b``: fitting from scratch gives the same
    numbers (to rounding: the two halves sum in other orders)."""
    from cadartifact.advice.advise import _make_scorer
    from cadartifact.analysis.budget import analysis_net
    from cadartifact.analysis.fitting import fit_points
    from cadartifact.analysis.settings import RunSettings, resolve_scheme

    i, j = np.meshgrid(np.arange(14.0), np.arange(11.0), indexing="ij")
    net = ca.ControlNet.from_points(np.stack([i, j, np.sin(0.7 * i) * np.cos(0.4 * j)], -1), degrees=(3, 3))
    sch = resolve_scheme(net)
    sc = _make_scorer(net, analysis_net(net, sch), sch, RunSettings(levels=2))
    for a, b in [(6, 5), (6, 7), (9, 5), (6, 5), (13, 11), (9, 8)]:
        Q, S, I, *_ , (cu, cv) = sc.fit(a, b)
        Q0, S0 = fit_points(I, cu, cv)
        assert np.allclose(Q, Q0, rtol=1e-12, atol=1e-12 * np.abs(Q0).max())
        assert np.allclose(S, S0, rtol=1e-12, atol=1e-12 * np.abs(S0).max())


def test_kept_advice_reuses_todays_budget_to_the_bit():
    """A face kept as it is: its stats are today's budget's (reused, not computed again), bit for bit."""
    i, j = np.meshgrid(np.arange(10.0), np.arange(10.0), indexing="ij")
    net = ca.ControlNet(points=np.stack([i, j, np.cos(2 * np.pi * (i + 0.5 * j) / (10 / 3.0))], -1))
    adv = ca.advise(net, 0.05, "bicubic", compare=False, verify=False)
    assert adv.kept_today
    fresh = ca.budget(net, "bicubic", 0.05)
    for k, s in fresh.stats.items():
        if k != "deviation":
            assert (adv.stats[k].peak, adv.stats[k].rms) == (s.peak, s.rms)


@pytest.mark.parametrize("cage", [True, False])
def test_baseband_rows_memo_gives_the_same_bits(cage):
    """The base band keeps its per-direction rows (and u halves): a call served from them equals one on a
    fresh budget's fields, for the separable (cage, bicubic) and the spectral (B-spline face) forms."""
    from cadartifact.analysis.baseband import baseband_at

    i, j = np.meshgrid(np.arange(12.0), np.arange(9.0), indexing="ij")
    pts = np.stack([i, j, np.sin(0.6 * i) * np.cos(0.5 * j)], -1)
    net = ca.ControlNet(points=pts) if cage else ca.ControlNet.from_points(pts, degrees=(3, 3))

    def fields():
        return ca.budget(net, "bicubic" if cage else None, 0.05, keep_fields=True).fields

    warm = fields()
    grids = [(np.linspace(0, 8, 17), np.linspace(0, 6, 13)), (np.linspace(0, 8, 9), np.linspace(0, 6, 13)),
             (np.linspace(0, 8, 17), np.linspace(0, 6, 7))]
    for x, y in grids + grids:
        assert np.array_equal(baseband_at(warm, x, y), baseband_at(fields(), x, y))


def test_cache_under_threads():
    """Dask workers run threads that share the caches: concurrent gets with evictions never fail."""
    import threading

    c = OperatorCache(4)
    errors = []

    def hammer(seed):
        rng = np.random.default_rng(seed)
        try:
            for k in rng.integers(0, 12, 3000):
                assert c.get(int(k), lambda k=int(k): k * 2) == 2 * int(k)
        except Exception as exc:  # noqa: BLE001
            errors.append(exc)

    threads = [threading.Thread(target=hammer, args=(s,)) for s in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(c) <= 4


def test_advise_releases_what_the_base_band_kept():
    from cadartifact.analysis.baseband import MEMO_BYTES

    i, j = np.meshgrid(np.arange(12.0), np.arange(9.0), indexing="ij")
    net = ca.ControlNet.from_points(np.stack([i, j, np.sin(0.6 * i) * np.cos(0.5 * j)], -1), degrees=(3, 3))
    adv = ca.advise(net, 0.01, compare=True, verify=False)
    assert "_rows" not in adv.current.fields.baseband
    assert MEMO_BYTES <= 64 * 2 ** 20


def test_base_band_memo_is_bounded_in_bytes(monkeypatch):
    from cadartifact.analysis import baseband

    monkeypatch.setattr(baseband, "MEMO_BYTES", 200_000)
    i, j = np.meshgrid(np.arange(12.0), np.arange(9.0), indexing="ij")
    net = ca.ControlNet.from_points(np.stack([i, j, np.sin(0.6 * i) * np.cos(0.5 * j)], -1), degrees=(3, 3))
    f = ca.budget(net, None, 0.05, keep_fields=True).fields
    for n in range(5, 60, 3):
        ref = baseband.baseband_at(f, np.linspace(0, 9, n), np.linspace(0, 6, 11))
        assert np.array_equal(ref, baseband.baseband_at(f, np.linspace(0, 9, n), np.linspace(0, 6, 11)))
        rows = f.baseband["_rows"].values()
        kept = sum(a.nbytes for r in rows for a in (r if isinstance(r, tuple) else (r,)))
        assert kept == f.baseband["_rows_bytes"] <= 200_000


def test_a_non_default_budget_given_is_not_reused():
    """advise(current=...) takes a caller's budget only when it is the one advise() would compute (default road
    and region): a predicted-road or interior-only budget of a face is computed again."""
    i, j = np.meshgrid(np.arange(10.0), np.arange(10.0), indexing="ij")
    net = ca.ControlNet(points=np.stack([i, j, np.cos(2 * np.pi * (i + 0.5 * j) / (10 / 3.0))], -1))
    plain = ca.advise(net, 0.05, "bicubic", compare=False, verify=False)
    for opts in ({"region": "interior"}, {"method": "measured"}):
        other = ca.budget(net, "bicubic", 0.05, keep_fields=True, **opts)
        adv = ca.advise(net, 0.05, "bicubic", compare=False, verify=False, current=other)
        assert adv.current is not other
        assert adv.shape == plain.shape and adv.stats["total"].peak == plain.stats["total"].peak
