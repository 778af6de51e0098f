"""Check a freeform CadQuery part for control-net ripple while it is modelled.

Run: python samples/cadquery_check.py [TOLERANCE_MM]   (default 0.002)

A 120 x 60 mm panel with a sharp ridge is built with ``Workplane.parametricSurface``
(OCCT fits a B-spline surface to the function), thickened into a solid, and checked
with the cadartifact hook in the middle of the chain: ``mode="warn"`` reports the worst
face and lets the chain go on (``mode="raise"`` would stop the script with exit code 1
semantics: ArtifactToleranceError). Then ``cadartifact.cq.report`` prints each face's
budget and the advised control net. OCCT fits the panel with a degree-6 net, whose surface is
smooth: its ripple is a few micrometres, so the default tolerance here is 2 um.
"""

from __future__ import annotations

import math
import sys
import warnings

import cadquery as cq

import cadartifact


def ridge_panel(u: float, v: float) -> tuple[float, float, float]:
    """A gentle dome with a narrow ridge across it (the ridge is what the net cannot follow)."""
    x, y = 120.0 * u, 60.0 * v
    dome = 4.0 * math.sin(math.pi * u) * math.sin(math.pi * v)
    ridge = 3.0 * math.exp(-(((x - 70.0) / 3.0) ** 2))
    return x, y, dome + ridge


def main(tol: float = 0.002) -> int:
    cadartifact.cq.register()  # adds Workplane.artifactCheck (same as .invoke(cadartifact.cq.check(...)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", cadartifact.cq.ArtifactToleranceWarning)
        part = (
            cq.Workplane("XY")
            .parametricSurface(ridge_panel, N=16, tol=0.02)
            .invoke(cadartifact.cq.check(tol=tol, mode="warn"))  # the chain goes on after a warning
        )
        solid = part.val().thicken(2.0)  # any modelling can follow
    for w in caught:
        print(f"warning: {w.message}")
    print(f"solid volume {solid.Volume():.0f} mm^3, {len(solid.Faces())} faces")

    rows = cadartifact.cq.report(part, tol=tol)
    print(f"\nper-face budget (tolerance {tol:g} mm, peak):")
    print(f"{'face':>4} {'net':>7} {'scheme':>13} {'method':>9} {'X1':>8} {'X2':>8} {'diag':>8} {'ripple':>8}  advised")
    for r in rows:
        b = r["budget"]
        net = "x".join(map(str, r["net"]))
        adv = "x".join(map(str, r["advice"]["net"]))
        verdict = "within" if r["meets_tolerance"] else "EXCEEDS"
        print(f"{r['face']:>4} {net:>7} {r['scheme']:>13} {r['method']:>9} {b['x1']['peak']:8.4f} "
              f"{b['x2']['peak']:8.4f} {b['diagonal']['peak']:8.4f} {b['total']['peak']:8.4f}  {adv} ({verdict})")
    return 0


if __name__ == "__main__":
    sys.exit(main(float(sys.argv[1]) if len(sys.argv) > 1 else 0.002))
