"""The control net: a frozen, validated record of a surface's control polyhedron.

Everything that reads a file produces :class:`ControlNet` objects and everything
that analyses one consumes them; this module imports numpy only.

Index space (SPEC §4): control point ``(i, j)`` sits at integer index ``(i, j)``;
for a B-spline face the parameter of point ``i`` is its Greville abscissa
``(t[i+1] + ... + t[i+p]) / p`` and parameter <-> index is the piecewise-linear
map through the Greville abscissae.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from .errors import InvalidNetError, check_option
from .numerics.arrays import frozen_array

__all__ = [
    "ControlNet",
    "NetOrigin",
    "NET_KINDS",
    "NET_FORMS",
    "EXACT_KINDS",
    "clamped_uniform_knots",
    "periodic_uniform_knots",
    "greville",
    "knots_are_uniform",
    "junctions",
    "knot_multiplicities",
    "knot_runs",
    "lifted",
    "bezier_direction",
    "no_ripple_by_construction",
]

#: What a net was made from.
NET_KINDS = ("bspline", "bezier", "converted", "quad-chart", "array")

#: What a net is: a B-spline face (degrees and knot vectors) or a subdivision cage (a quad chart: neither).
#: See :attr:`ControlNet.form`.
NET_FORMS = ("bspline", "cage")

#: Largest coordinate magnitude analysed: squares and products of larger values overflow float64
#: (no real model is this large; 1e12 mm is a light-hour).
MAX_COORDINATE = 1e12

#: Relative tolerance on knot spans for a knot vector to count as uniform.
UNIFORM_RTOL = 1e-6


@dataclass(frozen=True)
class NetOrigin:
    """Where a net came from.

    Attributes
    ----------
    file : str or None
        The file it was read from (None for nets built in memory).
    face : int or None
        0-based face index within the file (for OBJ: chart index).
    name : str or None
        The face's name where the file has one.
    kind : str
        One of :data:`NET_KINDS`.
    entity : int or None
        STEP files: the instance id of the face's ``ADVANCED_FACE`` entity (``#entity`` in the
        file), None elsewhere or when the reader cannot tell.
    """

    file: str | None = None
    face: int | None = None
    name: str | None = None
    kind: str = "array"
    entity: int | None = None

    def __post_init__(self):
        check_option("origin.kind", self.kind, NET_KINDS)

    def label(self) -> str:
        """A short human label such as ``part.step#3 (fillet)``."""
        base = self.file or "<memory>"
        if self.face is not None:
            base += f"#{self.face}"
        if self.name:
            base += f" ({self.name})"
        return base


#: What a direction of a face can exactly be (no artifact along it): see :attr:`ControlNet.exact`.
EXACT_KINDS = (None, "line", "circle", "surface")


def periodic_uniform_knots(n: int, degree: int) -> np.ndarray:
    """OCCT's flat periodic knot sequence of a uniform periodic direction of ``n`` poles on [0, 1].

    Returns
    -------
    knots : (n + 2 degree + 1,) float
        ``(j - degree) / n`` for ``j = 0 .. n + 2 degree``: one period's ``n + 1`` knots continued by ``degree``
        knots each side (:func:`cadartifact.exchange.occ.periodic_flat_knots` of simple equally spaced knots).
    """
    return (np.arange(n + 2 * degree + 1, dtype=float) - degree) / n


def clamped_uniform_knots(n: int, degree: int, start: float = 0.0, end: float = 1.0) -> np.ndarray:
    """Full clamped knot vector with uniform interior spacing.

    Parameters
    ----------
    n : int
        Number of control points (``n >= degree + 1``).
    degree : int
        Polynomial degree ``p >= 1``.
    start, end : float
        Parameter range.

    Returns
    -------
    knots : (n + degree + 1,) float
        ``p+1`` copies of ``start``, ``n-p-1`` equally spaced interior knots, ``p+1`` copies of ``end``.
    """
    if degree < 1 or n < degree + 1:
        raise InvalidNetError(f"clamped knots need n >= degree + 1 >= 2, received n={n}, degree={degree}")
    interior = np.linspace(start, end, n - degree + 1)
    return np.concatenate([np.full(degree, start), interior, np.full(degree, end)])


