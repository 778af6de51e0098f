"""Reflection lines (zebra stripes) of faces, seen from the camera of the ripple heatmap.

A surface lit by parallel light bars shows their reflections; engineers read G0, G1 and G2 from them (Klass,
1980): a gap or a crease (G1 break) *breaks* the stripes, a curvature jump (G2 break) *kinks* them, ripple makes
them *wave*. Here the bars are infinitely far (an environment map) and parallel to the picture's up ``a``: at a
surface point with unit normal ``n`` seen along ``v`` (from the eye towards the surface) the reflected ray is
``r = v - 2 (v . n) n``, and the reflection function is its elevation out of the plane of the bars and the eye:

    phase = asin(r . c),     c = a x (-v) normalised (the picture's horizontal),

which depends on the normal alone, so that it jumps where the normal jumps (by about twice a crease's angle seen
across the bars), kinks where the curvature jumps and oscillates with the ripple. Stripes are
``floor(k phase / 2 pi)`` mod 2 for ``k`` stripes per turn of the reflected ray (chosen per picture so that its
faces show about :data:`WANTED` stripes; the colours are interpolated in the stripe coordinate before they are
mapped, so stripes are crisp inside cells). The camera (:func:`cadartifact.viz.view.camera`) is the heatmap's: a
single face seen along its mean normal, several isometrically.

Normals come from the drawn fine grid (``FaceMap.points``, second-order central differences), so the stripes
show the surface the heatmap shows.

References: R. Klass, "Correction of local surface irregularities using reflection lines", *Computer-Aided
Design* 12 (1980) 73-77; K.-P. Beier, Y. Chen, "Highlight-line algorithm for realtime surface-quality
assessment", *Computer-Aided Design* 26 (1994) 268-277.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STRIPES", "MOST_STRIPES", "grid_normals", "reflection_phase", "face_phase", "stripes", "centred",
           "stripe_count", "stripe_values"]

#: Stripes per turn of the reflected ray around the tunnel's axis (black and white pairs: STRIPES / 2), at least.
STRIPES = 24
#: At most (one stripe per half degree of the reflected ray).
MOST_STRIPES = 720
#: Stripes across the scene a picture aims at (a flat panel gets more per turn than a blend).
WANTED = 14


def grid_normals(points: np.ndarray) -> np.ndarray:
    """Unit normals ``(a, b, 3)`` of a point grid ``points : (a, b, 3)`` (``d/di x d/dj``, second-order
    differences; NaN where undefined)."""
    p = np.asarray(points, float)
    edge = 2 if min(p.shape[0], p.shape[1]) >= 3 else 1
    du = np.gradient(p, axis=0, edge_order=edge)
    dv = np.gradient(p, axis=1, edge_order=edge)
    n = np.cross(du, dv)
    size = np.linalg.norm(n, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(size > 0, n / size, np.nan)


def reflection_phase(normals: np.ndarray, towards: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The reflection function (radians, in [-pi/2, pi/2]) of unit normals ``(..., 3)`` seen from ``towards`` (the
    unit direction to the camera) under light bars parallel to ``axis`` (the picture's up).

    ``r = v - 2 (v . n) n`` with ``v = -towards``; ``phase = asin(r . c)`` with ``c = axis x towards`` normalised
    (the picture's horizontal): the reflected ray's elevation out of the plane of the bars and the eye, which has
    no seam and no pole (an angle around the axis would crowd its stripes where ``r`` nears the axis).
    """
    t = np.asarray(towards, float) / np.linalg.norm(towards)
    c = np.cross(np.asarray(axis, float), t)
    if np.linalg.norm(c) < 1e-9:  # looking along the bars: any horizontal will do
        c = np.cross([1.0, 0.0, 0.0] if abs(t[0]) < 0.9 else [0.0, 1.0, 0.0], t)
    c /= np.linalg.norm(c)
    n = np.asarray(normals, float)
    v = -t
    r = v - 2.0 * (n @ v)[..., None] * n
    return np.arcsin(np.clip(r @ c, -1.0, 1.0))


def face_phase(m, towards: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The reflection function ``(a, b)`` on a face map's fine grid (NaN outside the trimmed face)."""
    # r is even in n: a face's orientation does not matter
    phase = reflection_phase(grid_normals(m.points), towards, up)
    return np.where(np.isfinite(m.values), phase, np.nan)


def stripes(phase: np.ndarray, count: int = STRIPES) -> np.ndarray:
    """0 / 1 stripe of each phase (``floor(count phase / 2 pi) mod 2``; -1 where the phase is NaN)."""
    k = np.floor(np.nan_to_num(phase, nan=0.0) * count / (2 * np.pi)).astype(int) % 2
    return np.where(np.isfinite(phase), k, -1)


def centred(phases) -> list:
    """The phases (a list of arrays) turned so that their circular mean is 0, in (-pi, pi]: a scene's stripes then
    never straddle the +-pi seam of ``atan2`` (a plane seen isometrically reflects at phase pi)."""
    finite = np.concatenate([np.asarray(p, float)[np.isfinite(p)].ravel() for p in phases] + [np.zeros(0)])
    mean = float(np.angle(np.exp(1j * finite).mean())) if finite.size else 0.0
    return [np.angle(np.exp(1j * (np.asarray(p, float) - mean))) for p in phases]


def stripe_count(phases, wanted: int = WANTED) -> int:
    """Stripes per turn so that the scene's phases (a list of arrays) span about ``wanted`` stripes: at least
    :data:`STRIPES`, at most :data:`MOST_STRIPES` (a plane reflects one direction: no stripe to see)."""
    spread = max((float(np.nanmax(p) - np.nanmin(p)) for p in phases if np.isfinite(p).any()), default=0.0)
    if not spread > 0:
        return STRIPES
    return int(np.clip(np.ceil(2 * np.pi * wanted / spread), STRIPES, MOST_STRIPES))


def stripe_values(phase: np.ndarray, count: int) -> np.ndarray:
    """The stripe coordinate ``count phase / 2 pi`` (continuous: whole numbers are the stripes' edges)."""
    return np.asarray(phase, float) * count / (2 * np.pi)
