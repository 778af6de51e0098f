"""Designing schemes: a binary quad mask of a given support and symmetry with the least artifact (paper: "a tool to
design schemes for which the error/artifact is zero at a certain sampling frequency").

The search space is affine. A mask with the chosen symmetry is ``m = sum_o p_o E_o`` (``E_o`` the indicator of one
orbit of the group: the square's eight symmetries, or the two axis reflections). The constraints are linear in
``p``:

* the sum rules of degree ``d`` (SPEC §2): ``M(0) = 4`` and, for ``V in {X1, X2, X1+X2}``, the modulated moments
  ``sum_k m_k (-1)^(V.a) k^alpha = 0`` for ``|alpha| <= d`` (``M(Omega + V)`` vanishes to order ``d + 1`` at 0), so
  polynomial nets of degree ``<= d`` carry no artifact;
* exact zeros: ``M(Omega_0 + V) = 0`` at each chosen ``Omega_0`` for the classes the objective names. Then the one-step
  artifact ``M(Omega_0 + V)/4`` and the limit artifact ``M(Omega_0 + V)/4 L(Omega_0 + V)`` vanish exactly (to
  rounding).

so ``p = p0 + N q`` (``N`` an orthonormal basis of the null space). Over ``q`` the objective

    J(q) = mean over the region of  (A(Omega) / a(Omega))^2  +  w mean over the band of (1 - a(Omega))^2

is minimised (``A`` the artifact asked for: energy ``sqrt((b^2 + c^2 + d^2)/3)``, one class, or the lateral artifact of
SPEC §3, at the limit or after one step; ``a`` the signal). By default the artifact is read on the paper's
normalisation, as a share of the signal at the same frequency (§3: "percent of the signal"); ``normalisation=
"absolute"`` minimises ``A^2`` itself, which rewards masks that shrink the signal along with the artifact. The
search is SLSQP from deterministic starts (the family's least-norm point, the B-spline and box-spline masks of the
support projected on the family, fixed pseudo-random points), subject to the Sobolev exponent bound
``nu_2 >= r + 1 + 0.02`` that proves ``C^r`` (:mod:`cadartifact.theory.regularity`) and to the signal bound
``a(Omega) >= min_signal > 0`` on the band ``|wx|, |wy| <= attenuation_band``: the signal response stays positive
there (a negative one inverts the net's content: the surface bulges where the net dips) and its attenuation is
bounded. The chosen mask is then checked again: convergence by the contractivity of
its difference scheme, the class by ``nu_2``; its responses come from :class:`~cadartifact.theory.catalogue.Scheme`,
the engine of the named schemes.

Reference: U. H. Augsdörfer, N. A. Dodgson, M. A. Sabin, "Artifact analysis on B-splines, box-splines and other
surfaces defined by quadrilateral polyhedra", CAGD 28 (2011), abstract and §9; SPEC §2-3.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import symbols as sy
from .catalogue import MAX_MASK_SIDE, SCHEME_NAMES, Scheme, scheme
from .regularity import ContinuityProof, continuity_proof, sobolev_exponent
from ..errors import InputError, OptionError, SchemeError, check_option

__all__ = ["DesignSpec", "Design", "design", "symmetric_basis", "affine_family", "objective_value",
           "signal_margin", "OBJECTIVES", "SYMMETRIES", "NORMALISATIONS", "DESIGN_STAGES", "MASK_FORMAT"]

OBJECTIVES = ("energy", "x1", "x2", "diagonal", "lateral")
SYMMETRIES = ("square", "axes")
NORMALISATIONS = ("signal", "absolute")
#: Below this the signal is taken as this in the normalised objective (a vanishing signal: 100000 % artifact).
_SIGNAL_FLOOR = 1e-5
DESIGN_STAGES = ("limit", "one_step")
#: ``format`` key of a mask file.
MASK_FORMAT = "cadartifact-mask"
_SHIFTS = ((0, 0), (1, 0), (0, 1), (1, 1))
#: Which alias classes (1: X1, 2: X2, 3: diagonal) an objective's exact zeros constrain.
_ZERO_CLASSES = {"energy": (1, 2, 3), "x1": (1,), "x2": (2,), "diagonal": (3,), "lateral": (1, 2, 3)}
_SOBOLEV_MARGIN = 0.02
#: Starts refined by the local search after screening.
_REFINED = 3


# ------------------------------------------------------------------ the specification
def _positive_int(name, value, lo, hi):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
        raise OptionError(name, f"an integer from {lo} to {hi}", value)
    return int(value)


def _fraction(name, value, lo, hi):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise OptionError(name, f"a number from {lo} to {hi}", value) from None
    if not np.isfinite(v) or not lo <= v <= hi:
        raise OptionError(name, f"a number from {lo} to {hi}", value)
    return v


@dataclass(frozen=True)
class DesignSpec:
    """What to design (validated once).

    Attributes
    ----------
    support : (int, int)
        Mask size ``s1 x s2`` (3 to 9 per side; even sides make dual schemes).
    symmetry : {"square", "axes"}
        The square's eight symmetries (needs ``s1 = s2``) or only the reflections in the two axes.
    degree : int
        Sum-rule degree: polynomial nets up to this degree carry no artifact (0 to 5).
    objective : {"energy", "x1", "x2", "diagonal", "lateral"}
        The artifact minimised (SPEC §3).
    stage : {"limit", "one_step"}
        Limit surface at the refined vertices (paper §6-7) or after one step.
    region : float
        The objective is averaged over ``|wx|, |wy| <= region`` (0.5: the Nyquist square).
    zeros : tuple of (float, float)
        Frequencies (cycles per control point) where the artifact must vanish exactly.
    continuity : int
        The smoothness class ``C^r`` (0, 1, 2) that must be proven.
    attenuation_weight : float
        ``w``: weight of the mean squared signal loss ``(1 - a)^2`` over ``|w| <= attenuation_band`` (0: artifact only).
    attenuation_band : float
        The band (cycles per control point) of the signal bound and of the signal loss.
    min_signal : float
        ``0 < s <= 1``: the signal response ``a`` is at least this on the band (checked on the design grid and
        again on a 4 times finer one).
    normalisation : {"signal", "absolute"}
        The artifact as a share of the signal (the paper's percent of the signal; default) or in absolute terms.
    resolution : int
        Midpoint-rule points per axis on the quadrant during the search (the report uses 4 times more).
    starts : int
        Pseudo-random starts besides the least-norm point and the catalogue masks that fit the support.
    """

    support: tuple = (6, 6)
    symmetry: str = "square"
    degree: int = 3
    objective: str = "energy"
    stage: str = "limit"
    region: float = 0.5
    zeros: tuple = ()
    continuity: int = 1
    attenuation_weight: float = 0.0
    attenuation_band: float = 0.25
    min_signal: float = 0.2
    normalisation: str = "signal"
    resolution: int = 24
    starts: int = 2

    def __post_init__(self):
        sup = self.support
        if isinstance(sup, (int, np.integer)) and not isinstance(sup, bool):
            sup = (sup, sup)
        if not isinstance(sup, (tuple, list)) or len(sup) != 2:
            raise OptionError("support", "two mask sizes such as (6, 6)", self.support)
        sup = tuple(_positive_int("support", s, 3, min(9, MAX_MASK_SIDE)) for s in sup)
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        set_("support", sup)
        check_option("symmetry", self.symmetry, SYMMETRIES)
        if self.symmetry == "square" and sup[0] != sup[1]:
            raise OptionError("symmetry", "'axes' for a support that is not square", self.symmetry)
        set_("degree", _positive_int("degree", self.degree, 0, 5))
        check_option("objective", self.objective, OBJECTIVES)
        check_option("stage", self.stage, DESIGN_STAGES)
        set_("region", _fraction("region", self.region, 0.01, 0.5))
        zeros = []
        for z in self.zeros:
            try:
                wx, wy = (float(v) for v in z)
            except (TypeError, ValueError):
                raise OptionError("zeros", "frequency pairs (wx, wy)", z) from None
            if not (np.isfinite(wx) and np.isfinite(wy)) or max(abs(wx), abs(wy)) > 0.5:
                raise OptionError("zeros", "frequency pairs inside the Nyquist square |w| <= 0.5", z)
            zeros.append((wx, wy))
        set_("zeros", tuple(zeros))
        set_("continuity", _positive_int("continuity", self.continuity, 0, 2))
        if self.degree < self.continuity + 1:  # the Sobolev bound of sum rules of order k is at most k
            raise OptionError("degree", f"at least {self.continuity + 1} to prove C{self.continuity} "
                                        f"(sum rules of degree d prove at most C(d-1))", self.degree)
        set_("attenuation_weight", _fraction("attenuation_weight", self.attenuation_weight, 0.0, 1e6))
        set_("attenuation_band", _fraction("attenuation_band", self.attenuation_band, 0.01, 0.5))
        set_("min_signal", _fraction("min_signal", self.min_signal, 0.0, 1.0))
        if self.min_signal <= 0:
            raise OptionError("min_signal", "a number above 0 and at most 1 (the signal stays positive)",
                              self.min_signal)
        check_option("normalisation", self.normalisation, NORMALISATIONS)
        set_("resolution", _positive_int("resolution", self.resolution, 4, 256))
        set_("starts", _positive_int("starts", self.starts, 0, 64))

    def as_dict(self) -> dict:
        return {"support": list(self.support), "symmetry": self.symmetry, "degree": self.degree,
                "objective": self.objective, "stage": self.stage, "region": self.region,
                "zeros": [list(z) for z in self.zeros], "continuity": f"C{self.continuity}",
                "attenuation_weight": self.attenuation_weight, "attenuation_band": self.attenuation_band,
                "min_signal": self.min_signal, "normalisation": self.normalisation}


# ------------------------------------------------------------------ the affine family
def symmetric_basis(shape, symmetry: str) -> np.ndarray:
    """Indicators of the orbits of the mask entries under the symmetry group.

    Returns
    -------
    E : (n_orbits, s1, s2) float
        ``E[o]`` is 1 on orbit ``o`` (orbits ordered by their first entry in row-major order).
    """
    s1, s2 = shape
    check_option("symmetry", symmetry, SYMMETRIES)
    seen = np.full((s1, s2), -1)
    out = []
    for i in range(s1):
        for j in range(s2):
            if seen[i, j] >= 0:
                continue
            orbit = {(i, j), (s1 - 1 - i, j), (i, s2 - 1 - j), (s1 - 1 - i, s2 - 1 - j)}
            if symmetry == "square":
                orbit |= {(b, a) for a, b in orbit}
            E = np.zeros((s1, s2))
            for a, b in orbit:
                E[a, b] = 1.0
                seen[a, b] = len(out)
            out.append(E)
    return np.array(out)


def _constraints(spec: DesignSpec, basis: np.ndarray):
    """Rows ``A p = c`` of the sum rules and the exact zeros."""
    s1, s2 = spec.support
    a1, a2 = np.meshgrid(np.arange(s1), np.arange(s2), indexing="ij")
    k1, k2 = a1 - (s1 - 1) / 2.0, a2 - (s2 - 1) / 2.0
    scale = max(1.0, np.abs(k1).max(), np.abs(k2).max())
    rows, rhs = [basis.sum(axis=(1, 2))], [4.0]
    signs = [(-1.0) ** a1, (-1.0) ** a2, (-1.0) ** (a1 + a2)]
    for q in range(spec.degree + 1):
        for e in range(q + 1):
            mono = (k1 / scale) ** e * (k2 / scale) ** (q - e)
            for sign in signs:
                rows.append(np.tensordot(basis, sign * mono, axes=2))
                rhs.append(0.0)
    for wx, wy in spec.zeros:
        for c in _ZERO_CLASSES[spec.objective]:
            v1, v2 = _SHIFTS[c]
            ph = np.cos(np.pi * ((wx + v1) * k1 + (wy + v2) * k2))  # symbols of symmetric masks are real
            rows.append(np.tensordot(basis, ph, axes=2))
            rhs.append(0.0)
    return np.array(rows), np.array(rhs)


def affine_family(spec: DesignSpec):
    """The masks that meet the constraints: ``m(q) = m0 + sum_j q_j N_j``.

    Returns
    -------
    m0 : (s1, s2) float
        The least-norm (in the orbit coefficients) mask of the family.
    N : (n_free, s1, s2) float
        Directions (orthonormal in the orbit coefficients).

    Raises
    ------
    OptionError
        When no mask of that support and symmetry meets the sum rules and the zeros.
    """
    basis = symmetric_basis(spec.support, spec.symmetry)
    A, c = _constraints(spec, basis)
    U, s, Vt = np.linalg.svd(A)
    rank = int(np.sum(s > 1e-10 * s[0]))
    p0 = Vt[:rank].T @ ((U[:, :rank].T @ c) / s[:rank])
    if np.abs(A @ p0 - c).max() > 1e-9:
        raise OptionError("support", f"a support large enough for sum rules of degree {spec.degree} with these "
                                     "zeros and symmetry", "x".join(map(str, spec.support)))
    N = Vt[rank:]
    return np.tensordot(p0, basis, axes=1), np.tensordot(N, basis, axes=1)


# ------------------------------------------------------------------ the objective
def _grid(limit: float, n: int) -> np.ndarray:
    """Midpoints of ``n`` equal cells of ``[0, limit]``."""
    return (np.arange(n) + 0.5) * (limit / n)


def _classes(mask: np.ndarray, stage: str, w: np.ndarray):
    """Signal and the three artifact classes on the outer grid ``w x w`` (rows wy, columns wx)."""
    coef = mask / 4.0
    if stage == "limit":
        L = sy.limit_stencil(mask)
        coef = sy._convolve2(mask, L) / 4.0
    k1, k2 = sy.centred_offsets(coef.shape[0]), sy.centred_offsets(coef.shape[1])
    return [np.real(sy.trig_sum(coef, k1, k2, w[None, :] + v1, w[:, None] + v2, np.pi)) for v1, v2 in _SHIFTS]


def _artifact_sq(objective: str, b, c, d, w):
    if objective == "energy":
        return (b * b + c * c + d * d) / 3.0
    if objective in ("x1", "x2", "diagonal"):
        x = {"x1": b, "x2": c, "diagonal": d}[objective]
        return x * x
    wx, wy = w[None, :], w[:, None]
    r2 = wx * wx + wy * wy  # midpoints: never 0
    return ((b * wy) ** 2 / r2 + (c * wx) ** 2 / r2 + (d * (wx * wx - wy * wy) / (2 * r2)) ** 2) / 3.0


def objective_value(mask, spec: DesignSpec, resolution: int | None = None) -> tuple[float, float, float]:
    """``(J, artifact, attenuation)`` of a mask: ``J = artifact^2 + w attenuation^2``.

    ``artifact`` is the RMS of the asked artifact over ``[0, region]^2`` (midpoint rule, ``resolution`` points per
    axis; the responses of symmetric masks are even in each frequency, so the quadrant stands for the square), divided
    pointwise by the signal ``|a|`` (at least ``1e-5``) when ``spec.normalisation == "signal"``, and
    ``attenuation`` the RMS of ``1 - a`` over ``[0, attenuation_band]^2``. ``inf`` for masks without a limit stencil.
    """
    mask = np.asarray(mask, dtype=float)
    n = spec.resolution if resolution is None else int(resolution)
    try:
        w = _grid(spec.region, n)
        a, b, c, d = _classes(mask, spec.stage, w)
        sq = _artifact_sq(spec.objective, b, c, d, w)
        if spec.normalisation == "signal":
            sq = sq / np.maximum(np.abs(a), _SIGNAL_FLOOR) ** 2
        art = float(np.sqrt(np.mean(sq)))
        att = 0.0
        if spec.attenuation_weight > 0:
            wb = _grid(spec.attenuation_band, n)
            a = _classes(mask, spec.stage, wb)[0]
            att = float(np.sqrt(np.mean((1.0 - a) ** 2)))
    except (sy.ConvergenceError, np.linalg.LinAlgError):
        return float("inf"), float("inf"), float("inf")
    return art * art + spec.attenuation_weight * att * att, art, att


def signal_margin(mask, spec: DesignSpec, resolution: int | None = None) -> np.ndarray:
    """``a(Omega) - min_signal`` on the band's grid (``resolution`` equally spaced points per axis from 0 to the band's
    edge, which it includes: the signal of a smoothing mask is least at the band's corner): ``(n, n) float``, all
    ``>= 0`` when the signal bound holds; ``-1`` everywhere for a mask without a limit stencil."""
    n = spec.resolution if resolution is None else int(resolution)
    wb = np.linspace(0.0, spec.attenuation_band, n)
    try:
        return _classes(np.asarray(mask, float), spec.stage, wb)[0] - spec.min_signal
    except (sy.ConvergenceError, np.linalg.LinAlgError):
        return -np.ones((n, n))


# ------------------------------------------------------------------ the search
def _catalogue_starts(spec: DesignSpec) -> list[np.ndarray]:
    """Masks of B-splines and box splines that fit the support (centred, same parity), for starting points."""
    s1, s2 = spec.support
    out = []
    candidates = [sy.box_mask(n1, n2, n3, n3) for n3 in range(4) for n1 in range(1, 8) for n2 in range(1, 8)]
    for m in candidates:
        t1, t2 = m.shape
        if t1 > s1 or t2 > s2 or (s1 - t1) % 2 or (s2 - t2) % 2:
            continue
        if spec.symmetry == "square" and t1 != t2:
            continue
        full = np.zeros((s1, s2))
        o1, o2 = (s1 - t1) // 2, (s2 - t2) // 2
        full[o1:o1 + t1, o2:o2 + t2] = m
        out.append(full)
    return out


def _search(spec: DesignSpec, m0: np.ndarray, N: np.ndarray):
    from scipy.optimize import minimize

    n = len(N)
    flatN = N.reshape(n, -1)
    to_mask = lambda q: m0 + np.tensordot(q, N, axes=1)  # noqa: E731
    need = spec.continuity + 1.0 + _SOBOLEV_MARGIN
    order = spec.degree + 1

    def f(q):
        J = objective_value(to_mask(q), spec)[0]
        return J if np.isfinite(J) else 1e6

    def smooth(q):
        return sobolev_exponent(to_mask(q), order) - need

    band_n = max(4, spec.resolution // 2)

    def signal(q):
        return signal_margin(to_mask(q), spec, band_n).ravel()

    def admissible(q, slack=0.0):
        return smooth(q) >= -slack and signal(q).min() >= -slack

    if n == 0:
        return np.zeros(0)
    starts = [np.zeros(n)]
    for m in _catalogue_starts(spec):
        starts.append(flatN @ (m - m0).ravel() / np.einsum("ij,ij->i", flatN, flatN))
    rng = np.random.default_rng(20110926)
    spread = np.abs(m0).max()
    starts += [rng.normal(0.0, 0.5 * spread, n) for _ in range(spec.starts)]
    # screen: the admissible starts (proven smooth, signal bound met) with the lowest objective first (ties keep
    # their order) are refined
    values = [(not admissible(q0), f(q0), i) for i, q0 in enumerate(starts)]
    picked = [v[2] for v in sorted(values)[:_REFINED]]
    best, best_val = None, np.inf
    for i in picked:
        # unconstrained first (the least-artifact masks are smooth ones); the Sobolev constraint only when needed
        res = minimize(f, starts[i], method="BFGS", options={"maxiter": 200, "gtol": 1e-10})
        q = res.x
        if not admissible(q):
            res = minimize(f, starts[i], method="SLSQP", constraints=[{"type": "ineq", "fun": smooth},
                                                                     {"type": "ineq", "fun": signal}],
                           options={"maxiter": 100, "ftol": 1e-12})
            q = res.x
            if not admissible(q, 1e-9):
                continue
        val = f(q)
        if val < best_val - 1e-15:
            best, best_val = q, val
    if best is None:
        raise OptionError("continuity", f"a class that a mask of this support can reach with a signal of at least "
                                        f"{spec.min_signal:g} on |w| <= {spec.attenuation_band:g} (no "
                                        f"C{spec.continuity} mask found; try a larger support, C0 or a lower "
                                        "min_signal)", f"C{spec.continuity}")
    return best


# ------------------------------------------------------------------ the result
@dataclass(frozen=True, eq=False)
class Design:
    """A designed scheme and its figures.

    Attributes
    ----------
    spec : DesignSpec
    scheme : Scheme
        The mask as a scheme (limit stencil, responses: the catalogue's engine).
    objective : float
        ``J`` at the report resolution (4 times the search's).
    artifact : float
        RMS artifact over the region at the report resolution (a share of the signal under the ``signal``
        normalisation).
    attenuation : float
        RMS signal loss over the band (0 when not asked).
    proof : ContinuityProof
    zeros : tuple of float
        The largest artifact class magnitude at each asked zero (exact engine).
    min_signal : float
        The least signal response on the band at the report resolution (at least ``spec.min_signal``).
    seconds : float
        Time of the search.
    references : dict
        Name -> ``(objective, artifact)`` of the named schemes under the same objective.
    """

    spec: DesignSpec
    scheme: Scheme
    objective: float
    artifact: float
    attenuation: float
    proof: ContinuityProof
    zeros: tuple
    min_signal: float
    seconds: float
    references: dict = field(default_factory=dict)

    @property
    def mask(self) -> np.ndarray:
        return self.scheme.mask

    def as_dict(self) -> dict:
        """The JSON document of the design (also the mask file :func:`load_mask` reads)."""
        return {
            "format": MASK_FORMAT, "version": 1, "name": self.scheme.name,
            "mask": self.mask.tolist(), "limit_stencil": self.scheme.limit_stencil.tolist(),
            "design": self.spec.as_dict(),
            "objective": self.objective, "artifact_rms": self.artifact, "attenuation_rms": self.attenuation,
            "zeros": [{"wx": z[0], "wy": z[1], "artifact": v} for z, v in zip(self.spec.zeros, self.zeros)],
            "continuity": self.proof.as_dict(),
            "generation_degree": self.scheme.generation_degree,
            "min_signal_on_band": self.min_signal,
            "compared": {k: {"objective": v[0], "artifact_rms": v[1]} for k, v in self.references.items()},
            "seconds": round(self.seconds, 3),
        }

    def save(self, stem) -> tuple[Path, Path]:
        """Write ``stem.json`` (the document) and ``stem.npy`` (the mask); returns both paths."""
        stem = Path(stem)
        js, npy = stem.with_suffix(".json"), stem.with_suffix(".npy")
        try:
            stem.parent.mkdir(parents=True, exist_ok=True)
            js.write_text(json.dumps(self.as_dict(), indent=2) + "\n")
            np.save(npy, np.array(self.mask))
        except OSError as exc:
            raise InputError(stem, f"cannot write the design ({exc.strerror or exc})") from None
        return js, npy


def zero_artifacts(s: Scheme, spec: DesignSpec) -> tuple:
    """Largest magnitude of the constrained artifact classes at each asked zero, by :meth:`Scheme.response`."""
    out = []
    for wx, wy in spec.zeros:
        r = s.response(wx, wy, stage=spec.stage)
        vals = {1: r.x1, 2: r.x2, 3: r.diagonal}
        out.append(float(max(abs(vals[c]) for c in _ZERO_CLASSES[spec.objective])))
    return tuple(out)


def design(support=(6, 6), symmetry: str = "square", degree: int = 3, objective: str = "energy",
           stage: str = "limit", region: float = 0.5, zeros=(), continuity: int = 1,
           attenuation_weight: float = 0.0, attenuation_band: float = 0.25, min_signal: float = 0.2,
           normalisation: str = "signal", name: str = "designed",
           resolution: int = 24, starts: int = 2, compare=SCHEME_NAMES) -> Design:
    """Design a binary quad subdivision mask (module notes); parameters as :class:`DesignSpec`.

    Parameters
    ----------
    name : str
        The scheme's label (reports, maps).
    compare : iterable of str
        Named schemes evaluated under the same objective (:attr:`Design.references`).

    Returns
    -------
    Design
        Deterministic: the same arguments give the same mask.

    Raises
    ------
    OptionError
        A bad argument (one line, the valid choices), an empty family, or no mask proven ``C^r``.

    Examples
    --------
    >>> d = design(support=(4, 4), degree=1, continuity=0, starts=0)   # doctest: +SKIP
    """
    spec = DesignSpec(support=support, symmetry=symmetry, degree=degree, objective=objective, stage=stage,
                      region=region, zeros=tuple(zeros), continuity=continuity,
                      attenuation_weight=attenuation_weight, attenuation_band=attenuation_band,
                      min_signal=min_signal, normalisation=normalisation, resolution=resolution, starts=starts)
    if not isinstance(name, str) or not name.strip():
        raise OptionError("name", "a non-empty label", name)
    t0 = time.perf_counter()
    m0, N = affine_family(spec)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):  # small matrices: threads only contend
        q = _search(spec, m0, N)
    mask = m0 + np.tensordot(q, N, axes=1)
    mask[np.abs(mask) < 1e-15] = 0.0
    seconds = time.perf_counter() - t0
    try:
        s = Scheme.from_mask(mask, name.strip())
    except SchemeError as exc:  # pragma: no cover - the proof below would have failed too
        raise OptionError("continuity", "a convergent design", str(exc)) from None
    proof = continuity_proof(mask)
    if proof.continuity < spec.continuity:
        raise OptionError("continuity", f"C{spec.continuity} proven for the best mask found", proof.as_dict()["proven"])
    fine = 4 * spec.resolution
    least = float(signal_margin(mask, spec, fine).min()) + spec.min_signal
    if least < spec.min_signal - 1e-6:  # the fine grid finds a dip the search's grid stepped over
        raise OptionError("min_signal", f"a bound the best mask meets on the fine grid (its signal falls to "
                                        f"{least:.4g} on |w| <= {spec.attenuation_band:g})", spec.min_signal)
    J, art, att = objective_value(mask, spec, fine)
    refs = {}
    for ref in compare:
        rJ, rart, _ = objective_value(scheme(ref).mask, spec, fine)
        refs[ref] = (rJ, rart)
    return Design(spec, s, J, art, att, proof, zero_artifacts(s, spec), least, seconds, refs)