def greville(knots: np.ndarray, degree: int, n: int | None = None) -> np.ndarray:
    """Greville abscissae ``xi_i = (t_{i+1} + ... + t_{i+p}) / p``.

    Parameters
    ----------
    knots : (m,) float
        Full knot vector.
    degree : int
        Degree ``p``.
    n : int, optional
        Number of abscissae wanted (default ``m - p - 1``, the number of control points
        of a non-periodic spline).

    Returns
    -------
    xi : (n,) float
    """
    knots = np.asarray(knots, dtype=float)
    if n is None:
        n = len(knots) - degree - 1
    if degree == 0:
        return knots[:n].copy()
    c = np.concatenate([[0.0], np.cumsum(knots)])
    idx = np.arange(n)
    return (c[idx + degree + 1] - c[idx + 1]) / degree


def knots_are_uniform(knots: np.ndarray, degree: int, periodic: bool = False, rtol: float = UNIFORM_RTOL) -> bool:
    """Whether a knot vector is uniform: simple interior knots, equal spacing within ``rtol``.

    The clamped end knots (multiplicity ``p+1``) of a non-periodic spline are allowed;
    a periodic knot vector must be equally spaced throughout.
    """
    t = np.asarray(knots, dtype=float)
    span = t[-1] - t[0]
    if span <= 0:
        return False
    inner = t if periodic else t[degree:len(t) - degree]
    d = np.diff(inner)
    if len(d) == 0:
        return True
    return bool(np.all(np.abs(d - d.mean()) <= rtol * span) and np.all(d > rtol * span))


def knot_runs(values: np.ndarray, scale: float) -> list[tuple[float, int, int]]:
    """``(value, first index, multiplicity)`` of each run of equal knots (relative 1e-12)."""
    out = []
    i = 0
    tol = 1e-12 * max(scale, 1e-300)
    while i < len(values):
        j = i
        while j + 1 < len(values) and values[j + 1] - values[i] <= tol:
            j += 1
        out.append((float(values[i]), i, j - i + 1))
        i = j + 1
    return out


def knot_multiplicities(knots: np.ndarray, degree: int, n: int, periodic: bool) -> list[tuple[float, int]]:
    """``(value, multiplicity)`` of each distinct interior knot (a periodic direction: each knot of one
    period, a run cut by the period's end merged with its start)."""
    t = np.asarray(knots, float)
    p = int(degree)
    scale = float(np.abs(t).max()) if t.size else 1.0
    if not periodic:
        lo, hi = t[p], t[n]
        return [(v, m) for v, _, m in knot_runs(t, scale) if lo < v < hi]
    # slots p+1 .. p+n hold every knot of one period once
    period = float(t[p + n] - t[p])
    total: dict = {}
    for v, _, m in knot_runs(t[p + 1: p + n + 1], scale):
        key = round(((v - t[p]) % period) / period, 9) % 1.0
        value = v - period if v - t[p] >= period - 1e-12 * scale else v  # the start, not one period on
        first, count = total.get(key, (value, 0))
        total[key] = (first, count + m)
    return sorted(total.values())


def junctions(knots: np.ndarray, degree: int, n: int, periodic: bool) -> list[float]:
    """Interior knot values of multiplicity ``>= degree``: deliberate junctions (SPEC §4).

    Parameters
    ----------
    knots : flat knot vector (OCCT's sequence: ``n + p + 1`` open, ``n + 2p + 1`` periodic)
    degree, n : int
    periodic : bool
    """
    return [v for v, m in knot_multiplicities(knots, degree, n, periodic) if m >= degree]


def bezier_direction(knots: np.ndarray, degree: int, n: int, periodic: bool) -> bool:
    """Whether every span of a direction is a piece of its own (every interior knot has multiplicity >= p:
    degree 1, piecewise Bezier): nothing along it aliases, it has no ripple band."""
    return all(m >= degree for _, m in knot_multiplicities(knots, degree, n, periodic))


