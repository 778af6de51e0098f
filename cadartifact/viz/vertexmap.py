"""A cage's extraordinary vertices on its limit surface: each vertex's faces coloured by its shape defect
(:mod:`cadartifact.analysis.extraordinary`) on the heatmaps' scale (0 .. tolerance, reds beyond), the rest
of the surface grey, a sphere at each vertex labelled with its valence and defect.

pyvista and matplotlib are imported lazily; rendering is off screen as in :mod:`.view`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..dependencies import require
from .facemaps import CMAP, number, vertex_colours, write_atomic

__all__ = ["limit_mesh", "defect_values", "render_vertex_defects", "write_vertex_png"]


def limit_mesh(mesh, steps: int = 3):
    """The cage's limit surface as quads: ``steps`` Catmull-Clark steps, then the limit stencil.

    Returns
    -------
    points : (n, 3) float
    quads : (f, 4) int
    ancestor : (f,) int
        The cage's face each quad lies in.
    """
    from ..numerics.catmull_clark import limit_stencil, subdivision_step

    P = np.asarray(mesh.vertices, float)
    F = [tuple(f) for f in mesh.faces]
    creases = {(min(a, b), max(a, b)): float(s) for (a, b), s in
               zip(np.asarray(mesh.crease_edges).tolist(), np.asarray(mesh.crease_sharpness).tolist()) if s > 0}
    ancestor = np.arange(len(F))
    for _ in range(steps):
        S, quads, parent, creases = subdivision_step(len(P), F, creases)
        P, F, ancestor = S @ P, quads.tolist(), ancestor[parent]
    quads = np.asarray(F, int)
    return np.asarray(limit_stencil(len(P), quads, creases) @ P), quads, ancestor


def defect_values(mesh, records, ancestor: np.ndarray) -> np.ndarray:
    """Per quad of :func:`limit_mesh`: the largest defect of the extraordinary vertices of its cage face
    (a face centre's record covers its face), NaN for faces without one."""
    worst = np.full(len(mesh.faces), np.nan)
    for r in records:
        faces = [r["face"]] if r["face"] is not None else [k for k, f in enumerate(mesh.faces) if r["vertex"] in f]
        for k in faces:
            worst[k] = np.fmax(worst[k], r["defect"])
    return worst[ancestor]


def render_vertex_defects(mesh, records, *, tol: float | None = None, title: str | None = None,
                          window_size=(1200, 800), steps: int = 3) -> np.ndarray:
    """The picture: limit surface, each extraordinary vertex's faces coloured by its defect, labelled spheres.

    Parameters
    ----------
    mesh : QuadMesh
    records : list of dict
        :func:`cadartifact.runs.cage_records.vertex_records` of ``mesh``.
    tol : float, optional
        Colour scale 0 .. tol, then reds up to the largest defect; default 0 .. the largest defect.
    title : str, optional
    window_size : (int, int)
    steps : int
        Subdivision steps of the drawn surface.

    Returns
    -------
    (height, width, 3) uint8
    """
    pv = require("pyvista", "3-D pictures")
    mpl = require("matplotlib", "3-D pictures")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    from .view import _autocrop, _quiet_vtk

    pts, quads, ancestor = limit_mesh(mesh, steps)
    values = defect_values(mesh, records, ancestor)
    peak = max((r["defect"] for r in records), default=0.0)
    hi = tol if tol is not None else (peak if peak > 0 else 1.0)
    clim = (0.0, hi)
    top = peak if tol is not None and peak > tol else None  # reds from the tolerance up to the worst
    width, height = (int(x) for x in window_size)
    with _quiet_vtk():
        plotter = pv.Plotter(off_screen=True, window_size=(width, height))
        try:
            plotter.set_background("white")
            surf = pv.PolyData(pts, np.hstack([np.full((len(quads), 1), 4), quads]).ravel())
            surf.cell_data["rgb"] = vertex_colours(values, clim, CMAP, top)[:, :3]
            plotter.add_mesh(surf, scalars="rgb", rgb=True, show_scalar_bar=False, smooth_shading=False)
            if records:
                at = np.array([r["position"] for r in records], float)
                spheres = pv.PolyData(at)
                spheres.point_data["rgb"] = vertex_colours(np.array([r["defect"] for r in records]), clim, CMAP,
                                                           top)[:, :3]
                plotter.add_mesh(spheres, scalars="rgb", rgb=True, point_size=16, render_points_as_spheres=True,
                                 show_scalar_bar=False)
                labels = [f"{r['valence']}: {number(r['defect'])}" for r in records]
                plotter.add_point_labels(at, labels, font_size=12, point_size=1, shape_opacity=0.6,
                                         always_visible=True)
            plotter.view_isometric()
            plotter.reset_camera()
            img = _autocrop(plotter.screenshot(None, return_img=True))
        finally:
            plotter.close()
    dpi = 100
    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor="white")
    FigureCanvasAgg(fig)
    top_y = 0.93 if title else 0.98
    bar_left = 1.0 - 110 / width
    ax = fig.add_axes([0.01, 0.02, bar_left - 0.03, top_y - 0.03])
    ax.imshow(img)
    ax.set_axis_off()
    cax = fig.add_axes([bar_left + 12 / width, 0.1, 18 / width, top_y - 0.2])
    if top is not None:
        from matplotlib.colors import LinearSegmentedColormap, ListedColormap, TwoSlopeNorm

        from .facemaps import ABOVE_COLOUR, PEAK_COLOUR

        reds = LinearSegmentedColormap.from_list("over", [ABOVE_COLOUR, PEAK_COLOUR])
        colours = ListedColormap(np.vstack([mpl.colormaps[CMAP](np.linspace(0, 1, 256)), reds(np.linspace(0, 1, 256))]))
        bar = fig.colorbar(mpl.cm.ScalarMappable(norm=TwoSlopeNorm(vmin=0.0, vcenter=tol, vmax=top), cmap=colours),
                           cax=cax)
        bar.set_ticks([0.0, tol / 2, tol, top])
        bar.set_ticklabels(["0", f"{tol / 2:.3g}", f"tol {tol:.3g}", f"{top:.3g}"])
    else:
        bar = fig.colorbar(mpl.cm.ScalarMappable(norm=Normalize(*clim), cmap=mpl.colormaps[CMAP]), cax=cax)
    bar.set_label("extraordinary-vertex defect [model units]", fontsize=11)
    bar.ax.tick_params(labelsize=9)
    if title:
        fig.text(0.01, 0.985, title, ha="left", va="top", fontsize=12)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def write_vertex_png(path, out, *, tol: float | None = None, window_size=(1200, 800)) -> Path:
    """Read an OBJ cage and write :func:`render_vertex_defects` of it to ``out`` (PNG). Returns ``out``."""
    from ..exchange.obj import read_obj
    from ..runs.cage_records import vertex_records
    from .view import png_bytes

    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a cage without charts is still drawn
        mesh = read_obj(path).mesh
    records = vertex_records(mesh, tol)
    title = (f"{Path(path).name}: {len(records)} extraordinary vertices, label valence: defect"
             + (f", tolerance {tol:g} model units (reds beyond it)" if tol is not None else ""))
    img = render_vertex_defects(mesh, records, tol=tol, title=title, window_size=window_size)
    return write_atomic(Path(out), png_bytes(img))
