"""The face maps the pictures draw, and what the PNG, GLB and HTML writers share: the directions, the
colour scale (the colormap up to the tolerance, red beyond it), the grid cells on the face, and writing a
file atomically."""

from __future__ import annotations

import contextlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..dependencies import require
from ..errors import check_option

__all__ = ["DIRECTIONS", "CMAP", "ABOVE_COLOUR", "PEAK_COLOUR", "OUTSIDE_COLOUR", "FaceMap", "label", "unit_text",
           "face_maps", "number", "colour_limits", "cells", "vertex_colours", "upper_limit", "write_atomic"]

#: Fields that can be shown (SPEC §4): ripple per direction, its total, the signal error and the
#: whole deviation from intent.
DIRECTIONS = ("total", "x1", "x2", "diagonal", "lateral", "signal_error", "deviation")

LABELS = {
    "total": "Ripple",
    "x1": "X1 ripple",
    "x2": "X2 ripple",
    "diagonal": "Diagonal ripple",
    "lateral": "Lateral ripple",
    "signal_error": "Signal error",
    "deviation": "Deviation",
}

CMAP = "viridis"
ABOVE_COLOUR = (0.86, 0.08, 0.08)  # red: beyond the tolerance
PEAK_COLOUR = (0.40, 0.0, 0.04)  # dark red: the largest peak, when it is beyond the tolerance
OUTSIDE_COLOUR = (0.75, 0.75, 0.75)  # grey: no value (glb only)
@dataclass(frozen=True, eq=False)
class FaceMap:
    """One face ready to draw.

    Attributes
    ----------
    net : ControlNet
    points : (a, b, 3) float
        The fine-grid limit surface.
    values : (a, b) float
        ``|field|`` in model units; NaN outside the trimmed face.
    peak : float
        Largest value on the face (0 if none).
    budget : Budget
    """

    net: object
    points: np.ndarray
    values: np.ndarray
    peak: float
    budget: object


def label(direction: str, unit: str = "mm") -> str:
    """Scalar-bar title such as ``"X1 ripple [mm]"``."""
    check_option("direction", direction, DIRECTIONS)
    return f"{LABELS[direction]} [{unit}]"


def unit_text(unit: str) -> str:
    """``"mm"`` as it is; an OBJ cage's unitless ``"model"`` as ``"model units"``."""
    return "model units" if unit == "model" else unit


def face_maps(nets, direction: str = "total", scheme=None, *, levels: int = 3, component: str = "normal") -> list:
    """Compute the fields of each net and the magnitudes to draw.

    Parameters
    ----------
    nets : list of ControlNet
    direction : str
        One of :data:`DIRECTIONS`.
    scheme : str or Scheme, optional
        As :func:`cadartifact.budget` (default: each face's own degrees).
    levels, component
        As :func:`cadartifact.budget`.

    Returns
    -------
    list of FaceMap
        ``values = |scalar_fields[direction]|`` on the fine grid, NaN outside the trimmed face
        (the budget's region: the trimmed face, its interior when measured), so
        ``peak == budget.stats[direction].peak``.
    """
    from ..analysis.budget import budget

    check_option("direction", direction, DIRECTIONS)
    out = []
    for net in nets:
        b = budget(net, scheme, levels=levels, component=component, keep_fields=True)
        keep = b.region  # the points the budget's stats cover (trimmed face; interior when measured)
        values = np.where(keep, np.abs(b.scalar_fields[direction]), np.nan)
        peak = float(np.nanmax(values)) if keep.any() else 0.0
        out.append(FaceMap(net=net, points=np.asarray(b.fields.surface), values=values, peak=peak, budget=b))
    return out


def number(value: float) -> str:
    """Three significant digits; values below 1e-10 (rounding noise in model units) print as 0."""
    return "0" if abs(value) < 1e-10 else f"{value:.3g}"


def colour_limits(maps, tol: float | None = None) -> tuple[float, float]:
    """``(0, tol)`` with a tolerance, else ``(0, largest peak)`` (a tiny positive number if all are 0)."""
    if tol is not None:
        return 0.0, float(tol)
    top = max((m.peak for m in maps), default=0.0)
    return 0.0, top if top > 0 else 1e-12


def _quads(a: int, b: int) -> np.ndarray:
    """``(a-1)(b-1), 4`` vertex indices of the grid cells of a C-ordered ``(a, b)`` point grid."""
    i, j = np.meshgrid(np.arange(a - 1), np.arange(b - 1), indexing="ij")
    k = (i * b + j).ravel()
    return np.stack([k, k + b, k + b + 1, k + 1], axis=1)


def cells(m: FaceMap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points ``(a b, 3)``, values ``(a b,)`` and the quads whose four corners lie on the face."""
    a, b = m.values.shape
    pts = m.points.reshape(-1, 3)
    vals = m.values.ravel()
    quads = _quads(a, b)
    inside = np.all(np.isfinite(vals[quads]), axis=1)
    return pts, vals, quads[inside]


def vertex_colours(values: np.ndarray, clim: tuple[float, float], cmap: str = CMAP,
                   top: float | None = None) -> np.ndarray:
    """RGBA ``uint8`` colours ``(n, 4)`` of magnitudes: the colormap over ``clim``, red above, grey for NaN.

    With ``top > clim[1]`` (the tolerance) the values above it keep their structure: a second
    segment runs linearly from :data:`ABOVE_COLOUR` at the tolerance to :data:`PEAK_COLOUR` at ``top``
    (a face far over tolerance is no longer solid red).
    """
    mpl = require("matplotlib", "heatmap colours")
    lo, hi = clim
    span = hi - lo if hi > lo else 1.0
    t = np.clip((np.nan_to_num(values, nan=lo) - lo) / span, 0.0, 1.0)
    rgba = np.asarray(mpl.colormaps[cmap](t), dtype=float)
    over = values > hi
    if top is not None and top > hi and over.any():
        s = np.clip((values[over] - hi) / (top - hi), 0.0, 1.0)[:, None]
        rgba[over, :3] = (1 - s) * np.array(ABOVE_COLOUR) + s * np.array(PEAK_COLOUR)
    else:
        rgba[over, :3] = ABOVE_COLOUR
    rgba[~np.isfinite(values), :3] = OUTSIDE_COLOUR
    return np.round(rgba * 255).astype(np.uint8)


def upper_limit(maps, tol: float | None) -> float | None:
    """The top of the over-tolerance segment: the largest peak when it exceeds ``tol``, else None."""
    if tol is None:
        return None
    top = max((m.peak for m in maps), default=0.0)
    return top if top > tol else None


def write_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename, so a reader
    never sees a half-written file; permissions as a plain ``open`` would give (umask)."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path