def no_ripple_by_construction(net: "ControlNet") -> str | None:
    """Why a B-spline face carries no ripple at all, when its writing says so in both directions; else None.

    A direction carries none when it is exact (a line or a circle: ``net.exact``), one Bezier piece
    (``n = p + 1``) or piecewise Bezier (every interior knot of multiplicity ``>= p``, degree 1 included): each
    span is then a polynomial of its own and nothing along it can alias (SPEC §4: a knot of multiplicity ``p``
    is a deliberate junction).

    Returns
    -------
    str or None
        ``"u: 4 Bezier pieces of degree 3; v: one Bezier piece of degree 3"``, or None when a direction of
        several spans joined with some continuity can carry ripple (or the net is not a B-spline face).

    Examples
    --------
    >>> import numpy as np
    >>> P = np.stack(np.meshgrid(np.arange(7.0), np.arange(4.0), [0.0], indexing="ij"), -1)[:, :, 0]
    >>> knots = (np.r_[0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2.0], np.r_[0, 0, 0, 0, 1, 1, 1, 1.0])
    >>> no_ripple_by_construction(ControlNet.from_points(P, degrees=(3, 3)).replace(knots=knots))
    'u: 2 Bezier pieces of degree 3; v: one Bezier piece of degree 3'
    """
    if not net.is_bspline or "surface" in net.exact:  # a canonical face says what it is on its own
        return None
    words = []
    for d, exact, knots, p, n, periodic in zip("uv", net.exact, net.knots, net.degrees, net.shape, net.periodic):
        if exact is not None:
            words.append(f"{d}: exactly a {exact}")
        elif not periodic and n == p + 1:
            words.append(f"{d}: one Bezier piece of degree {p}")
        elif bezier_direction(knots, p, n, periodic):
            pieces = len(knot_multiplicities(knots, p, n, periodic)) + (0 if periodic else 1)
            words.append(f"{d}: {pieces} Bezier pieces of degree {p}" if p > 1 else f"{d}: {pieces} straight spans")
        else:
            return None
    return "; ".join(words)


def lifted(net: "ControlNet") -> np.ndarray:
    """The points a net is analysed in: ``(nu, nv, 3)`` control points, or ``(nu, nv, 4)`` homogeneous
    ``(w P, w)`` when its weights vary (SPEC §4: a NURBS face is the projection of a non-rational
    B-spline in homogeneous coordinates, where the uniform theory applies exactly)."""
    P = np.asarray(net.points, float)
    if not net.weights_vary:
        return P
    w = np.asarray(net.weights, float)[:, :, None]
    return np.concatenate([P * w, w], axis=-1)


def _settled_form(degrees) -> str:
    """The form of a net built without one: a net given degrees is a B-spline face, else a cage."""
    return "cage" if degrees is None else "bspline"


