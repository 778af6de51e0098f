"""glb export of the heatmaps: one triangle mesh per face with vertex colours, in metres, with extras."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..dependencies import require
from ..errors import CadArtifactError
from .facemaps import CMAP, cells, colour_limits, unit_text, upper_limit, vertex_colours, write_atomic

__all__ = ["GLB_SCALE", "export_glb"]


def export_glb(maps, out, *, tol: float | None = None, cmap: str = CMAP, direction: str | None = None) -> Path:
    """Write the faces as one glb scene of triangle meshes with vertex colours (trimesh).

    Parameters
    ----------
    maps : list of FaceMap
    out : path-like
        ``.glb`` file, written atomically.
    tol : float, optional
        Colour scale 0..tol with the red segment beyond (as the picture), else 0..largest peak.
    direction : str, optional
        The field drawn (one of :data:`DIRECTIONS`), recorded in the extras.

    Returns
    -------
    Path
        One mesh per face, named ``face_<index>``; each quad of the fine grid is two triangles.

    Notes
    -----
    glTF coordinates are metres: faces in mm are scaled by 1e-3 (a 5.5 m hull is 5.5 m wide in a
    viewer); OBJ cages in model units are written as they are. Vertices outside the trimmed face
    (used by no triangle) are dropped. The scene's glTF ``extras`` hold the field drawn, its units,
    the tolerance and the peak (in the file's units, as the reports), and the coordinate scale;
    each mesh's ``extras`` its face index, name and peak.
    """
    trimesh = require("trimesh", "glb export")
    if not maps:
        raise CadArtifactError("nothing to export: no analysable face")
    clim = colour_limits(maps, tol)
    unit = maps[0].net.unit
    scale = GLB_SCALE.get(unit, 1.0)
    scene = trimesh.Scene()
    for m in maps:
        pts, vals, quads = cells(m)
        if len(quads) == 0:
            continue
        tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
        used = np.unique(tris)  # vertices of cells outside the trim carry no triangle
        remap = np.full(len(pts), -1)
        remap[used] = np.arange(len(used))
        mesh = trimesh.Trimesh(vertices=np.asarray(pts)[used] * scale, faces=remap[tris],
                               vertex_colors=vertex_colours(np.asarray(vals)[used], clim, cmap,
                                                            upper_limit(maps, tol)), process=False)
        mesh.metadata.update({"face": m.net.origin.face, "name": m.net.origin.name, "peak": float(m.peak)})
        name = f"face_{m.net.origin.face}"
        scene.add_geometry(mesh, node_name=name, geom_name=name)
    scene.metadata.update({
        "generator": "cadartifact", "field": direction, "units": unit_text(unit),
        "coordinates": "m" if unit in GLB_SCALE else unit_text(unit), "coordinate_scale": scale,
        "tolerance": None if tol is None else float(tol), "peak": float(max(m.peak for m in maps)),
        "colour_scale": [float(clim[0]), float(clim[1])],
    })
    return write_atomic(Path(out), scene.export(file_type="glb"))


#: glTF is in metres: the factor from a file's unit to metres (units not listed are written as they are).
GLB_SCALE = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "in": 0.0254}
