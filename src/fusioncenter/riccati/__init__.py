"""Kalman-filter covariance (Riccati) recursions and steady states.

Model: ``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k`` with ``w ~ N(0, Q)``, ``v ~ N(0, R)``.
``P`` denotes the *prediction* covariance ``P_{k|k-1}`` unless a name says otherwise:

* measurement update  ``P_{k|k}   = P - P C^T (C P C^T + R)^{-1} C P``
  (equivalently ``(P^{-1} + C^T R^{-1} C)^{-1}`` by the matrix inversion lemma);
* time update         ``P_{k+1|k} = A P_{k|k} A^T + Q``;
* one Riccati step    ``P_{k+1|k} = A P A^T + Q - A P C^T (C P C^T + R)^{-1} C P A^T``.

The matrix functions accept a leading batch axis (or several) on every argument and broadcast
them, so one call advances many Monte Carlo paths at once (random ``C_k`` as in fading channels).
The scalar functions broadcast like NumPy ufuncs.

The package: :mod:`~fusioncenter.riccati.scalar` (the scalar recursion and its steady state in
closed form), :mod:`~fusioncenter.riccati.matrix` (the batched matrix steps) and
:mod:`~fusioncenter.riccati.dare` (the matrix steady state); the names are re-exported here.
"""

from __future__ import annotations

from fusioncenter.riccati.dare import steady_state
from fusioncenter.riccati.matrix import (
    PINV_RCOND,
    measurement_update,
    riccati_sequence,
    riccati_step,
    singular,
    solve_psd,
)
from fusioncenter.riccati.scalar import (
    scalar_sequence,
    scalar_steady_state,
    scalar_step,
    scalar_update,
)

__all__ = [
    "scalar_update",
    "scalar_step",
    "scalar_sequence",
    "scalar_steady_state",
    "measurement_update",
    "riccati_step",
    "riccati_sequence",
    "steady_state",
    "solve_psd",
    "singular",
    "PINV_RCOND",
]
