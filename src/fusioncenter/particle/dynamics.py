"""The linear-Gaussian dynamics of a particle filter: ``x_0 ~ N(m0, P0)``, ``x_t = A x_{t-1} +
u``, ``u ~ N(0, Q)`` (:class:`LinearGaussianDynamics`, the initial law and the transition of a
:class:`fusioncenter.particle.loop.FilterModel`), and the thin factor of a covariance that
draws its noise with ``rank`` normals (:func:`psd_factor`).

The transition runs compiled (:mod:`fusioncenter._compiled.transitions`: the arithmetic of the
BLAS product NumPy calls), with the normals drawn inside the pass, NumPy's bit for bit, on an
SFC64 or PCG64 stream (:mod:`fusioncenter._compiled.ziggurat`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fusioncenter._compiled import transitions, ziggurat
from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import is_text
from fusioncenter._validate import nonempty as _nonempty
from fusioncenter._validate import square as _square

__all__ = ["psd_factor", "LinearGaussianDynamics"]


def psd_factor(M, *, rtol: float = 1e-12) -> np.ndarray:
    """A thin factor ``L`` (``d x rank``) with ``L L^T = M`` for a symmetric PSD matrix ``M``.

    Eigenvalues below ``rtol * max(eig)`` are treated as zero and their columns dropped, so a
    rank-deficient ``M`` (e.g. zheng2014's white-noise-acceleration ``Q``, rank 1) is sampled with
    ``rank`` normals per draw. ``M = 0`` gives a ``d x 0`` factor.

    Parameters
    ----------
    M : array_like
        A covariance ``(d, d)``: finite, symmetric and positive semi-definite (tolerances of
        :func:`fusioncenter._validate.covariance`).
    rtol : float
        Relative threshold below which an eigenvalue counts as zero, in ``[0, 1)``.

    Returns
    -------
    numpy.ndarray
        ``L`` shaped ``(d, rank)``.

    Raises
    ------
    ValueError
        If ``M`` is not finite, not square (or ``0x0``), not symmetric or not PSD, or ``rtol``
        is out of range.
    """
    M = _nonempty("M", _covariance("M", M), "a 0x0 covariance has no state")
    rtol = float(_finite("rtol", rtol))
    if not 0.0 <= rtol < 1.0:
        raise ValueError(f"rtol must lie in [0, 1), got {rtol!r}")
    w, V = np.linalg.eigh(0.5 * (M + M.T))
    top = max(float(w.max(initial=0.0)), 0.0)
    keep = w > rtol * top if top > 0 else np.zeros_like(w, dtype=bool)
    return V[:, keep] * np.sqrt(w[keep])


def _matrix(name: str, value, shape=None) -> np.ndarray:
    arr = np.asarray(value, dtype=float) if not is_text(value) else _finite(name, value)
    if arr.ndim != 2 or (shape is not None and arr.shape != shape):
        raise ValueError(f"{name} must be a matrix of shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr


def _psd(name: str, value, d: int) -> np.ndarray:
    arr = _matrix(name, value, (d, d))
    scale = max(1.0, float(np.abs(arr).max()))
    if np.any(np.abs(arr - arr.T) > 1e-10 * scale):
        raise ValueError(f"{name} must be symmetric")
    arr = 0.5 * (arr + arr.T)
    if np.linalg.eigvalsh(arr).min() < -1e-10 * scale:
        raise ValueError(f"{name} must be positive semi-definite (a covariance)")
    return arr


@dataclass(frozen=True, init=False)
class LinearGaussianDynamics:
    """``x_0 ~ N(m0, P0)``, ``x_t = A x_{t-1} + u_{t-1}``, ``u ~ N(0, Q)`` (zheng2014 eq. (1)).

    The initial law and the transition of a :class:`FilterModel`; a scenario combines it with its
    observation model. ``Q`` and ``P0`` may be singular (only ``rank`` normals are drawn). The
    letters are the library's (:mod:`fusioncenter.kalman`); zheng2014's ``F`` is an alias: the
    keyword ``F=`` is accepted for ``A`` and the attribute ``F`` returns ``A``.

    Parameters
    ----------
    A, Q, m0, P0 : array_like
        As the fields of :class:`fusioncenter.kalman.LinearGaussianModel` (``F=`` is accepted
        for ``A``); ``Q`` and ``P0`` are stored symmetrized.

    Raises
    ------
    ValueError
        If ``A`` and ``F`` are both given or both missing, or a field is not finite, of the
        wrong shape (``A`` ``0x0``: no state) or (``Q``, ``P0``) not a covariance; the message
        names it.
    """

    A: np.ndarray
    Q: np.ndarray
    m0: np.ndarray
    P0: np.ndarray

    def __init__(self, A=None, Q=None, m0=None, P0=None, *, F=None) -> None:
        if (A is None) == (F is None):
            raise ValueError("give the state transition once, as A (or its alias F)")
        name, A = ("A", A) if F is None else ("F", F)
        A = _nonempty(name, _square(name, _matrix(name, A)))
        d = A.shape[0]
        mean = np.asarray(m0, dtype=float).reshape(-1)
        if mean.shape != (d,) or not np.all(np.isfinite(mean)):
            raise ValueError(f"m0 must be a finite vector of length {d}, got {m0!r}")
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "Q", _psd("Q", Q, d))
        object.__setattr__(self, "m0", mean)
        object.__setattr__(self, "P0", _psd("P0", P0, d))
        object.__setattr__(self, "_LQ", psd_factor(self.Q))
        object.__setattr__(self, "_L0", psd_factor(self.P0))

    @property
    def F(self) -> np.ndarray:
        """zheng2014's name for ``A`` (read-only alias)."""
        return self.A

    @property
    def dim(self) -> int:
        """The state dimension ``d``."""
        return self.A.shape[0]

    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """``(n, P, d)`` draws from ``N(m0, P0)`` (no random numbers used when ``P0 = 0``).

        Parameters
        ----------
        rng : numpy.random.Generator
            The random stream (``rank(P0)`` normals per particle).
        n, P : int
            Trials and particles per trial.

        Returns
        -------
        numpy.ndarray
            The particles ``(n, P, d)``, C-contiguous.
        """
        x = np.broadcast_to(self.m0, (n, P, self.dim)).copy()
        if self._L0.shape[1]:
            x += rng.standard_normal((n, P, self._L0.shape[1])) @ self._L0.T
        return x

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """``A x + u`` for every particle. On an SFC64 or PCG64 (NumPy's default) stream the
        normals are drawn inside the compiled pass, NumPy's numbers bit for bit
        (:mod:`fusioncenter._compiled.ziggurat`).

        Parameters
        ----------
        rng : numpy.random.Generator
            The random stream (``rank(Q)`` normals per particle).
        t : int
            The time step (unused: the dynamics do not change with time).
        x : numpy.ndarray
            The particles ``(..., d)``.

        Returns
        -------
        numpy.ndarray
            The new particles, a new array of ``x``'s shape.
        """
        # stacked matmul: one small BLAS call per trial (a single (n P) x d product would be
        # split over BLAS threads, which is slow for d = 2 on a busy machine)
        k = self._LQ.shape[1]
        if (x.ndim == 3 and x.shape[1] >= 2 and x.shape[2] >= 2 and x.dtype == np.float64
                and x.flags.c_contiguous):
            # compiled: the arithmetic of BLAS dgemm (what matmul calls here) in one pass
            out = np.empty_like(x)
            bits = type(rng.bit_generator)
            draw = {np.random.SFC64: (ziggurat.tables,
                                      transitions.linear_transition_draw),
                    np.random.PCG64: (ziggurat.pcg64_tables,
                                      transitions.linear_transition_draw_pcg64),
                    }.get(bits) if k else None
            zig = draw[0]() if draw else None
            if zig is not None:  # NumPy's normals drawn inside the pass, in the same order
                st = ziggurat.draw_state(rng)
                draw[1](x, self.A, self._LQ, st, *zig, out)
                ziggurat.set_state(rng, st)
                return out
            g = rng.standard_normal((*x.shape[:-1], k)) if k else np.empty((*x.shape[:2], 0))
            transitions.linear_transition(x, self.A, g, self._LQ, out)
            return out
        out = x @ self.A.T
        if k:
            out += rng.standard_normal((*x.shape[:-1], k)) @ self._LQ.T
        return out
