"""Systematic resampling, compiled: the ancestors of every row (:func:`systematic_ancestors`),
the gather of the resampled particles (:func:`take_rows`), and the two fused in one pass
(:func:`resample_rows`, what :func:`fusioncenter.particle.run_filter` calls).

NumPy needs ``cumsum``, divide, ``ceil``, differences, ``repeat`` and a gather for systematic
resampling, each a pass over the ``(trials, particles)`` arrays; these kernels compute the same
integers from the same arithmetic, in its order, in one pass per trial. They go row by row (a
trial's result never depends on the other trials of a block) and draw no random numbers: the
uniform of each row is given. ``tests/test_kernels.py`` compares them with
:func:`fusioncenter.particle.systematic_resample` and :func:`fusioncenter.particle.resample`.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["systematic_ancestors", "take_rows", "resample_rows"]


@numba.njit(cache=True, nogil=True, inline="always")
def _mark_ancestors(w, b, total, ub, anc):
    """Row ``b``'s systematic resampling marks in ``anc (P,)``: particle ``i`` is written as
    the ancestor of slot ``c_{i-1}``, with ``c_i = ceil(P C_i / total - ub)`` from the running
    sum ``C`` of the weights (``c_{-1} = 0``, ``c_{P-1} = P``; particles with no offspring
    write the same slot before the one that owns it), every other slot 0. A running maximum
    over ``anc`` then gives the ancestors. The arithmetic, in its order, of the NumPy version
    (``cumsum``, divide, multiply, subtract, ``ceil``)."""
    P = w.shape[1]
    for k in range(P):
        anc[k] = 0
    c = 0.0
    lo = 0
    for i in range(P - 1):
        c += w[b, i]
        if lo < P:
            anc[lo] = i
        lo = int(math.ceil(c / total * P - ub))
    if lo < P:
        anc[lo] = P - 1


@numba.njit(cache=True, nogil=True, inline="always")
def _copy_particle(src, b, a, dst, k):
    """``dst[b, k, :] = src[b, a, :]`` (written out for ``d = 2``)."""
    d = src.shape[2]
    if d == 2:
        dst[b, k, 0] = src[b, a, 0]
        dst[b, k, 1] = src[b, a, 1]
    else:
        for j in range(d):
            dst[b, k, j] = src[b, a, j]


@numba.njit(cache=True, nogil=True)
def systematic_ancestors(w, S, u, todo, anc):
    """Ancestors ``anc (m, P)`` of systematic resampling for every row ``b`` with ``todo[b]``
    (one uniform ``u[b]``); the other rows get the identity. Particle ``i`` is kept
    ``c_i - c_{i-1}`` times, with ``c_i = ceil(P C_i / S - u)`` from the running sum ``C`` of
    the weights, ``c_{-1} = 0`` and ``c_{P-1} = P``: the arithmetic, in its order, of the NumPy
    version (``cumsum``, divide, multiply, subtract, ``ceil``). ``S[b]`` must be the row's
    sequential sum ``C_{P-1}``, as :func:`fusioncenter._compiled.weights.weighted_moments`
    computes it.

    Branch-light: particle ``i`` is written as the ancestor of slot ``c_{i-1}`` (particles with
    no offspring write the same slot before the one that owns it), then a running maximum
    fills the runs of repeated ancestors."""
    m, P = w.shape
    for b in range(m):
        if not todo[b]:
            for k in range(P):
                anc[b, k] = k
            continue
        _mark_ancestors(w, b, S[b], u[b], anc[b])
        a = 0
        for k in range(P):
            a = max(a, anc[b, k])
            anc[b, k] = a


@numba.njit(cache=True, nogil=True)
def take_rows(src, anc, dst):
    """``dst[b, k, :] = src[b, anc[b, k], :]`` (resampled particles ``(m, P, d)``, row by row)."""
    m, P = anc.shape
    for b in range(m):
        for k in range(P):
            _copy_particle(src, b, anc[b, k], dst, k)


@numba.njit(cache=True, nogil=True)
def resample_rows(w, S, u, todo, src, dst):
    """Systematic resampling fused with the gather: for every row ``b`` with ``todo[b]``,
    ``dst[b, k, :] = src[b, a_k, :]`` with the ancestors ``a_k`` of
    :func:`systematic_ancestors`, computed the same way (the same arithmetic, so the same
    integers) into a scratch row that stays in the cache; its running maximum and the gather are
    one pass. The other rows are copied. ``S[b]`` must be the row's sequential sum, as
    :func:`fusioncenter._compiled.weights.weighted_moments` computes it."""
    m, P = w.shape
    anc = np.empty(P, dtype=np.intp)
    for b in range(m):
        if not todo[b]:
            for k in range(P):
                _copy_particle(src, b, k, dst, k)
            continue
        _mark_ancestors(w, b, S[b], u[b], anc)
        a = 0
        for k in range(P):
            a = max(a, anc[k])
            _copy_particle(src, b, a, dst, k)
