"""Scheme design (issue 26): the affine family, the proofs, the search, the mask files and the command.

Independent roads: the sum rules are checked by subdividing polynomial nets in space (no symbol); the designed
mask's responses by brute-force subdivision of sinusoid nets (tests/theory/test_bruteforce.py); the Sobolev exponents
against the closed forms of B-splines (degree p: p + 1/2); the difference contraction against the factored
B-spline symbol (1/2 per step).
"""

import json
from functools import lru_cache

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from typer.testing import CliRunner

import cadartifact as ca
from cadartifact.errors import OptionError, SchemeError
from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.periodic_nets import SHIFTS, circular_convolve, omega_grid, project, sinusoid_nets, subdivide
from cadartifact.theory import symbols as sy
from cadartifact.theory.catalogue import SCHEME_NAMES, scheme
from cadartifact.theory.design import DesignSpec, affine_family, design, objective_value, symmetric_basis
from cadartifact.theory.regularity import continuity_proof, difference_contraction, proven_class, sobolev_exponent


@lru_cache(maxsize=None)
def designed(**kw):
    return design(**kw)


def cached(**kw):
    return designed(**kw)


# ------------------------------------------------------------------ proofs
@pytest.mark.parametrize("p", [1, 2, 3, 4])
def test_sobolev_exponent_of_bsplines_is_p_plus_half(p):
    """phi_hat = sinc^(p+1) sinc^(p+1): in H^s exactly for s < p + 1/2."""
    assert sobolev_exponent(scheme(f"bspline({p},{p})").mask) == pytest.approx(p + 0.5, abs=1e-9)


def test_sobolev_exponent_of_the_four_point_scheme():
    """Kobbelt's tensor 4-point scheme: the 1-D 4-point value 2.4408 (Villemoes 1994; Eirola 1992)."""
    assert sobolev_exponent(scheme("kobbelt").mask) == pytest.approx(2.4408, abs=1e-4)


@pytest.mark.parametrize("name,cls", [("bilinear", 0), ("bicubic", 2), ("4-3", 2), ("4-8", 2), ("kobbelt", 1)])
def test_named_schemes_are_proven_in_their_class(name, cls):
    p = continuity_proof(scheme(name).mask)
    assert p.convergent and p.continuity == cls


def test_difference_contraction_of_bsplines_halves_per_step():
    """(1 - z1) M = (1 - z1^2) 2 ((1+z1)/2)^3 ((1+z2)/2)^4: coefficient sums 1/2 per step, (1/2)^n for n steps."""
    for n in (1, 2, 3):
        assert difference_contraction(scheme("bicubic").mask, n) == pytest.approx(0.5 ** n, abs=1e-9)


def test_piecewise_constant_is_not_proven_convergent():
    """Mask ones(2, 2): refined nets keep their jumps (gamma = 1), no uniform convergence is claimed."""
    p = continuity_proof(np.ones((2, 2)))
    assert not p.convergent and p.continuity == -1


def test_proven_class_needs_a_strict_margin():
    assert [proven_class(s) for s in (0.9, 1.5, 2.0, 2.0001, 3.5, 9.0)] == [-1, 0, 0, 1, 2, 2]


# ------------------------------------------------------------------ the family
def test_symmetric_basis_partitions_the_mask():
    E = symmetric_basis((6, 6), "square")
    assert len(E) == 6 and np.all(E.sum(axis=0) == 1)
    assert len(symmetric_basis((5, 7), "axes")) == 12


@pytest.mark.parametrize("name,support", [("bicubic", (5, 5)), ("4-3", (5, 5)), ("4-8", (7, 7))])
def test_named_schemes_lie_in_their_family(name, support):
    m0, N = affine_family(DesignSpec(support=support, degree=3, continuity=2))
    m = scheme(name).mask
    flat = N.reshape(len(N), -1)
    q = np.linalg.lstsq(flat.T, (m - m0).ravel(), rcond=None)[0]
    np.testing.assert_allclose(m0 + np.tensordot(q, N, axes=1), m, atol=1e-12)


