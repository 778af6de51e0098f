"""Synthetic STEP files of the kinds the real files in the issues had and ../shared/realdata lacks (issue 24).

Run:  python benchmarks/synthetic_faces.py OUT_DIR      (the benchmarks call :func:`write_all` themselves)

* ``extended_jointed.step``: 6 clamped cubic faces (11-17 x 9-15 points) sampling smooth shapes, each
  surface extended by 1-5 % past its region on two to four sides along its end tangents, the extension bent a
  little (a crease: knots of multiplicity 3 at the joins), the face bounded by the original region, by the
  region plus 1e-9 (rounding), or a third of the way into the extension. The kind of the 5.5 m hull's
  faces 147, 149 and 151 (issue 23).
* ``nonuniform_shell.step``: 40 cubic faces of 8-16 points with non-uniform interior knots (spacing
  ratios up to 3), a freeform shell like the consumer-product one of issue 24.
* ``quintic_45x12.step``: one 45x12 quintic face (degree 5 both ways), uniform knots.

Seeded: the same files on every run.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np


def _clamped(n: int, p: int, interior=None) -> np.ndarray:
    k = np.linspace(0, 1, n - p + 1)[1:-1] if interior is None else np.asarray(interior, float)
    return np.concatenate([np.zeros(p + 1), k, np.ones(p + 1)])


def _shape(u, v, rng) -> np.ndarray:
    """Smooth known shape on [0, 1]^2, in mm (a 400 x 300 mm panel with cosines and a bump)."""
    a, b, c = rng.uniform(0.5, 2.0, 3)
    z = 8 * np.cos(np.pi * (a * u + 0.5 * b * v) + c) + 5 * np.exp(-((u - 0.4) ** 2 + (v - 0.6) ** 2) / 0.05)
    return np.stack([400 * u, 300 * v + 20 * u * v, z], axis=-1)


def _extend_axis(P: np.ndarray, t: np.ndarray, p: int, axis: int, ext: tuple[float, float], bend: float):
    """The net extended past each end of ``axis`` (``ext``: fractions of the range, 0 = none) by one Bezier
    span joined with multiplicity ``p`` (C0), along the end tangent, bent by ``bend`` of its length."""
    P = np.moveaxis(P, axis, 0)
    parts, knots = [P], list(t)
    for side, e in ((0, ext[0]), (1, ext[1])):
        if e <= 0:
            continue
        end = P[0] if side == 0 else P[-1]
        inner = P[1] if side == 0 else P[-2]
        tangent = (end - inner) * (e * (len(P) - p) / 1.0)  # one span of the net is about 1/(n - p)
        normal = np.zeros_like(end)
        normal[..., 2] = bend * np.linalg.norm(tangent, axis=-1)
        new = [end + tangent * (j / p) + normal * (j / p) ** 2 for j in range(1, p + 1)]
        if side == 0:
            parts.insert(0, np.stack(new[::-1]))
            knots = [knots[0] - e] * (p + 1) + knots[1:]  # the old end knot (p+1 times) becomes a p-fold join
        else:
            parts.append(np.stack(new))
            knots = knots[:-1] + [knots[-1] + e] * (p + 1)
    return np.moveaxis(np.concatenate(parts), 0, axis), np.array(knots)


def extended_jointed_nets(seed: int = 24):
    import cadartifact as ca

    rng = np.random.default_rng(seed)
    nets = []
    for k in range(6):
        nu, nv, p = int(rng.integers(11, 18)), int(rng.integers(9, 16)), 3
        tu, tv = _clamped(nu, p), _clamped(nv, p)
        from cadartifact.net import greville

        gu, gv = greville(tu, p, nu), greville(tv, p, nv)
        P = _shape(*np.meshgrid(gu, gv, indexing="ij"), rng)
        sides = rng.uniform(0.01, 0.05, 4) * (rng.random(4) < 0.75)
        sides[k % 4] = max(sides[k % 4], 0.02)  # at least one side extended
        bend = float(rng.uniform(0.0, 0.15))
        P, tu = _extend_axis(P, tu, p, 0, (sides[0], sides[1]), bend)
        P, tv = _extend_axis(P, tv, p, 1, (sides[2], sides[3]), bend)
        trim = ("region", "rounding", "into")[k % 3]
        past = {"region": 0.0, "rounding": 1e-9}.get(trim)
        bounds = []
        for lo, hi, e0, e1 in ((0.0, 1.0, sides[0], sides[1]), (0.0, 1.0, sides[2], sides[3])):
            if past is None:  # a third of the way into each extension
                bounds += [lo - e0 / 3, hi + e1 / 3]
            else:
                bounds += [lo - (past if e0 > 0 else 0.0), hi + (past if e1 > 0 else 0.0)]
        nets.append(ca.ControlNet(points=P, degrees=(p, p), knots=(tu, tv), uv_bounds=tuple(bounds),
                                  unit="mm"))
    return nets


def nonuniform_shell_nets(seed: int = 40, count: int = 40):
    import cadartifact as ca

    rng = np.random.default_rng(seed)
    nets = []
    for k in range(count):
        nu, nv, p = int(rng.integers(8, 17)), int(rng.integers(8, 17)), 3
        knots = []
        for n in (nu, nv):
            gaps = rng.uniform(1.0, 3.0, n - p)
            inner = np.cumsum(gaps)[:-1] / gaps.sum()
            knots.append(_clamped(n, p, inner))
        from cadartifact.net import greville

        gu, gv = greville(knots[0], p, nu), greville(knots[1], p, nv)
        P = _shape(*np.meshgrid(gu, gv, indexing="ij"), rng)
        P[..., 0] += 420 * (k % 8)  # tiles of a shell, side by side
        P[..., 1] += 320 * (k // 8)
        nets.append(ca.ControlNet(points=P, degrees=(p, p), knots=tuple(knots), unit="mm"))
    return nets


def quintic_nets(seed: int = 45):
    import cadartifact as ca

    rng = np.random.default_rng(seed)
    nu, nv, p = 45, 12, 5
    tu, tv = _clamped(nu, p), _clamped(nv, p)
    from cadartifact.net import greville

    P = _shape(*np.meshgrid(greville(tu, p, nu), greville(tv, p, nv), indexing="ij"), rng)
    P[..., 0] *= 4  # a long face: 1.6 m by 0.3 m
    return [ca.ControlNet(points=P, degrees=(p, p), knots=(tu, tv), unit="mm")]


def write_all(folder) -> list[Path]:
    """Write the three files into ``folder``; their paths."""
    import cadartifact as ca

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for name, nets in (("extended_jointed.step", extended_jointed_nets()),
                       ("nonuniform_shell.step", nonuniform_shell_nets()),
                       ("quintic_45x12.step", quintic_nets())):
        out.append(ca.write_step(nets, folder / name))
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__.splitlines()[2])
    for path in write_all(sys.argv[1]):
        print(path)
