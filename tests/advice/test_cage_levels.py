"""The level that brings a chart's ripple within the tolerance: ceil(log4 share), checked against the distance
between a regular cage's level-k control points and their limit positions, measured (it falls by 4 per level)."""

import numpy as np
import pytest

from cadartifact.advice.cage_levels import cage_advice, ripple_level
from cadartifact.numerics.catmull_clark import limit_stencil, subdivision_step


@pytest.mark.parametrize("share, level", [(None, None), (0.0, 0), (1.0, 0), (1.01, 1), (4.0, 1), (4.1, 2),
                                          (16.0, 2), (4.0 ** 6, 6), (4.0 ** 6 * 1.01, None)])
def test_ripple_level(share, level):
    assert ripple_level(share) == level


@pytest.mark.parametrize("cycles", [1.0, 1.5])
@pytest.mark.parametrize("phase", [0.0, 0.7])
def test_net_to_limit_distance_falls_by_four_per_level(cycles, phase):
    """A 12 x 12 grid cage (closed in u: a tube, so no boundary rule intervenes) of a sinusoidal height: the
    largest distance of a level-k vertex from its limit position falls by 4 per level (the premise of
    ripple_level)."""
    nu, nv = 12, 12
    u, v = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    P = np.stack([np.cos(2 * np.pi * u / nu), np.sin(2 * np.pi * u / nu),
                  v / nv + 0.05 * np.sin(2 * np.pi * cycles * v / nv + phase)], axis=-1).reshape(-1, 3)
    F = [(i * nv + j, ((i + 1) % nu) * nv + j, ((i + 1) % nu) * nv + j + 1, i * nv + j + 1)
         for i in range(nu) for j in range(nv - 1)]
    dist = []
    for _ in range(4):
        S, quads, _, _ = subdivision_step(len(P), F)
        P, F = S @ P, quads.tolist()
        inner = np.abs(P[:, 2] - 0.5) < 0.25  # away from the tube's open ends
        dist.append(np.linalg.norm((limit_stencil(len(P), quads) @ P - P)[inner], axis=1).max())
    ratios = np.array(dist[:-1]) / np.array(dist[1:])
    assert ratios[-1] == pytest.approx(4.0, rel=0.05)


def test_cage_advice_levels_and_vertices_needing_control():
    faces = [{"face": 0, "net": [9, 3], "share": {"deviation": 3.0}}, {"face": 1, "net": [4, 4], "share": {"deviation": 0.5}}]
    verts = [{"vertex": 7, "face": None, "valence": 5, "level": 2}, {"vertex": 9, "face": 3, "valence": 3, "level": 0}]
    a = cage_advice(faces, verts)
    assert a["level"] == 2 and a["need_control"] == []
    assert [r["level"] for r in a["regions"]] == [1, 0]
    assert "chart 0 (9x3 points): level 1 (17x5 points)" in a["text"]
    assert "vertex 7 (valence 5): level 2 around it" in a["text"]
    b = cage_advice(faces, verts + [{"vertex": 11, "face": None, "valence": 12, "level": None}])
    assert b["level"] is None and b["need_control"] == [11]
    assert any("vertex 11 (valence 12): not within by level 6: needs more control" in t for t in b["text"])
    c = cage_advice([faces[1]], [verts[1]])
    assert c["level"] == 0 and c["text"] == ["the cage as it is: every region and extraordinary vertex within the "
                                            "tolerance"]


def test_crease_vertices_are_reported_not_advised():
    verts = [{"vertex": 7, "face": None, "valence": 5, "level": None, "crease": True}]
    a = cage_advice([], verts)
    assert a["vertices"] == [] and a["need_control"] == [] and a["level"] == 0
