"""Build the sample files in this folder (deterministic; run from anywhere).

    python samples/make_samples.py

Each STEP file holds one named B-spline face (names become ``ADVANCED_FACE`` names
and read back as ``origin.name``); ``cage.obj`` is a small Catmull-Clark quad cage.
The nets are sampled from closed-form shapes so tests can check the files are what
they claim:

- ``wavy_panel_diagonal.step``: 12x12 bicubic over 100x100 mm, z = h exp(-((x-y)/w)^2),
  h = 8 mm, w = 9 mm (about one control spacing, 100/11 mm): a ridge running diagonally
  to the grid on a coarse net, the paper's Figure 1 case.
- ``hull_freeform.step``: 16x8 bicubic hull-like face (length 1000 mm, keel to deck).
- ``car_hood_coarse.step``: 8x6 bicubic hood (1200x900 mm dome) with a swage line along x that
  only one row of control points carries (a 12 mm crease on the row at y = 360 mm, 180 mm
  spacing): the net is far too coarse for the feature it has to shape, so it ripples.
- ``clean_panel.step``: 10x10 bicubic, a twisted plane (z bilinear in x and y) sampled at the
  control points' Greville abscissae: the bicubic reproduces it, so it carries no ripple.
- ``cage.obj``: 8x8-vertex grid with a bump, one 3x3-quad corner removed (an L shape,
  whose inner corner is an irregular boundary vertex of valence 4), and an OpenSubdiv tag.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from cadartifact.net import ControlNet, NetOrigin  # noqa: E402

FIXED_STAMP = "2025-01-01T00:00:00"


def grid(nu: int, nv: int, width: float, depth: float) -> tuple[np.ndarray, np.ndarray]:
    """Uniform control-point positions ``x (nu, nv)``, ``y (nu, nv)`` over ``[0, width] x [0, depth]``."""
    x, y = np.meshgrid(np.linspace(0.0, width, nu), np.linspace(0.0, depth, nv), indexing="ij")
    return x, y


def wavy_panel() -> ControlNet:
    x, y = grid(12, 12, 100.0, 100.0)
    z = 8.0 * np.exp(-(((x - y) / 9.0) ** 2))
    return ControlNet.from_points(np.stack([x, y, z], -1), (3, 3),
                                  origin=NetOrigin(name="wavy_panel_diagonal", kind="bspline"))


def hull() -> ControlNet:
    nu, nv, length, beam, draft = 16, 8, 1000.0, 180.0, 120.0
    s = np.linspace(0.0, 1.0, nu)[:, None]           # along the length
    t = np.linspace(0.0, 0.5 * np.pi, nv)[None, :]   # keel (0) to deck (pi/2)
    fullness = np.sqrt(np.clip(1.0 - (2.0 * s - 1.0) ** 4, 0.0, None)) * (0.35 + 0.65 * np.sin(np.pi * s) ** 0.5)
    half_breadth = 0.5 * beam * (0.08 + 0.92 * fullness)
    x = length * s + 0.0 * t
    y = half_breadth * np.sin(t)
    z = -draft * (0.15 + 0.85 * fullness) * np.cos(t) + 25.0 * (2.0 * s - 1.0) ** 2  # sheer rises at the ends
    return ControlNet.from_points(np.stack([x, y, z], -1), (3, 3), origin=NetOrigin(name="hull_freeform", kind="bspline"))


def car_hood() -> ControlNet:
    x, y = grid(8, 6, 1200.0, 900.0)
    xi, eta = x / 1200.0 - 0.5, y / 900.0 - 0.5
    dome = 60.0 * (1.0 - 1.6 * xi**2 - 2.0 * eta**2) + 40.0 * xi
    swage = 12.0 * np.clip(1.0 - np.abs(y - 360.0) / 40.0, 0.0, None)  # crease-like line along x, on the y = 360 row
    return ControlNet.from_points(np.stack([x, y, dome + swage], -1), (3, 3),
                                  origin=NetOrigin(name="car_hood_coarse", kind="bspline"))


def clean_panel() -> ControlNet:
    from cadartifact.net import clamped_uniform_knots, greville

    # the points sample a twisted plane (bilinear in x and y) at their Greville abscissae: the bicubic
    # reproduces it exactly, so neither road sees any ripple
    knots = clamped_uniform_knots(10, 3)
    g = greville(knots, 3, 10)
    x, y = np.meshgrid(200.0 * g, 150.0 * g, indexing="ij")
    z = 0.0015 * (x - 100.0) * (y - 75.0) + 0.04 * x - 0.02 * y
    return ControlNet(points=np.stack([x, y, z], -1), degrees=(3, 3), knots=(knots, knots),
                      origin=NetOrigin(name="clean_panel", kind="bspline"))


def cage_obj() -> str:
    n, removed = 8, 3  # vertices per side; quads removed from the (+x, +y) corner
    lines = ["# cadartifact sample: 8x8-vertex quad cage with a bump, an L-shaped outline",
             "# (the inner corner is an irregular boundary vertex) and an OpenSubdiv tag"]
    ids = {}
    for i in range(n):
        for j in range(n):
            if i > n - 1 - removed and j > n - 1 - removed:
                continue  # vertices only used by the removed quads
            x, y = 10.0 * i, 10.0 * j
            z = 6.0 * np.exp(-((x - 30.0) ** 2 + (y - 30.0) ** 2) / 200.0)
            ids[i, j] = len(ids) + 1
            lines.append(f"v {x:.6f} {y:.6f} {z:.6f}")
    for i in range(n - 1):
        for j in range(n - 1):
            if i >= n - 1 - removed and j >= n - 1 - removed:
                continue
            a, b, c, d = ids[i, j], ids[i + 1, j], ids[i + 1, j + 1], ids[i, j + 1]
            lines.append(f"f {a} {b} {c} {d}")
    lines.append("t interpolateboundary 1/0/0 1")
    return "\n".join(lines) + "\n"


def write_step_deterministic(net: ControlNet, path: Path) -> None:
    from cadartifact.exchange.load import write_step

    write_step([net], path)
    text = path.read_text()
    # OCCT stamps the time of writing into the header: fix it so reruns give identical files
    text = re.sub(r"(FILE_NAME\('[^']*',)'[^']*'", rf"\1'{FIXED_STAMP}'", text, count=1)
    path.write_text(text)


def main(out: Path = HERE) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, build in (("wavy_panel_diagonal", wavy_panel), ("hull_freeform", hull),
                        ("car_hood_coarse", car_hood), ("clean_panel", clean_panel)):
        path = out / f"{name}.step"
        write_step_deterministic(build(), path)
        written.append(path)
    path = out / "cage.obj"
    path.write_text(cage_obj())
    written.append(path)
    return written


if __name__ == "__main__":
    for p in main(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE):
        print(f"wrote {p} ({p.stat().st_size} bytes)")