def _poly_values(coef, x, y):
    return sum(c * x ** i * y ** j for (i, j), c in coef.items())


@settings(max_examples=25, deadline=None)
@given(size=st.sampled_from([(5, 5), (6, 6), (7, 7), (6, 8), (7, 5)]), degree=st.integers(0, 3),
       seed=st.integers(0, 2 ** 31 - 1))
def test_family_masks_are_symmetric_and_reproduce_polynomials(size, degree, seed):
    """Any mask of the family: symmetric, sums 4, and one step maps degree-d polynomial nets to polynomial nets."""
    sym = "square" if size[0] == size[1] else "axes"
    try:
        m0, N = affine_family(DesignSpec(support=size, symmetry=sym, degree=degree, continuity=0))
    except OptionError:
        return
    rng = np.random.default_rng(seed)
    m = m0 + np.tensordot(rng.normal(0, 0.1, len(N)), N, axes=1)
    assert np.allclose(m, m[::-1, :]) and np.allclose(m, m[:, ::-1]) and abs(m.sum() - 4) < 1e-12
    if sym == "square":
        assert np.allclose(m, m.T)
    assert sy.sum_rule_order(m) >= degree
    # space domain: upsample a polynomial net and convolve with the mask (array offsets as in test_bruteforce)
    n = 12
    coef = {(i, j): rng.normal() for i in range(degree + 1) for j in range(degree + 1 - i)}
    J = np.arange(n, dtype=float)
    net = _poly_values(coef, J[:, None], J[None, :])
    up = np.zeros((2 * n, 2 * n))
    up[::2, ::2] = net
    out = np.zeros((2 * n + m.shape[0] - 1, 2 * n + m.shape[1] - 1))
    for a in range(m.shape[0]):
        for b in range(m.shape[1]):
            out[a:a + 2 * n, b:b + 2 * n] += m[a, b] * up
    s1, s2 = m.shape
    inner = out[s1:2 * n - 1, s2:2 * n - 1]  # every output fed by a full mask of net points
    P1 = np.arange(s1, 2 * n - 1)[:, None] * np.ones((1, inner.shape[1]))
    P2 = np.ones((inner.shape[0], 1)) * np.arange(s2, 2 * n - 1)[None, :]
    basis = np.array([(P1 / 10) ** i * (P2 / 10) ** j for i in range(degree + 1) for j in range(degree + 1 - i)])
    fit, *_ = np.linalg.lstsq(basis.reshape(len(basis), -1).T, inner.ravel(), rcond=None)
    resid = inner.ravel() - basis.reshape(len(basis), -1).T @ fit
    assert np.abs(resid).max() <= 1e-8 * max(1.0, np.abs(inner).max())


# ------------------------------------------------------------------ the search
@pytest.mark.parametrize("objective,names", [("energy", ("bicubic", "4-3")), ("lateral", ("4-3", "bicubic"))])
def test_rediscovery_at_5x5_is_at_least_as_good(objective, names):
    d = cached(support=(5, 5), degree=3, objective=objective, continuity=2)
    assert d.proof.continuity == 2
    for name in names:
        assert d.objective <= d.references[name][0] * (1 + 1e-9)


@pytest.mark.slow
def test_rediscovery_of_4_8_at_7x7_is_at_least_as_good():
    d = cached(support=(7, 7), degree=3, objective="energy", continuity=2, starts=0)
    assert d.proof.continuity == 2
    assert d.objective <= d.references["4-8"][0] * (1 + 1e-9)


