"""The inverses of the compiled kernels: the pseudo-inverse and the damped least-squares inverse
of a small matrix (a Jacobian: m, n <= 7), written as loops.

- :func:`pseudo_inverse`: where it can be shown cheaply that no singular value is cut, the normal
  equations (:func:`pinv_by_normal_equations`); else the SVD of scipy.linalg, LAPACK's ``gesdd``
  (through ``scipy.linalg.cython_lapack``, which numba's ``np.linalg.svd`` calls), with the cut-off
  of :func:`armanim.arm.linalg.pseudo_inverse` (singular values below ``PINV_RTOL`` times the
  largest count as zero);
- :func:`damped`: J^T (J J^T + lambda^2 I)^-1 by Gaussian elimination with partial pivoting, as
  LAPACK's ``gesv`` (:func:`armanim.motion.solvers.linear.damped_inverse`, the numpy reference).

Pure core: numpy and numba only.
"""

from __future__ import annotations

import math

import numpy as np

from armanim.arm.kernel import INLINE, JIT, compiled
from armanim.arm.linalg import PINV_RTOL
from armanim.motion.kernels.layout import PINV

WELL_CONDITIONED = 1e5
"""A Jacobian is inverted by its normal equations when trace(G) |G^-1|_F, a bound on its
condition number squared (G = J J^T or J^T J), is at most this: then every singular value is far
above the pseudo-inverse's cut-off, and the normal equations' rounding (kappa^2 eps) is below
1e-10."""


@compiled(**INLINE)
def cholesky(g: np.ndarray, size: int, floor: float) -> bool:
    """G = L L^T in place for the leading (size, size) block of ``g`` (its lower triangle read,
    L written there); False where a pivot is not above ``floor`` (G not positive definite)."""
    for j in range(size):
        s = g[j, j]
        for k in range(j):
            s -= g[j, k] * g[j, k]
        if not s > floor:
            return False
        g[j, j] = math.sqrt(s)
        for i in range(j + 1, size):
            s = g[i, j]
            for k in range(j):
                s -= g[i, k] * g[j, k]
            g[i, j] = s / g[j, j]
    return True


@compiled(**JIT)
def pinv_by_normal_equations(jac: np.ndarray, out: np.ndarray) -> bool:
    """J^+ = J^T (J J^T)^-1 (m <= n) or (J^T J)^-1 J^T into ``out`` (n, m), where it can be shown
    cheaply that no singular value is cut (:data:`WELL_CONDITIONED`): the condition number
    squared of G is at most trace(G) |G^-1|_F, since lambda_max <= trace and 1 / lambda_min =
    |G^-1|_2 <= |G^-1|_F. False (``out`` untouched) where it cannot be shown."""
    m, n = jac.shape
    wide = m <= n
    c = m if wide else n
    r = n if wide else m
    g = np.empty((c, c))
    trace = 0.0
    for i in range(c):
        for j in range(i + 1):
            s = 0.0
            for k in range(r):
                s += (jac[i, k] * jac[j, k]) if wide else (jac[k, i] * jac[k, j])
            g[i, j] = s
        trace += g[i, i]
    if not cholesky(g, c, 0.0):  # G = L L^T, in the lower triangle
        return False
    inverse = np.empty((c, c))  # G^-1, column by column: L y = e_col, L^T x = y
    for col in range(c):
        for i in range(c):
            s = 1.0 if i == col else 0.0
            for k in range(i):
                s -= g[i, k] * inverse[k, col]
            inverse[i, col] = s / g[i, i]
        for i in range(c - 1, -1, -1):
            s = inverse[i, col]
            for k in range(i + 1, c):
                s -= g[k, i] * inverse[k, col]
            inverse[i, col] = s / g[i, i]
    frobenius = 0.0
    for i in range(c):
        for j in range(c):
            frobenius += inverse[i, j] * inverse[i, j]
    if not trace * math.sqrt(frobenius) <= WELL_CONDITIONED:
        return False
    for i in range(n):
        for j in range(m):
            s = 0.0
            for k in range(c):
                s += (jac[k, i] * inverse[k, j]) if wide else (inverse[i, k] * jac[j, k])
            out[i, j] = s
    return True


