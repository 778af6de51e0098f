"""Issue 10 on the real STEP files: invariance under re-expression, plausibility, the largest peaks explained.

Re-expressions are OCCT's (knot insertion, degree elevation, multiplicity raised to the degree); the
budgets are cadartifact's. Files are read in place from ``../shared/realdata/step``.
"""

from __future__ import annotations


import numpy as np
import pytest

import cadartifact as ca

pytest.importorskip("OCP")

from cadartifact.exchange.load import read  # noqa: E402
from cadartifact.exchange.occ import net_from_surface, occ_surface  # noqa: E402
from cadartifact.testing.paths import REAL_STEP

STEP = sorted(REAL_STEP.glob("*"))
pytestmark = [pytest.mark.realdata, pytest.mark.slow]  # every real file read and analysed

DIRECTIONS = ("total", "x1", "x2", "diagonal", "lateral")


def size_of(net) -> float:
    return float(np.linalg.norm(np.ptp(net.points.reshape(-1, 3), axis=0)))


def unique_faces():
    """Every B-spline face of every real file, one per distinct net (patterned features repeat faces)."""
    out, seen = [], set()
    for path in STEP:
        for net in read(path).nets:
            key = (path.name, net.shape, net.points.round(9).tobytes()[:4096], net.knots[0].tobytes())
            if key not in seen:
                seen.add(key)
                out.append((path.name, net))
    return out


@pytest.fixture(scope="module")
def faces():
    return unique_faces()


def reexpressed(net):
    """OCCT's re-expressions of the same surface with more control points."""
    out = {}
    s = occ_surface(net)
    ku = [s.UKnot(i) for i in range(1, s.NbUKnots() + 1)]
    kv = [s.VKnot(i) for i in range(1, s.NbVKnots() + 1)]
    for a, b in zip(ku[:-1], ku[1:]):
        s.InsertUKnot((a + b) / 2, 1, 1e-12, True)
    for a, b in zip(kv[:-1], kv[1:]):
        s.InsertVKnot((a + b) / 2, 1, 1e-12, True)
    out["knot insertion at every span's midpoint"] = s
    s = occ_surface(net)
    s.IncreaseDegree(net.degrees[0] + 1, net.degrees[1] + 1)
    out["degree elevation by one"] = s
    s = occ_surface(net)
    for i in range(1, s.NbUKnots() + 1):
        if 1 < i < s.NbUKnots() or s.IsUPeriodic():
            s.IncreaseUMultiplicity(i, net.degrees[0])
    for i in range(1, s.NbVKnots() + 1):
        if 1 < i < s.NbVKnots() or s.IsVPeriodic():
            s.IncreaseVMultiplicity(i, net.degrees[1])
    out["Bezier patches (every knot to multiplicity p)"] = s
    return {k: net_from_surface(v, origin=net.origin, uv_bounds=net.uv_bounds) for k, v in out.items()}


@pytest.mark.slow
def test_re_expressing_a_real_face_with_more_points_never_raises_its_ripple(faces):
    """SPEC §4 invariance on every real face: more control points for the same surface never raise the reported
    ripple peak by more than 1e-9 of the face's size (knot insertion and Bezier splitting: no direction rises
    either; degree elevation: the total)."""
    worst = {}
    for name, net in faces:
        before = ca.budget(net).stats
        scale = size_of(net)
        for how, more in reexpressed(net).items():
            assert more.size > net.size or how.startswith("Bezier")
            after = ca.budget(more).stats
            keys = ("total",) if how.startswith("degree") else DIRECTIONS
            for k in keys:
                rise = (after[k].peak - before[k].peak) / scale
                worst[how] = max(worst.get(how, -np.inf), rise)
                assert rise <= 1e-9, f"{name} face {net.origin.face}: {how} raises {k} {before[k].peak:.4g} -> {after[k].peak:.4g}"
    assert len(worst) == 3


# ---------------------------------------------------------------- plausibility
#: Largest ripple peak of any real face, as a share of its size (the diagonal of its control net's box).
#: Found: 0.55 % (linkrods face 36, a 3 mm blend strip of three spans; 0.26 % before the fifth-order bridge of
#: 2026-12-03). The bound is twice the
#: largest found: a misreading of the kind issue 10 reported (a 129 mm "ripple" on a fuselage skin, 446 % on a
#: ruled face) is orders of magnitude above it.
PLAUSIBLE_SHARE = 0.011


@pytest.fixture(scope="module")
def all_budgets():
    out = []
    for path in STEP:
        for net in read(path).nets:
            out.append((path.name, net, ca.budget(net, tolerance=0.05)))
    return out


def test_every_real_face_ripples_by_a_small_fraction_of_its_size(all_budgets):
    assert len(all_budgets) == 108
    for name, net, b in all_budgets:
        assert b.stats["total"].peak <= PLAUSIBLE_SHARE * size_of(net), f"{name} face {net.origin.face}"
    # and at 0.05 mm every real face passes: the largest ripple is 0.0156 mm
    assert max(b.stats["total"].peak for _, _, b in all_budgets) < 0.05 * 0.4


