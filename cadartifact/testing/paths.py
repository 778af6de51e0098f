"""The checkout's folders the tests and benchmarks read: defined here once.

``REALDATA`` is ``../shared/realdata`` beside the checkout (real STEP and OBJ files kept out of the repository; its
SOURCES.md says where each comes from). Tests that need it carry the ``realdata``
marker and are skipped, with :data:`REALDATA_MISSING` as the reason, when it is absent.
"""

from __future__ import annotations

from pathlib import Path

#: The repository's root (this file is ``cadartifact/testing/paths.py``).
ROOT = Path(__file__).resolve().parents[2]
#: The committed samples (``samples/``; the package ships a copy in ``cadartifact/samples``).
SAMPLES = ROOT / "samples"
#: The golden documents (tests/integration/test_documents_unchanged.py).
GOLDEN = ROOT / "tests" / "golden"
#: Real files beside the checkout: ``../shared/realdata/{step,obj}``.
REALDATA = ROOT.parent / "shared" / "realdata"
REAL_STEP = REALDATA / "step"
REAL_OBJ = REALDATA / "obj"
#: Why a ``realdata`` test is skipped.
REALDATA_MISSING = f"real files are not in the repository: {REALDATA} (../shared/realdata beside the checkout) " \
                   "is absent"


def have_realdata() -> bool:
    """Whether ``../shared/realdata`` is beside the checkout."""
    return REALDATA.is_dir()
