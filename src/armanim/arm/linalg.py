"""The Moore-Penrose pseudo-inverse of the course notes (Eq. 20), from scipy.linalg's SVD.

Pure core: numpy and scipy only, no I/O. The SVD is ``scipy.linalg.svd``'s, LAPACK's
divide-and-conquer driver ``gesdd``, as the design card says, called through scipy's LAPACK
wrapper directly (the same factors, without svd's per-call checks: :func:`_gesdd`). scipy.linalg is imported at
the first pseudo-inverse, not with this module: importing it costs about 0.3 s, which the
commands that never invert a Jacobian (``fk``, ``validate``, ``schema``, ``--version``) do
not pay (benchmarks/README.md has the figures).
"""

from __future__ import annotations

from typing import Any, cast

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
    (..., m, n), k = min(m, n), as ``scipy.linalg.svd(jac, full_matrices=False,
    lapack_driver="gesdd")`` computes them (bit for bit: the same LAPACK call, :func:`_gesdd`).

    scipy.linalg is imported here, at the first call. A matrix with a NaN or an infinity is a
    :class:`numpy.linalg.LinAlgError`, as a non-converged SVD is (the solvers report both
    as ``numerical``); an empty stack gives empty factors.

    >>> u, d, vt = singular_factors(np.array([[3.0, 0.0], [0.0, -2.0]]))
    >>> d.tolist(), (u @ np.diag(d) @ vt).tolist()
    ([3.0, 2.0], [[3.0, 0.0], [0.0, -2.0]])
    """
    jac = np.asarray(jac, dtype=float)
    m, n = jac.shape[-2:]
    k = min(m, n)
    batch = jac.shape[:-2]
    if jac.size == 0:
        return np.zeros((*batch, m, k)), np.zeros((*batch, k)), np.zeros((*batch, k, n))
    if not np.isfinite(jac).all():
        raise np.linalg.LinAlgError("SVD did not converge (the matrix holds a NaN or an infinity)")
    gesdd, lwork = _gesdd(m, n)
    if not batch:
        return _thin_svd(gesdd, lwork, jac)
    u, d, vt = np.empty((*batch, m, k)), np.empty((*batch, k)), np.empty((*batch, k, n))
    for index in np.ndindex(batch):
        u[index], d[index], vt[index] = _thin_svd(gesdd, lwork, jac[index])
    return u, d, vt


_GESDD: dict[tuple[int, int], tuple[Any, int]] = {}


def _gesdd(m: int, n: int) -> tuple[Any, int]:
    """LAPACK's ``gesdd`` and the work size ``scipy.linalg.svd`` would ask it for, for (m, n)
    matrices (looked up once per shape). Calling it as ``svd`` does, without ``svd``'s checks
    and its loop over a stack, gives the same factors bit for bit at half the cost: a
    frame inverts a few tiny matrices, where the wrapper was most of the time."""
    kept = _GESDD.get((m, n))
    if kept is None:
        from scipy.linalg import (
            get_lapack_funcs,  # imported at the first solve: fk, validate and schema never pay for it
        )
        from scipy.linalg.lapack import _compute_lwork  # the work size svd asks for (kept private by scipy since 1.0)

        gesdd, gesdd_lwork = get_lapack_funcs(("gesdd", "gesdd_lwork"), (np.zeros((1, 1)),), ilp64="preferred")
        kept = _GESDD[(m, n)] = (gesdd, _compute_lwork(gesdd_lwork, m, n, compute_uv=True, full_matrices=False))
    return kept


def _thin_svd(gesdd: Any, lwork: int, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One matrix's thin SVD by ``gesdd`` (:func:`_gesdd`)."""
    u, d, vt, info = gesdd(jac, compute_uv=1, lwork=lwork, full_matrices=0, overwrite_a=0)
    if info != 0:
        raise np.linalg.LinAlgError("SVD did not converge")
    return u, d, vt
