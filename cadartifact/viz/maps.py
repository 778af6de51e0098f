"""Response maps over the frequency square (the paper's Figures 8 and 10-17).

Two pictures:

* :func:`plot_maps` -- per scheme a row of three panels over Ω = (ωx, ωy): the
  signal magnitude |a| (grey, bright = signal kept), the artifact energy as a
  percentage of the signal (filled contours on a log scale) and the lateral
  artifact magnitude. Several schemes share one colour scale per column, as in
  the paper's Figures 16-17, so rows compare at a glance.
* :func:`plot_grid` -- the paper's Figure 8 array: the artifact energy of the
  box splines box(g, g, d, d), g = 0..3 axis smoothing stages (columns) and
  d = 0..3 diagonal smoothing stages (rows).

The numbers come from :meth:`Scheme.response` (SPEC §3); :func:`response_map`
and :func:`grid_energies` return the arrays that are drawn so they can be
checked without looking at pixels. matplotlib is imported lazily (Agg canvas,
no pyplot, so the global backend is never touched).

Reference: Dodgson, Sabin et al., "Artifact analysis of subdivision schemes"
(``/work/shared/paper``), §4 (Figure 8) and §7-8 (Figures 10-17).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..dependencies import require
from ..errors import CadArtifactError, InputError, OptionError, check_option

__all__ = [
    "STAGES",
    "DOMAINS",
    "ResponseMap",
    "response_map",
    "box_one_step_energy",
    "grid_energies",
    "plot_maps",
    "plot_grid",
    "maps_figure",
    "grid_figure",
    "maps_figure_size",
    "grid_figure_size",
]

#: Responses that can be mapped (SPEC §3).
STAGES = ("one_step", "limit", "continuous")
#: Part of the Nyquist square drawn: the positive quadrant [0, 1/2]² (as the paper; every catalogue
#: mask is symmetric, so its responses are even in ωx and ωy) or the whole square [-1/2, 1/2]².
DOMAINS = ("quadrant", "square")
#: Axis and diagonal smoothing stages of the Figure 8 array: box(g, g, d, d).
GRID_STAGES = (0, 1, 2, 3)

MIN_RESOLUTION = 16
MAX_RESOLUTION = 4096
DPI = 120
#: Filled-contour levels of the artifact percentage: 1, 2, 5 per decade from 0.001 % to 100 %.
PERCENT_LEVELS = tuple(m * 10.0**e for e in range(-3, 2) for m in (1, 2, 5)) + (100.0,)
#: Decades of artifact energy shown in the Figure 8 array, below energy 1 (pure sampling).
GRID_DECADES = 4

_STAGE_TITLES = {
    "one_step": "after one subdivision step",
    "limit": "limit surface at the refined vertices",
    "continuous": "continuous limit surface",
}
_WRITABLE_SUFFIXES = (".png", ".pdf", ".svg")
# Layout in inches: one panel, the column headers/figure title, one horizontal colour bar row.
_PANEL_W, _PANEL_H = 3.8, 3.9
_TITLE_H, _AXIS_LABEL_H, _COLORBAR_H = 0.4, 0.4, 0.8
_GRID_PANEL = 2.6
#: Decades shown by the lateral-artifact colour scale below its (shared) maximum.
LATERAL_DECADES = 5


@dataclass(frozen=True)
class ResponseMap:
    """The arrays :func:`plot_maps` draws for one scheme.

    Attributes
    ----------
    title : str
        Scheme name and arrow counts, as printed above the row.
    stage : str
        One of :data:`STAGES`.
    wx, wy : (n,) float
        Frequencies of the grid columns / rows, cycles per control point.
    signal : (n, n) float
        |a|, the signal magnitude; ``signal[i, j]`` is at ``(wx[j], wy[i])``.
    percent : (n, n) float
        100·√((b²+c²+d²)/3)/|a| (NaN where a = 0).
    lateral : (n, n) float
        Lateral artifact magnitude (SPEC §3).
    """

    title: str
    stage: str
    wx: np.ndarray
    wy: np.ndarray
    signal: np.ndarray
    percent: np.ndarray
    lateral: np.ndarray


# ------------------------------------------------------------------ validation and data
def _check_resolution(resolution) -> int:
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)):
        raise OptionError("resolution", f"an integer from {MIN_RESOLUTION} to {MAX_RESOLUTION}", resolution)
    if not MIN_RESOLUTION <= resolution <= MAX_RESOLUTION:
        raise OptionError("resolution", f"an integer from {MIN_RESOLUTION} to {MAX_RESOLUTION}", resolution)
    return int(resolution)


def _check_out(out) -> Path:
    try:
        path = Path(out)
    except TypeError:
        raise OptionError("out", "a file path", out) from None
    check_option("out suffix", path.suffix.lower(), _WRITABLE_SUFFIXES)
    return path


def _frequencies(resolution: int, domain: str) -> np.ndarray:
    lo = 0.0 if domain == "quadrant" else -0.5
    return np.linspace(lo, 0.5, resolution)


def _resolve(scheme_or_name):
    """A :class:`Scheme` from a catalogue name, or the object itself if it already is one."""
    if isinstance(scheme_or_name, str):
        from ..theory.catalogue import scheme

        return scheme(scheme_or_name)
    if not hasattr(scheme_or_name, "response"):
        raise OptionError("schemes", "scheme names or Scheme objects", scheme_or_name)
    return scheme_or_name


def _scheme_title(s) -> str:
    arrows = getattr(s, "arrows", None)
    if arrows is None:
        return f"{s.name}  (not a box spline)"
    return f"{s.name}  (arrows {','.join(str(int(n)) for n in arrows)})"


def response_map(scheme, stage: str = "limit", resolution: int = 401, domain: str = "quadrant") -> ResponseMap:
    """Evaluate the responses of one scheme on a regular grid over the frequency square.

    Parameters
    ----------
    scheme : str or Scheme
        Catalogue name (``"bicubic"``, ``"box(2,2,1,1)"``, ...) or a :class:`Scheme`.
    stage : {"one_step", "limit", "continuous"}
    resolution : int
        Grid points per axis (16 to 4096), end points included.
    domain : {"quadrant", "square"}
        [0, 1/2]² or [-1/2, 1/2]².

    Returns
    -------
    ResponseMap
        |a|, percent = 100·√((b²+c²+d²)/3)/|a| and the lateral magnitude on the (n, n) grid.
    """
    check_option("stage", stage, STAGES)
    check_option("domain", domain, DOMAINS)
    resolution = _check_resolution(resolution)
    s = _resolve(scheme)
    w = _frequencies(resolution, domain)
    r = s.response(w[None, :], w[:, None], stage=stage)
    shape = (resolution, resolution)
    with np.errstate(divide="ignore", invalid="ignore"):
        signal = np.broadcast_to(np.abs(np.asarray(r.signal, dtype=float)), shape).copy()
        percent = np.broadcast_to(np.asarray(r.percent, dtype=float), shape).copy()
        lateral = np.broadcast_to(np.abs(np.asarray(r.lateral, dtype=float)), shape).copy()
    return ResponseMap(_scheme_title(s), stage, w, w.copy(), signal, percent, lateral)


def box_one_step_energy(arrows, wx, wy) -> np.ndarray:
    """Artifact energy after one step of a box-spline scheme, from its closed-form symbol.

    M̂(θ)/4 = Π_ξ ((1 + z^ξ)/2)^{n_ξ}, so |M̂(θ)/4| = Π_ξ |cos(π θ·ξ / 2)|^{n_ξ} over
    ξ ∈ {X1, X2, X1+X2, X1−X2}; b, c, d are its values at θ = Ω + X1, Ω + X2, Ω + X1 + X2
    and the energy is √((b² + c² + d²)/3) (paper §3-4, Table 1; SPEC §2-3). Needs no limit,
    so it also covers non-convergent boxes such as box(0,0,0,0) (pure sampling: energy 1).

    Parameters
    ----------
    arrows : (4,) int
        Arrow counts (n1, n2, n3, n4) along X1, X2, X1+X2, X1−X2.
    wx, wy : array_like float
        Frequencies in cycles per control point (broadcast together).

    Returns
    -------
    energy : float array of the broadcast shape
    """
    n1, n2, n3, n4 = (int(n) for n in arrows)
    wx = np.asarray(wx, dtype=float)
    wy = np.asarray(wy, dtype=float)

    def symbol(tx, ty):
        c = lambda t, n: np.abs(np.cos(0.5 * np.pi * t)) ** n  # noqa: E731
        return c(tx, n1) * c(ty, n2) * c(tx + ty, n3) * c(tx - ty, n4)

    b, c, d = symbol(wx + 1, wy), symbol(wx, wy + 1), symbol(wx + 1, wy + 1)
    return np.sqrt((b * b + c * c + d * d) / 3.0)


def grid_energies(stage: str = "one_step", resolution: int = 201, domain: str = "quadrant"):
    """The artifact energies of the Figure 8 array.

    Panel (d, g) is box(g, g, d, d): g smoothing stages ((1+z1)/2)^g((1+z2)/2)^g along the grid
    lines and d diagonal ones ((1+z1 z2)/2)^d((1+z2/z1)/2)^d (paper Figure 8 caption; one stage is
    one arrow, so g = 2, d = 0 is the bilinear scheme).

    Returns
    -------
    w : (n,) float
        The grid frequencies (both axes).
    energies : dict (d, g) -> (n, n) float or None
        None where the catalogue has no such stage for the box (e.g. no limit for
        non-convergent boxes); for ``stage="one_step"`` those panels come from
        :func:`box_one_step_energy`.
    """
    check_option("stage", stage, STAGES)
    check_option("domain", domain, DOMAINS)
    resolution = _check_resolution(resolution)
    from ..theory.catalogue import box

    w = _frequencies(resolution, domain)
    shape = (resolution, resolution)
    energies = {}
    for d in GRID_STAGES:
        for g in GRID_STAGES:
            try:
                e = box(g, g, d, d).response(w[None, :], w[:, None], stage=stage).energy
                energies[d, g] = np.broadcast_to(np.abs(np.asarray(e, dtype=float)), shape).copy()
            except CadArtifactError:
                # The catalogue refuses boxes without a convergent limit (pure sampling, piecewise
                # constants, diagonal-only): the one-step response needs only the symbol.
                energies[d, g] = (box_one_step_energy((g, g, d, d), w[None, :], w[:, None])
                                  if stage == "one_step" else None)
    return w, energies


# ------------------------------------------------------------------ drawing
def maps_figure_size(rows: int) -> tuple[float, float]:
    """(width, height) in inches of a :func:`plot_maps` figure with ``rows`` schemes."""
    return 3 * _PANEL_W, _TITLE_H + rows * _PANEL_H + _AXIS_LABEL_H + _COLORBAR_H


def grid_figure_size() -> tuple[float, float]:
    """(width, height) in inches of the :func:`plot_grid` figure."""
    n = len(GRID_STAGES)
    return n * _GRID_PANEL + 1.0, n * (_GRID_PANEL + 0.3) + _TITLE_H + _AXIS_LABEL_H + _COLORBAR_H


def _new_figure(size):
    require("matplotlib", "response maps")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, dpi=DPI, layout="compressed")
    FigureCanvasAgg(fig)
    return fig


def _save(fig, path: Path) -> Path:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=DPI)
    except OSError as exc:
        raise InputError(path, f"cannot write the picture ({exc.strerror or exc})") from None
    return path


def _frequency_axes(ax, w, first_col: bool, last_row: bool):
    lo, hi = float(w[0]), float(w[-1])
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_aspect("equal")
    ticks = np.linspace(lo, hi, 3 if lo == 0 else 5)
    labels = [f"{t:g}" for t in ticks]  # "0.5" not "0.50": neighbouring panels' labels stay apart
    ax.set_xticks(ticks, labels)
    ax.set_yticks(ticks, labels)
    if last_row:
        ax.set_xlabel(r"$\omega_x$ (cycles per control point)")
    if first_col:
        ax.set_ylabel(r"$\omega_y$ (cycles per control point)")


def _image(ax, data, w, **kw):
    h = (w[-1] - w[0]) / (len(w) - 1) / 2  # pixel centres on the grid points
    return ax.imshow(data, origin="lower", extent=(w[0] - h, w[-1] + h, w[0] - h, w[-1] + h),
                     interpolation="nearest", **kw)


def _levels_125(top: float, decades: int) -> np.ndarray:
    """Levels 1, 2, 5 × 10^k from ``decades`` decades below ``top`` up to the first level >= top."""
    top = top if np.isfinite(top) and top > 0 else 1.0
    e = math.floor(math.log10(top))
    upper = next(m * 10.0**e for m in (1, 2, 5, 10) if m * 10.0**e >= top * (1 - 1e-12))
    lower = 10.0 ** (e - decades)
    levels = [m * 10.0**k for k in range(e - decades, e + 2) for m in (1, 2, 5)]
    return np.array([v for v in levels if lower * (1 - 1e-12) <= v <= upper * (1 + 1e-12)])


def _power_of_ten(value, _pos=None) -> str:
    """Tick label 10^k for a decade level."""
    return rf"$10^{{{round(math.log10(value))}}}$" if value > 0 else "0"


def _log_contours(ax, w, data, levels, cmap_name, line_every: int = 3):
    """Filled contours of non-negative ``data`` on log-spaced ``levels``, lines every ``line_every`` levels.

    Values below the first level (including exact zeros, e.g. the artifact at Ω = 0) fill the
    lowest band and NaN/inf (a zero signal) the highest; both are shown as the colour bar's
    extensions.
    """
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm

    cmap = colormaps[cmap_name].resampled(len(levels) + 1)
    norm = BoundaryNorm(levels, cmap.N, extend="both")
    big = levels[-1] * 10
    z = np.clip(np.nan_to_num(data, nan=big, posinf=big), levels[0] / 10, None)
    filled = ax.contourf(w, w, z, levels=levels, cmap=cmap, norm=norm, extend="both")
    if np.ptp(z) > 0:  # a constant field (pure sampling) has no contour line
        ax.contour(w, w, z, levels=levels[::line_every], colors="k", linewidths=0.4, alpha=0.6)
    return filled


def plot_maps(schemes, out, stage: str = "limit", resolution: int = 401, domain: str = "quadrant") -> Path:
    """Draw signal, artifact-percentage and lateral-artifact maps of one or more schemes.

    One row per scheme, three columns: |a| (grey, bright = signal kept, 0..1), artifact energy
    100·√((b²+c²+d²)/3)/|a| in % (filled contours on a log scale, 0.001 %..100 %, bright = small)
    and the lateral artifact magnitude (log scale, bright = small). Each column has one colour
    scale shared by all rows and one colour bar (paper Figures 10-17).

    Parameters
    ----------
    schemes : list of str or Scheme
        At least one (a single name or Scheme is taken as a list of one).
    out : str or Path
        Picture to write (.png; .pdf and .svg also work); parent folders are created.
    stage : {"one_step", "limit", "continuous"}
    resolution : int
        Grid points per axis, 16 to 4096.
    domain : {"quadrant", "square"}
        [0, 1/2]² (default, as the paper) or the whole Nyquist square [-1/2, 1/2]².

    Returns
    -------
    Path
        ``out``. Nothing is written if any argument or scheme is bad.
    """
    path = _check_out(out)
    return _save(maps_figure(schemes, stage, resolution, domain), path)


def maps_figure(schemes, stage: str = "limit", resolution: int = 401, domain: str = "quadrant"):
    """The :func:`plot_maps` picture as a matplotlib Figure (Agg canvas), e.g. for a notebook.

    Axes are ``fig.axes[3 * row + column]`` with columns signal, percent, lateral; the signal
    panel's image holds :attr:`ResponseMap.signal`. Parameters as :func:`plot_maps`.
    """
    if isinstance(schemes, str) or hasattr(schemes, "response"):
        schemes = [schemes]
    if not hasattr(schemes, "__iter__"):
        raise OptionError("schemes", "a list of scheme names or Scheme objects", schemes)
    schemes = list(schemes)
    if not schemes:
        raise OptionError("schemes", "at least one scheme", schemes)
    check_option("stage", stage, STAGES)
    check_option("domain", domain, DOMAINS)
    resolution = _check_resolution(resolution)
    maps = [response_map(s, stage, resolution, domain) for s in schemes]  # all data before any drawing

    fig = _new_figure(maps_figure_size(len(maps)))
    from matplotlib.colors import Normalize

    w = maps[0].wx
    axes = fig.subplots(len(maps), 3, squeeze=False, sharex=True, sharey=True)
    fig.suptitle(f"Responses to one sinusoid, {_STAGE_TITLES[stage]}", fontsize="x-large")

    signal_norm = Normalize(0.0, max(1.0, max(float(np.nanmax(m.signal)) for m in maps)))
    percent_levels = np.array(PERCENT_LEVELS)
    lateral_max = max(float(np.nanmax(m.lateral)) for m in maps)
    lateral_levels = _levels_125(lateral_max, LATERAL_DECADES)

    for row, m in enumerate(maps):
        ax_s, ax_p, ax_l = axes[row]
        im_s = _image(ax_s, m.signal, w, cmap="gray", norm=signal_norm)
        cs_p = _log_contours(ax_p, w, m.percent, percent_levels, "magma_r")
        cs_l = _log_contours(ax_l, w, m.lateral, lateral_levels, "bone_r")
        for col, (ax, what) in enumerate(((ax_s, "signal |a|"), (ax_p, "artifact, % of signal"),
                                          (ax_l, "lateral artifact"))):
            ax.set_title(f"{m.title}\n{what}", fontsize="medium")
            _frequency_axes(ax, w, col == 0, row == len(maps) - 1)

    bar = dict(location="bottom", shrink=0.9, aspect=30)
    fig.colorbar(im_s, ax=axes[:, 0], **bar).set_label("signal magnitude |a|  (1 = kept)")
    fig.colorbar(cs_p, ax=axes[:, 1], ticks=percent_levels[::3], format="%g", **bar).set_label(
        "artifact energy, % of signal (log scale)")
    fig.colorbar(cs_l, ax=axes[:, 2], ticks=lateral_levels[::3], format=_power_of_ten, **bar).set_label(
        "lateral artifact magnitude (log scale)")
    return fig


def plot_grid(out, stage: str = "one_step", resolution: int = 201, domain: str = "quadrant") -> Path:
    """Draw the paper's Figure 8 array: artifact energy of box(g, g, d, d), g, d = 0..3.

    Columns: g smoothing stages along each grid line direction; rows: d stages along each
    diagonal. Each panel shows √((b²+c²+d²)/3) as filled contours with contour lines on one
    shared log scale 10⁻⁴..1 (grey, bright = small artifact). Panels whose box has no convergent limit
    are marked "no limit" for the limit and continuous stages.

    Parameters
    ----------
    out : str or Path
        Picture to write; parent folders are created.
    stage : {"one_step", "limit", "continuous"}
        Default "one_step", as the paper's Figure 8.
    resolution : int
        Grid points per axis, 16 to 4096.
    domain : {"quadrant", "square"}

    Returns
    -------
    Path
        ``out``.
    """
    path = _check_out(out)
    return _save(grid_figure(stage, resolution, domain), path)


def grid_figure(stage: str = "one_step", resolution: int = 201, domain: str = "quadrant"):
    """The :func:`plot_grid` picture as a matplotlib Figure; panel (d, g) is ``fig.axes[4 * d + g]``."""
    w, energies = grid_energies(stage, resolution, domain)

    fig = _new_figure(grid_figure_size())
    n = len(GRID_STAGES)
    axes = fig.subplots(n, n, squeeze=False, sharex=True, sharey=True)
    fig.suptitle(f"Artifact energy √((b²+c²+d²)/3) {_STAGE_TITLES[stage]}: box(g, g, d, d)",
                 fontsize="large")
    top = max([1.0] + [float(np.nanmax(e)) for e in energies.values() if e is not None])
    levels = _levels_125(top, GRID_DECADES)
    filled = None
    for (d, g), e in energies.items():
        ax = axes[d, g]
        ax.set_title(f"g = {g}, d = {d}: box({g},{g},{d},{d})", fontsize="small")
        _frequency_axes(ax, w, g == 0, d == n - 1)
        ax.xaxis.label.set_fontsize("small")
        ax.yaxis.label.set_fontsize("small")
        if e is None:
            ax.set_facecolor("0.85")
            ax.text(0.5, 0.5, "no limit\n(not convergent)", transform=ax.transAxes,
                    ha="center", va="center", fontsize="small")
            continue
        filled = _log_contours(ax, w, e, levels, "gray_r", line_every=1)
    if filled is not None:
        cb = fig.colorbar(filled, ax=axes, location="bottom", shrink=0.6, aspect=40,
                          ticks=levels[::3], format=_power_of_ten)
        cb.set_label("artifact energy, log scale (1 = as large as the signal; bright = small)")
    return fig
