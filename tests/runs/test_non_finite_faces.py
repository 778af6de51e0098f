"""A face whose analysis overflows is an error worded as each door worded it before they shared one pipeline.

The gate: ``face N: the analysis gave a non-finite value (coordinates too large?)``, checked before the verdict.
``advise``: its sure advice is searched first and checked with its record, so the search's own error comes first.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from cadartifact.analysis.settings import RunSettings
from cadartifact.errors import CadArtifactError, FileFormatError
from cadartifact.gate.policy import FileSettings
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.runs.face_sharing import advise_faces, analyse_faces


@pytest.fixture
def overflowing():
    """A rational face whose one huge weight (finite, so the net is valid) overflows the budget."""
    i, j = np.meshgrid(np.linspace(0, 1, 8), np.linspace(0, 1, 7), indexing="ij")
    points = np.stack([100 * i, 80 * j, 5 * np.sin(7 * i)], -1) * 1e9
    weights = np.ones((8, 7))
    weights[3, 3] = 1e300
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield ControlNet.from_points(points, degrees=(3, 3), weights=weights,
                                     origin=NetOrigin(file="x.step", face=0, kind="bspline"))


def test_the_gate_words_a_non_finite_value_as_it_did(overflowing):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (out,) = analyse_faces([overflowing], FileSettings(tolerance=0.05), False)
    assert isinstance(out, CadArtifactError)
    assert str(out) == "face 0: the analysis gave a non-finite value (coordinates too large?)"


def test_advise_searches_before_it_checks_as_it_did(overflowing):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (out,) = advise_faces([overflowing], RunSettings(tolerance=0.05), {"compare": "auto", "verify": True}, "x.step")
    assert isinstance(out, Exception) and not isinstance(out, FileFormatError)
    assert "NaN or infinite coordinate" in str(out)