@dataclass(frozen=True, eq=False)
class ControlNet:
    """A quad control net with the spline data needed to analyse it.

    Attributes
    ----------
    points : (nu, nv, 3) float
        Control points in model units.
    weights : (nu, nv) float or None
        NURBS weights (None: polynomial).
    degrees : (int, int) or None
        ``(p, q)`` for a B-spline face; None for a subdivision cage (quad chart).
    knots : ((mu,) float, (mv,) float) or None
        Full (flat, multiplicities expanded) knot vectors, as OCCT's ``UKnotSequence``; None for a cage.
        A B-spline net given degrees without knots gets uniform ones on [0, 1] (clamped, or periodic
        along a periodic direction).
    periodic : (bool, bool)
        Periodic flags in u and v.
    uv_bounds : (u0, u1, v0, v1) or None
        Parameter bounds of the trimmed face (the net itself is untrimmed).
    unit : str
        Model unit of ``points`` (``"mm"`` for STEP as OCCT gives it).
    origin : NetOrigin
        File, face index, name and kind.
    canonical : str or None
        What the face exactly is when it is a canonical surface or is exactly circular/straight along
        a direction (``"sphere r=12.5"``, ``"revolved: circular in u"``), as the reader recognised it
        (OCCT's ``GeomConvert_SurfToAnaSurf`` / ``GeomConvert_CurveToAnaCurve``); None otherwise.
    exact : (str or None, str or None)
        Per direction u, v: ``"line"`` or ``"circle"`` when every isocurve along that direction is
        exactly one, ``"surface"`` (both directions) when the face is a canonical surface: the
        direction carries no artifact (SPEC §4). None otherwise.
    trim_gaps : tuple of (int, float, float)
        Parameter intervals ``(axis, lo, hi)`` within ``uv_bounds`` that the trimmed face does not use: a trim
        across a periodic direction's opening, once the direction is opened at a junction, keeps two ranges
        (:func:`cadartifact.analysis.pieces.split_net`). Empty otherwise.
    form : str
        What the net is, one of :data:`NET_FORMS`: ``"bspline"`` (a face with degrees and knots) or ``"cage"``
        (a subdivision cage, neither). Settled from ``degrees`` when not given; code asks
        :attr:`is_bspline`, never whether ``knots`` or ``degrees`` is None.
    trim_loops : tuple of (k, 2) float
        The trimmed face's boundary in the surface's parameters: one closed polyline per wire (outer and holes,
        the last point not repeated), as the reader samples the edges' pcurves; a point is on the face when a
        ray from it crosses the loops an odd number of times. Empty: the face is its ``uv_bounds`` box.

    Notes
    -----
    Arrays are copied and made read-only at construction; validation happens
    once, here, so every consumer can rely on finite points and consistent
    knot lengths.
    """

    points: np.ndarray
    weights: np.ndarray | None = None
    degrees: tuple[int, int] | None = None
    knots: tuple[np.ndarray, np.ndarray] | None = None
    periodic: tuple[bool, bool] = (False, False)
    uv_bounds: tuple[float, float, float, float] | None = None
    unit: str = "mm"
    origin: NetOrigin = field(default_factory=NetOrigin)
    canonical: str | None = None
    exact: tuple = (None, None)
    trim_gaps: tuple = ()
    form: str | None = None
    trim_loops: tuple = ()

    def __post_init__(self):
        where = self.origin.label()
        form = _settled_form(self.degrees) if self.form is None else self.form
        check_option("form", form, NET_FORMS)
        object.__setattr__(self, "form", form)
        pts = np.asarray(self.points)
        if pts.ndim != 3 or pts.shape[2] != 3:
            raise InvalidNetError(f"{where}: points must have shape (nu, nv, 3), received {pts.shape}")
        if pts.shape[0] < 2 or pts.shape[1] < 2:
            raise InvalidNetError(f"{where}: a net needs at least 2x2 control points, received {pts.shape[0]}x{pts.shape[1]}")
        if not np.issubdtype(pts.dtype, np.number):
            raise InvalidNetError(f"{where}: points must be numbers, received dtype {pts.dtype}")
        pts = frozen_array(pts)
        if not np.all(np.isfinite(pts)):
            bad = np.argwhere(~np.isfinite(pts))[0]
            raise InvalidNetError(f"{where}: control point ({bad[0]}, {bad[1]}) has a NaN or infinite coordinate")
        big = np.abs(pts).max()
        if big > MAX_COORDINATE:
            raise InvalidNetError(f"{where}: control point coordinates up to {big:.3g} are too large to analyse "
                                  f"(limit {MAX_COORDINATE:.0e} model units)")
        extent = np.ptp(pts.reshape(-1, 3), axis=0).max()
        if extent == 0.0:
            raise InvalidNetError(f"{where}: degenerate net, all control points coincide")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "trim_gaps", tuple((int(a), float(lo), float(hi)) for a, lo, hi in self.trim_gaps))
        loops = tuple(frozen_array(np.asarray(loop, float)) for loop in self.trim_loops)
        for loop in loops:
            if loop.ndim != 2 or loop.shape[1] != 2 or len(loop) < 3 or not np.all(np.isfinite(loop)):
                raise InvalidNetError(f"{where}: a trim loop must be (k >= 3, 2) finite uv points, received "
                                      f"shape {loop.shape}")
        object.__setattr__(self, "trim_loops", loops)

        if self.weights is not None:
            w = frozen_array(self.weights)
            if w.shape != pts.shape[:2]:
                raise InvalidNetError(f"{where}: weights must have shape {pts.shape[:2]}, received {w.shape}")
            if not np.all(np.isfinite(w)) or np.any(w <= 0):
                raise InvalidNetError(f"{where}: weights must be finite and positive")
            object.__setattr__(self, "weights", w)

        per = tuple(bool(x) for x in self.periodic)
        if len(per) != 2:
            raise InvalidNetError(f"{where}: periodic must be two flags, received {self.periodic}")
        object.__setattr__(self, "periodic", per)

        if form == "cage":
            if self.degrees is not None:
                raise InvalidNetError(f"{where}: degrees: expected None for a cage (form='cage'), "
                                      f"received {self.degrees}")
            if self.knots is not None:
                raise InvalidNetError(f"{where}: knots given without degrees (a cage, form='cage', has neither)")
        else:
            self._settle_spline(where, pts.shape[:2], per)

        exact = tuple(self.exact) if self.exact is not None else (None, None)
        if len(exact) != 2 or any(e not in EXACT_KINDS for e in exact):
            raise InvalidNetError(f"{where}: exact must be two of {EXACT_KINDS}, received {self.exact}")
        object.__setattr__(self, "exact", exact)

        if self.uv_bounds is not None:
            b = tuple(float(x) for x in self.uv_bounds)
            if len(b) != 4 or not all(np.isfinite(b)):
                raise InvalidNetError(f"{where}: uv_bounds must be four finite numbers, received {self.uv_bounds}")
            object.__setattr__(self, "uv_bounds", b)

    def _settle_spline(self, where: str, shape: tuple[int, int], per: tuple[bool, bool]) -> None:
        """Validate a B-spline net's degrees and knots; uniform knots when none were given."""
        if self.degrees is None:
            raise InvalidNetError(f"{where}: degrees: expected two degrees >= 1 for a B-spline net "
                                  f"(form='bspline'), received None")
        p, q = (int(d) for d in self.degrees)
        if p < 1 or q < 1:
            raise InvalidNetError(f"{where}: degrees must be >= 1, received {self.degrees}")
        object.__setattr__(self, "degrees", (p, q))
        if self.knots is None:  # no knot vectors supplied: uniform ones, as from_points makes
            if any(d > n - 1 for d, n in zip((p, q), shape)):
                raise InvalidNetError(f"{where}: degrees: expected at most {(shape[0] - 1, shape[1] - 1)} for "
                                      f"{shape[0]}x{shape[1]} control points without knots, received {(p, q)}")
            object.__setattr__(self, "knots", tuple(
                periodic_uniform_knots(n, d) if pr else clamped_uniform_knots(n, d)
                for n, d, pr in zip(shape, (p, q), per)))
        ku, kv = (frozen_array(k) for k in self.knots)
        for name, k, n, d, pr in (("u", ku, shape[0], p, per[0]), ("v", kv, shape[1], q, per[1])):
            if k.ndim != 1 or not np.all(np.isfinite(k)):
                raise InvalidNetError(f"{where}: {name} knots must be a finite 1-D array")
            if np.any(np.diff(k) < 0):
                raise InvalidNetError(f"{where}: {name} knots must be non-decreasing")
            # OCCT's flat sequence: n+p+1 knots when open, n+2p+1 when periodic
            expected = n + 2 * d + 1 if pr else n + d + 1
            if len(k) != expected:
                raise InvalidNetError(
                    f"{where}: {name} knot vector has {len(k)} knots, expected {expected} for "
                    f"{n} poles of degree {d}{' (periodic)' if pr else ''}")
        object.__setattr__(self, "knots", (ku, kv))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_points(cls, points, degrees: tuple[int, int] | None = (3, 3), *, weights=None,
                    periodic=(False, False), unit: str = "mm", origin: NetOrigin | None = None) -> "ControlNet":
        """A B-spline net with uniform knots on [0, 1], clamped (periodic along a periodic direction); a cage when
        ``degrees`` is None.

        Parameters
        ----------
        points : (nu, nv, 3) array_like
            Control points; a (nu, nv) array is taken as heights z over the grid x=i, y=j.
        degrees : (int, int) or None
            Degrees; clipped to ``n - 1`` per direction so small nets stay valid.
        """
        pts = np.asarray(points, dtype=float)
        if pts.ndim == 2:
            i, j = np.meshgrid(np.arange(pts.shape[0]), np.arange(pts.shape[1]), indexing="ij")
            pts = np.stack([i, j, pts], axis=-1).astype(float)
        if pts.ndim != 3:
            raise InvalidNetError(f"points must have shape (nu, nv, 3) or (nu, nv), received {pts.shape}")
        if degrees is not None:  # the argument: a cage is asked for by passing None
            degrees = tuple(min(int(d), n - 1) for d, n in zip(degrees, pts.shape[:2]))
        # uniform knots (clamped, or periodic along a periodic direction) are settled by the constructor
        return cls(points=pts, weights=weights, degrees=degrees, periodic=periodic,
                   unit=unit, origin=origin or NetOrigin(kind="array"))

    def replace(self, **changes) -> "ControlNet":
        """A copy with some fields replaced (validated again); new ``degrees`` settle the form again unless
        ``form`` is given too (``replace(degrees=None, knots=None)`` is the cage of a face's points)."""
        if "degrees" in changes and "form" not in changes:
            changes["form"] = None
        return dataclasses.replace(self, **changes)

    def __setstate__(self, state: dict) -> None:
        """Unpickle; a net pickled before nets carried their form is built again (its form settled)."""
        if "form" not in state:
            names = [f.name for f in dataclasses.fields(self) if f.name in state]
            state = dict(vars(ControlNet(**{name: state[name] for name in names})))
        self.__dict__.update(state)
        self.__dict__.setdefault("trim_loops", ())  # pickled before nets carried their trim loops

    # ------------------------------------------------------------------ derived
    @property
    def shape(self) -> tuple[int, int]:
        """``(nu, nv)``."""
        return self.points.shape[0], self.points.shape[1]

    @property
    def size(self) -> int:
        """Number of control points."""
        return self.shape[0] * self.shape[1]

    @property
    def is_bspline(self) -> bool:
        """Whether the net is a B-spline face (``form == "bspline"``: it has degrees and knot vectors), not a
        subdivision cage."""
        return self.form == "bspline"

    @property
    def rational(self) -> bool:
        """Whether the net carries weights."""
        return self.weights is not None

    @property
    def weights_vary(self) -> bool:
        """Whether the weights differ (relative 1e-12): a rational face outside the uniform theory."""
        if self.weights is None:
            return False
        w = self.weights
        return bool(np.ptp(w) > 1e-12 * np.abs(w).max())

    @property
    def knots_uniform(self) -> tuple[bool, bool]:
        """Per direction, whether the knots are uniform (True for cages, which have none)."""
        if not self.is_bspline:
            return (True, True)
        return tuple(knots_are_uniform(k, d, pr) for k, d, pr in zip(self.knots, self.degrees, self.periodic))

    @property
    def uniform(self) -> bool:
        """Whether the uniform spectral theory applies: uniform knots both ways (a rational net is analysed
        in homogeneous coordinates, where it applies exactly: SPEC §4)."""
        return all(self.knots_uniform)

    def greville(self) -> tuple[np.ndarray, np.ndarray]:
        """Greville abscissae ``(xi_u (nu,), xi_v (nv,))``; integer indices for a cage."""
        nu, nv = self.shape
        if not self.is_bspline:
            return np.arange(nu, dtype=float), np.arange(nv, dtype=float)
        return (greville(self.knots[0], self.degrees[0], nu), greville(self.knots[1], self.degrees[1], nv))

    def __repr__(self) -> str:
        nu, nv = self.shape
        deg = f"degree {self.degrees}" if self.is_bspline else "cage"
        return f"<ControlNet {nu}x{nv} {deg} {self.origin.kind} from {self.origin.label()}>"
