"""The place of a field's peak, the same on every CPU."""

from __future__ import annotations

import numpy as np

__all__ = ["first_peak"]


def first_peak(values: np.ndarray, rtol: float = 1e-9) -> tuple[int, ...]:
    """The index of the first entry (C order) within ``rtol`` of the largest.

    A symmetric face peaks at two places equal to rounding; ``argmax`` alone picks whichever rounding (another
    CPU's BLAS kernel) made larger, so the reported place moved between machines (2026-12-03). The first of
    the near-equal entries does not move.

    Parameters
    ----------
    values : (n, m) float
        ``-inf`` where a place does not count.
    rtol : float, optional
        Entries ``>= max - rtol * |max|`` are equal to the peak.

    Returns
    -------
    tuple of int
        ``np.unravel_index`` of that entry.
    """
    top = float(np.max(values))
    return tuple(int(k) for k in np.unravel_index(int(np.argmax(values >= top - rtol * abs(top))), values.shape))