def test_designed_6x6_c1_beats_4_8_on_the_nyquist_square_not_at_low_frequencies():
    """The design itself takes about a minute: benchmarks/time_limits.py. On the paper's normalisation (the energy
    artifact as a share of the signal) its RMS over the Nyquist square is below 4-8's; at low frequencies 4-8's
    share is far lower (docs/scheme-design.md)."""
    d = cached(support=(6, 6), degree=2, objective="energy", continuity=1)
    assert d.spec.normalisation == "signal"
    assert d.proof.convergent and d.proof.continuity >= 1
    assert d.artifact < d.references["4-8"][1]
    # the reported number is the exact engine's: RMS of Response.energy / signal on the same midpoint grid
    n = 4 * d.spec.resolution
    w = (np.arange(n) + 0.5) * (0.5 / n)
    r = d.scheme.response(w[None, :], w[:, None], "limit")
    assert np.sqrt(np.mean((np.asarray(r.energy) / np.asarray(r.signal)) ** 2)) == pytest.approx(d.artifact,
                                                                                               rel=1e-12)
    low, low48 = d.scheme.response(0.1, 0.2, "limit"), scheme("4-8").response(0.1, 0.2, "limit")
    assert low.energy / low.signal > 10 * low48.energy / low48.signal


def symbol_classes(mask, wx, wy):
    """Signal and artifact classes after one step by summing the mask's symbol directly (no library engine):
    ``M(Omega + V) / 4 = sum_k m_k cos(pi (w + V) . k) / 4`` with ``k`` the centred offsets (symmetric masks)."""
    s1, s2 = mask.shape
    k1 = np.arange(s1)[:, None] - (s1 - 1) / 2
    k2 = np.arange(s2)[None, :] - (s2 - 1) / 2
    return [float(np.sum(mask * np.cos(np.pi * ((wx + v1) * k1 + (wy + v2) * k2))) / 4)
            for v1, v2 in ((0, 0), (1, 0), (0, 1), (1, 1))]


@pytest.mark.parametrize("name", ["bicubic", "4-3", "4-8", "kobbelt"])
@pytest.mark.parametrize("normalisation", ["signal", "absolute"])
def test_objective_normalisation_by_the_masks_symbol(name, normalisation):
    """The one-step objective against a direct evaluation of the mask's symbol on the same midpoint grid."""
    spec = DesignSpec(support=(7, 7), degree=2, stage="one_step", normalisation=normalisation, resolution=8)
    mask = scheme(name).mask
    w = (np.arange(8) + 0.5) * (0.5 / 8)
    vals = []
    for wy in w:
        for wx in w:
            a, b, c, d = symbol_classes(mask, wx, wy)
            e2 = (b * b + c * c + d * d) / 3
            vals.append(e2 / a ** 2 if normalisation == "signal" else e2)
    J, art, _ = objective_value(mask, spec)
    assert art == pytest.approx(np.sqrt(np.mean(vals)), rel=1e-12) and J == pytest.approx(art ** 2, rel=1e-12)


def test_designed_signal_stays_positive_and_bounded_on_the_band():
    """The default bound (signal >= 0.2 on |w| <= 0.25) by the exact engine on a finer grid than the design's."""
    d = cached(support=(6, 6), degree=2, objective="energy", continuity=1)
    n = 200
    w = (np.arange(n + 1)) * (d.spec.attenuation_band / n)  # the band's edges included
    a = np.asarray(d.scheme.response(w[None, :], w[:, None], "limit").signal)
    assert a.min() >= d.spec.min_signal - 1e-3 and d.min_signal >= d.spec.min_signal - 1e-9
    assert d.as_dict()["min_signal_on_band"] == d.min_signal


@pytest.mark.slow
def test_a_tighter_signal_bound_is_met_or_refused():
    """min_signal 0.6 on |w| <= 0.15: the design meets it (checked by the exact engine) where the free design does
    not, at the price of artifact."""
    free = cached(support=(6, 6), degree=2, objective="energy", continuity=1, min_signal=0.01,
                  attenuation_band=0.15)
    n = 60
    w = (np.arange(n + 1)) * (0.15 / n)
    a_free = np.asarray(free.scheme.response(w[None, :], w[:, None], "limit").signal).min()
    kept = cached(support=(6, 6), degree=2, objective="energy", continuity=1, min_signal=a_free + 0.05,
                  attenuation_band=0.15)
    a_kept = np.asarray(kept.scheme.response(w[None, :], w[:, None], "limit").signal).min()
    assert a_kept >= a_free + 0.05 - 1e-3
    assert kept.artifact >= free.artifact * (1 - 1e-9)


