"""Tensor-product products of per-axis matrices with a grid of points."""

from __future__ import annotations

import numpy as np

__all__ = ["sandwich"]


def sandwich(A: np.ndarray, P: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A P B^T`` for each coordinate.

    Parameters
    ----------
    A : (a, n) float
    P : (n, m, c) float
    B : (b, m) float

    Returns
    -------
    (a, b, c) float
    """
    n, m, c = P.shape
    tmp = (A @ P.reshape(n, m * c)).reshape(A.shape[0], m, c)  # (a, m, c)
    return np.tensordot(tmp, B, axes=(1, 1)).transpose(0, 2, 1)  # (a, b, c)
