"""The ``surface`` reading's intent anywhere: the base band of a face's fields (SPEC §4).

:mod:`cadartifact.analysis.fields` splits the surface into bands and keeps the smooth part in a form that
evaluates anywhere (``ArtifactFields.baseband``): the per-direction syntheses of a tensor scheme,
or the base-band bins of the fine-grid spectrum plus a polynomial. The advice samples it on every
candidate's check grid, and the scheme comparison at every cage density it tries.
"""

from __future__ import annotations

import numpy as np

from .intent import _legendre, from_homogeneous
from ..numerics.tensor import sandwich, sandwich_left, sandwich_right

__all__ = ["baseband_at", "release", "MEMO_ENTRIES", "MEMO_BYTES"]


def baseband_at(fields, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The ``surface`` reading's intent (the surface less its ripple) at analysis coordinates ``x x y``.

    A polynomial (tensor Legendre coefficients) plus ``sum_kl X_kl exp(2 pi i (f_k z + g_l w)) / N``
    over the base-band bins of the fine-grid spectrum (lattice coordinates ``z = x - offset``;
    direct DFT sums, no FFT grid).

    Parameters
    ----------
    fields : ArtifactFields
        With ``baseband`` (:func:`cadartifact.analysis.fields.artifact_fields`).
    x : (a,) float
    y : (b,) float

    Returns
    -------
    (a, b, 3) float
    """
    bb = fields.baseband
    if "evaluate" in bb:  # a face split into pieces (cadartifact.analysis.pieces)
        return bb["evaluate"](np.asarray(x, float), np.asarray(y, float))
    out = _baseband_lifted(bb, x, y)
    return from_homogeneous(out) if bb.get("homogeneous") else out


#: What a base band keeps of its per-direction evaluation (the scheme comparison samples it at a few dozen
#: counts): rows per abscissae, along u with the spectrum already applied (the first half of each product);
#: at most this many entries and bytes, oldest first out, and all of it dropped by :func:`release`.
MEMO_ENTRIES, MEMO_BYTES = 64, 64 * 2 ** 20


def _axis_rows(bb: dict, axis: int, pts: np.ndarray, build):
    """``build(pts)`` memoised in the base band per direction and abscissae (valid because a base band is
    never changed once built: its points and spectrum are the fields')."""
    memo = bb.setdefault("_rows", {})
    key = (axis, pts.tobytes())
    got = memo.get(key)
    if got is None:
        got = build(pts)
        size = sum(a.nbytes for a in (got if isinstance(got, tuple) else (got,)))
        used = bb.get("_rows_bytes", 0) + size
        while memo and (len(memo) >= MEMO_ENTRIES or used > MEMO_BYTES):
            old = memo.pop(next(iter(memo)))
            used -= sum(a.nbytes for a in (old if isinstance(old, tuple) else (old,)))
        if size <= MEMO_BYTES:
            memo[key] = got
        else:
            used -= size
        bb["_rows_bytes"] = used
    return got


def release(fields) -> None:
    """Drop what :func:`baseband_at` kept in a face's fields (and its pieces'), once its callers are done."""
    bb = getattr(fields, "baseband", None)
    if not bb:
        return
    bb.pop("_rows", None)
    bb.pop("_rows_bytes", None)
    for piece in getattr(bb.get("intent"), "fields_list", ()) or ():
        release(piece)


def _baseband_lifted(bb: dict, x, y) -> np.ndarray:
    x, y = np.asarray(x, float), np.asarray(y, float)
    if "separable" in bb:
        lu, lv = bb["separable"]
        half = _axis_rows(bb, 0, x, lambda pts: sandwich_left(lu(pts), bb["points"]))
        return sandwich_right(half, _axis_rows(bb, 1, y, lv))

    def dft_rows(frame, f):
        def build(pts):
            # the fine grid was rolled by the whole fine steps of `shift`: evaluate on that same grid
            z = pts + frame.shift / frame.K
            ph = 2 * np.pi * np.outer(z, f)
            N = frame.K * frame.period
            return np.cos(ph) / N, np.sin(ph) / N
        return build

    (fu, fv), (gu, gv) = bb["frames"], bb["freqs"]

    def left_halves(pts):  # the u half of each product (sandwich_left), kept with the u abscissae
        Cu, Su = dft_rows(fu, gu)(pts)
        spec = bb["spec"]
        Xr, Xi = np.ascontiguousarray(spec.real), np.ascontiguousarray(spec.imag)
        return tuple(sandwich_left(A, X) for A, X in ((Cu, Xr), (Su, Xr), (Cu, Xi), (Su, Xi)))

    CXr, SXr, CXi, SXi = _axis_rows(bb, 0, x, left_halves)
    Cv, Sv = _axis_rows(bb, 1, y, dft_rows(fv, gv))
    out = (sandwich_right(CXr, Cv) - sandwich_right(SXr, Sv) - sandwich_right(CXi, Sv)
           - sandwich_right(SXi, Cv))
    M = bb["poly"]
    return out + sandwich(_legendre(x, fu.spans, M.shape[0] - 1), M, _legendre(y, fv.spans, M.shape[1] - 1))