def test_generation_degree_is_generation_not_reproduction():
    """Bicubic: generation degree 3; x^2 data come out as x^2 + 1/3 at the limit (generated, not reproduced)."""
    s = scheme("bicubic")
    assert s.generation_degree == s.reproduction_degree == 3
    L = np.asarray(s.limit_stencil)
    k = np.arange(L.shape[0]) - (L.shape[0] - 1) / 2
    for x0 in (0.0, 1.0, 2.5):  # the limit at a control point of x^2 data: x0^2 + 1/3
        assert np.sum(L * ((x0 + k)[:, None] ** 2)) == pytest.approx(x0 ** 2 + 1 / 3, abs=1e-12)
    doc = cached(support=(6, 6), degree=2, objective="energy", continuity=1).as_dict()
    assert doc["generation_degree"] == 2 and "reproduction_degree" not in doc


def test_design_is_deterministic():
    a = design(support=(6, 6), degree=2)
    b = design(support=(6, 6), degree=2)
    assert np.array_equal(a.mask, b.mask)


@pytest.mark.parametrize("objective,zeros", [("energy", ((0.25, 0.25),)), ("x1", ((0.25, 0.25), (0.4, 0.1)))])
def test_exact_zeros_where_asked(objective, zeros):
    """Each zero costs one linear condition per artifact class asked (fewer on the diagonal, by symmetry)."""
    d = cached(support=(6, 6), degree=2, objective=objective, zeros=zeros)
    assert d.proof.continuity >= 1 and max(d.zeros) <= 1e-12
    for stage in ("limit", "one_step"):
        for wx, wy in zeros:
            r = d.scheme.response(wx, wy, stage)
            asked = (r.x1,) if objective == "x1" else (r.x1, r.x2, r.diagonal)
            assert max(abs(v) for v in asked) <= 1e-12


def test_designed_responses_equal_brute_force_subdivision():
    """One step and the limit at the refined vertices over 13 x 13 frequencies, to 1e-12 (as test_bruteforce)."""
    s = cached(support=(6, 6), degree=2, zeros=((0.25, 0.25),)).scheme
    n = 12
    om = omega_grid(n)
    refined = subdivide(sinusoid_nets(om, n), s.mask)
    c = [(k - 1) / 2 for k in s.mask.shape]
    pos = [np.arange(2 * n) - c[0], np.arange(2 * n) - c[1]]
    L = s.limit_stencil
    limit = circular_convolve(refined, L)
    lpos = [pos[0] - (L.shape[0] - 1) / 2, pos[1] - (L.shape[1] - 1) / 2]
    one = s.response(om[:, 0], om[:, 1], "one_step")
    lim = s.response(om[:, 0], om[:, 1], "limit")
    for V, a, alpha in zip(SHIFTS, (one.signal, one.x1, one.x2, one.diagonal),
                           (lim.signal, lim.x1, lim.x2, lim.diagonal)):
        f = (om + np.array(V)) / 2
        np.testing.assert_allclose(project(refined, f, pos), a, atol=1e-12)
        np.testing.assert_allclose(project(limit, f, lpos), alpha, atol=1e-12)
    # and the zero asked for is a zero of the simulation too
    k = np.argmin(np.abs(om - 0.25).sum(axis=1))
    for V in SHIFTS[1:]:
        assert abs(project(limit, (om[k:k + 1] + np.array(V)) / 2, lpos)[0]) <= 1e-12


@pytest.mark.slow
def test_attenuation_weight_trades_artifact_for_signal():
    plain = cached(support=(6, 6), degree=2)
    kept = cached(support=(6, 6), degree=2, attenuation_weight=1.0)
    spec = DesignSpec(support=(6, 6), degree=2, attenuation_weight=1.0)
    att_plain = objective_value(plain.mask, spec, 96)[2]
    assert kept.attenuation < att_plain
    assert kept.artifact >= plain.artifact


