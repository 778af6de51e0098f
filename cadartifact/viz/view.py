"""3-D heatmaps of the ripple on each face: off-screen pyvista pictures and coloured glb meshes.

Each analysed face is drawn as its fine-grid surface (``Budget.fields.surface``, ``2**levels``
samples per control spacing) coloured by the magnitude of one band of its artifact field
(``|Budget.scalar_fields[direction]|``, model units), with the control net as thin lines on top.
Points outside the trimmed face's parameter rectangle are left out, as in the budget's statistics,
so the largest colour on a face is its budget peak in that direction.

With a tolerance the colour scale runs from 0 to the tolerance and anything beyond it is drawn in
red, so the places that break the tolerance stand out; without one it runs from 0 to the largest
value shown.

>>> from cadartifact.viz.view import view
>>> view("part.step", direction="x1", tol=0.05)          # doctest: +SKIP
ViewResult(png=PosixPath('part_x1.png'), ...)

pyvista (VTK) and trimesh are imported lazily; rendering is off screen (EGL/OSMesa when there is
no display), nothing opens a window.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..dependencies import require
from ..errors import CadArtifactError, OptionError, check_option
from .facemaps import (ABOVE_COLOUR, CMAP, DIRECTIONS, PEAK_COLOUR, FaceMap, cells, colour_limits,
                       LABELS, face_maps, label, number, unit_text, upper_limit, vertex_colours, write_atomic)

__all__ = [
    "DIRECTIONS",
    "FaceMap",
    "ViewResult",
    "face_maps",
    "colour_limits",
    "vertex_colours",
    "LAYOUTS",
    "choose_layout",
    "render_image",
    "write_png",
    "png_bytes",
    "export_glb",
    "write_atomic",
    "view",
]

DEFAULT_SIZE = (1200, 900)


@dataclass(frozen=True)
class ViewResult:
    """What :func:`view` wrote and the largest value shown (model units)."""

    png: Path | None
    glb: Path | None
    direction: str
    peak: float
    faces: tuple
    reflection: Path | None = None


@contextlib.contextmanager
def _quiet_vtk():
    """Hide VTK's warnings while a window is made (without a display it tries X11 first, warns, then
    falls back to EGL/OSMesa); errors still show."""
    try:
        from vtkmodules.vtkCommonCore import vtkLogger
    except ImportError:  # older VTK: nothing to quiet
        yield
        return
    before = vtkLogger.GetCurrentVerbosityCutoff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    try:
        yield
    finally:
        vtkLogger.SetStderrVerbosity(before)


LAYOUTS = ("auto", "model", "tiles")
#: ``auto`` draws faces as tiles when their median size is below this share of the whole scene.
TILE_SPREAD = 0.2
MAX_TILES = 25


def choose_layout(maps, layout: str = "auto") -> str:
    """``model`` (faces in place, one scene) or ``tiles`` (one zoomed view per face).

    ``auto`` gives tiles for 2..:data:`MAX_TILES` faces whose median bounding-box diagonal is below
    :data:`TILE_SPREAD` of the scene's (small blends of a large part would otherwise be specks).
    """
    check_option("layout", layout, LAYOUTS)
    if layout != "auto":
        return layout
    if not 1 < len(maps) <= MAX_TILES:
        return "model"
    boxes = [np.ptp(m.points.reshape(-1, 3), axis=0) for m in maps]
    allpts = np.concatenate([m.points.reshape(-1, 3) for m in maps])
    scene = float(np.linalg.norm(np.ptp(allpts, axis=0)))
    sizes = [float(np.linalg.norm(b)) for b in boxes]
    return "tiles" if scene > 0 and np.median(sizes) < TILE_SPREAD * scene else "model"


def camera(maps) -> tuple[np.ndarray, np.ndarray]:
    """``(towards, up)``: the unit direction from the scene to the camera and the camera's up vector of the scene of
    ``maps``: one face seen along its mean normal, several faces (or a face curved all round) isometrically."""
    normal = best_view(maps[0]) if len(maps) == 1 else None
    if normal is None:  # pyvista's isometric view
        return np.ones(3) / np.sqrt(3.0), np.array([0.0, 0.0, 1.0])
    up = np.array([0.0, 0.0, 1.0]) if abs(normal[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    return np.asarray(normal, float), up


def _scene(maps, clim, tol, size, show_net: bool, face_labels: bool, cmap: str, reflection: bool = False,
           markers=None) -> np.ndarray:
    """One off-screen pyvista scene of ``maps`` (no text, no colour bar), white background; with ``reflection``
    (on :data:`REFLECTION_GROUND`)
    the faces carry their reflection lines (:mod:`cadartifact.viz.reflection`) instead of the heatmap, from the
    same camera; ``markers`` ``(points (k, 3), values (k,))``: spheres coloured on the heatmap's scale (a cage's
    extraordinary vertices)."""
    pv = require("pyvista", "3-D heatmaps")
    towards, up = camera(maps)
    if reflection:
        from .reflection import centred, face_phase, stripe_count, stripe_values

        phases = centred([face_phase(m, towards, up) for m in maps])
        count = stripe_count(phases)
        zebra = [stripe_values(p, count) for p in phases]
        lo = math.floor(min((np.nanmin(z) for z in zebra if np.isfinite(z).any()), default=0.0))
        hi = max(lo + 1, math.ceil(max((np.nanmax(z) for z in zebra if np.isfinite(z).any()), default=1.0)))
        from matplotlib.colors import ListedColormap

        bands = ListedColormap([(0.97, 0.97, 0.97) if k % 2 == 0 else (0.05, 0.05, 0.05) for k in range(lo, hi)])
    with _quiet_vtk():
        plotter = pv.Plotter(off_screen=True, window_size=size)
        try:
            # reflection lines: a grey-blue ground, so that the light stripes keep the face's outline
            plotter.set_background(REFLECTION_GROUND if reflection else "white")
            extra = {"above_color": ABOVE_COLOUR} if tol is not None else {}
            floor = noise_floor(maps)
            top = upper_limit(maps, tol)
            for k, m in enumerate(maps):
                pts, vals, quads = cells(m)
                if len(quads) == 0:
                    continue
                mesh = pv.PolyData(pts, np.hstack([np.full((len(quads), 1), 4), quads]).ravel())
                # rounding noise (1e-13 mm on a clean panel) is drawn as the zero it is
                shown = np.where(np.nan_to_num(vals, nan=0.0) < floor, 0.0, np.nan_to_num(vals, nan=0.0))
                if reflection:
                    mesh.point_data["stripe"] = np.nan_to_num(zebra[k].ravel(), nan=lo)
                    plotter.add_mesh(mesh, scalars="stripe", cmap=bands, clim=(lo, hi), n_colors=hi - lo,
                                     interpolate_before_map=True, lighting=False, show_scalar_bar=False)
                elif top is not None:  # two segments: the colours are computed here, drawn as they are
                    mesh.point_data["rgb"] = vertex_colours(np.where(np.isfinite(vals), shown, np.nan), clim,
                                                            cmap, top)[:, :3]
                    plotter.add_mesh(mesh, scalars="rgb", rgb=True, smooth_shading=True, show_scalar_bar=False)
                else:
                    mesh.point_data["value"] = shown
                    plotter.add_mesh(mesh, scalars="value", cmap=cmap, clim=clim, smooth_shading=True,
                                     show_scalar_bar=False, **extra)
                if show_net and not reflection:
                    nu, nv = m.net.shape
                    cage = pv.PolyData(np.asarray(m.net.points, float).reshape(-1, 3), lines=_net_lines(nu, nv))
                    # lighter when many faces share the view, so the colours stay readable
                    plotter.add_mesh(cage, color="black", line_width=1, opacity=0.5 if len(maps) <= 4 else 0.2)
                if m.peak > floor and not reflection:  # a marker at the peak
                    k = int(np.nanargmax(m.values))
                    plotter.add_points(m.points.reshape(-1, 3)[k][None, :], color="magenta", point_size=12,
                                       render_points_as_spheres=True)
            if markers is not None and len(markers[0]):
                at = pv.PolyData(np.asarray(markers[0], float))
                at.point_data["rgb"] = vertex_colours(np.asarray(markers[1], float), clim, cmap, top)[:, :3]
                plotter.add_mesh(at, scalars="rgb", rgb=True, point_size=16, render_points_as_spheres=True,
                                 show_scalar_bar=False)
            if face_labels:
                shown = labelled_faces(maps)
                centres = np.array([_centre(m) for m in shown])
                plotter.add_point_labels(centres, [str(m.net.origin.face) for m in shown],
                                         font_size=14 if len(shown) <= 12 else 10, point_size=1, shape_opacity=0.5,
                                         always_visible=True)
            if len(maps) == 1 and best_view(maps[0]) is not None:  # a face seen square on, not edge-on
                plotter.view_vector(towards, viewup=up)
            else:
                plotter.view_isometric()
            if len(maps) > 1:  # the whole-model view: an axis triad and a scale bar along the longest side
                plotter.add_axes()
            if len(maps) > 1 and not reflection:  # (the stripes read better without the bar across them)
                a, b = ruler_ends(maps)
                plotter.add_ruler(a, b, title=unit_text(maps[0].net.unit), number_labels=3, font_size_factor=0.6,
                                  label_size_factor=0.6)
            plotter.reset_camera()
            return plotter.screenshot(None, return_img=True)
        finally:
            plotter.close()


#: The reflection picture's background (RGB): neither stripe colour, so the light stripes do not melt into it.
REFLECTION_GROUND = (0.62, 0.68, 0.76)

#: A face smaller than this share of the scene's size is tiny: a whole-model view does not label it.
TINY_FACE = 0.03


def labelled_faces(maps) -> list:
    """The faces a whole-model view labels with their index: every face whose bounding box's diagonal is at
    least :data:`TINY_FACE` of the scene's (a tiny face's label would cover its neighbours)."""
    pts = np.concatenate([m.points.reshape(-1, 3) for m in maps])
    scene = float(np.linalg.norm(np.ptp(pts, axis=0)))
    return [m for m in maps if float(np.linalg.norm(np.ptp(m.points.reshape(-1, 3), axis=0))) >= TINY_FACE * scene]


def ruler_ends(maps) -> tuple[np.ndarray, np.ndarray]:
    """The scale bar of a whole-model view: along the model's longest side, moved off the model by a tenth of
    its extent below its shortest side and beyond its middle one, the side the isometric camera (from +x+y+z)
    sees in front, so that neither the bar nor its labels cover a face."""
    pts = np.concatenate([m.points.reshape(-1, 3) for m in maps])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    shortest, middle, k = (int(j) for j in np.argsort(hi - lo))
    size = float((hi - lo)[k])
    a = lo.copy()
    a[shortest] -= 0.1 * size
    a[middle] = hi[middle] + 0.1 * size
    b = a.copy()
    b[k] = hi[k]
    return a, b


def noise_floor(maps) -> float:
    """Values below ``1e-9`` of the scene's size are rounding noise: pictures draw them as 0."""
    pts = np.concatenate([m.points.reshape(-1, 3) for m in maps])
    size = float(np.linalg.norm(np.ptp(pts, axis=0))) if len(pts) else 0.0
    return 1e-9 * max(size, 1e-300)


