"""Quad cages with one extraordinary vertex of a chosen valence, sampling known surfaces.

A *fan cage* is ``n`` sectors of ``m x m`` quads meeting at a centre vertex (valence ``n``), laid
out in the plane around the origin (sector ``j`` spans the directions ``2 pi j / n`` to
``2 pi (j + 1) / n``; a *boundary* fan spans a half plane, its ``n`` sectors ``pi / n`` wide, so the
centre is a boundary vertex of valence ``n + 1``). Every other interior vertex is regular. The plane
is then mapped onto a surface: a plane, a sphere, a cylinder or a torus (the vertices lie on it).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fan_cage", "cube_cage", "SURFACES", "write_obj"]


def _plane(p):
    # a tilted plane: z = 0.3 x - 0.2 y + 0.1
    return np.stack([p[:, 0], p[:, 1], 0.3 * p[:, 0] - 0.2 * p[:, 1] + 0.1], axis=1)


def _sphere(p, R=2.0):
    r = np.linalg.norm(p, axis=1)
    s = np.where(r > 0, np.sin(r / R) / np.where(r > 0, r, 1), 1 / R)
    return R * np.stack([s * p[:, 0], s * p[:, 1], np.cos(r / R)], axis=1)


def _cylinder(p, R=1.5):
    return np.stack([R * np.sin(p[:, 0] / R), p[:, 1], R * np.cos(p[:, 0] / R)], axis=1)


def _torus(p, R=3.0, r=1.0):
    u, v = p[:, 0] / R, p[:, 1] / r
    return np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], axis=1)


#: name -> map of (k, 2) plane points onto (k, 3) points of the surface (plane: tilted; sphere radius 2;
#: cylinder radius 1.5; torus radii 3 and 1).
SURFACES = {"plane": _plane, "sphere": _sphere, "cylinder": _cylinder, "torus": _torus}


def fan_cage(n: int, m: int = 4, surface: str = "plane", boundary: bool = False, radius: float = 1.0):
    """A fan cage: ``n`` sectors of ``m x m`` quads around vertex 0, mapped onto ``surface``.

    Parameters
    ----------
    n : int
        Sectors (quads at the centre): the centre's valence when interior, valence - 1 on a boundary.
    m : int
        Quads along each sector's side.
    surface : str
        A key of :data:`SURFACES`.
    boundary : bool
        The fan spans a half plane (the centre on the boundary).
    radius : float
        The sectors' side length in the plane.

    Returns
    -------
    vertices : (k, 3) float
    faces : list of tuple of int
        Counter-clockwise seen from +z in the plane.
    """
    span = np.pi if boundary else 2 * np.pi
    arms = n + 1 if boundary else n
    d = [np.array([np.cos(span * j / n), np.sin(span * j / n)]) for j in range(arms)]
    ids: dict = {}
    pts = []

    def vid(j, a, b):
        # (a, b) in sector j; points on a sector's arms are shared with the neighbouring sector
        if a == 0 and b == 0:
            key = ("c",)
        elif b == 0:
            key = ("arm", j % arms, a)
        elif a == 0:
            key = ("arm", (j + 1) % arms, b)
        else:
            key = ("in", j, a, b)
        if key not in ids:
            ids[key] = len(pts)
            pts.append(radius * (a * d[j % arms] + b * d[(j + 1) % arms]) / m)
        return ids[key]

    faces = []
    for j in range(n):
        for a in range(m):
            for b in range(m):
                faces.append((vid(j, a, b), vid(j, a + 1, b), vid(j, a + 1, b + 1), vid(j, a, b + 1)))
    return SURFACES[surface](np.array(pts)), faces


def write_obj(path, vertices, faces) -> None:
    """Write ``vertices`` and polygon ``faces`` (0-based) as an OBJ file."""
    with open(path, "w") as f:
        for v in np.asarray(vertices, float):
            f.write("v {!r} {!r} {!r}\n".format(*map(float, v)))
        for face in faces:
            f.write("f " + " ".join(str(i + 1) for i in face) + "\n")


def cube_cage(n: int = 3):
    """A closed cube cage of ``n x n`` quads per side on ``[-1, 1]^3``, faces wound outwards.

    Returns
    -------
    vertices : (m, 3) float
        Shared corners (each grid point once: valence 3 at the cube's 8 corners, 4 elsewhere).
    faces : list of (4,) tuple of int
    """
    verts, index, faces = [], {}, []

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]

    t = np.linspace(-1, 1, n + 1)
    for axis in range(3):
        for sign in (-1, 1):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis] = sign
                        p[(axis + 1) % 3], p[(axis + 2) % 3] = t[i + di], t[j + dj]
                        quad.append(vid(p))
                    faces.append(tuple(quad) if sign > 0 else tuple(quad[::-1]))
    return np.array(verts), faces