@compiled(**JIT)
def pseudo_inverse(jac: np.ndarray, out: np.ndarray) -> None:
    """The Moore-Penrose pseudo-inverse of ``jac`` (m, n) into ``out`` (n, m): singular values
    below ``PINV_RTOL`` times the largest count as zero (:func:`armanim.arm.linalg.pseudo_inverse`,
    the numpy reference). A well-conditioned Jacobian takes its normal equations
    (:func:`pinv_by_normal_equations`); any other, LAPACK's ``gesdd`` as scipy.linalg's SVD calls
    it (numba's ``np.linalg.svd`` calls ``scipy.linalg.cython_lapack``): J^+ = V diag(1/d) U^T.
    A matrix with a NaN or an infinity gives NaN (the caller's proposal is then not finite)."""
    if pinv_by_normal_equations(jac, out):
        return
    m, n = jac.shape
    for i in range(m):
        for j in range(n):
            if not (jac[i, j] - jac[i, j] == 0.0):  # NaN or infinity: gesdd would not converge
                out[:, :] = np.nan
                return
    u, d, vt = np.linalg.svd(jac, full_matrices=False)
    top = d[0] if d.shape[0] else 0.0
    inverse = np.empty(d.shape[0])
    for k in range(d.shape[0]):
        inverse[k] = 1.0 / d[k] if (d[k] > PINV_RTOL * top and top > 0.0) else 0.0
    for i in range(n):
        for j in range(m):
            s = 0.0
            for k in range(d.shape[0]):
                s += vt[k, i] * inverse[k] * u[j, k]
            out[i, j] = s


@compiled(**JIT)
def damped(jac: np.ndarray, damping: float, out: np.ndarray) -> bool:
    """J^T (J J^T + lambda^2 I)^-1 of ``jac`` (m, n) into ``out`` (n, m), by Gaussian elimination
    with partial pivoting (the solve of :func:`armanim.motion.solvers.linear.damped_inverse`);
    False when a pivot is zero (a singular matrix: numpy raises there)."""
    m, n = jac.shape
    gram = np.empty((m, m))
    rhs = np.empty((m, n))
    for i in range(m):
        for j in range(m):
            s = 0.0
            for k in range(n):
                s += jac[i, k] * jac[j, k]
            gram[i, j] = s + (damping * damping if i == j else 0.0)
        for k in range(n):
            rhs[i, k] = jac[i, k]
    for col in range(m):
        pivot = col
        for i in range(col + 1, m):
            if abs(gram[i, col]) > abs(gram[pivot, col]):
                pivot = i
        if gram[pivot, col] == 0.0:
            return False
        if pivot != col:
            for j in range(m):
                gram[col, j], gram[pivot, j] = gram[pivot, j], gram[col, j]
            for k in range(n):
                rhs[col, k], rhs[pivot, k] = rhs[pivot, k], rhs[col, k]
        for i in range(col + 1, m):
            f = gram[i, col] / gram[col, col]
            for j in range(col, m):
                gram[i, j] -= f * gram[col, j]
            for k in range(n):
                rhs[i, k] -= f * rhs[col, k]
    for i in range(m - 1, -1, -1):
        for k in range(n):
            s = rhs[i, k]
            for j in range(i + 1, m):
                s -= gram[i, j] * rhs[j, k]
            rhs[i, k] = s / gram[i, i]
    for i in range(n):
        for j in range(m):
            out[i, j] = rhs[j, i]
    return True


@compiled(**JIT)
def invert(jac: np.ndarray, method: int, damping: float, out: np.ndarray) -> bool:
    """The method's inverse of ``jac`` (m, n) into ``out`` (n, m): :func:`pseudo_inverse` or
    :func:`damped`; False where it fails (a zero pivot: a NaN proposal)."""
    if method == PINV:
        pseudo_inverse(jac, out)
        return True
    return damped(jac, damping, out)


@compiled(**INLINE)
def matvec(a: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    for i in range(a.shape[0]):
        s = 0.0
        for k in range(a.shape[1]):
            s += a[i, k] * x[k]
        out[i] = s
