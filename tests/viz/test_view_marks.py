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


@pytest.mark.parametrize("sweep", [np.pi, 1.5 * np.pi, 2 * np.pi])
@pytest.mark.parametrize("axis", [0, 1, 2])
def test_a_face_curving_all_round_is_seen_square_on(sweep, axis):
    """A cylinder's patch of ``sweep`` radians around ``axis``: no mean normal; the view looks across the axis
    (perpendicular to it), from where the patch shows its length, never along the axis (a curve)."""
    from cadartifact.viz.view import best_view, mean_normal

    t, h = np.meshgrid(np.linspace(0, sweep, 40), np.linspace(0, 30.0, 12), indexing="ij")
    local = np.stack([10 * np.cos(t), 10 * np.sin(t), h], axis=-1)
    pts = np.roll(local, axis - 2, axis=-1)  # the cylinder's axis along x, y or z
    m = SimpleNamespace(points=pts, values=np.zeros(pts.shape[:2]), peak=0.0)
    view = best_view(m)
    axis_dir = np.eye(3)[axis]
    assert view is not None and abs(np.linalg.norm(view) - 1) < 1e-9
    assert abs(view @ axis_dir) < 1e-6
    if mean_normal(m) is not None:  # a half cylinder has a mean normal: the same road as before
        assert np.allclose(view, mean_normal(m))


def test_a_flat_face_is_seen_along_its_normal():
    from cadartifact.viz.view import best_view

    m = face((0, 0, 3.0), (10, 5))
    m.values = np.zeros(m.points.shape[:2])
    assert abs(abs(best_view(m)[2]) - 1) < 1e-12
