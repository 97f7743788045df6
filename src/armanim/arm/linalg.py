"""The Moore-Penrose pseudo-inverse of the course notes (Eq. 20), from scipy.linalg's SVD.

Pure core: numpy and scipy only, no I/O.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

_gesdd = scipy.linalg.get_lapack_funcs("gesdd", dtype=np.float64)  # scipy.linalg.svd's own driver, minus its per-call checks

PINV_RTOL = 1e-6
"""Singular values below this fraction of the largest are treated as zero: a
forward-difference Jacobian (h = 1e-6) carries noise of about that size where the
true Jacobian has lost rank, and inverting the noise would fling the arm."""


def pseudo_inverse(jac: np.ndarray) -> np.ndarray:
    """Moore-Penrose pseudo-inverse J+ = V D+ U^T (the notes' Eq. 20), from the SVD of
    ``scipy.linalg``.

    Singular values below ``PINV_RTOL`` times the largest count as zero.

    >>> pseudo_inverse(np.array([[2.0, 0.0], [0.0, 0.0]]))
    array([[0.5, 0. ],
           [0. , 0. ]])
    """
    u, d, vt, info = _gesdd(jac, compute_uv=1, full_matrices=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"SVD did not converge (LAPACK gesdd info {info})")
    keep = d > PINV_RTOL * d[0] if len(d) and d[0] > 0 else np.zeros(len(d), dtype=bool)
    inverse = np.where(keep, 1.0 / np.where(keep, d, 1.0), 0.0)
    return (vt.T * inverse) @ u.T
