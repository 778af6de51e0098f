"""The density search's cheaper roads (issue 24) give the numbers of the direct ones.

Each cheaper computation is checked against the plain one it replaces, on families of random cases: the
candidate's error a block of rows at a time against the whole surface projected at once, the pruned border
distance against the full scan, the cached halves of a fit in either order against one product, and a
predicted hint against none on monotone predicates (brute force).
"""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cadartifact.advice.density_search import first_true, frontier, predicted_hint
from cadartifact.analysis.fields import project
from cadartifact.analysis.fitting import CandidateAxis, curve_distance, error_planes, fit_error
from cadartifact.numerics.operator_cache import OperatorCache


def _axis(rng, n, m):
    B = rng.normal(size=(m, n))
    return CandidateAxis(n, 3, np.zeros(n + 4), np.linspace(0.0, 1.0, m), B, np.linalg.pinv(B))


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 30), st.integers(1, 30), st.integers(1, 90), st.integers(1, 2500),
       st.sampled_from(["normal", "vector"]), st.sampled_from(["all", "some", "none", "rows"]),
       st.floats(0.0, 0.5), st.integers(0, 2 ** 31))
def test_blocked_error_is_the_whole_surface_projected(a, b, mu, mv, component, mask, zeros, seed):
    """``fit_error`` (blocks of rows, either inner dimension, normals with zeros, any mask) equals projecting
    ``Bu Q Bv^T - I`` at once (:func:`project`), then the peak and rms of what the mask keeps."""
    mv = max(1, mv // max(mu, 1) + 1)  # grids of up to a few thousand points
    rng = np.random.default_rng(seed)
    cu, cv = _axis(rng, a, mu), _axis(rng, b, mv)
    Q, target = rng.normal(size=(a, b, 3)), rng.normal(size=(mu, mv, 3))
    normal = rng.normal(size=(mu, mv, 3))
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    normal[rng.random((mu, mv)) < zeros] = 0.0  # collapsed points: the whole displacement counts there
    keep = {"all": np.ones((mu, mv), bool), "some": rng.random((mu, mv)) < 0.6,
            "none": np.zeros((mu, mv), bool), "rows": np.broadcast_to(np.arange(mu)[:, None] % 3 == 0, (mu, mv))}[mask]
    S = np.einsum("ia,abc,jb->ijc", cu.B, Q, cv.B)
    f = np.abs(project(S - target, normal, component))[keep]
    got = fit_error(Q, cu, cv, error_planes(target, normal, component), keep)
    assert got["peak"] == pytest.approx(float(f.max()) if f.size else 0.0, rel=1e-12, abs=1e-12)
    assert got["rms"] == pytest.approx(float(np.sqrt(np.mean(f ** 2))) if f.size else 0.0, rel=1e-12, abs=1e-12)


def _full_scan(points, curve):
    a, d = curve[:-1], curve[1:] - curve[:-1]
    L2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(np.einsum("kij,ij->ki", points[:, None, :] - a[None], d) / L2, 0.0, 1.0)
    near = a[None] + t[..., None] * d[None]
    return float(np.sqrt(np.min(np.sum((points[:, None, :] - near) ** 2, axis=-1), axis=1)).max())


@settings(max_examples=80, deadline=None)
@given(st.integers(2, 700), st.integers(1, 700), st.sampled_from(["same", "sorted", "shuffled", "squeezed"]),
       st.sampled_from([0.0, 1e-6, 1e-2, 1.0]), st.floats(0.01, 100.0), st.integers(0, 2 ** 31))
def test_pruned_border_distance_is_the_full_scan(m, k, order, noise, scale, seed):
    """``curve_distance`` (a window, then exact scans while they can beat the best) equals scanning every
    segment for every point, whatever the two curves' parametrisations."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 1.0, m)
    wiggle = rng.uniform(0.0, 3.0)
    shape = lambda u: np.stack([np.cos(3 * u), np.sin(5 * u) * wiggle, u], axis=-1) * scale  # noqa: E731
    u = {"same": np.linspace(0.0, 1.0, k), "sorted": np.sort(rng.random(k)), "shuffled": rng.random(k),
         "squeezed": np.linspace(0.0, 1.0, k) ** 3}[order]
    points = shape(u) + rng.normal(scale=noise * scale, size=(k, 3))
    assert curve_distance(points, shape(s)) == pytest.approx(_full_scan(points, shape(s)), rel=1e-12, abs=1e-300)


class _Monotone:
    def __init__(self, c, pu, pv, t=1.0):
        self.c, self.pu, self.pv, self.t, self.calls = c, pu, pv, t, 0

    def value(self, a, b):
        self.calls += 1
        return self.c / ((a - 1) ** self.pu * (b - 1) ** self.pv)

    def ok(self, a, b):
        return self.value(a, b) <= self.t


@settings(max_examples=150, deadline=None)
@given(st.integers(2, 120), st.integers(2, 120), st.floats(0.2, 6.0), st.floats(0.2, 6.0), st.floats(1.0, 1e7),
       st.integers(1, 5), st.integers(1, 5))
def test_a_predicted_hint_changes_the_tries_not_the_answer(a0, b0, pu, pv, c, p, q):
    """On any monotone error, :func:`frontier` from :func:`predicted_hint` returns the same density as from
    today's (and the hint lies in the box)."""
    lo, hi = (2, 2), (120, 120)
    plain = _Monotone(c, pu, pv)
    expect = frontier(plain.ok, lo, hi, (a0, b0))
    hinted = _Monotone(c, pu, pv)
    hint = predicted_hint(hinted.value(a0, b0), 1.0, (a0, b0), (p, q), lo)
    assert all(l <= h <= n for l, h, n in zip(lo, hint, (a0, b0)))
    assert frontier(hinted.ok, lo, hi, (a0, b0), hint=hint) == expect


@pytest.mark.parametrize("n,p,true_n", [(100, 3, 14), (100, 3, 60), (275, 1, 40), (40, 5, 12)])
def test_the_hint_is_near_the_answer_on_the_error_model(n, p, true_n):
    """On an error that falls as ``n^-(p+1)`` exactly, the hint is the smallest feasible count."""
    err = lambda k: (true_n / k) ** (p + 1)  # noqa: E731  (t = 1 at true_n)
    hint = predicted_hint(err(n), 1.0, (n, n), (p, p), (p + 1, p + 1))
    assert hint == (first_true(p + 1, n, lambda k: err(k) <= 1.0),) * 2


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=1, max_size=25), st.integers(0, 2 ** 31))
def test_the_fits_halves_in_any_order_give_the_direct_product(requests, seed):
    """The scorer's control points (a ``u`` half kept per count, a ``v`` half per count, whichever a
    candidate finds) equal ``Fu I Fv^T`` computed at once, whatever order the candidates come in."""
    from cadartifact.advice.scorer import _Scorer

    rng = np.random.default_rng(seed)
    mu, mv = 23, 19
    I = rng.normal(size=(mu, mv, 3))
    axes = {("u", n): _axis(rng, n + 2, mu) for n in range(7)} | {("v", n): _axis(rng, n + 2, mv) for n in range(7)}
    sc = _Scorer.__new__(_Scorer)
    sc._halves = OperatorCache(4, shared=False)
    sc.axes = lambda a, b: (axes[("u", a)], axes[("v", b)])
    sc.target = lambda x, y: (I, None, np.ones((mu, mv), bool))
    for a, b in requests:
        Q = sc.points(a, b)[0]
        cu, cv = axes[("u", a)], axes[("v", b)]
        assert np.allclose(Q, np.einsum("ai,ijc,bj->abc", cu.pinv, I, cv.pinv), rtol=1e-12, atol=1e-12)


def test_peek_finds_what_get_built_and_builds_nothing():
    cache = OperatorCache(2, shared=False)
    assert cache.peek("a") is None and len(cache) == 0
    cache.get("a", lambda: 1)
    cache.get("b", lambda: 2)
    assert cache.peek("a") == 1  # now the most recently used: "b" goes first
    cache.get("c", lambda: 3)
    assert cache.peek("b") is None and cache.peek("a") == 1 and cache.peek("c") == 3
