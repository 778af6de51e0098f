"""The uncertainty of the design intent, in model units, from the net alone (SPEC §4 "Uncertainty and decisions").

A finite net determines its intent only up to an uncertainty ``U``: the shapes its samples admit differ
between the samples, most near the borders, for short nets and for content near the Nyquist limit. ``U`` is
estimated as the spread of **admissible reconstructions**: the intent of :mod:`cadartifact.analysis.intent`
rebuilt with other choices that fit the same samples equally well,

* band limit ``F_MAX`` = 0.35 and 0.45 cycles per control point (the band edge),
* ridge weight ``RIDGE`` x 10 (how smooth the continuation is; / 10 moved the intent least of all and was
  dropped for its cost),
* trend degree - 1 (never below a line: a face's coordinates are ramps hundreds of times the shape, which no
  scheme leaves to the extension) and + 1 (what the polynomial takes, what the extension takes),
* the period of the extension 3 x the span instead of 2 x (the border continuation),

one direction at a time. Per direction ``d`` and check-grid point ``z`` the spread is
``D_d(z) = max_a |I_a(z) - I(z)|`` over the alternates ``a`` of that direction; the face's is

    U = k * max_z sqrt(D_u(z)^2 + D_v(z)^2),      U_d = k * max_z D_d(z)

over the (trimmed) face, ``k`` = :data:`COVERAGE_FACTOR`, calibrated on known-shape families (nets of 6-40
points, degrees 1-5, content 0.05-0.45 cycles per point, cosines in four directions, sums of cosines, bumps,
polynomials) so that the intent's true whole-face error is within ``U`` in at least 95 % of cases
(``tests/test_uncertainty.py``, docs/uncertainty.md).

For the ``surface`` reading (the surface less its ripple) the surface is known, and so are the control
points the scheme aliases: an intent that moves between the points moves nothing the split reads. What would
be uncertain is the split itself at the borders (the continuation past them). No estimate of it has been
validated yet, so this reading reports ``U = 0`` with ``estimated = False`` and its decisions are the plain
comparison with the tolerance, as before. Two constructions were tried and left (docs/uncertainty.md): the
net reading's alternates pushed through the scheme's synthesis of the lattice move with the lattice's
continuation past the borders, which the real clamped surface never reads (up to 100 times the real ripple);
the measured road's split with the bridge over 2 or 5 times the span instead of 3 moved the samples' ripple by
more than its own size (0.22 mm on a 0.095 mm ripple), which no check confirms.

Periodic directions (a closed net samples a whole period: its trigonometric interpolant is unique below the
Nyquist limit) and exact lines and circles add no spread.

References
----------
ISO/IEC Guide 98-3 (GUM), §6 (expanded uncertainty ``U = k u``). ISO 14253-1:2017, *Decision rules for
verifying conformity or nonconformity with specifications*.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .intent import F_MAX, RIDGE, AxisIntent, Intent, axis_intent, from_homogeneous
from ..numerics.tensor import sandwich, sandwich_left, sandwich_right

__all__ = ["Uncertainty", "intent_uncertainty", "ALTERNATES", "COVERAGE_FACTOR"]

#: The admissible reconstructions, per direction: (name, band limit, ridge, trend degree change, extension).
ALTERNATES = (
    ("band 0.35", 0.35, RIDGE, 0, None),
    ("band 0.45", 0.45, RIDGE, 0, None),
    ("ridge x10", F_MAX, RIDGE * 10, 0, None),
    ("trend -1", F_MAX, RIDGE, -1, None),
    ("trend +1", F_MAX, RIDGE, +1, None),
    ("period 3L", F_MAX, RIDGE, 0, 3),
)


#: Coverage factor ``k`` of the ``net`` reading (calibrated: tests/test_uncertainty.py, docs/uncertainty.md).
COVERAGE_FACTOR = 2.0



@dataclass(frozen=True)
class Uncertainty:
    """The intent's expanded uncertainty (model units).

    Attributes
    ----------
    peak : float
        ``U`` over the face.
    u, v : float
        Each direction's share ``U_d``.
    reading : str
        ``"net"`` or ``"surface"``.
    factor : float
        The coverage factor ``k`` applied to the spread.
    estimated : bool
        False where no estimate exists (the ``surface`` reading): ``U`` is then 0.
    """

    peak: float
    u: float
    v: float
    reading: str
    factor: float
    estimated: bool = True

    def to_dict(self) -> dict:
        return {"peak": float(self.peak), "u": float(self.u), "v": float(self.v), "reading": self.reading,
                "coverage_factor": float(self.factor), "estimated": bool(self.estimated)}

    @staticmethod
    def zero(reading: str) -> Uncertainty:
        return Uncertainty(0.0, 0.0, 0.0, reading, 0.0, estimated=False)


def _judged(frame) -> bool:
    """Whether a direction's reconstruction is open to choice (open, and not exactly a line or a circle)."""
    return not (frame.periodic or frame.exact)


