"""Kalman filtering over fading channels (dey2009): the random Riccati equation and its bounds.

A sensor amplifies and forwards its measurement over a fading channel with power gain
``r = h^2``; the fusion centre knows ``h`` and runs the Kalman filter. For a scalar state
(the paper's model (5), ``c = 1``) the prediction variance obeys the random Riccati equation (15)

    ``p_{k+1} = sigma_w2 + a^2 p_k (r sigma_v2 + sigma_n2) / (r (p_k + sigma_v2) + sigma_n2)``.

Everything here is written in terms of one expectation of the channel law,

    ``g(b) = E[b / (r + b)]``  (:meth:`Rayleigh.ratio_mean`),

because the posterior variance is ``p - p^2 / (p + sigma_v2) * r / (r + b)`` with
``b = sigma_n2 / (p + sigma_v2)``, so ``E_r[posterior] = p (sigma_v2 + p g(b)) / (p + sigma_v2)``.
For Rayleigh fading ``g(b) = mu e^mu E1(mu)`` with ``mu = lam b`` (the paper's (17), whose
``m_k``; the book writes μ so that ``m`` is the Nakagami shape alone); for
Nakagami(1/2) ``g(b) = sqrt(pi) u erfcx(u)`` with ``u = sqrt(lam b / 2)`` ((19)); for general
Nakagami-m ``g(b) = z^m U(m, m, z)`` with ``z = lam m b`` (Tricomi's confluent hypergeometric U).

Entry points (the variances are passed as variances):

* channel laws :class:`Rayleigh` and :class:`Nakagami` (sampling, the expectations, the
  inequalities the loose bounds use);
* :func:`scalar_mc` / :func:`scalar_paths`: ``E[p_k]`` by Monte Carlo of (15) through
  :func:`fusioncenter.montecarlo.simulate`; :func:`scalar_bounds` the tight and loose bound
  sequences ((17)-(18) Rayleigh, (19)-(20) Nakagami(1/2)); :func:`scalar_bound_limits` their
  fixed points;
* :func:`multisensor_mc` / :func:`multisensor_paths` and :func:`multisensor_bounds` (the
  worst-sensor bound ``s`` and the AM-HM bound ``t``) for the multi-access (7) and orthogonal (8)
  schemes under Rayleigh fading;
* :func:`vector_mc` / :func:`vector_paths` and :func:`vector_bound` (the sequence ``Zbar_k`` of
  the vector-state, scalar-measurement section 3.2);
* :func:`exp_e1`, a numerically safe ``e^x E1(x)``.

The package is split by concern (each module imports only those before it):
:mod:`~fusioncenter.fading.channels` (the special functions and the channel laws),
:mod:`~fusioncenter.fading.scalar` (the scalar equation (15): Monte Carlo, bounds, limits),
:mod:`~fusioncenter.fading.multisensor` (Section 3.3) and :mod:`~fusioncenter.fading.vector`
(Section 3.2); the argument checks, the runner of the variance paths and the glossary of argument
descriptions they share are in the private ``_common``. The names below are re-exported here.
"""

from __future__ import annotations

from fusioncenter.fading import channels, multisensor, scalar, vector
from fusioncenter.fading.channels import Nakagami, Rayleigh, exp_e1
from fusioncenter.fading.multisensor import (
    ACCESS_SCHEMES,
    multisensor_bound_limits,
    multisensor_bounds,
    multisensor_mc,
    multisensor_paths,
)
from fusioncenter.fading.scalar import (
    expected_posterior,
    nakagami_q_as_printed,
    scalar_bound_limits,
    scalar_bounds,
    scalar_mc,
    scalar_paths,
)
from fusioncenter.fading.vector import triu_to_symmetric, vector_bound, vector_mc, vector_paths

__all__ = [
    "channels",
    "multisensor",
    "scalar",
    "vector",
    "ACCESS_SCHEMES",
    "Nakagami",
    "Rayleigh",
    "exp_e1",
    "expected_posterior",
    "multisensor_bound_limits",
    "multisensor_bounds",
    "multisensor_mc",
    "multisensor_paths",
    "nakagami_q_as_printed",
    "scalar_bound_limits",
    "scalar_bounds",
    "scalar_mc",
    "scalar_paths",
    "triu_to_symmetric",
    "vector_bound",
    "vector_mc",
    "vector_paths",
]