@pytest.mark.parametrize("kwargs,parameter", [
    (dict(support=(6, 5)), "symmetry"), (dict(support=(2, 2)), "support"), (dict(objective="ripple"), "objective"),
    (dict(symmetry="round"), "symmetry"), (dict(degree=1, continuity=1), "degree"), (dict(zeros=[(0.7, 0)]), "zeros"),
    (dict(stage="continuous"), "stage"), (dict(support=(4, 4), degree=3, continuity=0), "support"),
    (dict(support=(5, 5), degree=3, continuity=2, zeros=[(0.25, 0.25)]), "support"),
    (dict(min_signal=0), "min_signal"), (dict(min_signal=1.5), "min_signal"), (dict(normalisation="percent"),
                                                                              "normalisation"),
])
def test_bad_requests_are_one_line_option_errors(kwargs, parameter):
    with pytest.raises(OptionError) as err:
        design(**kwargs)
    assert err.value.parameter == parameter and "\n" not in str(err.value)


# ------------------------------------------------------------------ mask files and the command
def test_saved_design_is_a_scheme_everywhere(tmp_path):
    d = cached(support=(6, 6), degree=2)
    js, npy = d.save(tmp_path / "d6")
    doc = json.loads(js.read_text())
    assert doc["format"] == "cadartifact-mask" and doc["continuity"]["proven"] == "C1"
    for path in (js, npy):
        s = ca.scheme(f"file:{path}")
        np.testing.assert_array_equal(s.mask, d.mask)
        assert s.name == f"file:{path}"
    np.testing.assert_allclose(np.array(doc["limit_stencil"]), d.scheme.limit_stencil)
    from cadartifact.analysis.settings import RunSettings
    from cadartifact.gate.policy import check_cli

    RunSettings(scheme=f"file:{js}")
    check_cli({"scheme": f"file:{js}"})


def test_bad_mask_files_are_scheme_errors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"mask": [[1, 1], [1, 2]]}')
    nomask = tmp_path / "nomask.json"
    nomask.write_text('{"x": 1}')
    for name in (f"file:{tmp_path / 'missing.json'}", f"file:{bad}", f"file:{nomask}", f"file:{tmp_path}"):
        with pytest.raises(SchemeError) as err:
            scheme(name)
        assert "\n" not in str(err.value)


def _cli(args):
    from cadartifact.cli.app import app

    return CliRunner().invoke(app, [str(a) for a in args])


def test_design_command_writes_the_mask_and_the_maps(tmp_path):
    r = _cli(["design", "--support", "6x6", "--degree", "2", "--name", "d5", "--out", tmp_path,
              "--zero", "0.25,0.25", "--json"])
    assert r.exit_code == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["zeros"][0]["artifact"] <= 1e-12
    for f in ("d5.json", "d5.npy", "d5-maps.png"):
        assert (tmp_path / f).stat().st_size > 0
    r = _cli(["maps", "-s", f"file:{tmp_path / 'd5.json'}", "-s", "4-8", "-o", tmp_path / "m.png",
              "--resolution", "32"])
    assert r.exit_code == 0, r.stderr


@pytest.mark.parametrize("args,option", [
    (["--support", "6y6"], "--support"), (["--objective", "ripple"], "--objective"),
    (["--continuity", "C3"], "--continuity"),
    (["--zero", "0.2"], "--zero"), (["--stage", "continuous"], "--stage"), (["--name", "a/b"], "--name"),
    (["--symmetry", "round"], "--symmetry"),
])
def test_design_command_errors_are_one_line(args, option):
    r = _cli(["design", *args, "--no-maps"])
    assert r.exit_code == 2
    lines = [x for x in r.stderr.splitlines() if x.strip()]
    assert len(lines) == 1 and option in lines[0], r.stderr
    no_traceback(r, r.stderr)


def test_the_named_schemes_are_compared_under_the_same_objective():
    d = cached(support=(6, 6), degree=2)
    assert set(d.references) == set(SCHEME_NAMES)
    for name, (J, art) in d.references.items():
        assert J == pytest.approx(objective_value(scheme(name).mask, d.spec, 4 * d.spec.resolution)[0])
