"""occ_surface / evaluate_grid: OCCT's evaluator vs OCCT's own Value and vs a plain de Boor written here."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("OCP")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.Geom import Geom_BSplineSurface, Geom_RectangularTrimmedSurface  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.TColgp import TColgp_Array2OfPnt  # noqa: E402
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal, TColStd_Array2OfReal  # noqa: E402

from cadartifact.errors import OptionError  # noqa: E402
from cadartifact.exchange.load import evaluate_grid, occ_surface, read  # noqa: E402
from cadartifact.exchange.occ import iter_faces, net_from_surface, periodic_flat_knots  # noqa: E402
from cadartifact.exchange.step import read_step  # noqa: E402
from cadartifact.net import ControlNet, NetOrigin  # noqa: E402
from cadartifact.testing.paths import REALDATA


# ---------------------------------------------------------------- plain Cox-de Boor (independent road)
def basis(t: np.ndarray, p: int, x: float) -> np.ndarray:
    """All ``len(t) - p - 1`` B-spline basis values at ``x`` by the textbook recursion."""
    t = np.asarray(t, float)
    m = len(t) - 1
    hi = t[m - p]
    N = np.array([1.0 if t[i] <= x < t[i + 1] else 0.0 for i in range(m)])
    if x >= hi:  # right end: the last non-empty span of the valid range
        k = max(i for i in range(m) if t[i] < t[i + 1] and t[i + 1] <= hi + 1e-15)
        N[:] = 0.0
        N[k] = 1.0
    for d in range(1, p + 1):
        new = np.zeros(m - d)
        for i in range(m - d):
            a = (x - t[i]) / (t[i + d] - t[i]) * N[i] if t[i + d] > t[i] else 0.0
            b = (t[i + d + 1] - x) / (t[i + d + 1] - t[i + 1]) * N[i + 1] if t[i + d + 1] > t[i + 1] else 0.0
            new[i] = a + b
        N = new
    return N


def de_boor(net: ControlNet, u: float, v: float) -> np.ndarray:
    (ku, kv), (p, q) = net.knots, net.degrees
    nu, nv = net.shape
    Bu, Bv = basis(ku, p, u), basis(kv, q, v)
    # periodic: flat basis function k acts on pole k mod n
    Wu = np.zeros(nu)
    np.add.at(Wu, np.arange(len(Bu)) % nu, Bu)
    Wv = np.zeros(nv)
    np.add.at(Wv, np.arange(len(Bv)) % nv, Bv)
    w = np.ones((nu, nv)) if net.weights is None else net.weights
    num = np.einsum("i,ijk,j->k", Wu, net.points * w[..., None], Wv)
    return num / (Wu @ w @ Wv)


def param_range(net: ControlNet, axis: int) -> tuple[float, float]:
    t, p = net.knots[axis], net.degrees[axis]
    return t[p], t[len(t) - p - 1]


# ---------------------------------------------------------------- real faces
@pytest.mark.realdata
@pytest.mark.parametrize("name", ["nist_ctc_02_asme1_ap242-1.stp", "boxed_sphere.step", "MAINBODY_BACK.stp"])
def test_evaluate_grid_matches_occt_value_and_de_boor(name):
    path = REALDATA / "step" / name
    nets = read(path).nets
    shape, _ = read_step(path)
    surfaces = {}
    for index, face in iter_faces(shape):
        s = BRep_Tool.Surface_s(face)
        while isinstance(s, Geom_RectangularTrimmedSurface):
            s = s.BasisSurface()
        surfaces[index] = s
    rng = np.random.default_rng(7)
    for net in [n for n in nets if any(n.periodic)] + nets[:8]:
        original = surfaces[net.origin.face]
        u0, u1, v0, v1 = original.Bounds()
        u = np.sort(rng.uniform(u0, u1, 5))
        v = np.sort(rng.uniform(v0, v1, 4))
        grid = evaluate_grid(net, u, v)
        scale = max(1.0, np.abs(net.points).max())
        for a, uu in enumerate(u):
            for b, vv in enumerate(v):
                p = original.Value(uu, vv)
                np.testing.assert_allclose(grid[a, b], [p.X(), p.Y(), p.Z()], rtol=0, atol=1e-10 * scale)
                np.testing.assert_allclose(grid[a, b], de_boor(net, uu, vv), rtol=0, atol=1e-8 * scale)


# ---------------------------------------------------------------- random nets (hypothesis)
def _occ_random_surface(rng, nu, nv, p, q, rational, periodic_u, first_mult):
    """A random OCCT surface; periodic in u with a seam knot of multiplicity ``first_mult``."""
    def knot_data(n, deg, periodic, m0):
        if periodic:
            # n poles = sum(mults) - m_last with m_first = m_last = m0 and simple interior knots
            interior = n - m0
            values = np.cumsum(rng.uniform(0.5, 1.5, interior + 2))
            return values - values[0], [m0] + [1] * interior + [m0]
        interior = n - deg - 1
        values = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 1.5, interior + 1))])
        return values, [deg + 1] + [1] * interior + [deg + 1]

    ku, mu = knot_data(nu, p, periodic_u, first_mult)
    kv, mv = knot_data(nv, q, False, 1)
    poles = TColgp_Array2OfPnt(1, nu, 1, nv)
    weights = TColStd_Array2OfReal(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*rng.normal(size=3) * 10))
            weights.SetValue(i + 1, j + 1, rng.uniform(0.5, 2.0))

    def arr(values, cls, cast):
        a = cls(1, len(values))
        for k, x in enumerate(values, 1):
            a.SetValue(k, cast(x))
        return a

    args = (arr(ku, TColStd_Array1OfReal, float), arr(kv, TColStd_Array1OfReal, float),
            arr(mu, TColStd_Array1OfInteger, int), arr(mv, TColStd_Array1OfInteger, int), p, q, periodic_u, False)
    return Geom_BSplineSurface(poles, weights, *args) if rational else Geom_BSplineSurface(poles, *args)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), p=st.integers(1, 4), q=st.integers(1, 3), rational=st.booleans(),
       periodic=st.booleans(), first_mult=st.integers(1, 3), extra_u=st.integers(0, 6), extra_v=st.integers(0, 4))
def test_net_round_trips_through_occt_and_evaluates_like_de_boor(seed, p, q, rational, periodic, first_mult,
                                                                  extra_u, extra_v):
    rng = np.random.default_rng(seed)
    first_mult = min(first_mult, p)
    nu = (p + 1 if not periodic else max(p + 1, first_mult + 2)) + extra_u
    nv = q + 1 + extra_v
    surface = _occ_random_surface(rng, nu, nv, p, q, rational, periodic, first_mult)
    net = net_from_surface(surface, origin=NetOrigin(kind="bspline"))
    assert net.periodic == (periodic, False)
    rebuilt = occ_surface(net)
    again = net_from_surface(rebuilt, origin=NetOrigin(kind="bspline"))
    assert again.points.tobytes() == net.points.tobytes()
    assert all(a.tobytes() == b.tobytes() for a, b in zip(again.knots, net.knots))
    for d in "UV":
        count = getattr(surface, f"Nb{d}Knots")()
        assert getattr(rebuilt, f"Nb{d}Knots")() == count
        for i in range(1, count + 1):
            assert getattr(rebuilt, f"{d}Knot")(i) == getattr(surface, f"{d}Knot")(i)
            assert getattr(rebuilt, f"{d}Multiplicity")(i) == getattr(surface, f"{d}Multiplicity")(i)
    (u0, u1), (v0, v1) = param_range(net, 0), param_range(net, 1)
    u = np.concatenate([[u0, u1], rng.uniform(u0, u1, 3)])
    v = np.concatenate([[v0, v1], rng.uniform(v0, v1, 3)])
    grid = evaluate_grid(net, u, v)
    for a, uu in enumerate(u):
        for b, vv in enumerate(v):
            p_ = surface.Value(uu, vv)
            np.testing.assert_allclose(grid[a, b], [p_.X(), p_.Y(), p_.Z()], rtol=0, atol=1e-9)
            np.testing.assert_allclose(grid[a, b], de_boor(net, uu, vv), rtol=0, atol=1e-8)


def test_periodic_flat_knots_simple_seam_is_occt_sequence():
    rng = np.random.default_rng(3)
    surface = _occ_random_surface(rng, 9, 4, 3, 2, False, True, 1)
    seq = surface.UKnotSequence()
    occ = [seq.Value(i) for i in range(seq.Lower(), seq.Upper() + 1)]
    knots = [surface.UKnot(i) for i in range(1, surface.NbUKnots() + 1)]
    mults = [surface.UMultiplicity(i) for i in range(1, surface.NbUKnots() + 1)]
    flat = periodic_flat_knots(knots, mults, 3)
    assert len(flat) == 9 + 2 * 3 + 1 == len(occ)
    np.testing.assert_array_equal(flat, occ)


# ---------------------------------------------------------------- edges
def test_evaluate_grid_rejects_cages_and_out_of_range():
    cage = ControlNet.from_points(np.random.default_rng(0).normal(size=(3, 3)), None)
    with pytest.raises(OptionError, match="net"):
        evaluate_grid(cage, [0.5], [0.5])
    net = ControlNet.from_points(np.random.default_rng(0).normal(size=(5, 5)))
    with pytest.raises(OptionError, match="u"):
        evaluate_grid(net, [1.5], [0.5])
    with pytest.raises(OptionError, match="v"):
        evaluate_grid(net, [0.5], [np.nan])
    assert evaluate_grid(net, [], [0.5]).shape == (0, 1, 3)


def test_evaluate_grid_speed_is_reported_not_asserted():
    net = ControlNet.from_points(np.random.default_rng(1).normal(size=(20, 20)))
    u = np.linspace(0, 1, 160)
    start = time.perf_counter()
    grid = evaluate_grid(net, u, u)
    elapsed = time.perf_counter() - start
    assert grid.shape == (160, 160, 3)
    print(f"evaluate_grid: {elapsed / grid[..., 0].size * 1e6:.2f} us/point")
