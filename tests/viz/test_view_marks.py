"""The marks of a whole-model view (issue 42): every face that is not tiny labelled, the scale bar off the model,
a legend for the peak's dot and the net. Faces are stand-ins with known boxes (``points``, ``peak``)."""

from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from cadartifact.viz.view import TINY_FACE, labelled_faces, legend_handles, ruler_ends  # noqa: E402


def face(lo, size, peak=0.0, n=5):
    """A flat grid face from ``lo`` spanning ``size`` (x, y), at z = lo[2]."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    pts = np.stack([lo[0] + size[0] * u, lo[1] + size[1] * v, np.full_like(u, lo[2])], axis=-1)
    return SimpleNamespace(points=pts, peak=peak)


@pytest.mark.parametrize("count", [3, 12, 40])
@pytest.mark.parametrize("tiny", [0, 1, 4])
def test_every_face_but_the_tiny_is_labelled(count, tiny):
    faces = [face((10.0 * k, 0.0, 0.0), (10.0, 8.0)) for k in range(count)]
    scene = np.linalg.norm([10.0 * count, 8.0, 0.0])
    small = [face((5.0 * k, 20.0, 0.0), (0.2 * TINY_FACE * scene,) * 2) for k in range(tiny)]
    shown = labelled_faces(faces + small)
    assert [id(s) for s in shown] == [id(f) for f in faces]


@pytest.mark.parametrize("size", [(100.0, 40.0, 5.0), (3.0, 90.0, 20.0), (10.0, 10.0, 70.0)])
def test_the_scale_bar_lies_off_the_model(size):
    rng = np.random.default_rng(7)
    pts = rng.uniform(0, 1, (6, 6, 3)) * np.array(size) + np.array([5.0, -3.0, 2.0])
    a, b = ruler_ends([SimpleNamespace(points=pts, peak=0.0)])
    lo, hi = pts.reshape(-1, 3).min(axis=0), pts.reshape(-1, 3).max(axis=0)
    k = int(np.argmax(hi - lo))
    assert b[k] - a[k] == pytest.approx(hi[k] - lo[k])  # as long as the longest side: the scale reads true
    others = [j for j in range(3) if j != k]
    # outside the model's box on both other sides: no face under the bar or its labels
    assert all(a[j] == b[j] and not lo[j] <= a[j] <= hi[j] for j in others)


def test_the_legend_names_the_marks():
    rippled = [face((0, 0, 0), (10, 10), peak=0.2), face((10, 0, 0), (10, 10))]
    assert [h.get_label() for h in legend_handles(rippled, True)] == ["peak of each face", "control net"]
    assert [h.get_label() for h in legend_handles(rippled, False)] == ["peak of each face"]
    assert legend_handles([face((0, 0, 0), (10, 10))], False) == []  # no ripple: no dot to explain
