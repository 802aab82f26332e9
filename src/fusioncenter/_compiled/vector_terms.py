"""Compiled passes of the vector fusion centre (:mod:`fusioncenter.censoring.vector_fusion`):
the sensors' local Kalman step of the exact no-feedback filter, around its draws
(:func:`local_innovations`, :func:`silent_offsets`, :func:`local_update`), a received sensor's
terms of that filter (:func:`exact_received`), the whitened Gaussian terms of a group of
sensors (:func:`white_gauss_add`), and the rounds of rejection sampling of a normal
conditioned to an ellipse (:func:`ellipse_reject`).

Row by row (a trial's result never depends on the other trials of a block), the NumPy code's
arithmetic operation for operation, in its order (``tests/test_kernels.py`` and
``tests/test_censoring_vector.py`` compare each kernel with that code, bit for bit).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["local_innovations", "silent_offsets", "local_update", "exact_received",
           "white_gauss_add", "ellipse_reject"]

@numba.njit(cache=True, nogil=True)
def local_innovations(z, H, h0, h1, nu):
    """``nu[j, b, p] = z[b, j] - (H[j, 0] h0[b, p] + H[j, 1] h1[b, p])``: a sensor's innovation
    against every particle's local prediction ``(h0, h1)`` (the NumPy arithmetic of
    ``censoring.vector_fusion``, in its order)."""
    m = H.shape[0]
    n, P = h0.shape
    for j in range(m):
        for b in range(n):
            zb = z[b, j]
            for p in range(P):
                nu[j, b, p] = zb - (H[j, 0] * h0[b, p] + H[j, 1] * h1[b, p])


@numba.njit(cache=True, nogil=True)
def silent_offsets(A, pos, vel, h0, h1, sil, out):
    """``out[r P + p, j] = A[j, 0] (pos - h0) + A[j, 1] (vel - h1)`` at ``[sil[r], p]``: the
    canonical offsets of the silent rows' particles, stacked ``(len(sil) P, m)``."""
    P = pos.shape[1]
    for r in range(sil.shape[0]):
        b = sil[r]
        for p in range(P):
            d0 = pos[b, p] - h0[b, p]
            d1 = vel[b, p] - h1[b, p]
            for j in range(A.shape[0]):
                out[r * P + p, j] = A[j, 0] * d0 + A[j, 1] * d1


@numba.njit(cache=True, nogil=True)
def local_update(W, F, nu, nus, sil, h0, h1):
    """The sensor's Kalman update and prediction of every particle's local estimate, in place:
    first ``nu[:, sil[r], p] = nus[r P + p, :]`` (the imputed innovations of the silent rows),
    then ``u_i = h_i + (0 + sum_j W[i, j] nu_j)`` and ``h_i <- F[i, 0] u_0 + F[i, 1] u_1``
    (the NumPy arithmetic of ``censoring.vector_fusion``, the sum in Python's order)."""
    m, n, P = nu.shape
    for r in range(sil.shape[0]):
        b = sil[r]
        for p in range(P):
            for j in range(m):
                nu[j, b, p] = nus[r * P + p, j]
    for b in range(n):
        for p in range(P):
            s0 = 0.0
            s1 = 0.0
            for j in range(m):
                s0 = s0 + W[0, j] * nu[j, b, p]
                s1 = s1 + W[1, j] * nu[j, b, p]
            u0 = h0[b, p] + s0
            u1 = h1[b, p] + s1
            h0[b, p] = F[0, 0] * u0 + F[0, 1] * u1
            h1[b, p] = F[1, 0] * u0 + F[1, 1] * u1


@numba.njit(cache=True, nogil=True)
def exact_received(lz, M, zi, H, Si, eta, p, v, h0, h1, rows, lw, ok):
    """The received sensor's terms of the exact no-feedback vector filter, for the rows
    ``rows`` (``r``) of the particles ``(p, v)`` and their local predictions ``(h0, h1)``:
    ``lw += -0.5 sum_j (lz[j, r] - (M[j, 0] p + M[j, 1] v))^2`` (the whitened Gaussian
    log-likelihood), and ``ok &= nu^T Si nu >= eta`` with ``nu_j = zi[r, j] - (H[j, 0] h0 +
    H[j, 1] h1)`` (the sensor would have sent), the sum in Python's order: the NumPy arithmetic
    of ``censoring.vector_fusion``, in one pass."""
    m = M.shape[0]
    P = p.shape[1]
    nu = np.empty(m)
    for r in range(rows.shape[0]):
        b = rows[r]
        for q in range(P):
            acc = 0.0
            for j in range(m):
                d = lz[j, r] - (M[j, 0] * p[b, q] + M[j, 1] * v[b, q])
                d = d * d
                acc = d if j == 0 else acc + d
            lw[b, q] = lw[b, q] + -0.5 * acc
            for j in range(m):
                nu[j] = zi[r, j] - (H[j, 0] * h0[b, q] + H[j, 1] * h1[b, q])
            nis = 0.0
            for j in range(m):
                for jj in range(m):
                    nis = nis + Si[j, jj] * nu[j] * nu[jj]
            ok[b, q] = ok[b, q] and nis >= eta


@numba.njit(cache=True, nogil=True)
def white_gauss_add(GT, p, v, cbar, coef, lw):
    """``lw[b, i] += coef[b] sum_j (GT[j, 0] p + GT[j, 1] v - cbar[b, j])^2``: a group's
    received sensors' whitened Gaussian log-likelihood (``coef = -n_obs / 2``), the NumPy
    arithmetic of ``censoring.vector_fusion`` in its order, in one pass."""
    m = GT.shape[0]
    n, P = p.shape
    for b in range(n):
        c = coef[b]
        for i in range(P):
            acc = 0.0
            for j in range(m):
                w = GT[j, 0] * p[b, i] + GT[j, 1] * v[b, i]
                w = w - cbar[b, j]
                w = w * w
                acc = w if j == 0 else acc + w
            lw[b, i] = lw[b, i] + acc * c


@numba.njit(cache=True, nogil=True)
def ellipse_reject(u, b, todo, inv_a2, out):
    """One round of rejection sampling in the ellipse ``sum_j u_j^2 inv_a2[j] < 1``: for
    ``t < todo.size`` the proposal for point ``i = todo[t]`` is ``u[t] + b[i]``; if inside it is
    stored in ``out[i]``, otherwise ``i`` is kept. The kept points are packed at the front of
    ``todo`` (in their order); returns how many. ``u (k, m)`` (standard normal draws; ``k >=
    todo.size``), ``b, out (K, m)``, ``inv_a2 (m,)``; the arithmetic of
    ``censoring.vector_fusion``'s NumPy rounds (the draw plus the mean, then ``u_1^2 inv_1``,
    ``+ u_2^2 inv_2``, ...)."""
    m = b.shape[1]
    kept = 0
    for t in range(todo.shape[0]):
        i = todo[t]
        q = 0.0
        for j in range(m):
            uj = u[t, j] + b[i, j]
            u[t, j] = uj
            if j == 0:
                q = uj * uj * inv_a2[0]
            else:
                q += uj * uj * inv_a2[j]
        if q < 1.0:
            for j in range(m):
                out[i, j] = u[t, j]
        else:
            todo[kept] = i
            kept += 1
    return kept