def mean_normal(m: FaceMap) -> np.ndarray | None:
    """The unit mean normal of a face's fine-grid surface (area-weighted), None when the face curves
    all round (a cylinder's normals cancel): then there is no single direction to look from."""
    p = np.asarray(m.points, float)
    if p.shape[0] < 2 or p.shape[1] < 2:
        return None
    du, dv = np.diff(p, axis=0)[:, :-1], np.diff(p, axis=1)[:-1, :]
    n = np.cross(du, dv)
    on_face = np.isfinite(m.values[:-1, :-1]) & np.isfinite(m.values[1:, 1:])  # cells inside the trim
    if on_face.any():
        n = n[on_face]
    total = n.reshape(-1, 3).sum(axis=0)
    length = float(np.linalg.norm(total))
    area = float(np.linalg.norm(n, axis=-1).sum())
    if not area > 0 or length < 0.2 * area:
        return None
    return total / length


def best_view(m: FaceMap) -> np.ndarray | None:
    """The direction a face's picture looks from: its mean normal (:func:`mean_normal`), else, for a face that
    curves all round (a cylinder), the normal of the plane that best fits its points inside the trim (the
    principal axis of least spread), from which the face shows its largest extent, never edge-on as a curve."""
    normal = mean_normal(m)
    if normal is not None:
        return normal
    p = np.asarray(m.points, float).reshape(-1, 3)
    inside = np.isfinite(np.asarray(m.values, float).reshape(-1))
    p = p[inside] if inside.sum() >= 3 else p
    if len(p) < 3:
        return None
    _, s, vt = np.linalg.svd(p - p.mean(axis=0), full_matrices=False)
    return vt[-1] if s[0] > 0 else None


