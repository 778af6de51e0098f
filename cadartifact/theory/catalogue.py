"""The scheme catalogue: binary quad subdivision schemes given by their masks (SPEC §2).

A :class:`Scheme` is a validated, immutable mask plus everything derived from it: the limit
stencil (from the eigenvector of the local subdivision matrix, never typed in), whether it
interpolates, the degree of polynomials it reproduces, and the frequency-domain functions the
spectral engine needs (symbol, limit symbol, Fourier transform of the limit function, transfer
to a refined grid). Named schemes use closed forms (box splines: products of cosines and sincs;
tensor products: products of 1-D functions); any other mask goes through the generic array
routines of :mod:`cadartifact.theory.symbols`.

>>> from cadartifact.theory.catalogue import scheme
>>> s = scheme("bicubic")
>>> s.limit_stencil * 36                                   # doctest: +NORMALIZE_WHITESPACE
array([[ 1.,  4.,  1.],
       [ 4., 16.,  4.],
       [ 1.,  4.,  1.]])
>>> round(float(s.response(0.1, 0.2).percent), 3)
0.273

Reference: U. H. Augsdörfer, N. A. Dodgson, M. A. Sabin, "Artifact analysis on B-splines,
box-splines and other surfaces defined by quadrilateral polyhedra", CAGD 28 (2011) (text in
``shared/paper``; SPEC §2 is the contract where they differ).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from . import maskfiles as mf
from . import symbols as sy
from ..errors import OptionError, SchemeError
from ..registry import LiveTuple
from ..numerics.arrays import frozen_array

__all__ = ["Scheme", "BasisSamples", "scheme", "schemes", "box", "bspline", "NAMED", "SCHEME_NAMES"]

#: The named catalogue (SPEC §2): name (lower case, no spaces) -> the constructor of its :class:`Scheme` (called
#: once, :func:`_named`). Adding a named scheme is one entry here: :func:`scheme`, :func:`schemes`,
#: :data:`SCHEME_NAMES`, the error messages, ``cadartifact schemes`` and the advice's scheme comparison
#: (:mod:`cadartifact.advice.scheme_comparison`) read it.
NAMED: dict = {
    "bilinear": lambda: Scheme("bilinear", sy.box_mask(2, 2, 0, 0), arrows=(2, 2, 0, 0), degrees=(1, 1)),
    "bicubic": lambda: Scheme("bicubic", sy.box_mask(4, 4, 0, 0), arrows=(4, 4, 0, 0), degrees=(3, 3)),
    "4-3": lambda: Scheme("4-3", sy.box_mask(2, 2, 1, 1), arrows=(2, 2, 1, 1)),
    "4-8": lambda: Scheme("4-8", sy.box_mask(2, 2, 2, 2), arrows=(2, 2, 2, 2)),
    "kobbelt": lambda: Scheme("kobbelt", np.outer(_KOBBELT, _KOBBELT) / 256.0),
}
_KOBBELT = (-1.0, 0.0, 9.0, 16.0, 9.0, 0.0, -1.0)  # the four-point rule's row

#: The names of :data:`NAMED`, in its order (read from it at each use).
SCHEME_NAMES = LiveTuple(lambda: tuple(NAMED))

_ALIASES = {"catmull-clark": "bicubic", "catmull_clark": "bicubic", "catmullclark": "bicubic"}


def _valid_names() -> str:
    """The names an error message lists: the named catalogue (with each one's first alias) and the forms."""
    alias = {}
    for other, target in _ALIASES.items():
        alias.setdefault(target, other)
    named = "".join(f"'{n}'" + (f" (alias '{alias[n]}')" if n in alias else "") + ", " for n in NAMED)
    return named + "'bspline(p,q)', 'bspline(p)', 'box(n1,n2,n3,n4)', 'file:MASK.json' or 'file:MASK.npy'"

#: Largest mask side accepted from users (the continuous stage works with the autocorrelation
#: mask, about twice as large, through dense eigen-decompositions).
MAX_MASK_SIDE = 17

#: Target |xi| / 2^J below which infinite products and alias recursions are cut (see _depth).
_TINY = 2.0 ** -26


def _depth(xi_max: float, target: float = _TINY) -> int:
    """Number of halvings J with ``xi_max / 2^J <= target`` (at least 1)."""
    if not np.isfinite(xi_max) or xi_max <= target:
        return 1
    return max(1, int(np.ceil(np.log2(xi_max / target))))


def _trig1(coef: np.ndarray, k: np.ndarray, w, scale: float = np.pi):
    """1-D ``sum_a coef[a] exp(-i scale w k[a])`` for any array ``w`` (real when coef is symmetric)."""
    w = np.asarray(w, dtype=float)
    ph = scale * np.multiply.outer(w, k)
    if np.allclose(coef, coef[::-1], rtol=0, atol=1e-14 * np.abs(coef).max()) and np.allclose(k, -k[::-1]):
        return np.cos(ph) @ coef
    return np.exp(-1j * ph) @ coef


def _bspline_degree(u: np.ndarray):
    """The degree p when the 1-D mask is the B-spline row of degree p, else None."""
    p = len(u) - 2
    if p >= 1 and np.allclose(u, sy.bspline_row(p), rtol=0, atol=1e-14):
        return p
    return None


class _Axis:
    """Everything 1-D about one factor ``u`` (sum 2) of a tensor-product mask."""

    def __init__(self, u: np.ndarray):
        self.mask = u
        self.size = len(u)
        self.offsets = sy.centred_offsets(self.size)
        self.dual = self.size % 2 == 0
        self.samples = sy.integer_samples(u)  # phi~ at 0..s-1 (raises ConvergenceError)
        stencil = sy.shifted_samples(u, self.samples, 0.0)
        self.stencil = stencil / stencil.sum()
        grid = sy.shifted_samples(u, self.samples, 0.5 if self.dual else 0.0)
        self.grid_stencil = grid / grid.sum()
        self.degree = _bspline_degree(u)
        self.order = sy.sum_rule_order(u)
        self.moment = float(np.sum(u * self.offsets)) / 4.0
        self._psi = None

    def symbol(self, w):
        if self.degree is not None:
            return 2.0 * sy._ipow(np.cos(0.5 * np.pi * np.asarray(w, dtype=float)), self.degree + 1)
        return _trig1(self.mask, self.offsets, w)

    def stencil_symbol(self, w, grid: bool = False):
        st = self.grid_stencil if grid else self.stencil
        return _trig1(st, sy.centred_offsets(len(st)), w)

    def basis_hat(self, w):
        w = np.asarray(w, dtype=float)
        if self.degree is not None:
            return sy._ipow(np.sinc(w), self.degree + 1)
        J = _depth(np.abs(w).max() if w.size else 0.0)
        out = np.exp(-2j * np.pi * self.moment * w / 2.0 ** J) if self.moment else 1.0
        for j in range(J):
            out = out * (self.symbol(w / 2.0 ** j) / 2.0)
        return out

    @property
    def psi(self) -> np.ndarray:
        """``psi = phi * phi(-.)`` at the integers (centred), for alias sums."""
        if self._psi is None:
            self._psi = sy.limit_stencil(sy.autocorrelation_mask(self.mask))
        return self._psi


class BasisSamples(NamedTuple):
    """The limit basis function sampled on ``(Z / 2^levels)^2``.

    ``values[i, j] = phi(ix[i] / 2^levels, iy[j] / 2^levels)`` with the centred ``phi`` (support
    symmetric about 0 for symmetric masks), ``ix``, ``iy`` integer offsets.
    """

    values: np.ndarray
    ix: np.ndarray
    iy: np.ndarray
    levels: int


@dataclass(frozen=True, eq=False)
class Scheme:
    """A binary, stationary subdivision scheme on a quad grid, given by its mask.

    Attributes
    ----------
    name : str
        Catalogue name (``"bicubic"``, ``"bspline(2,3)"``, ``"box(2,2,1,1)"``) or the user's.
    mask : (s1, s2) float, read-only
        Refined-grid mask, axis 0 along X1 (u). It sums to 4 and each of its four parity cosets
        sums to 1. The origin is the array's geometric centre: for odd sizes the centre entry
        (a primal scheme), for even sizes a half-integer offset (a dual scheme, e.g. even-degree
        B-splines), so symmetric masks have real symbols (bspline degree p:
        ``M/4 = cos(pi wx/2)^(p+1) cos(pi wy/2)^(q+1)``).
    arrows : (int, int, int, int) or None
        Box-spline arrow counts along X1, X2, X1+X2, X1-X2; None when the mask is not a box
        spline (kobbelt, user masks not recognised).
    degrees : (int, int) or None
        B-spline degrees ``(p, q)`` for tensor B-spline schemes (bilinear, bicubic, bspline), else None.
    interpolating : bool
        The mask is 1 at the centre and 0 at the other even-even offsets: control points are
        points of the limit surface.
    reproduction_degree : int
        The highest total degree ``d`` such that control data sampled from any polynomial of degree
        ``<= d`` give a limit surface that is again a polynomial: such data carry no artifact.
        Derived from the mask (sum rules: ``M(Omega + V)`` has a zero of order ``d+1`` at
        ``Omega = 0`` for ``V`` in X1, X2, X1+X2). For approximating schemes the polynomial is
        reproduced only up to lower-order terms (it is smoothed): that is signal error, not artifact.
        Bilinear 1, bicubic 3, 4-3 3, 4-8 3, kobbelt 3, bspline(p, q) ``min(p, q)``.
        The sum rules make every refined net of such data a polynomial again; the limit surface can
        reproduce more than that (4-8's box spline has Strang-Fix order 6: quartic and quintic data
        give polynomial limit surfaces although their refined nets ripple). This attribute is the
        sum-rule degree, a safe lower bound for the limit surface.
    limit_stencil : (r1, r2) float, read-only
        The limit basis function ``phi`` sampled at the integers (odd size, centred, zero borders
        trimmed), derived from the mask: the eigenvalue-1 eigenvector of the local subdivision
        matrix ``S[n, j] = m[2n - j]`` normalised to sum 1 (one cascade step moves it to the
        integers on dual axes). The limit point at refined vertex ``P`` is ``sum_n L_n R_(P-n)``.

    Notes
    -----
    Construct with :func:`scheme`, :func:`box`, :func:`bspline` or :meth:`from_mask`; the
    constructor validates the mask once (SchemeError on a bad or non-convergent mask).
    """

    name: str
    mask: np.ndarray
    arrows: tuple[int, int, int, int] | None = None
    degrees: tuple[int, int] | None = None
    interpolating: bool = field(init=False)
    reproduction_degree: int = field(init=False)
    limit_stencil: np.ndarray = field(init=False, repr=False)

    # ------------------------------------------------------------------ construction
    def __post_init__(self):
        mask = _validated_mask(self.mask)
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        set_("mask", frozen_array(mask))
        if self.arrows is not None:
            arrows = tuple(int(n) for n in self.arrows)
            ok = len(arrows) == 4 and min(arrows) >= 0
            if ok:
                expect = sy.box_mask(*arrows)
                ok = expect.shape == mask.shape and np.allclose(expect, mask, rtol=0, atol=1e-12)
            if not ok:
                raise SchemeError("arrows", "the arrow counts of this mask's box spline", self.arrows)
            set_("arrows", arrows)
        factors = sy.tensor_factors(mask)
        try:
            if factors is not None:
                axes = (_Axis(factors[0]), _Axis(factors[1]))
                stencil = np.outer(axes[0].stencil, axes[1].stencil)
                samples = np.outer(axes[0].samples, axes[1].samples)
                grid = np.outer(axes[0].grid_stencil, axes[1].grid_stencil)
            else:
                axes = None
                samples = sy.integer_samples(mask)
                stencil = sy.shifted_samples(mask, samples, 0.0)
                stencil = stencil / stencil.sum()
                grid = sy.shifted_samples(mask, samples, tuple(0.5 * (s % 2 == 0) for s in mask.shape))
                grid = grid / grid.sum()
        except sy.ConvergenceError as exc:
            raise SchemeError("mask", "a convergent scheme (eigenvalue 1 of the local subdivision "
                                      "matrix simple and dominant)", str(exc)) from None
        if self.degrees is not None:
            p, q = (int(d) for d in self.degrees)
            if axes is None or (axes[0].degree, axes[1].degree) != (p, q):
                raise SchemeError("degrees", "the B-spline degrees of this mask", self.degrees)
            set_("degrees", (p, q))
        set_("limit_stencil", frozen_array(stencil))
        set_("reproduction_degree", sy.sum_rule_order(mask))
        set_("interpolating", _is_interpolating(mask))
        set_("_axes", axes)
        set_("_samples", samples)
        grid = frozen_array(grid)
        set_("_grid_stencil", grid)
        set_("_cache", {})

    @classmethod
    def from_mask(cls, array, name: str = "custom", *, detect_arrows: bool = True) -> "Scheme":
        """A scheme from any binary quad mask.

        Parameters
        ----------
        array : (s1, s2) array_like
            The mask (axis 0 along X1), summing to 4 with each parity coset summing to 1.
        name : str
            A label for reports.
        detect_arrows : bool
            Recognise box-spline masks and use their closed forms (benchmarks switch it off to time
            the generic path).

        Raises
        ------
        SchemeError
            One line saying what is wrong: not 2-D/finite, sum != 4, a coset sum != 1, or not
            convergent (eigenvalue 1 of the local subdivision matrix not simple and dominant).
        """
        mask = _validated_mask(array)
        arrows = sy.detect_box_arrows(mask) if detect_arrows else None
        return cls(name=str(name), mask=mask, arrows=arrows)

    def __repr__(self) -> str:
        s1, s2 = self.mask.shape
        extra = f", arrows {self.arrows}" if self.arrows is not None else ""
        return f"<Scheme {self.name!r} {s1}x{s2} mask{extra}>"

    # ------------------------------------------------------------------ derived facts
    @property
    def generation_degree(self) -> int:
        """Degree generated (data of degree <= d -> a limit of that degree, not the same one: x^2 -> x^2 + c)."""
        return self.reproduction_degree

    @property
    def dual(self) -> tuple[bool, bool]:
        """Per axis, whether the mask has even size: refined vertices then sit at quarter offsets
        (``J +- 1/4, +- 3/4``), never on the net's half-grid."""
        return tuple(bool(s % 2 == 0) for s in self.mask.shape)

    @property
    def grid_stencil(self) -> np.ndarray:
        """``phi`` sampled at ``Z + dual/2`` (centred; even length on dual axes, half-integer offsets).

        It takes the vertices of ``L >= 1`` subdivision steps to the limit surface at the points of
        ``2^-L Z^2`` (for primal axes it is the limit stencil); :meth:`transfer` uses its symbol.
        """
        return self._grid_stencil

    @property
    def tensor(self) -> bool:
        """Whether the mask is an outer product of two 1-D masks."""
        return self._axes is not None

    @property
    def symmetric(self) -> bool:
        """Whether the mask is point-symmetric about its centre (then every response is real)."""
        return bool(np.allclose(self.mask, self.mask[::-1, ::-1], rtol=0, atol=1e-14 * np.abs(self.mask).max()))

    # ------------------------------------------------------------------ frequency domain
    def symbol(self, wx, wy):
        """Mask symbol ``M(Omega) = sum_k m_k exp(-i pi Omega.k)`` (``Omega`` in cycles per control point).

        Parameters
        ----------
        wx, wy : array_like float
            Broadcast together; outer grids (``(1, N)`` with ``(M, 1)``) are evaluated by products of
            1-D factors or two small matrix products.

        Returns
        -------
        M : float array (complex for masks that are not point-symmetric)
        """
        if self.arrows is not None:
            return sy.box_symbol(self.arrows, wx, wy)
        if self._axes is not None:
            return self._axes[0].symbol(wx) * self._axes[1].symbol(wy)
        return sy.mask_symbol(self.mask, wx, wy)

    def limit_symbol(self, wx, wy):
        """Symbol of the limit stencil on the refined grid: ``L(Omega) = sum_n L_n exp(-i pi Omega.n)``."""
        if self._axes is not None:
            return self._axes[0].stencil_symbol(wx) * self._axes[1].stencil_symbol(wy)
        L = self.limit_stencil
        return sy.trig_sum(L, sy.centred_offsets(L.shape[0]), sy.centred_offsets(L.shape[1]), wx, wy, np.pi)

    def _grid_symbol(self, wx, wy):
        """Symbol of the stencil taking level-L vertices to the limit on ``2^-L Z`` (phi at ``Z + dual/2``)."""
        if self._axes is not None:
            return self._axes[0].stencil_symbol(wx, grid=True) * self._axes[1].stencil_symbol(wy, grid=True)
        G = self._grid_stencil
        return sy.trig_sum(G, sy.centred_offsets(G.shape[0]), sy.centred_offsets(G.shape[1]), wx, wy, np.pi)

    def basis_hat(self, wx, wy):
        """Fourier transform of the limit basis function, ``phi_hat(xi) = prod_{j>=0} M(xi/2^j)/4``.

        Closed form ``prod_d sinc(xi.d)^(n_d)`` for box splines; otherwise the product is cut at
        ``|xi|/2^J <= 2^-26`` and finished with ``exp(-2 pi i mu.xi/2^J)`` (``mu = sum_k m_k k / 8`` the
        first moment of phi), leaving an error ``O(2^-52)``.
        """
        if self.arrows is not None:
            return sy.box_basis_hat(self.arrows, wx, wy)
        if self._axes is not None:
            return self._axes[0].basis_hat(wx) * self._axes[1].basis_hat(wy)
        wx = np.asarray(wx, dtype=float)
        wy = np.asarray(wy, dtype=float)
        J = _depth(max(np.abs(wx).max(initial=0.0), np.abs(wy).max(initial=0.0)))
        k1, k2 = np.meshgrid(sy.centred_offsets(self.mask.shape[0]), sy.centred_offsets(self.mask.shape[1]),
                             indexing="ij")
        mu = (np.sum(self.mask * k1) / 8.0, np.sum(self.mask * k2) / 8.0)
        out = 1.0
        if mu[0] or mu[1]:
            out = np.exp(-2j * np.pi * (mu[0] * wx + mu[1] * wy) / 2.0 ** J)
        for j in range(J):
            out = out * (self.symbol(wx / 2.0 ** j, wy / 2.0 ** j) / 4.0)
        return out

    def transfer(self, wx, wy, levels: int):
        """Response of the limit surface sampled on the grid ``2^-L Z^2`` (``L = levels``).

        ``T_L(xi) = G(xi / 2^(L-1)) prod_{j=0}^{L-1} M(xi / 2^j) / 4 = sum_m phi_hat(xi + 2^L m)``:
        ``L`` subdivision steps followed by the stencil ``G`` that takes level-``L`` vertices to the
        limit surface at the points of ``2^-L Z^2`` (which contains the net's points). ``G`` is the
        limit stencil for primal axes; on a dual axis the level-``L`` vertices sit half a fine step
        off that grid and ``G`` is ``phi`` at the half-integers. A net ``A_J = exp(2 pi i xi.J)``
        gives the samples ``T_L(xi) exp(2 pi i xi.x)`` plus the ``2^L``-periodic images; for
        ``L = 1`` and a primal scheme ``T_1(Omega + V)`` is alpha_V of SPEC §3; as ``L`` grows
        ``T_L -> phi_hat``.

        Parameters
        ----------
        wx, wy : array_like float
            ``xi`` in cycles per control point, ``|xi| <= 2^L / 2`` covers one period.
        levels : int
            ``L >= 0`` (``L = 0``: the limit surface at the net points, ``L_hat(2 xi)``).

        Returns
        -------
        T : float array (complex for non-symmetric masks) of the broadcast shape
        """
        L = _levels(levels)
        if self._axes is not None:
            return self._transfer_1d(self._axes[0], wx, L) * self._transfer_1d(self._axes[1], wy, L)
        wx = np.asarray(wx, dtype=float)
        wy = np.asarray(wy, dtype=float)
        if L == 0:
            return self.limit_symbol(2.0 * wx, 2.0 * wy)
        out = self._grid_symbol(wx / 2.0 ** (L - 1), wy / 2.0 ** (L - 1))
        for j in range(L):
            out = out * (self.symbol(wx / 2.0 ** j, wy / 2.0 ** j) / 4.0)
        return out

    @staticmethod
    def _transfer_1d(axis: _Axis, w, L: int):
        w = np.asarray(w, dtype=float)
        if L == 0:
            return axis.stencil_symbol(2.0 * w)
        out = axis.stencil_symbol(w / 2.0 ** (L - 1), grid=True)
        for j in range(L):
            out = out * (axis.symbol(w / 2.0 ** j) / 2.0)
        return out

    def basis_samples(self, levels: int) -> BasisSamples:
        """The limit basis function ``phi`` on ``(Z / 2^L)^2`` by the space-domain cascade.

        Starting from the integer samples (eigenvector of the local subdivision matrix),
        ``phi(x) = sum_k m_k phi(2x - k)`` refines them level by level; no Fourier transform
        is involved, so these samples are an independent road to :meth:`transfer`
        (``T_L(xi) = 4^-L sum_n phi(n/2^L) exp(-2 pi i xi.n/2^L)``).

        Returns
        -------
        BasisSamples
            ``(values, ix, iy, levels)``, ``values[i, j] = phi(ix[i]/2^L, iy[j]/2^L)``.
        """
        L = _levels(levels)
        Lc = max(L, 1)
        f = sy.cascade(self.mask, self._samples, Lc)  # phi~ on (Z/2^Lc), indices 0..(s-1)2^Lc
        idx, offs = [], []
        for s in self.mask.shape:
            centre = (s - 1) * 2 ** (Lc - 1)  # phi(x) = phi~(x + (s-1)/2), in level-Lc units
            step = 2 ** (Lc - L)
            first = centre % step
            i = np.arange(first, (s - 1) * 2 ** Lc + 1, step)
            idx.append(i)
            offs.append((i - centre) // step)
        return BasisSamples(f[np.ix_(*idx)], offs[0], offs[1], L)

    def response(self, wx, wy, stage: str = "limit"):
        """Signal and artifact amplitudes for control data ``exp(2 pi i Omega.J)`` (SPEC §3).

        See :func:`cadartifact.theory.spectral.response`; ``stage`` is ``"one_step"`` (or ``"one-step"``),
        ``"limit"`` or ``"continuous"``.
        """
        from .spectral import response

        return response(self, wx, wy, stage)


# ------------------------------------------------------------------ validation helpers
def _levels(levels) -> int:
    try:
        L = int(levels)
    except (TypeError, ValueError):
        raise OptionError("levels", "an integer >= 0", levels) from None
    if L != levels or L < 0 or L > 30:
        raise OptionError("levels", "an integer between 0 and 30", levels)
    return L


def _validated_mask(array) -> np.ndarray:
    try:
        mask = np.array(array, dtype=float)
    except (TypeError, ValueError):
        raise SchemeError("mask", "a 2-D array of numbers", type(array).__name__) from None
    if mask.ndim != 2 or mask.size == 0:
        raise SchemeError("mask", "a non-empty 2-D array", f"shape {mask.shape}")
    if max(mask.shape) > MAX_MASK_SIDE:
        raise SchemeError("mask", f"at most {MAX_MASK_SIDE} entries per side", f"shape {mask.shape}")
    if not np.all(np.isfinite(mask)):
        raise SchemeError("mask", "finite entries", "NaN or infinity")
    scale = np.abs(mask).sum()
    total = mask.sum()
    if abs(total - 4.0) > 1e-9 * max(scale, 1.0):
        raise SchemeError("mask", "entries summing to 4 (a binary quad scheme)", f"sum {total:.6g}")
    cosets = {(a, b): float(mask[a::2, b::2].sum()) for a in (0, 1) for b in (0, 1)}
    bad = {k: v for k, v in cosets.items() if abs(v - 1.0) > 1e-9 * max(scale, 1.0)}
    if bad:
        where = ", ".join(f"(row {a}, col {b} parity) {v:.6g}" for (a, b), v in bad.items())
        raise SchemeError("mask", "each parity coset summing to 1", f"coset sums {where}")
    return mask


def _is_interpolating(mask: np.ndarray) -> bool:
    s1, s2 = mask.shape
    if s1 % 2 == 0 or s2 % 2 == 0:
        return False
    c1, c2 = (s1 - 1) // 2, (s2 - 1) // 2
    even = mask[c1 % 2::2, c2 % 2::2].copy()
    centre = even[c1 // 2, c2 // 2]
    even[c1 // 2, c2 // 2] = 0.0
    return bool(abs(centre - 1.0) < 1e-12 and np.all(np.abs(even) < 1e-12))


# ------------------------------------------------------------------ constructors
def _check_count(parameter: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise SchemeError(parameter, f"an integer >= {minimum}", value)
    if value > 15:
        raise SchemeError(parameter, "an integer <= 15", value)
    return int(value)


def bspline(p: int, q: int | None = None) -> Scheme:
    """Tensor-product uniform B-spline scheme of degrees ``(p, q)`` (``q = p`` by default).

    Mask: outer product of the binomial rows of length ``p+2`` and ``q+2``, scaled to sum 4
    (``M/4 = cos(pi wx/2)^(p+1) cos(pi wy/2)^(q+1)``; even degrees are dual schemes).
    """
    p = _check_count("bspline degree p", p, 1)
    q = p if q is None else _check_count("bspline degree q", q, 1)
    return _named(f"bspline({p},{q})")


def box(n1: int, n2: int, n3: int, n4: int) -> Scheme:
    """Box-spline scheme with ``n1, n2, n3, n4`` arrows along X1, X2, X1+X2, X1-X2 (SPEC §2).

    Raises SchemeError when the box has no convergent scheme (e.g. piecewise constant or
    diagonal-only boxes, whose cosets do not sum to 1).
    """
    counts = tuple(_check_count(f"box n{i + 1}", n, 0) for i, n in enumerate((n1, n2, n3, n4)))
    return _named("box({},{},{},{})".format(*counts))


def schemes() -> list[str]:
    """The named catalogue (:data:`NAMED`): ``['bilinear', 'bicubic', '4-3', '4-8', 'kobbelt']``."""
    return list(NAMED)


_PATTERN = re.compile(r"^(bspline|b-spline|box)\(([\d,]+)\)$")


def scheme(name) -> Scheme:
    """Resolve a scheme name (case-insensitive, spaces ignored) or pass a :class:`Scheme` through.

    Names: ``bilinear``, ``bicubic`` (alias ``catmull-clark``), ``4-3``, ``4-8``, ``kobbelt``,
    ``bspline(p,q)``, ``bspline(p)``, ``box(n1,n2,n3,n4)``, or ``file:PATH`` for a mask file: JSON with a ``"mask"``
    array (what ``cadartifact design`` writes) or a NumPy ``.npy`` array; the scheme's name is the given string.
    Instances are cached (files by path, size and modification time).

    Raises
    ------
    SchemeError
        Unknown name (the message lists the valid ones) or invalid parameters.
    """
    if isinstance(name, Scheme):
        return name
    if not isinstance(name, str):
        raise SchemeError("scheme", f"a scheme name ({_valid_names()}) or a Scheme", name)
    if mf.is_file_name(name):
        return _file_scheme(name.strip(), *mf.mask_path(name))
    key = re.sub(r"\s+", "", name).lower()
    key = _ALIASES.get(key, key)
    if key in NAMED:
        return _named(key)
    m = _PATTERN.match(key)
    if m:
        try:
            nums = [int(x) for x in m.group(2).split(",")]
        except ValueError:
            nums = []
        if m.group(1) != "box" and len(nums) in (1, 2):
            return bspline(*nums)
        if m.group(1) == "box" and len(nums) == 4:
            return box(*nums)
    raise SchemeError("scheme", f"one of {_valid_names()}", name)


@lru_cache(maxsize=32)
def _file_scheme(name: str, path: str, _size: int, _mtime: int) -> Scheme:
    """The scheme of a mask file (cached by path, size and modification time)."""
    array = mf.read_mask(name, path)
    try:
        return Scheme.from_mask(array, name)
    except SchemeError as exc:
        raise SchemeError("scheme", f"a valid mask in {name}", f"{exc.expected}; received {exc.received}") from None


@lru_cache(maxsize=128)
def _named(key: str) -> Scheme:
    """Build (once) the scheme of a canonical name: a :data:`NAMED` one, ``bspline(p,q)`` or ``box(n1,n2,n3,n4)``."""
    if key in NAMED:
        return NAMED[key]()
    m = re.match(r"^bspline\((\d+),(\d+)\)$", key)
    if m:
        p, q = int(m.group(1)), int(m.group(2))
        return Scheme(key, np.outer(sy.bspline_row(p), sy.bspline_row(q)),
                      arrows=(p + 1, q + 1, 0, 0), degrees=(p, q))
    m = re.match(r"^box\((\d+),(\d+),(\d+),(\d+)\)$", key)
    n = tuple(int(x) for x in m.groups())
    mask = sy.box_mask(*n)
    degrees = (n[0] - 1, n[1] - 1) if n[2] == n[3] == 0 and min(n[:2]) >= 2 else None
    return Scheme(key, mask, arrows=n, degrees=degrees)
