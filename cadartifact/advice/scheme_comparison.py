"""The scheme comparison of an advice: how many points each named scheme needs for the same intent.

The face's own scheme's row, and a named scheme of the same B-spline degrees (``bicubic`` for a bicubic face), is
the advice itself. A named scheme whose limit surface is a uniform B-spline (``bilinear``: degree 1, ``bicubic``:
degree 3) is advised by the advice's own search and objective: its best net of a density is the least-squares fit
of the intent by uniform B-splines of its degrees (the same fit, on the same check grid, with the same decision
rule ``value + U <= t``), and the fewest-points density is searched on the frontier ``b(a)``. For the schemes with
no B-spline limit (``4-3``, ``4-8``: not tensor products; ``kobbelt``: interpolating) no best net of a density
is built: the intent is sampled at a cage of ``a x b`` points and the cage's total ripple under that scheme is
read (its predicted road), and their rows say ``"objective": "ripple"``. The cages are shared by those schemes
(their frontiers start alike).
"""

from __future__ import annotations

from ..analysis.budget import total_ripple
from ..analysis.settings import RunSettings
from ..analysis.baseband import baseband_at
from ..theory.catalogue import SCHEME_NAMES, scheme as get_scheme
from .density_search import frontier
from ..analysis.frames import fine_positions
from ..net import ControlNet

__all__ = ["NAMED_SCHEMES", "compare_schemes"]

#: The schemes compared: the named catalogue (:data:`cadartifact.theory.catalogue.NAMED`, read at each use).
NAMED_SCHEMES = SCHEME_NAMES


def compare_schemes(net: ControlNet, work: ControlNet, sch, shape, meets: bool, settings: RunSettings, fine, *,
                    growth: int, max_points: int, objective: str = "deviation", value=None) -> dict:
    """Fewest points per named scheme for the intent's ripple (the intent sampled at each scheme's net).

    Parameters
    ----------
    net, work : ControlNet
        Today's net and the net its scheme analyses.
    sch : Scheme
        The face's own scheme: its entry is the advice itself (``shape``, ``meets``, objective ``deviation``).
    shape : (int, int)
    meets : bool
    settings : RunSettings
        The run's ``tolerance``, ``metric`` and ``component``.
    fine : cadartifact.advice.advise._Scorer
        The advice's scorer at the confirmation grid: its intent, fields and frames.
    objective : {"deviation", "ripple"}
        The advice's objective (its rows' ``"objective"``; the other schemes' rows read ripple, see
        :func:`_value`).
    growth, max_points : int
        The search's bounds (:data:`cadartifact.advice.advise.GROWTH`, :data:`~cadartifact.advice.advise.MAX_POINTS`).
    value : callable ``(scorer, a, b) -> float``, optional
        The advice's value of a candidate (its objective plus the intent's uncertainty U), compared with the
        tolerance: the B-spline schemes' rows are searched with it on ``fine`` under their own degrees. Without
        it, every other scheme's row reads the sampled cage's ripple.

    Returns
    -------
    dict
        ``{scheme name: {"net", "points", "meets_tolerance", "objective", "advice"}}``: the face's own scheme (and
        a named scheme of the same B-spline degrees) is the advice itself (``"advice": true``); for the other
        schemes the fewest-points cage ``(a, b)`` whose total ripple (predicted road, ``K = 2``) is within the
        tolerance,
        searched on the frontier from ``shape`` (:func:`cadartifact.advice.density_search.frontier`).
    """
    out = {}
    fu, fv = fine.frames
    cages: dict = {}  # the intent sampled at a density, for every scheme (their frontiers start alike)
    room = [32 * 2 ** 20]  # bytes of cage points kept; the first ones asked (the shared start) stay

    def cage_of(a, b):
        got = cages.get((a, b))
        if got is None:
            xa, yb = fine_positions(fu, a), fine_positions(fv, b)  # no repeated seam row when periodic
            pts = fine.intent.evaluate(xa, yb) if fine.reading == "net" else baseband_at(fine.fields, xa, yb)
            got = ControlNet(points=pts, periodic=net.periodic, unit=net.unit)
            if pts.nbytes <= room[0]:
                cages[(a, b)], room[0] = got, room[0] - pts.nbytes
        return got

    own = {"net": list(shape), "points": int(shape[0] * shape[1]), "meets_tolerance": bool(meets),
           "objective": objective, "advice": True}
    out[sch.name] = dict(own)  # the face's own scheme's row is the advice itself
    for name in NAMED_SCHEMES:
        other = get_scheme(name)
        if other.name == sch.name or (sch.degrees is not None and other.degrees == tuple(sch.degrees)):
            # the advice's candidates are uniform B-splines of the face's degrees: this scheme's own nets
            out[other.name] = dict(own)
            continue

        if value is not None and other.degrees is not None:
            out[other.name] = _bspline_row(other, work, shape, fine, value, settings.tolerance, objective,
                                           growth=growth, max_points=max_points)
            continue
        seen = {}  # a memo per scheme: the frontier asks about some densities twice
        under = settings.replace(scheme=other, levels=1, tolerance=None)

        def ok(a, b, under=under, seen=seen):
            if (a, b) not in seen:
                seen[(a, b)] = _value(cage_of(a, b), under, objective, settings.metric) <= settings.tolerance
            return seen[(a, b)]

        low = (3, 3)
        high = _search_high(low, work, growth, max_points)
        s2, ok2 = frontier(ok, low, high, tuple(shape))  # the schemes' answers lie near this scheme's
        out[other.name] = {"net": list(s2), "points": int(s2[0] * s2[1]), "meets_tolerance": bool(ok2),
                           "objective": "ripple", "advice": False}
    return out


def _search_high(low, work: ControlNet, growth: int, max_points: int) -> tuple[int, int]:
    """The comparison's search bound per direction: ``growth`` times today's points, within ``max_points / 4``."""
    return tuple(max(l + 1, min(max_points // 4, growth * n)) for l, n in zip(low, work.shape))


def _bspline_row(other, work: ControlNet, shape, fine, value, tolerance: float, objective: str, *, growth: int,
                 max_points: int) -> dict:
    """A B-spline scheme's row: the fewest-points uniform B-spline net of its degrees that the advice's own value
    accepts (``value(scorer, a, b) <= tolerance``), searched on the frontier from the advised ``shape``."""
    sc = fine.with_degrees(other.degrees)
    low = tuple(d + 1 for d in sc.degrees)  # a uniform B-spline of degree d needs d + 1 points
    high = _search_high(low, work, growth, max_points)
    start = tuple(max(l, min(h, s)) for l, h, s in zip(low, high, shape))
    s2, ok2 = frontier(lambda a, b: value(sc, a, b) <= tolerance, low, high, start)
    return {"net": list(s2), "points": int(s2[0] * s2[1]), "meets_tolerance": bool(ok2), "objective": objective,
            "advice": False}


def _value(cage: ControlNet, under: RunSettings, objective: str, metric: str) -> float:
    """A cage's value under a scheme with no B-spline limit: its ripple (predicted road).

    The deviation objective is not carried to these schemes: their cages are the intent sampled, not fitted
    (no best net of a density is built through their limit operators), so their deviation is mostly the
    attenuation a designer would correct (tried: 4-3 and 4-8 then failed at 8x the advice's points on the hull
    sample, and the comparison cost about 4x). Their rows say ``"objective": "ripple"``."""
    return total_ripple(cage, under)