def little_surface_reason(m: FaceMap) -> str:
    """Why a face's tile shows little surface, or ``""``: it curves all round, it is mostly turned away
    from any one viewing direction, or its trim keeps a small part of its net's surface."""
    why = []
    normal = mean_normal(m)
    if normal is None:
        why.append("curved all round: no single side to face, isometric view")
    else:
        p = np.asarray(m.points, float)
        n = np.cross(np.diff(p, axis=0)[:, :-1], np.diff(p, axis=1)[:-1, :])
        area = float(np.linalg.norm(n, axis=-1).sum())
        facing = float(np.abs(n @ normal).sum()) / area if area > 0 else 1.0
        if facing < 0.6:
            why.append(f"strongly curved: {facing:.0%} of its area faces the viewer")
    kept = float(np.isfinite(m.values).mean()) if m.values.size else 1.0
    if kept < 0.5:
        why.append(f"trimmed to {kept:.0%} of its net's surface")
    return "; ".join(why)


def _autocrop(img: np.ndarray, pad: int = 6, reflection: bool = False) -> np.ndarray:
    """Cut the margin of background (white, or :data:`REFLECTION_GROUND`) around a rendered scene."""
    ground = np.array(REFLECTION_GROUND if reflection else (1.0, 1.0, 1.0)) * 255
    ink = np.any(np.abs(img[..., :3].astype(float) - ground) > 5, axis=-1)
    if not ink.any():
        return img
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    r0, r1 = max(rows[0] - pad, 0), min(rows[-1] + pad + 1, img.shape[0])
    c0, c1 = max(cols[0] - pad, 0), min(cols[-1] + pad + 1, img.shape[1])
    return img[r0:r1, c0:c1]


