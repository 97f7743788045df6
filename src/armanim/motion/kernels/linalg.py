"""The inverses of the compiled kernels: the pseudo-inverse and the damped least-squares inverse
of a small matrix (a Jacobian: m, n <= 7), written as loops.

- :func:`pseudo_inverse`: where it can be shown cheaply that no singular value is cut, the normal
  equations (:func:`pinv_by_normal_equations`); else a one-sided Jacobi SVD with the cut-off of
  :func:`armanim.arm.linalg.pseudo_inverse` (singular values below ``PINV_RTOL`` times the
  largest count as zero), warm-started from the last step's rotation;
- :func:`damped`: J^T (J J^T + lambda^2 I)^-1 by Gaussian elimination with partial pivoting, as
  LAPACK's ``gesv`` (:func:`armanim.motion.solvers.linear.damped_inverse`, the numpy reference).

Pure core: numpy and numba only.
"""

from __future__ import annotations

import math

import numpy as np

from armanim.arm.kernel import compiled
from armanim.arm.linalg import PINV_RTOL
from armanim.motion.kernels.layout import PINV

_JIT = dict(error_model="numpy", nogil=True)
_INLINE = dict(inline="always", **_JIT)


JACOBI_SWEEPS = 60
"""Most sweeps of the one-sided Jacobi SVD (a 6 x 7 Jacobian takes 5 to 8)."""

WELL_CONDITIONED = 1e5
"""A Jacobian is inverted by its normal equations when trace(G) |G^-1|_F, a bound on its
condition number squared (G = J J^T or J^T J), is at most this: then every singular value is far
above the pseudo-inverse's cut-off, and the normal equations' rounding (kappa^2 eps) is below
1e-10."""


@compiled(**_JIT)
def orthogonalise(a: np.ndarray, w: np.ndarray) -> None:
    """One-sided Jacobi (Hestenes): rotates the columns of ``a`` (r, c) until they are
    orthogonal, the same rotations applied to the columns of ``w`` (c, c, orthogonal), so that
    a_in w_in^T = a_out w_out^T. The columns' lengths are then the singular values, each to
    high relative accuracy."""
    r, c = a.shape
    for _ in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(c - 1):
            for j in range(i + 1, c):
                alpha = 0.0
                beta = 0.0
                gamma = 0.0
                for k in range(r):
                    alpha += a[k, i] * a[k, i]
                    beta += a[k, j] * a[k, j]
                    gamma += a[k, i] * a[k, j]
                if gamma == 0.0 or abs(gamma) <= 1e-15 * math.sqrt(alpha) * math.sqrt(beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.hypot(1.0, zeta))
                cs = 1.0 / math.sqrt(1.0 + t * t)
                sn = cs * t
                for k in range(r):
                    ai = a[k, i]
                    aj = a[k, j]
                    a[k, i] = cs * ai - sn * aj
                    a[k, j] = sn * ai + cs * aj
                for k in range(c):
                    wi = w[k, i]
                    wj = w[k, j]
                    w[k, i] = cs * wi - sn * wj
                    w[k, j] = sn * wi + cs * wj
        if not rotated:
            return


@compiled(**_INLINE)
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


@compiled(**_JIT)
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


@compiled(**_JIT)
def pseudo_inverse(jac: np.ndarray, out: np.ndarray, w: np.ndarray) -> None:
    """The Moore-Penrose pseudo-inverse of ``jac`` (m, n) into ``out`` (n, m): singular values
    below ``PINV_RTOL`` times the largest count as zero (:func:`armanim.arm.linalg.pseudo_inverse`).

    The columns orthogonalised are those of J^T (m <= n) or of J (c = min(m, n) of them),
    starting from the orthogonal ``w`` (c, c), which is left holding the rotation found: a
    guess for the next step's Jacobian, which differs little (the identity at the start).
    J^T W = Q gives J^+ = Q diag(1/sigma^2) W^T, J W = Q gives J^+ = W diag(1/sigma^2) Q^T.
    A well-conditioned Jacobian takes its normal equations instead (:func:`pinv_by_normal_equations`)."""
    if pinv_by_normal_equations(jac, out):
        return
    m, n = jac.shape
    wide = m <= n
    r = n if wide else m
    c = m if wide else n
    a = np.empty((r, c))
    for i in range(r):
        for j in range(c):
            s = 0.0
            for k in range(c):
                s += (jac[k, i] if wide else jac[i, k]) * w[k, j]
            a[i, j] = s
    orthogonalise(a, w)
    inverse = np.empty(c)
    top = 0.0
    for j in range(c):
        s = 0.0
        for k in range(r):
            s += a[k, j] * a[k, j]
        inverse[j] = math.sqrt(s)
        top = max(top, inverse[j])
    for j in range(c):
        sigma = inverse[j]
        inverse[j] = 1.0 / (sigma * sigma) if (sigma > PINV_RTOL * top and top > 0.0) else 0.0
    for i in range(n):
        for j in range(m):
            s = 0.0
            for k in range(c):
                if wide:
                    s += a[i, k] * inverse[k] * w[j, k]
                else:
                    s += w[i, k] * inverse[k] * a[j, k]
            out[i, j] = s


@compiled(**_JIT)
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


@compiled(**_INLINE)
def invert(jac: np.ndarray, method: int, damping: float, out: np.ndarray, w: np.ndarray) -> bool:
    """The method's inverse of ``jac`` into ``out`` (``w``: :func:`pseudo_inverse`'s guess); False where it
    fails (a NaN proposal)."""
    if method == PINV:
        pseudo_inverse(jac, out, w)
        return True
    return damped(jac, damping, out)


@compiled(**_JIT)
def invert_cold(jac: np.ndarray, method: int, damping: float, out: np.ndarray) -> bool:
    """The method's inverse of ``jac`` (m, n) into ``out`` (n, m); False where it fails."""
    if method == PINV:
        c = min(jac.shape[0], jac.shape[1])
        guess = np.zeros((c, c))
        for i in range(c):
            guess[i, i] = 1.0
        pseudo_inverse(jac, out, guess)
        return True
    return damped(jac, damping, out)


@compiled(**_INLINE)
def matvec(a: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    for i in range(a.shape[0]):
        s = 0.0
        for k in range(a.shape[1]):
            s += a[i, k] * x[k]
        out[i] = s
