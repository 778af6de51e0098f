"""Faces with deliberate junctions: split at knots of multiplicity >= p (SPEC §4).

A knot of multiplicity ``m >= p`` in a direction of degree ``p`` makes the surface only C0 (or G1
by construction) there: a designed junction, not ripple. The analysis treats the pieces either
side as separate nets. Each piece is the same surface, exactly: its poles are the face's poles
between the junctions (a knot of multiplicity ``p`` is interpolated by the pole both pieces
share) and its knots the face's, clamped at the junction. A periodic direction with a junction is
opened there first (its poles unrolled over one period).

A direction with a junction at every knot (degree 1, or piecewise Bezier: each span a piece of one
polynomial) is not split: nothing along it can alias, so it has no ripple band at all
(:attr:`cadartifact.analysis.frames.AxisFrame.ripple_free`; a polyline's corners are deliberate). Only
directions whose pieces have several spans are split.

Then :func:`cadartifact.budget` analyses each piece and gathers them: peaks are the largest over
the pieces, RMS over all their fine-grid samples, and the fields for pictures and advice are the
pieces' fields side by side (:func:`gather_fields`); the intent of the whole face, evaluated
anywhere, is each piece's intent on its own parameter range (:class:`PiecewiseIntent`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .baseband import baseband_at
from .fields import ArtifactFields
from .frames import axis_frames
from ..net import ControlNet, bezier_direction, junctions, knot_runs as _runs

__all__ = ["Piece", "junctions", "split_net", "gather_fields", "PiecewiseIntent", "MAX_PIECES", "face_kind"]

#: A face split into more pieces than this is analysed whole (its junctions are then read as ripple).
MAX_PIECES = 400


@dataclass(frozen=True, eq=False)
class Piece:
    """One piece of a split face.

    Attributes
    ----------
    net : ControlNet
        The piece (same surface, clamped at its junctions; a split direction is open).
    lo, hi : (float, float)
        Its parameter range per direction ``(u, v)``.
    index : (int, int)
        Its position in the grid of pieces.
    note : str or None
        Why a face was left whole although it has junctions (too many pieces).
    """

    net: ControlNet
    lo: tuple
    hi: tuple
    index: tuple
    note: str | None = None


def _open_pieces(t: np.ndarray, p: int, n: int) -> list[tuple[np.ndarray, np.ndarray, float, float]]:
    """Split an open direction: ``(pole indices, clamped knots, lo, hi)`` per piece."""
    scale = float(np.abs(t).max()) if t.size else 1.0
    lo_all, hi_all = float(t[p]), float(t[n])
    cuts = []
    for v, s, m in _runs(t, scale):
        if lo_all < v < hi_all and m >= p:
            cuts.append((v, s - 1, s + m - p - 1))  # (value, last pole before, first pole after)
    out = []
    start, lo = 0, lo_all
    for v, end, nxt in cuts + [(hi_all, n - 1, None)]:
        idx = np.arange(start, end + 1)
        k = np.array(t[start: end + p + 2], float)
        k[: p + 1], k[-(p + 1):] = lo, v
        out.append((idx, k, lo, v))
        start, lo = nxt, v
    return out


def _axis_pieces(net: ControlNet, axis: int):
    """``[(pole indices mod n, knots, lo, hi, periodic)]`` along one direction (one entry: unsplit)."""
    n, p, per = net.shape[axis], net.degrees[axis], net.periodic[axis]
    t = np.asarray(net.knots[axis], float)
    cuts = junctions(t, p, n, per)
    if not cuts or bezier_direction(t, p, n, per):  # one span between junctions: ripple-free, no split needed
        return [(np.arange(n), t, float(t[p]), float(t[n + p] if per else t[n]), per)]
    if not per:
        return [(idx, k, lo, hi, False) for idx, k, lo, hi in _open_pieces(t, p, n)]
    # periodic: unroll one period starting at the first junction, then split it as an open direction
    period = float(t[p + n] - t[p])

    def ext(k):
        k = np.asarray(k)
        return t[p + (k - p) % n] + ((k - p) // n) * period

    tol = 1e-12 * max(abs(cuts[0]), period)

    def at_cut(k):
        d = (ext(k) - cuts[0] + period / 2) % period - period / 2
        return np.abs(d) <= tol

    first = p + 1 + int(np.flatnonzero(at_cut(np.arange(p + 1, p + n + 1)))[0])
    while at_cut(first - 1):  # the run may start before the window
        first -= 1
    m = 1
    while at_cut(first + m):
        m += 1
    u0 = float(ext(first))
    a = first + m - p - 1  # first pole of the unrolled net
    b = first + n - 1  # last pole: the junction one period on
    poles = np.arange(a, b + 1)
    knots = np.array(ext(np.arange(a, b + p + 2)), float)
    knots[: p + 1], knots[-(p + 1):] = u0, u0 + period
    out = []
    for idx, k, lo, hi in _open_pieces(knots, p, len(poles)):
        out.append((poles[idx] % n, k, lo, hi, False))
    return out


def split_net(net: ControlNet) -> list[Piece]:
    """The pieces of a B-spline face between its junctions (one piece: the face itself, unsplit).

    Parameters
    ----------
    net : ControlNet
        A face with knots (a cage is returned whole).

    Returns
    -------
    list of Piece
        In grid order (u major); ``[Piece(net, ...)]`` when no knot reaches multiplicity ``p`` or the
        split would exceed :data:`MAX_PIECES`.
    """
    if not net.is_bspline:
        return [Piece(net, (0.0, 0.0), (0.0, 0.0), (0, 0))]
    axes = [_axis_pieces(net, k) for k in (0, 1)]
    unsplit = all(len(a) == 1 and a[0][4] == per for a, per in zip(axes, net.periodic))
    count = len(axes[0]) * len(axes[1])
    if unsplit or count > MAX_PIECES:
        note = None if unsplit else (f"{count} pieces between its junctions (more than {MAX_PIECES}): analysed "
                                     "whole, so its junctions read as ripple")
        return [Piece(net, (axes[0][0][2], axes[1][0][2]), (axes[0][0][3], axes[1][0][3]), (0, 0), note)]
    out = []
    for a, (iu, ku, ulo, uhi, up) in enumerate(axes[0]):
        for b, (iv, kv, vlo, vhi, vp) in enumerate(axes[1]):
            pts = net.points[np.ix_(iu, iv)]
            w = None if net.weights is None else net.weights[np.ix_(iu, iv)]
            bounds, gaps = None, []
            if net.uv_bounds is not None:
                # a direction left whole keeps the face's bounds (a periodic one may cross its seam); a periodic
                # direction opened at a junction may keep two ranges of one piece (the trim across the opening)
                bs = []
                for k, (lo, hi, opened, whole) in enumerate(((ulo, uhi, up, len(axes[0]) == 1),
                                                             (vlo, vhi, vp, len(axes[1]) == 1))):
                    b0, b1 = net.uv_bounds[2 * k], net.uv_bounds[2 * k + 1]
                    if whole and opened == net.periodic[k]:
                        bs.append((b0, b1))
                        continue
                    ranges = _clip_ranges(b0, b1, lo, hi, net.periodic[k], _period(net, k))
                    bs.append((ranges[0][0], ranges[-1][1]) if ranges else None)
                    gaps += [(k, a[1], b[0]) for a, b in zip(ranges[:-1], ranges[1:])]
                if bs[0] is None or bs[1] is None:
                    continue  # trimmed away
                bounds = bs[0] + bs[1]
            piece = ControlNet(points=pts, weights=w, degrees=net.degrees, knots=(ku, kv), periodic=(up, vp),
                               uv_bounds=bounds, unit=net.unit, origin=net.origin, canonical=net.canonical,
                               exact=net.exact, trim_gaps=tuple(gaps))
            out.append(Piece(piece, (ulo, vlo), (uhi, vhi), (a, b)))
    return out


def _period(net: ControlNet, axis: int) -> float | None:
    if not net.periodic[axis]:
        return None
    t, p, n = net.knots[axis], net.degrees[axis], net.shape[axis]
    return float(t[p + n] - t[p])


def _clip(b0: float, b1: float, lo: float, hi: float, periodic: bool, period: float | None = None):
    """The face's trimmed range ``[b0, b1]`` within a piece's ``[lo, hi]`` (None: empty)."""
    a, b = max(b0, lo), min(b1, hi)
    if periodic:  # the trimmed range may sit a period away from the piece's (unrolled) range
        period = period or (hi - lo)
        a, b = max(((max(b0 + k * period, lo), min(b1 + k * period, hi)) for k in (-2, -1, 0, 1, 2)),
                   key=lambda r: r[1] - r[0])
    if b - a <= 1e-12 * max(1.0, abs(hi - lo)):
        return None
    return (a, b)


def _clip_ranges(b0: float, b1: float, lo: float, hi: float, periodic: bool, period: float | None = None) -> list:
    """Every part of the face's trimmed range ``[b0, b1]`` within a piece's ``[lo, hi]``, in order: one (or
    none) for an open direction; for a periodic one opened at a junction, the range shifted by whole periods, so
    a trim across the opening keeps both of its parts."""
    if not periodic:
        got = _clip(b0, b1, lo, hi, False)
        return [got] if got is not None else []
    period = period or (hi - lo)
    out = []
    for k in (-2, -1, 0, 1, 2):
        got = _clip(b0 + k * period, b1 + k * period, lo, hi, False)
        if got is not None:
            out.append(got)
    out.sort()
    merged = []
    for a, b in out:
        if merged and a <= merged[-1][1] + 1e-12 * max(1.0, abs(hi - lo)):
            merged[-1] = (merged[-1][0], max(merged[-1][1], b))
        else:
            merged.append((a, b))
    return merged


# ---------------------------------------------------------------- gathering the pieces' results
def _grid_of(pieces: list[Piece]):
    rows = sorted({p.index[0] for p in pieces})
    cols = sorted({p.index[1] for p in pieces})
    return rows, cols


def _whole_coords(frame, u: np.ndarray) -> np.ndarray:
    return (np.asarray(u, float) - frame.u0) / frame.h


def gather_fields(net: ControlNet, pieces: list[Piece], fields: list[ArtifactFields], arrays: list[dict],
                  levels: int):
    """The pieces' fine-grid fields side by side on one grid of the whole face.

    Parameters
    ----------
    net : ControlNet
        The whole face.
    pieces : list of Piece
    fields : list of ArtifactFields
        Per piece (same order).
    arrays : list of dict str -> (a, b) array
        Per piece, further arrays to gather (scalar fields, region masks).

    Returns
    -------
    (fields, arrays) : (ArtifactFields, dict)
        ``x, y`` in the whole face's analysis coordinates (the first sample of every piece after the
        first is dropped: it repeats the junction); ``baseband`` evaluates each piece's intent.
    """
    intent = PiecewiseIntent(net, pieces, fields, levels)
    fu, fv = intent.frames
    frames_of = dict(zip((p.index for p in pieces), intent.piece_frames))
    by_index = {p.index: (p, f, a) for p, f, a in zip(pieces, fields, arrays)}
    rows, cols = _grid_of(pieces)
    full = len(by_index) == len(rows) * len(cols)

    def axis_coords(k, keys, frame):
        out = []
        for i, key in enumerate(keys):
            index, (p, f, _) = next((kk, v) for kk, v in by_index.items() if kk[k] == key)
            x = _whole_coords(frame, frames_of[index][k].param(f.x if k == 0 else f.y))
            out.append(x if i == 0 else x[1:])
        return out

    xs, ys = axis_coords(0, rows, fu), axis_coords(1, cols, fv)

    def block(get):
        out_rows = []
        for i, r in enumerate(rows):
            parts = []
            for j, c in enumerate(cols):
                if (r, c) in by_index:
                    a = get(*by_index[(r, c)])
                else:  # a piece trimmed away: nothing there
                    like = get(*next(iter(by_index.values())))
                    shape_ = (len(xs[i]) + (0 if i == 0 else 1), len(ys[j]) + (0 if j == 0 else 1))
                    a = np.zeros(shape_ + like.shape[2:], dtype=like.dtype)
                a = a[(0 if i == 0 else 1):, (0 if j == 0 else 1):]
                parts.append(a)
            out_rows.append(np.concatenate(parts, axis=1))
        return np.concatenate(out_rows, axis=0)

    first = fields[0]
    bands = {name: block(lambda p, f, a, name=name: f.bands[name]) for name in first.bands}
    gathered = {name: block(lambda p, f, a, name=name: a[name]) for name in arrays[0]}
    if not full:
        gathered = {k: (v & _present(by_index, rows, cols, xs, ys) if v.dtype == bool else v)
                    for k, v in gathered.items()}
    out = ArtifactFields(x=np.concatenate(xs), y=np.concatenate(ys), surface=block(lambda p, f, a: f.surface),
                         intent=block(lambda p, f, a: f.intent), bands=bands, method=first.method,
                         levels=first.levels, reading=first.reading,
                         baseband={"evaluate": intent.surface_reading, "intent": intent}
                         if first.baseband is not None else None)
    return out, gathered


def _present(by_index, rows, cols, xs, ys) -> np.ndarray:
    mask = np.zeros((sum(map(len, xs)), sum(map(len, ys))), bool)
    r0 = 0
    for i, r in enumerate(rows):
        c0 = 0
        for j, c in enumerate(cols):
            if (r, c) in by_index:
                mask[r0: r0 + len(xs[i]), c0: c0 + len(ys[j])] = True
            c0 += len(ys[j])
        r0 += len(xs[i])
    return mask


class PiecewiseIntent:
    """The design intent of a split face: each piece's own, on its parameter range.

    Parameters
    ----------
    net : ControlNet
        The whole face (``frames`` are its analysis frames).
    pieces : list of Piece
    fields : list of ArtifactFields or None
        The pieces' fields (the ``surface`` reading evaluates their base band).
    levels : int
    """

    def __init__(self, net: ControlNet, pieces: list[Piece], fields, levels: int):
        # the surface reading needs the pieces' fields; the net reading builds each piece's intent on demand
        self.net, self.pieces, self.fields_list = net, pieces, fields
        self.frames = axis_frames(net, levels)
        self.piece_frames = [axis_frames(p.net, levels) for p in pieces]  # built once: evaluations reuse them
        self._intents = None

    @property
    def levels(self) -> int:
        return self.frames[0].levels

    def _assign(self, k: int, x: np.ndarray):
        """Per piece range along direction ``k``: the parameters of ``x`` there, which piece reads each sample, and
        for a sample on a join the piece on its other side (else -1)."""
        frame = self.frames[k]
        u = frame.param(x)
        keys = sorted({p.index[k] for p in self.pieces})
        ranges = {}
        for p in self.pieces:
            ranges.setdefault(p.index[k], (p.lo[k], p.hi[k]))
        if frame.periodic:
            start = ranges[keys[0]][0]
            u = start + np.mod(u - start, frame.h * frame.spans)
        which = np.full(len(u), keys[-1])
        other = np.full(len(u), -1)
        for key, nxt in zip(reversed(keys), [None] + list(reversed(keys))[:-1]):
            end = ranges[key][1] + 1e-12 * max(1.0, abs(ranges[key][1]))
            which = np.where(u <= end, key, which)
            if nxt is not None:
                on = np.abs(u - ranges[key][1]) <= 1e-12 * max(1.0, abs(ranges[key][1]))
                other = np.where(on, nxt, other)
        return u, which, other

    def _fill(self, u, wu, v, wv, one) -> np.ndarray:
        out = np.zeros((len(u), len(v), 3))
        for i, (p, (pu, pv)) in enumerate(zip(self.pieces, self.piece_frames)):
            ru, rv = np.flatnonzero(wu == p.index[0]), np.flatnonzero(wv == p.index[1])
            if ru.size == 0 or rv.size == 0:
                continue
            xl, yl = (u[ru] - pu.u0) / pu.h, (v[rv] - pv.u0) / pv.h
            out[np.ix_(ru, rv)] = one(i, p, xl, yl)
        return out

    def _evaluate(self, x, y, one) -> np.ndarray:
        """Each sample read by its piece; a sample on a join by both pieces, their mean: the order of the pieces
        must not choose (a reversed face would read the other piece there)."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        (u, wu, au), (v, wv, av) = self._assign(0, x), self._assign(1, y)
        out = self._fill(u, wu, v, wv, one)
        ju, jv = np.flatnonzero(au >= 0), np.flatnonzero(av >= 0)
        if ju.size:
            rows = self._fill(u[ju], au[ju], v, wv, one)
        if jv.size:
            cols = self._fill(u, wu, v[jv], av[jv], one)
        if ju.size and jv.size:
            both = self._fill(u[ju], au[ju], v[jv], av[jv], one)
            corner = (out[np.ix_(ju, jv)] + rows[:, jv] + cols[ju] + both) / 4.0
        if ju.size:
            out[ju] = (out[ju] + rows) / 2.0
        if jv.size:
            out[:, jv] = (out[:, jv] + cols) / 2.0 if not ju.size else np.where(
                np.isin(np.arange(len(u)), ju)[:, None, None], out[:, jv], (out[:, jv] + cols) / 2.0)
        if ju.size and jv.size:
            out[np.ix_(ju, jv)] = corner
        return out

    def surface_reading(self, x, y) -> np.ndarray:
        """The ``surface`` reading (each piece less its ripple) on the grid ``x x y`` -> ``(a, b, 3)``."""
        return self._evaluate(x, y, lambda i, p, xl, yl: baseband_at(self.fields_list[i], xl, yl))

    def evaluate(self, x=None, y=None) -> np.ndarray:
        """The ``net`` reading (each piece's intent) on the grid ``x x y`` -> ``(a, b, 3)``."""
        from .intent import design_intent
        from ..theory.catalogue import bspline

        if self._intents is None:  # a split face is analysed under its own degrees
            sch = bspline(*self.net.degrees)
            self._intents = [design_intent(p.net, sch, self.levels) for p in self.pieces]
        x = self.frames[0].x if x is None else x
        y = self.frames[1].x if y is None else y
        return self._evaluate(x, y, lambda i, p, xl, yl: self._intents[i].evaluate(xl, yl))


def face_kind(net: ControlNet) -> str | None:
    """How a face is written when it is not one uniform polynomial net: "piecewise-Bezier", "rational"..."""
    if not net.is_bspline:
        return None
    words = []
    dirs = list(zip(net.knots, net.degrees, net.shape, net.periodic))
    if any(bezier_direction(k, p, n, per) and n > p + 1 for k, p, n, per in dirs):
        words.append("piecewise-Bezier")
    elif any(junctions(k, p, n, per) for k, p, n, per in dirs):
        words.append("jointed")
    elif not all(net.knots_uniform):
        words.append("non-uniform")
    if net.weights_vary:
        words.append("rational")
    return " ".join(words) or None