def render_image(maps, *, direction: str = "total", tol: float | None = None, title: str | None = None,
                 window_size=DEFAULT_SIZE, show_net: bool = True, layout: str = "auto",
                 cmap: str = CMAP, reflection: bool = False, markers=None) -> np.ndarray:
    """Render faces off screen and return the picture: heatmap(s), colour bar, title.

    Parameters
    ----------
    maps : list of FaceMap
    direction : str
        Names the colour bar (e.g. ``"X1 ripple [mm]"``).
    tol : float, optional
        Colour scale 0..tol; beyond it a red segment up to the largest peak (the bar is broken at the
        tolerance), so faces over tolerance keep their structure.
    title : str, optional
    window_size : (int, int)
        Width and height of the picture in pixels.
    show_net : bool
        Draw each control net as thin black lines.
    layout : {"auto", "model", "tiles"}
        See :func:`choose_layout`. ``model`` labels faces with their index when there are several;
        each tile is titled with its face index and peak.
    reflection : bool
        Draw the faces' reflection lines (:mod:`cadartifact.viz.reflection`) instead of the heatmap, from the
        same camera and layout (no net, no colour bar).
    markers : ((k, 3), (k,)) float, optional
        Points drawn as spheres coloured by their values on the same scale (``model`` layout): a cage's
        extraordinary vertices and their defects.

    Returns
    -------
    (height, width, 3) uint8

    Notes
    -----
    The 3-D views are pyvista off-screen renders; the page around them (tiles, titles, colour bar)
    is a matplotlib Agg figure, so the picture looks the same for one face or twenty.
    """
    mpl = require("matplotlib", "3-D heatmaps")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    if not maps:
        raise CadArtifactError("nothing to draw: no analysable face")
    check_option("direction", direction, DIRECTIONS)
    try:
        width, height = (int(x) for x in window_size)
    except (TypeError, ValueError):
        raise OptionError("window_size", "(width, height) in pixels", window_size) from None
    if not (64 <= width <= 8192 and 64 <= height <= 8192):
        raise OptionError("window_size", "width and height between 64 and 8192 pixels", tuple(window_size))
    layout = choose_layout(maps, layout)
    clim = colour_limits(maps, tol)
    unit = maps[0].net.unit

    dpi = 100
    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor="white")
    FigureCanvasAgg(fig)
    top = 0.93 if title else 0.98
    bar_left = 1.0 - 110 / width
    if layout == "model":
        img = _autocrop(_scene(maps, clim, tol, (width, height), show_net, len(maps) > 1, cmap, reflection,
                               markers), reflection=reflection)
        ax = fig.add_axes([0.01, 0.02, bar_left - 0.03, top - 0.03])
        ax.imshow(img)
        ax.set_axis_off()
    else:
        n = len(maps)
        cols = max(1, min(n, int(round(math.sqrt(n * (bar_left - 0.02) * width / ((top - 0.02) * height))))))
        rows = math.ceil(n / cols)
        cw, ch = (bar_left - 0.02) / cols, (top - 0.02) / rows
        tile = (max(64, int(cw * width)), max(64, int(ch * height)))
        for k, m in enumerate(maps):
            r, c = divmod(k, cols)
            ax = fig.add_axes([0.01 + c * cw, top - (r + 1) * ch, cw * 0.96, ch * 0.9])
            ax.imshow(_autocrop(_scene([m], clim, tol, tile, show_net, False, cmap, reflection), reflection=reflection))
            ax.set_axis_off()
            why = little_surface_reason(m)
            why = f"\n({why})" if why else ""
            ax.set_title(f"face {m.net.origin.face}: peak {number(m.peak)} {unit_text(unit)}{why}", fontsize=9, pad=2)
    cax = None if reflection else fig.add_axes([bar_left + 12 / width, 0.1, 18 / width, top - 0.2])
    top = None if reflection else upper_limit(maps, tol)
    if reflection:  # no colour scale: the stripes are the reflections of a light tunnel
        fig.text(bar_left + 4 / width, 0.5, "reflection\nlines",
                 fontsize=9, va="center")
    elif top is not None:  # two segments: 0..tolerance (colormap), tolerance..peak (reds), broken at the tolerance
        from matplotlib.colors import LinearSegmentedColormap, ListedColormap, TwoSlopeNorm

        reds = LinearSegmentedColormap.from_list("over", [ABOVE_COLOUR, PEAK_COLOUR])
        colours = ListedColormap(np.vstack([mpl.colormaps[cmap](np.linspace(0, 1, 256)),
                                            reds(np.linspace(0, 1, 256))]))
        sm = mpl.cm.ScalarMappable(norm=TwoSlopeNorm(vmin=clim[0], vcenter=tol, vmax=top), cmap=colours)
        bar = fig.colorbar(sm, cax=cax)
        bar.set_ticks([clim[0], tol / 2, tol, (tol + top) / 2, top])
        bar.set_ticklabels(["0", f"{tol / 2:.3g}", f"tol {tol:.3g}", f"{(tol + top) / 2:.3g}",
                            f"{top:.3g}"])
        bar.ax.axhline(tol, color="black", linewidth=1.5)
    else:
        colours = mpl.colormaps[cmap].with_extremes(over=ABOVE_COLOUR)
        sm = mpl.cm.ScalarMappable(norm=Normalize(*clim), cmap=colours)
        bar = fig.colorbar(sm, cax=cax, extend="max" if tol is not None else "neither")
    if not reflection:
        bar.set_label(label(direction, unit_text(unit)), fontsize=11)
        bar.ax.tick_params(labelsize=9)
        fig.legend(handles=legend_handles(maps, show_net), loc="lower right", fontsize=9, frameon=False)
    if title:
        fig.text(0.01, 0.985, title, ha="left", va="top", fontsize=12)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def legend_handles(maps, show_net: bool) -> list:
    """What the marks on the faces mean: the peak's magenta dot (faces with ripple) and the control net."""
    from matplotlib.lines import Line2D

    handles = []
    if any(m.peak > noise_floor(maps) for m in maps):
        handles.append(Line2D([], [], color="magenta", marker="o", linestyle="", label="peak of each face"))
    if show_net:
        handles.append(Line2D([], [], color="black", alpha=0.5, label="control net"))
    return handles


