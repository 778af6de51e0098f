"""Tensor-product products of per-axis matrices with a grid of points."""

from __future__ import annotations

import numpy as np

__all__ = ["sandwich", "sandwich_left", "sandwich_right"]


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
    return sandwich_right(sandwich_left(A, P), B)


def sandwich_left(A: np.ndarray, P: np.ndarray) -> np.ndarray:
    """The first half of :func:`sandwich`: ``(a, m, c)`` = ``A`` applied along the first axis (a caller
    pairing one ``A`` with many ``B`` keeps it; the result is the same to the bit)."""
    n, m, c = P.shape
    return (A @ P.reshape(n, m * c)).reshape(A.shape[0], m, c)


def sandwich_right(tmp: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The second half of :func:`sandwich`: ``(a, b, c)`` from :func:`sandwich_left`'s ``(a, m, c)``."""
    return np.tensordot(tmp, B, axes=(1, 1)).transpose(0, 2, 1)
