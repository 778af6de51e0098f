"""Fixtures and markers shared by every test folder (tests/<wing>/, tests/integration/).

Markers (registered in pyproject.toml):

- ``realdata``: the test reads ``../shared/realdata`` (real files beside the checkout, not in the repository);
  it is skipped, saying so, when that folder is absent. The folder is defined once, in
  :mod:`cadartifact.testing.paths`.
- ``slow``: the test takes seconds to minutes; ``pytest -m "not slow"`` is the fast lane, CI runs everything.
- ``cluster``: the test starts a Dask cluster on 127.0.0.1 (one xdist group).

Helpers the tests and the benchmarks share live in :mod:`cadartifact.testing` (known shapes, the fuzzer, the
outcome checks): import them as ``from cadartifact.testing import known_shapes``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cadartifact.testing.paths import REALDATA, REALDATA_MISSING, SAMPLES, have_realdata


def pytest_runtest_setup(item: pytest.Item) -> None:
    if item.get_closest_marker("realdata") is not None and not have_realdata():
        pytest.skip(REALDATA_MISSING)


@pytest.fixture(scope="session")
def realdata() -> Path:
    """``../shared/realdata`` (with ``step/`` and ``obj/``); the test is skipped when it is absent."""
    if not have_realdata():
        pytest.skip(REALDATA_MISSING)
    return REALDATA


@pytest.fixture(scope="session")
def samples() -> Path:
    """The committed samples (``samples/``)."""
    return SAMPLES


@pytest.fixture(scope="module")
def models(tmp_path_factory) -> dict:
    """The gate's STEP files of known ripple (:func:`cadartifact.testing.gate_models.write_models`): ``{"root":
    folder of ridge.step, clean.step, pair.step, broken.step; "value": the ridge face's ripple}``."""
    pytest.importorskip("OCP")
    from cadartifact.testing.gate_models import write_models

    return write_models(tmp_path_factory.mktemp("models"))