def _net_lines(nu: int, nv: int) -> np.ndarray:
    """VTK line cells along both parameter directions of a C-ordered ``(nu, nv)`` net."""
    idx = np.arange(nu * nv).reshape(nu, nv)
    rows = [np.concatenate([[nv], idx[i]]) for i in range(nu)]
    cols = [np.concatenate([[nu], idx[:, j]]) for j in range(nv)]
    return np.concatenate(rows + cols)


def _centre(m: FaceMap) -> np.ndarray:
    ok = np.isfinite(m.values)
    pts = m.points[ok] if ok.any() else m.points.reshape(-1, 3)
    return pts.mean(axis=0)


def png_bytes(image: np.ndarray) -> bytes:
    """PNG encoding of an ``(h, w, 3|4) uint8`` image."""
    import io

    mpl_image = require("matplotlib.image", "PNG encoding")
    buf = io.BytesIO()
    mpl_image.imsave(buf, image, format="png")
    return buf.getvalue()


def write_png(maps, out, **options) -> Path:
    """:func:`render_image` written to ``out`` atomically (options as there). Returns ``out``."""
    return write_atomic(Path(out), png_bytes(render_image(maps, **options)))


def export_glb(maps, out, *, tol: float | None = None, cmap: str = CMAP, direction: str | None = None) -> Path:
    """Write the faces as one glb scene (see :func:`cadartifact.viz.glb.export_glb`: metres, extras)."""
    from .glb import export_glb as _export

    return _export(maps, out, tol=tol, cmap=cmap, direction=direction)


