"""The Moore-Penrose pseudo-inverse of the course notes (Eq. 20), from scipy.linalg's SVD.

Pure core: numpy and scipy only, no I/O. The SVD is ``scipy.linalg.svd``, LAPACK's
divide-and-conquer driver ``gesdd``, as the design card says. scipy.linalg is imported at
the first pseudo-inverse, not with this module: importing it costs about 0.3 s, which the
commands that never invert a Jacobian (``fk``, ``validate``, ``schema``, ``--version``) do
not pay (benchmarks/README.md has the figures).
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
        The SVD did not converge, or ``jac`` holds a NaN or an infinity.

    >>> pseudo_inverse(np.array([[2.0, 0.0], [0.0, 0.0]]))
    array([[0.5, 0. ],
           [0. , 0. ]])
    """
    u, d, vt = singular_factors(jac)
    top = d[..., :1]
    keep = (d > PINV_RTOL * top) & (top > 0)
    inverse = np.where(keep, 1.0 / np.where(keep, d, 1.0), 0.0)
    return cast(np.ndarray, np.matmul(np.swapaxes(vt, -1, -2) * inverse[..., None, :], np.swapaxes(u, -1, -2)))


def singular_factors(jac: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The thin SVD ``U (..., m, k)``, ``d (..., k)``, ``V^T (..., k, n)`` of ``jac``
    (..., m, n), k = min(m, n), from ``scipy.linalg.svd`` (``gesdd``).

    scipy.linalg is imported here, at the first call. A matrix with a NaN or an infinity is a
    :class:`numpy.linalg.LinAlgError`, as a non-converged SVD is (the solvers report both
    as ``numerical``); an empty stack gives empty factors.

    >>> u, d, vt = singular_factors(np.array([[3.0, 0.0], [0.0, -2.0]]))
    >>> d.tolist(), (u @ np.diag(d) @ vt).tolist()
    ([3.0, 2.0], [[3.0, 0.0], [0.0, -2.0]])
    """
    from scipy.linalg import svd  # imported at the first solve: fk, validate and schema never pay for it

    jac = np.asarray(jac, dtype=float)
    m, n = jac.shape[-2:]
    if jac.size == 0:
        k = min(m, n)
        batch = jac.shape[:-2]
        return np.zeros((*batch, m, k)), np.zeros((*batch, k)), np.zeros((*batch, k, n))
    if not np.isfinite(jac).all():
        raise np.linalg.LinAlgError("SVD did not converge (the matrix holds a NaN or an infinity)")
    return cast(tuple[np.ndarray, np.ndarray, np.ndarray], svd(jac, full_matrices=False, check_finite=False, lapack_driver="gesdd"))
