"""Fixtures of the analysis wing's tests."""

import pytest


@pytest.fixture
def uniform_band(monkeypatch):
    """The measured road cut at half a cycle per span on every direction, the band the predicted road reads.

    The predicted road is the uniform theory's (one lattice point per span, continued past the ends); on a short
    clamped direction (fewer than ``2 p - 1`` spans) the measured road cuts higher, at half a cycle per control
    point in index space (:func:`cadartifact.analysis.frames.index_space_cut`). Tests that hold one road to the
    other compare them on the same band.
    """
    from cadartifact.analysis import fields

    monkeypatch.setattr(fields, "index_space_cut", lambda frame: 0.5)