#: The faces carrying the ten largest ripple peaks over all real files: (file, faces) -> (peak in mm, the
#: direction carrying it, ...). Patterned copies of one face (same net, moved) are listed together.
EXPLAINED = {
    ("linkrods.step", (23, 36)): (
        (0.005813, 0.006231), "x1",
        "Two 6x2 faces, cubic along u with 3 uneven spans (0.76/1.52/0.72 and 0.98/1.37/0.65 of the mean), "
        "straight (degree 1, recognised 'extruded: straight in v') across: a 3 mm wide blend strip of the "
        "Euclid-exported link rod. The cubic's uneven knots put third-derivative jumps at two interior knots that "
        "no placement of its 6 points can smooth away: 0.0062 and 0.0058 mm, 0.2 % of the strip's width, "
        "all along u (x1), none across (straight) and none diagonal. On three spans the reading is mostly the "
        "split's continuation past the borders: 0.0136 and 0.0156 mm with the continuation over twice the strip "
        "(before 2026-12-05), 0.0072 mm each with the third-order bridge; their midpoint re-expressions read 0.0005 "
        "and 0.0009: docs/model.md)."),
    ("linkrods.step", (33,)): (
        (0.007026, 0.007026), "x2",
        "A 7x275 rational face, 46 mm: one degree-6 Bezier span across u (no ripple), degree 10 along v with 31 "
        "distinct knots, many of them multiple, crowded near one end (spans down to 1e-3 of the range). The "
        "ripple peaks in v's first span, at a border, and moves with the continuation there (0.0084 mm with the "
        "continuation over twice the face, 0.0013 mm with the third-order bridge): 0.015 % of the face's size."),
    ("nist_ctc_02_asme1_ap242-1.stp", (35, 361)): (
        (0.006255, 0.006255), "x1",
        "Two closed (periodic) rational cubic 18x3 faces, swept circular in v (recognised 'swept: circular in v'), "
        "with one knot of multiplicity 3 (a C0 seam): opened there into one uniform 19-pole piece (SPEC §4). "
        "Along the 323 mm sweep the uniform cubic carries 0.0063 mm of ripple (1.9e-5 of its size), analysed in "
        "homogeneous coordinates (weights 0.71-1); the circular direction carries none."),
    ("MAINBODY_BACK.stp", (12, 13)): (
        (0.002067, 0.002067), "x1",
        "The space-ship's rear body, two mirrored 12x6 degree-5 faces (CATIA V5): along u two knots of "
        "multiplicity 3 (C2 joins, below the degree, so not junctions) over spans 0.7/1.15/1.15 of the mean; v is "
        "one Bezier span (no ripple). 0.0021 mm over a 170 mm face (1.4e-5): the fifth-degree joins' unsteerable "
        "part, in x1 only."),
    ("nist_ftc_07_asme1_rd.stp", (90, 102, 91, 103, 95, 106, 121, 125)): (
        (0.003358, 0.003440), "x1+x2",
        "Bicubic 5x5 corner blends of the FTC-07 part (4.6 mm): one interior knot per direction splitting the "
        "range 0.57/0.43, a C2 join whose third-derivative jump reads 0.0020 mm along each direction (x1, x2; "
        "diagonal none): 0.08 % of the blend's size. Eight copies (the part's eight corners, mirrored)."),
    ("nist_ftc_07_asme1_rd.stp", (58, 65, 71, 78)): (
        (0.003523, 0.003523), "x2",
        "4x5 bicubic edge blends next to those corners: u is one Bezier span (no ripple), v has the same 0.43/0.57 "
        "interior knot: 0.0035 mm along v only."),
}


def test_the_ten_largest_ripple_peaks_are_the_explained_faces(all_budgets):
    """Each of the ten largest peaks over all real files belongs to a face explained in :data:`EXPLAINED` (what
    it is, why the number is right), with its pinned value and its direction; the re-expression test above
    checks independently that the numbers belong to the surfaces, not to how they are written."""
    ranked = sorted(all_budgets, key=lambda r: -r[2].stats["total"].peak)
    tenth = ranked[9][2].stats["total"].peak
    top = [(name, net.origin.face) for name, net, b in ranked if b.stats["total"].peak >= tenth * (1 - 1e-6)]
    explained = {(name, face): key for key in EXPLAINED for name, faces in [key] for face in faces}
    assert len(top) >= 10
    for item in top:
        assert item in explained, f"unexplained large ripple peak: {item}"
    by_face = {(name, net.origin.face): b for name, net, b in all_budgets}
    for (name, faces), ((lo, hi), direction, _why) in EXPLAINED.items():
        for face in faces:
            s = by_face[(name, face)].stats
            assert lo * 0.99 <= s["total"].peak <= hi * 1.01, (name, face, s["total"].peak)
            carried = {k for k in ("x1", "x2", "diagonal") if s[k].peak > 1e-3 * s["total"].peak}
            assert carried == set(direction.split("+")), (name, face, carried)