def _check_out(option: str, path, suffix: str) -> Path:
    path = Path(path)
    if path.suffix.lower() != suffix:
        raise OptionError(option, f"a {suffix} file", str(path))
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OptionError(option, "a file in an existing folder", str(path))
    return path


def view(path, *, direction: str = "total", tol: float | None = None, out=None, glb=None, faces=None,
         scheme=None, window_size=DEFAULT_SIZE, show_net: bool = True, layout: str = "auto",
         progress=None, reflection: bool = False) -> ViewResult:
    """Heatmap picture (and optionally a glb) of a file's faces.

    Parameters
    ----------
    path : path-like
        STEP/IGES/BREP/OBJ file.
    direction : str
        One of :data:`DIRECTIONS`.
    tol : float, optional
        Colour scale 0..tol, then reds up to the peak.
    out : path-like, optional
        PNG to write; default ``<file stem>_<direction>.png`` in the current folder. ``False``: no PNG.
    glb : path-like, optional
        Also write the coloured meshes here.
    faces : iterable of int, optional
        Only these face indices.
    scheme : str or Scheme, optional
    window_size, show_net, layout
        As :func:`render_image`.
    progress : callable, optional
        ``progress(message)`` at each stage: the file read, each face's fields, the picture, the glb.
    reflection : bool
        Also write the faces' reflection lines (zebra stripes, :mod:`cadartifact.viz.reflection`) from the
        heatmap's camera and layout, beside the heatmap: ``<png stem>_reflection.png`` (with ``out=False``:
        ``<file stem>_reflection.png``).

    Returns
    -------
    ViewResult

    Raises
    ------
    OptionError
        Bad direction, tolerance, output path or face index (before anything is computed or written).
    CadArtifactError
        The file cannot be read or has no analysable face.
    """
    from ..exchange.load import read

    check_option("direction", direction, DIRECTIONS)
    check_option("layout", layout, LAYOUTS)  # every option before any work (and any progress line)
    if tol is not None:
        try:
            tol = float(tol)
        except (TypeError, ValueError):
            raise OptionError("tol", "a positive number of model units", tol) from None
        if not math.isfinite(tol) or tol <= 0:
            raise OptionError("tol", "a positive number of model units", tol)
    src = Path(path)
    png = None if out is False else _check_out("out", out if out is not None else f"{src.stem}_{direction}.png",
                                               ".png")
    glb_path = None if glb is None else _check_out("glb", glb, ".glb")
    if scheme is not None:
        from ..theory.catalogue import scheme as get_scheme

        scheme = get_scheme(scheme)
    res = read(src)
    nets = res.nets
    markers = None
    if getattr(res, "mesh", None) is not None and faces is None:  # a cage: its extraordinary vertices too
        from ..runs.cage_records import vertex_records

        verts = vertex_records(res.mesh, tol)
        markers = (np.array([v["position"] for v in verts], float).reshape(-1, 3), [v["defect"] for v in verts])
    if not nets:
        raise CadArtifactError(f"{src}: no analysable face to draw")
    if faces is not None:
        wanted = sorted(set(int(f) for f in faces))
        have = {n.origin.face for n in nets}
        missing = [f for f in wanted if f not in have]
        if missing:
            shown = ", ".join(str(f) for f in sorted(have)[:20]) + (", ..." if len(have) > 20 else "")
            raise OptionError("face", f"an analysable face index of {src.name} ({shown})", missing[0])
        nets = [n for n in nets if n.origin.face in wanted]
    say = progress or (lambda message: None)
    say(f"read {src}: {len(nets)} face{'' if len(nets) == 1 else 's'} to draw")
    maps = []
    for k, net in enumerate(nets, 1):
        maps += face_maps([net], direction, scheme)
        say(f"fields of face {net.origin.face} ({k}/{len(nets)})")
    peak = max(m.peak for m in maps)
    unit = unit_text(nets[0].unit)
    if png is not None:
        what = f"face {nets[0].origin.face}" if len(nets) == 1 else f"{len(nets)} faces"
        title = f"{src.name}  ({what}): {LABELS[direction]}, peak {number(peak)} {unit}"
        if tol is not None:
            title += f", tolerance {tol:g} {unit} (reds beyond it, darkest at the peak)"
        say(f"rendering {png}")
        if markers is not None and len(markers[1]):
            title += "; spheres: extraordinary vertices"
        write_png(maps, png, direction=direction, tol=tol, title=title, window_size=window_size, show_net=show_net,
                  layout=layout, markers=markers)
    zebra = None
    if reflection:
        zebra = (png.with_name(f"{png.stem}_reflection.png") if png is not None
                 else Path(f"{src.stem}_reflection.png"))
        what = f"face {nets[0].origin.face}" if len(nets) == 1 else f"{len(nets)} faces"
        say(f"rendering {zebra}")
        write_png(maps, zebra, direction=direction, title=f"{src.name}  ({what}): reflection lines", layout=layout,
                  window_size=window_size, reflection=True)
    if glb_path is not None:
        say(f"writing {glb_path}")
        export_glb(maps, glb_path, tol=tol, direction=direction)
    return ViewResult(png=png, glb=glb_path, direction=direction, peak=peak,
                      faces=tuple(n.origin.face for n in nets), reflection=zebra)
