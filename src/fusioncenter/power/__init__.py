"""Steady states, 1/M laws and optimal power allocation for analog forwarding (leong2011).

Model (scalar state, ``M`` sensors, |a| < 1)::

    x_{k+1} = a x_k + w_k,          w_k ~ N(0, sigma_w2)
    y_{i,k} = c_i x_k + v_{i,k},    v_{i,k} ~ N(0, sigma_v2[i])

Sensor ``i`` forwards ``alpha_i y_{i,k}`` over a channel of gain ``h_i > 0`` (after transmit
beamforming with channel-state information, CSI). The fusion centre receives either the sum
(``"multi-access"``, eq. (2)) or every signal on its own channel (``"orthogonal"``), each with
receiver noise of variance ``sigma_n2``. The Kalman filter's steady-state prediction variance is
eq. (8) in the signal-to-noise ratio

* multi-access  ``S   = (sum alpha_i h_i c_i)^2 / (sum alpha_i^2 h_i^2 sigma_v2_i + sigma_n2)``
* orthogonal    ``S^o = sum alpha_i^2 h_i^2 c_i^2 / (alpha_i^2 h_i^2 sigma_v2_i + sigma_n2)``

and sensor ``i`` spends ``gamma_i = alpha_i^2 kappa_i`` with ``kappa_i = E[y_i^2] = c_i^2
sigma_w2 / (1 - a^2) + sigma_v2_i``.

Conventions: every variance is a variance (never a standard deviation); ``h``, ``c``,
``sigma_v2`` and ``alpha`` are per-sensor arrays whose *last* axis indexes the sensors (leading
axes, if any, broadcast: many realizations at once); ``access`` is ``"multi-access"`` or
``"orthogonal"``. Bad input raises ``ValueError`` naming the argument; an unreachable error target
raises :class:`InfeasibleError` (a ``ValueError``) whose message states the threshold.

The four allocation problems of Section IV are solved in the paper's general form
(``rho_i``, ``tau_i``, ``kappa_i``, ``sigma_n2`` and ``x, y`` or ``gamma_total``):

==========================  =====================================  =========================
problem                     general solver                         printed solution
==========================  =====================================  =========================
(19) coherent, min power    :func:`coherent_min_power`             (20)-(22), correct
(23) coherent, max SNR      :func:`coherent_max_snr`               (24) has an erratum
(26) orthogonal, min power  :func:`orthogonal_min_power`           (27) + M_1 rule, erratum
(28) orthogonal, max SNR    :func:`orthogonal_max_snr`             (29) + M_1 rule, correct
==========================  =====================================  =========================

The static problems (18)/(25) and their converses are :func:`min_power` / :func:`min_error`;
with fading and CSI the greedy per-step problems (30)/(31) and their orthogonal counterparts are
:func:`csi_min_power_step`, :func:`csi_min_error_step` and the time loops :func:`greedy_min_power`
/ :func:`greedy_min_error`; without CSI the linear MMSE estimator (32)-(33) is
:func:`lmmse_matrices`, :func:`lmmse_filter` and its steady state :func:`lmmse_steady_state`.
:func:`solve_numerically` solves the same problems with SciPy's SLSQP (an independent check of
the closed forms). The errata are on the book's errata page, ``book/errata.md``.

The package is split by concern (each module imports only those before it):
:mod:`~fusioncenter.power.model` (stationary variance, ``kappa``, transmit power, the SNR, the
steady state (8) and its inverse), :mod:`~fusioncenter.power.asymptotics` (the 1/M laws and
Lemma 4), :mod:`~fusioncenter.power.allocation` (the four general problems and
:class:`InfeasibleError`), :mod:`~fusioncenter.power.static` (static channels and equal power),
:mod:`~fusioncenter.power.csi` (fading with CSI: the greedy steps and loops),
:mod:`~fusioncenter.power.lmmse` (fading without CSI) and :mod:`~fusioncenter.power.numerical`
(the SLSQP check). The argument checks and the glossary of argument descriptions they share are
in the private ``_common``. The names below are re-exported here.
"""

from __future__ import annotations

from fusioncenter.power import allocation, asymptotics, csi, lmmse, model, numerical, static
from fusioncenter.power._common import ACCESS
from fusioncenter.power.allocation import (
    InfeasibleError,
    coherent_max_snr,
    coherent_max_snr_printed,
    coherent_min_power,
    general_max_snr,
    general_min_power,
    orthogonal_max_snr,
    orthogonal_min_power,
)
from fusioncenter.power.asymptotics import lemma4_bounds, symmetric_asymptotics
from fusioncenter.power.csi import (
    csi_min_error_step,
    csi_min_power_step,
    greedy_min_error,
    greedy_min_power,
)
from fusioncenter.power.lmmse import (
    beamformed,
    lmmse_coefficients,
    lmmse_filter,
    lmmse_matrices,
    lmmse_min_error,
    lmmse_min_power,
    lmmse_snr,
    lmmse_steady_state,
    simulate_nocsi,
)
from fusioncenter.power.model import (
    kappa,
    required_snr,
    snr,
    static_coefficients,
    stationary_variance,
    steady_recursion,
    steady_state,
    transmit_power,
)
from fusioncenter.power.numerical import solve_numerically
from fusioncenter.power.static import equal_power, equal_power_min_power, min_error, min_power

__all__ = [
    "allocation",
    "asymptotics",
    "csi",
    "lmmse",
    "model",
    "numerical",
    "static",
    "ACCESS",
    "InfeasibleError",
    "stationary_variance",
    "kappa",
    "transmit_power",
    "steady_state",
    "required_snr",
    "snr",
    "symmetric_asymptotics",
    "lemma4_bounds",
    "coherent_min_power",
    "coherent_max_snr",
    "coherent_max_snr_printed",
    "orthogonal_min_power",
    "orthogonal_max_snr",
    "general_min_power",
    "general_max_snr",
    "static_coefficients",
    "min_power",
    "min_error",
    "equal_power",
    "equal_power_min_power",
    "csi_min_power_step",
    "csi_min_error_step",
    "greedy_min_power",
    "greedy_min_error",
    "steady_recursion",
    "beamformed",
    "lmmse_matrices",
    "lmmse_snr",
    "lmmse_coefficients",
    "lmmse_steady_state",
    "lmmse_min_power",
    "lmmse_min_error",
    "lmmse_filter",
    "simulate_nocsi",
    "solve_numerically",
]
