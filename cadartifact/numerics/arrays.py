"""Read-only arrays: the frozen dataclasses of every wing hold arrays nobody can change in place."""

from __future__ import annotations

import numpy as np

__all__ = ["frozen_array"]


def frozen_array(a, dtype=float) -> np.ndarray:
    """A read-only copy of ``a`` (frozen dataclasses of arrays stay immutable)."""
    arr = np.array(a, dtype=dtype, copy=True)
    arr.setflags(write=False)
    return arr
