"""STEP files of known ripple for the gate's tests (tests/gate/test_gate.py, test_gate_advise.py): a sharp ridge
on a coarse bicubic net (clear ripple) and a saddle the bicubic reproduces exactly (no ripple on either road).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cadartifact.net import ControlNet, NetOrigin


def ridge_points(nu=14, nv=10, amp=2.0, width=9.0):
    """A sharp ridge along v on a coarse bicubic net: clear ripple."""
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    x, y = 100.0 * i / (nu - 1), 80.0 * j / (nv - 1)
    d = x - 50.0
    z = amp * np.where(np.abs(d) < width, 0.5 * (1 + np.cos(np.pi * d / width)), 0.0) ** 2
    return np.stack([x, y, z], axis=-1)


def clean_points(nu=8, nv=6):
    """A saddle sampled at the Greville abscissae: bilinear in the parameters, so the bicubic reproduces
    it exactly and its ripple is zero on both roads."""
    from cadartifact.net import clamped_uniform_knots, greville

    gu, gv = greville(clamped_uniform_knots(nu, 3), 3, nu), greville(clamped_uniform_knots(nv, 3), 3, nv)
    x, y = 70.0 * gu[:, None] + 0 * gv[None, :], 50.0 * gv[None, :] + 0 * gu[:, None]
    return np.stack([x, y, 0.002 * (x - 35) * (y - 25) + 0.1 * x], axis=-1)


def named(points, name, knots=None):
    net = ControlNet.from_points(points, degrees=(3, 3), origin=NetOrigin(name=name, kind="bspline"))
    if knots is not None:
        net = net.replace(knots=knots)
    return net


def write_models(root: Path) -> dict:
    """``ridge.step``, ``clean.step``, ``pair.step`` (both faces) and ``broken.step`` in ``root``; returns
    ``{"root": root, "value": the ridge face's ripple (budget total peak)}``."""
    import cadartifact as ca
    from cadartifact.exchange.load import write_step

    ridge, clean = named(ridge_points(), "ridge"), named(clean_points(), "dome")
    write_step([ridge], root / "ridge.step")
    write_step([clean], root / "clean.step")
    write_step([clean, ridge], root / "pair.step")
    (root / "broken.step").write_text("ISO-10303-21;\nHEADER;\nthis is not a STEP file\n")
    value = ca.budget(ca.load(root / "ridge.step")[0]).stats["total"].peak
    clean_value = ca.budget(ca.load(root / "clean.step")[0]).stats["total"].peak
    assert value > 1e-3 and clean_value < 1e-6 * value
    return {"root": root, "value": value}