def _alternates(intent: Intent, axis: int):
    """The admissible alternate intents along ``axis`` (the other direction as it is)."""
    frame, ax = intent.frames[axis], intent.axes[axis]
    for _name, fmax, ridge, ddeg, ext in ALTERNATES:
        deg = ax.degree + ddeg
        if deg < min(1, ax.degree) or deg > frame.n - 1:  # every scheme reproduces lines: never below a line
            continue
        f = frame if ext is None else dataclasses.replace(frame, extension=ext)
        alt = axis_intent(f, deg, fmax, ridge, like=ax)  # a trend alternate reuses the Fourier part
        if alt is ax:
            continue
        frames = tuple(f if k == axis else intent.frames[k] for k in (0, 1))
        axes = tuple(alt if k == axis else intent.axes[k] for k in (0, 1))
        yield frames, axes


def _spread_net(intent: Intent, x, y) -> tuple[np.ndarray, np.ndarray]:
    """``(D_u, D_v)``: each direction's pointwise spread of the ``net`` reading on ``x x y``."""
    P = intent.lifted_points
    rows = [intent.axes[0].full_at(x), intent.axes[1].full_at(y)]
    homogeneous = P.shape[-1] == 4
    base = from_homogeneous(sandwich(rows[0], P, rows[1])) if homogeneous else None
    halves = (sandwich_right(P, rows[1]), sandwich_left(rows[0], P))  # (nu, b, c), (a, nv, c)
    out = []
    for axis in (0, 1):
        D = np.zeros((len(x), len(y)))
        if _judged(intent.frames[axis]):
            for _frames, axes in _alternates(intent, axis):
                delta = axes[axis].full_at(x if axis == 0 else y) - rows[axis]
                if homogeneous:  # the projection is not linear: the alternate surface itself
                    alt = list(rows)
                    alt[axis] = rows[axis] + delta
                    diff = from_homogeneous(sandwich(alt[0], P, alt[1])) - base
                else:
                    diff = sandwich_left(delta, halves[0]) if axis == 0 else sandwich_right(halves[1], delta)
                D = np.maximum(D, np.sqrt(np.sum(diff * diff, axis=-1)))
        out.append(D)
    return out[0], out[1]


def intent_uncertainty(intent, scheme=None, reading: str = "net", keep=None) -> Uncertainty:
    """The expanded uncertainty ``U`` of a face's design intent (model units).

    Parameters
    ----------
    intent : Intent or PiecewiseIntent
        The ``net`` reading's intent (a split face: each piece's, the face's ``U`` is the largest).
    scheme : Scheme, optional
        The analysis scheme (the ``surface`` reading's split needs it).
    reading : {"net", "surface"}
    keep : callable, optional
        ``keep(x, y) -> (a, b) bool``: the part of the check grid that is the face (its trim).

    Returns
    -------
    Uncertainty
        ``U = k max_z sqrt(D_u^2 + D_v^2)`` and ``U_d = k max_z D_d`` (module docstring), ``k`` =
        :data:`COVERAGE_FACTOR`; the ``surface`` reading: zero, ``estimated=False``.
    """
    if reading == "surface":  # not estimated yet (module docstring)
        return Uncertainty.zero("surface")
    factor = COVERAGE_FACTOR
    pieces = getattr(intent, "pieces", None)
    if pieces is not None:  # a split face (cadartifact.analysis.pieces): each piece's own intent
        from .intent import design_intent

        parts = [intent_uncertainty(design_intent(p.net, scheme_of(p.net), intent.levels), scheme_of(p.net),
                                    reading) for p in pieces]
        return Uncertainty(max(p.peak for p in parts), max(p.u for p in parts), max(p.v for p in parts),
                           reading, factor)
    if not isinstance(intent, Intent) or not isinstance(intent.axes[0], AxisIntent):
        return Uncertainty.zero(reading)
    x, y = (_grid(f) for f in intent.frames)
    Du, Dv = _spread_net(intent, x, y)
    D = np.sqrt(Du ** 2 + Dv ** 2)
    if keep is not None:
        mask = np.asarray(keep(x, y), bool)
        if mask.any():
            D, Du, Dv = D[mask], Du[mask], Dv[mask]
    top = lambda a: float(a.max()) if a.size else 0.0  # noqa: E731
    return Uncertainty(factor * top(D), factor * top(Du), factor * top(Dv), reading, factor)


#: Samples per span of the grid the spread is taken on (the alternates differ smoothly between the points).
GRID_PER_SPAN = 4


def _grid(frame) -> np.ndarray:
    """The check grid of the spread: :data:`GRID_PER_SPAN` samples per span over the domain."""
    count = GRID_PER_SPAN * frame.spans + (0 if frame.periodic else 1)
    return np.arange(count) / GRID_PER_SPAN


def scheme_of(net):
    """A piece's analysis scheme: its own B-spline degrees."""
    from ..theory.catalogue import bspline

    return bspline(*net.degrees)
