"""The Moore-Penrose pseudo-inverse of the course notes (Eq. 20), from an SVD.

Pure core: numpy only, no I/O. The SVD is numpy's, LAPACK's divide-and-conquer driver
``gesdd``, the one ``scipy.linalg.svd`` calls too (bit for bit the same factors): importing
scipy.linalg for it cost every armanim process about 0.45 s of start-up, against some 17 us
more per call in numpy's wrapper (a few ms for a whole scene).
"""

from __future__ import annotations

from typing import cast

import numpy as np

PINV_RTOL = 1e-6
"""Singular values below this fraction of the largest are treated as zero: a
forward-difference Jacobian (h = 1e-6) carries noise of about that size where the
true Jacobian has lost rank, and inverting the noise would fling the arm."""


def pseudo_inverse(jac: np.ndarray) -> np.ndarray:
    """Moore-Penrose pseudo-inverse J+ = V D+ U^T (the notes' Eq. 20), from the SVD.

    Singular values below ``PINV_RTOL`` times the largest count as zero. A stack of matrices
    is inverted in one call, each bit for bit as alone.

    Parameters
    ----------
    jac : (..., m, n) array

    Returns
    -------
    (..., n, m) array

    Raises
    ------
    numpy.linalg.LinAlgError
        The SVD did not converge.

    >>> pseudo_inverse(np.array([[2.0, 0.0], [0.0, 0.0]]))
    array([[0.5, 0. ],
           [0. , 0. ]])
    """
    u, d, vt = np.linalg.svd(jac, full_matrices=False)
    top = d[..., :1]
    keep = (d > PINV_RTOL * top) & (top > 0)
    inverse = np.where(keep, 1.0 / np.where(keep, d, 1.0), 0.0)
    return cast(np.ndarray, np.matmul(np.swapaxes(vt, -1, -2) * inverse[..., None, :], np.swapaxes(u, -1, -2)))
