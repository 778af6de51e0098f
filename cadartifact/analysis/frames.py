"""Analysis coordinates of one direction of a control net (SPEC §1, §4).

Each direction of a net is analysed in *span units*: the coordinate ``x`` is affine in the
face's parameter, ``x = (u - u0) / h`` with ``h`` the mean knot span, so one control spacing of
a uniform net is one unit and frequencies are in cycles per control point. On the interior of a
uniform net this is the Greville index space shifted by a constant; unlike the piecewise-linear
Greville map it has no kinks near clamped ends, so a smooth shape stays smooth (and a polynomial
a polynomial) in analysis coordinates.

The uniform theory works on the *lattice* ``x = j + offset`` (``j`` integer): the Greville
abscissae of the interior control points of a uniform B-spline. The spectral road extends every
direction to a period of ``T`` lattice points: ``T = n`` for a periodic direction, ``T = 2 L``
for an open one (the intent is continued smoothly past the net, see :mod:`cadartifact.analysis.intent`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..errors import OptionError
from ..net import ControlNet, bezier_direction, greville, lifted

__all__ = ["AxisFrame", "axis_frames", "fine_positions", "index_space_cut", "MAX_CUT", "MAX_CROWDED_DEGREE"]


@dataclass(frozen=True, eq=False)
class AxisFrame:
    """One direction of the analysis grid.

    Attributes
    ----------
    n : int
        Control points.
    periodic : bool
    spans : int
        Domain length ``L`` in span units: ``x`` runs over ``[0, L]`` (open) or ``[0, L)`` (periodic,
        ``L = n``).
    offset : float
        Lattice offset: the uniform theory's control points sit at ``x = j + offset``.
    xs : (n,) float
        Where each control point sits in ``x`` (its Greville abscissa).
    levels : int
        ``K = 2**levels`` fine samples per span.
    u0, h : float
        Parameter of ``x = 0`` and of one span: ``u = u0 + h x`` (cages: ``u0 = 0, h = 1``).
    extension : int
        Open directions: period of the extended data in multiples of the spans.
    gap : int
        Open directions, when positive: the period is the domain plus this many lattice points of continuation,
        rounded up to a multiple of :attr:`alignment` (the measured road's border convention,
        ``fields.MEASURED_GAP``), instead of ``extension`` times the spans.
    pad : int
        Open directions: lattice points added to that period (the border convention's latitude,
        :mod:`cadartifact.analysis.border_convention`; 0 in every reading); with :attr:`gap`, ``pad / 2`` times
        the alignment (at least 2), so that the padded period keeps its bin at the cut.
    exact : bool
        The direction carries no artifact: it is exactly a line or a circle (``ControlNet.exact``).
    polynomial : bool
        Nothing along this direction can alias: the surface is one polynomial along it (each row's
        ``(w P, w)``: every interior knot removable, as after knot insertion into a Bezier direction),
        or every span is a piece of its own (every knot a junction: degree 1, piecewise Bezier).
    cut : float
        Cycles per span at which a band split cuts this direction: half a cycle per span (the uniform
        theory's half a cycle per control point), or the measured road's :func:`index_space_cut`.
    """

    n: int
    periodic: bool
    spans: int
    offset: float
    xs: np.ndarray
    levels: int
    u0: float = 0.0
    h: float = 1.0
    extension: int = 2
    exact: bool = False
    gap: int = 0
    pad: int = 0
    polynomial: bool = False
    cut: float = 0.5

    @property
    def ripple_free(self) -> bool:
        """Whether nothing along this direction can alias: exact (line, circle) or one polynomial piece
        (an open direction of a single span, or whose knots are all removable: a Bezier direction has no
        knot structure, however it is written)."""
        return self.exact or self.polynomial or (not self.periodic and self.spans <= 1)

    @property
    def K(self) -> int:
        return 2 ** self.levels

    @property
    def period(self) -> int:
        """Lattice points in one period of the extended data: ``n`` periodic, ``extension * L`` open
        (at least ``n + 4``: room for every point and a gap) plus :attr:`pad`, or with :attr:`gap` ``L + gap``
        rounded up to a multiple of ``m`` = :attr:`alignment` (even where the cut is half a cycle per span), plus
        ``pad max(m, 2) / 2``."""
        if self.periodic:
            return self.spans
        if self.gap > 0:
            T = max(self.spans + self.gap, self.n + 4)
            m = self.alignment
            return -(-T // m) * m + self.pad * max(m, 2) // 2
        return max(self.extension * self.spans, self.n + 4) + self.pad

    @property
    def alignment(self) -> int:
        """Lattice points the measured period is a multiple of, so that a bin sits exactly at :attr:`cut` (bins
        are ``k / T`` cycles per span): the least ``m`` with ``m cut`` whole, 2 (an even period) at half a cycle
        per span; 2 where no ``m`` up to 128 is (the cut then falls between bins)."""
        for m in range(1, 129):
            if abs(m * self.cut - round(m * self.cut)) < 1e-9:
                return m
        return 2

    @property
    def fine_count(self) -> int:
        """Fine samples over the domain (``K L`` periodic, ``K L + 1`` open)."""
        return self.K * self.spans + (0 if self.periodic else 1)

    @property
    def x(self) -> np.ndarray:
        """Analysis coordinates of the fine samples, ``(fine_count,)``."""
        return np.arange(self.fine_count) / self.K

    @property
    def shift(self) -> int:
        """Fine index of ``x = 0`` on the lattice-aligned periodic fine grid (``z = x - offset = k / K``)."""
        return int(round(-self.offset * self.K)) % (self.K * self.period)

    def param(self, x: np.ndarray) -> np.ndarray:
        """Face parameters of analysis coordinates."""
        return self.u0 + self.h * np.asarray(x, float)

    def with_extension(self, extension: int) -> "AxisFrame":
        """The same frame with a longer period of extended data (``extension * n`` lattice points)."""
        return dataclasses.replace(self, extension=extension)


#: The highest cut of :func:`index_space_cut`, in cycles per span.
MAX_CUT = 1.0
#: The highest degree whose clamped ends' crowding :func:`index_space_cut` counts (SPEC §4's short nets: 2-5).
MAX_CROWDED_DEGREE = 5


def index_space_cut(frame: AxisFrame) -> float:
    """Half a cycle per control point, counted in index space, as cycles per span of an open direction.

    SPEC §1 and §4 put the base band below half a cycle per control point, in index space (control point ``i`` at
    its Greville abscissa). Where a direction has an interior, its Greville abscissae are one span apart there and
    the cut is half a cycle per span. A clamped end crowds its points into its first spans (Greville abscissae
    ``1/p, 2/p, ...`` span apart at degree ``p``): a short direction is mostly ends, its ``n - 1 = L + p - 1``
    Greville intervals lie on ``L`` spans, and its points steer content the interior's count calls ripple. One cut
    per direction (the split is one transform) counts, in cycles over the direction, ``C / 2`` with

        ``C = L + (q - 1) max(0, 1 - L / (2 q))``,  ``q = min(p, 5)``,  capped at one cycle per span:

    the ends' ``p - 1`` extra intervals count whole on the shortest direction and not at all from ``2 p`` spans
    on (half a cycle per span, the uniform theory's cut). ``C`` rises strictly with ``L`` below ``2 p`` spans and
    never falls with ``p``, so inserting knots or raising the degree always widens the base band over the
    direction (SPEC §4 "Invariance"; a cut that stayed level over a range of ``L`` let the reading move with the
    border convention's latitude under re-expression). The crowding is counted up to degree 5 (the SPEC's short
    nets) and the cut kept below one cycle per span: on degree-10 blend pieces a cut counting all their points read
    what the continuation leaves, and moved by a third under knot insertion (docs/model.md).

    Parameters
    ----------
    frame : AxisFrame
        A periodic direction, or a cage's (``n = L + 1``), keeps half a cycle per span.

    Returns
    -------
    float
        Cycles per span, from 0.5 to :data:`MAX_CUT`.

    Examples
    --------
    >>> from cadartifact.analysis.frames import AxisFrame, index_space_cut
    >>> import numpy as np
    >>> [round(index_space_cut(AxisFrame(L + 3, False, L, 0.0, np.zeros(L + 3), 3)), 3) for L in (2, 3, 4, 5, 6)]
    [0.833, 0.667, 0.583, 0.533, 0.5]
    """
    L, p = frame.spans, min(frame.n - frame.spans, MAX_CROWDED_DEGREE)
    if frame.periodic or L < 1 or p <= 1:
        return 0.5
    return min(0.5 * (L + (p - 1) * max(0.0, 1.0 - L / (2.0 * p))) / L, MAX_CUT)


def fine_positions(frame: AxisFrame, count: int) -> np.ndarray:
    """``count`` evenly spaced analysis coordinates covering the domain (periodic: without the end)."""
    if frame.periodic:
        return np.arange(count) * (frame.spans / count)
    return np.linspace(0.0, float(frame.spans), count)


def _axis(net: ControlNet, axis: int, levels: int) -> AxisFrame:
    n, per = net.shape[axis], net.periodic[axis]
    if not net.is_bspline:  # a cage: control point i at x = i
        spans = n if per else n - 1
        return AxisFrame(n, per, max(spans, 1), 0.0, np.arange(n, dtype=float), levels)
    p, t = net.degrees[axis], np.asarray(net.knots[axis], float)
    lo, hi = float(t[p]), float(t[len(t) - p - 1])
    if per:
        from ..numerics.splines import periodic_greville

        h = (hi - lo) / n
        g = periodic_greville(t, p, n)
        xs = (g - lo) / h
        # the lattice through the poles (uniform periodic knots: exactly j + offset)
        offset = float(np.mod(np.median(xs - np.arange(n)), 1.0))
        return AxisFrame(n, True, n, offset, xs, levels, lo, h)
    spans = n - p
    h = (hi - lo) / spans
    xs = (greville(t, p, n) - lo) / h
    return AxisFrame(n, False, spans, float(((p - 1) / 2) % 1.0), xs, levels, lo, h)


def axis_frames(net: ControlNet, levels: int = 3) -> tuple[AxisFrame, AxisFrame]:
    """The two :class:`AxisFrame` of a net.

    Parameters
    ----------
    net : ControlNet
    levels : int
        ``K = 2**levels`` fine samples per span (1 to 6).
    """
    if not isinstance(levels, (int, np.integer)) or levels < 1 or levels > 6:
        raise OptionError("levels", "an integer from 1 to 6 (K = 2..64)", levels)
    frames = [_axis(net, 0, int(levels)), _axis(net, 1, int(levels))]
    for k in (0, 1):
        if net.exact[k] is not None:
            frames[k] = dataclasses.replace(frames[k], exact=True)
        elif net.is_bspline and bezier_direction(net.knots[k], net.degrees[k], net.shape[k], net.periodic[k]):
            frames[k] = dataclasses.replace(frames[k], polynomial=True)
        elif not frames[k].periodic and frames[k].spans > 1 and one_polynomial(net, k):
            frames[k] = dataclasses.replace(frames[k], polynomial=True)
    return tuple(frames)


#: Relative residual (of the net's size) below which a direction is one polynomial.
POLYNOMIAL_RTOL = 1e-9


def one_polynomial(net: ControlNet, axis: int) -> bool:
    """Whether an open B-spline direction is one polynomial of its degree (all interior knots removable).

    The homogeneous surface ``(w S, w)`` on ``4 (p + 1)`` parameters along the direction and on the
    other direction's Greville abscissae is fitted by one Legendre polynomial of degree ``p``; the
    direction is one polynomial when the residual is below :data:`POLYNOMIAL_RTOL` of the net's size.
    """
    if not net.is_bspline or net.periodic[axis]:
        return False
    from numpy.polynomial import legendre as L

    from ..numerics.splines import basis_matrix

    p, t, n = net.degrees[axis], np.asarray(net.knots[axis], float), net.shape[axis]
    lo, hi = float(t[p]), float(t[n])
    if hi <= lo:
        return False
    s = np.linspace(lo, hi, 4 * (p + 1))
    B = basis_matrix(t, p, s, n, False)  # (m, n)
    P = np.moveaxis(lifted(net), axis, 0).reshape(n, -1)
    rows = B @ P  # the surface along the direction, at every pole of the other one (it is linear in them)
    V = L.legvander(2 * (s - lo) / (hi - lo) - 1, p)
    resid = rows - V @ np.linalg.lstsq(V, rows, rcond=None)[0]
    size = float(np.ptp(net.points.reshape(-1, 3), axis=0).max())
    return bool(np.abs(resid).max() <= POLYNOMIAL_RTOL * max(size, 1e-300) * max(1.0, float(np.abs(P).max()) / size))
