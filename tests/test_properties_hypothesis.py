"""Issue 17, item 3: property-based tests of the public surface of riccati, kalman, models, fading,
power, event, ``particle.psd_factor`` and synthesis's Kalman-filter helpers.

Two kinds of properties:

* **invalid inputs**: :data:`ENTRY_POINTS` lists every public entry point with one valid call
  and, per argument, the kinds of bad value it must refuse (NaN, +-inf, a negative variance, a
  non-symmetric or indefinite covariance, a non-integer or boolean count or seed). Hypothesis
  picks an entry point, an argument and a bad value; the call must raise ``ValueError`` whose
  message names the argument.
* **valid inputs**: random valid inputs give finite outputs with the module's invariants:
  covariances symmetric PSD and never above the prior, probabilities in [0, 1], fixed points,
  monotonicity, bounds above Monte Carlo means, optimal allocations at least as good as equal
  power, closed forms of inverses.

``test_every_public_function_is_covered`` checks that the table covers each module's
``__all__`` (minus constants, classes documented as results, and the particle filters owned by
the censoring modules). Examples tried are counted in :data:`EXAMPLES` (printed with ``-s``).
Settings: at most 25-60 examples per property, ``deadline=None``; the file runs in about 20 s.
"""

from __future__ import annotations

import collections
import inspect
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fusioncenter import (
    censoring,
    comparison,
    event,
    fading,
    kalman,
    models,
    particle,
    power,
    riccati,
)
from fusioncenter.censoring import nonlinear
from fusioncenter.censoring import probability as cprob
from fusioncenter.fading import Nakagami, Rayleigh

EXAMPLES: collections.Counter = collections.Counter()
SETTINGS = settings(max_examples=40, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

RNG = np.random.default_rng


def fl(lo, hi):
    """Floats in ``[lo, hi]`` without subnormals (products of those lose their digits)."""
    return st.floats(lo, hi, allow_subnormal=False)


E2 = np.eye(2)
P2 = np.array([[2.0, 0.5], [0.5, 1.0]])
TRK = models.tracking_model(2)
H3, C3, V3 = np.array([1.0, 0.5, 2.0]), np.array([1.0, -0.5, 2.0]), np.array([1.0, 2.0, 0.5])

# --------------------------------------------------------------------------- the table
# kinds of bad value
NAN, INF, NINF, NEG, ASYM, INDEF, NOTINT, BOOL = ("nan", "inf", "-inf", "neg", "asym",
                                                  "indef", "notint", "bool")
# issue 29: numbers as text ("1" was converted silently), a wrong last-axis length (NumPy's
# matmul/broadcast message instead of the argument's name), ancestor indices out of range,
# negative (wrapped around silently) or not integers
TEXT, SHAPE, OUTIDX, NEGIDX, FLTIDX = "text", "shape", "outidx", "negidx", "fltidx"
NUM = (NAN, INF, NINF, TEXT)
VAR = NUM + (NEG,)
COV = NUM + (ASYM, INDEF)
INT = (NOTINT, BOOL)
IDX = (OUTIDX, NEGIDX, FLTIDX)
#: For entry points whose table lambda converts its arrays itself (text is no input there).
NUM0, COV0 = (NAN, INF, NINF), (NAN, INF, NINF, ASYM, INDEF)


def _bad(kind: str, good, where: int = 0, size: float = 1.0):
    """A bad value of ``kind`` shaped like ``good`` (``where``: which entry is spoiled, ``size``
    how far from valid)."""
    if kind in (OUTIDX, NEGIDX, FLTIDX):
        g = np.array(good).copy()
        if kind == FLTIDX:
            return g.astype(float)
        g.flat[where % max(g.size, 1)] = -1 if kind == NEGIDX else 10**6
        return g
    g = np.array(good, dtype=float)
    if kind == TEXT:  # the same numbers, written as text
        return str(float(g)) if g.ndim == 0 else g.astype(str)
    if kind == SHAPE:  # one entry too many on the last axis
        return np.concatenate([g, g[..., :1]], axis=-1)
    if kind in (NAN, INF, NINF):
        g = g.copy()
        g.flat[where % max(g.size, 1)] = {NAN: np.nan, INF: np.inf, NINF: -np.inf}[kind]
        return g
    if kind == NEG:
        g = g.copy()
        g.flat[where % max(g.size, 1)] = -size
        return g
    if kind == ASYM:
        out = g.copy()
        out[..., 0, -1] += size
        return out
    if kind == INDEF:
        return g - (np.abs(g).max() + size) * np.eye(g.shape[-1])
    if kind == NOTINT:
        return float(good) + 0.5
    if kind == BOOL:
        return True
    raise AssertionError(kind)


def _ch(lam=1.0):
    return Rayleigh(lam)


SC = dict(a=0.9, sigma_w2=1.0, sigma_v2=2.0, sigma_n2=3.0, channel=_ch(), p0=1.0, steps=3)
SC_BAD = dict(a=NUM, sigma_w2=VAR, sigma_v2=VAR, sigma_n2=VAR, p0=VAR, steps=INT)
MS = dict(access="orthogonal", a=0.9, c=[1.0, 0.5], sigma_v2=[1.0, 2.0], sigma_n2=2.0,
          lams=[1.0, 2.0], sigma_w2=1.0, p0=1.0, steps=3)
MS_BAD = dict(a=NUM, c=NUM, sigma_v2=VAR, sigma_n2=VAR, lams=VAR, sigma_w2=VAR, p0=VAR, steps=INT)
VEC = dict(A=0.9 * E2, c=[1.0, 0.5], Sigma_w=E2, sigma_v2=1.0, sigma_n2=2.0, channel=_ch(),
           P0=P2, steps=3)
VEC_BAD = dict(A=NUM, c=NUM, Sigma_w=COV, sigma_v2=VAR, sigma_n2=VAR, P0=COV, steps=INT)
ST = dict(a=0.5, sigma_w2=1.0, h=H3, c=C3, sigma_v2=V3, sigma_n2=1.0)
ST_BAD = dict(a=NUM, sigma_w2=VAR, h=VAR, c=NUM, sigma_v2=VAR, sigma_n2=VAR)
GEN = dict(rho=[1.0, 0.5], tau=[1.0, 2.0], kappa=[2.0, 3.0], sigma_n2=1.0)
GEN_BAD = dict(rho=NUM, tau=VAR, kappa=VAR, sigma_n2=VAR)
NOCSI = dict(a=0.5, sigma_w2=1.0, c=[1.0, 2.0], sigma_v2=[1.0, 2.0], sigma_n2=1.0,
             h_mean=[1.0, 0.8], h_var_re=[0.1, 0.2], h_var_im=[0.1, 0.2])
NOCSI_BAD = dict(a=NUM, sigma_w2=VAR, c=NUM, sigma_v2=VAR, sigma_n2=VAR, h_var_re=VAR,
                 h_var_im=VAR)
_CBAR, _RBAR = power.lmmse_matrices("multi-access", power.beamformed([1.0, 1.0], [1.0, 0.8]),
                                    **NOCSI)
EV = dict(xbar=np.zeros(2), Sigma=P2, C=np.array([[1.0, 0.0], [1.0, 1.0]]), R=np.ones(2),
          delta=np.ones(2), gamma=np.array([1, 0]), y=np.ones(2))


NL = nonlinear.NonlinearScenario()
#: A likelihood call: sensor 0 sent (its z must be finite), sensor 1 was silent.
LL = dict(sent=[True, False], z=[1.5, 0.0], hx=[1.0, 0.2], hx_pred=[0.8, 0.1], s=[2.0, 2.0],
          r=[1.0, 1.0], eta=1.0)


def _model(**kw):
    base = dict(A=0.9 * E2, Q=E2, C=[[1.0, 0.0]], R=[[1.0]], m0=[0.0, 1.0], P0=P2)
    return kalman.LinearGaussianModel(**{**base, **kw})


def _kf_filter(**kw):
    from fusioncenter import censoring
    sc = censoring.LinearScenario()
    d = _DRAW
    lost = np.zeros(d.z.shape, dtype=bool)
    args = dict(z=d.z, xi=d.xi, delta=1.0)
    args.update(kw)
    return comparison.kf_filter(sc, args["z"], args["xi"], lost, "stochastic",
                                delta=args["delta"])


# (qualified name, function of keyword arguments, valid keyword arguments, bad kinds per argument)
ENTRY_POINTS = [
    ("riccati.scalar_update", riccati.scalar_update, dict(p=1.0, c=1.0, r=1.0),
     dict(p=VAR, c=NUM, r=VAR)),
    ("riccati.scalar_step", riccati.scalar_step, dict(p=1.0, a=0.5, q=1.0, c=1.0, r=1.0),
     dict(p=VAR, a=NUM, q=VAR, c=NUM, r=VAR)),
    ("riccati.scalar_sequence", riccati.scalar_sequence,
     dict(p0=1.0, a=0.5, q=1.0, c=1.0, r=1.0, steps=3),
     dict(p0=VAR, a=NUM, q=VAR, c=NUM, r=VAR, steps=INT)),
    ("riccati.scalar_steady_state", riccati.scalar_steady_state, dict(a=0.5, q=1.0, c=1.0, r=1.0),
     dict(a=NUM, q=VAR, c=NUM, r=VAR)),
    ("riccati.measurement_update", riccati.measurement_update,
     dict(P=P2, C=[[1.0, 0.0]], R=[[1.0]]), dict(P=COV, C=NUM, R=COV)),
    ("riccati.riccati_step", riccati.riccati_step,
     dict(P=P2, A=E2, Q=E2, C=[[1.0, 0.0]], R=[[1.0]]), dict(P=COV, A=NUM, Q=COV, C=NUM, R=COV)),
    ("riccati.riccati_sequence", riccati.riccati_sequence,
     dict(P0=P2, A=E2, Q=E2, C=[[1.0, 0.0]], R=[[1.0]], steps=2),
     dict(P0=COV, A=NUM, Q=COV, C=NUM, R=COV, steps=INT)),
    ("riccati.steady_state", riccati.steady_state, dict(A=0.9 * E2, Q=E2, C=E2, R=E2),
     dict(A=NUM, Q=COV, C=NUM, R=COV)),
    ("riccati.solve_psd", lambda S, B: riccati.solve_psd(np.asarray(S), np.asarray(B)),
     dict(S=P2, B=np.ones((2, 1))), dict(S=NUM0, B=NUM0)),
    ("riccati.singular", riccati.singular, dict(R=P2), dict(R=NUM)),
    ("kalman.LinearGaussianModel", _model, {}, dict(A=NUM, Q=COV, C=NUM, R=COV, m0=NUM, P0=COV)),
    ("kalman.LinearGaussianModel.sample",
     lambda n, steps: _model().sample(RNG(0), n, steps), dict(n=2, steps=2),
     dict(n=INT, steps=INT)),
    ("kalman.LinearGaussianModel.filter", lambda y: _model().filter(y),
     dict(y=np.ones((2, 3, 1))), dict(y=NUM)),
    ("kalman.constant_velocity", kalman.constant_velocity, dict(dt=1.0, q=1.0, r=1.0),
     dict(dt=VAR, q=VAR, r=VAR)),
    ("models.tracking_model", models.tracking_model,
     dict(n_sensors=2, dt=1.0, sigma2=4.0, r=1.0, x0=(0.0, 10.0)),
     dict(n_sensors=INT, dt=VAR, sigma2=VAR, r=VAR, x0=NUM)),
    ("particle.psd_factor", particle.psd_factor, dict(M=P2), dict(M=COV)),
    ("fading.exp_e1", fading.exp_e1, dict(x=1.0), dict(x=(NAN, NEG))),
    ("fading.Rayleigh", Rayleigh, dict(lam=1.0), dict(lam=VAR)),
    ("fading.Nakagami", Nakagami, dict(m=2.0, lam=1.0), dict(m=VAR, lam=VAR)),
    ("fading.Rayleigh.ratio_mean", lambda b: _ch().ratio_mean(b), dict(b=1.0),
     dict(b=(NAN, NEG))),
    ("fading.Rayleigh.ratio_mean_bound", lambda b: _ch().ratio_mean_bound(b), dict(b=1.0),
     dict(b=(NAN, NEG))),
    ("fading.Rayleigh.inverse_mean", lambda b: _ch().inverse_mean(b), dict(b=1.0), dict(b=VAR)),
    ("fading.Rayleigh.pdf", lambda r: _ch().pdf(r), dict(r=1.0), dict(r=(NAN,))),
    ("fading.Nakagami.ratio_mean", lambda b: Nakagami(2.5, 1.0).ratio_mean(b), dict(b=1.0),
     dict(b=(NAN, NEG))),
    ("fading.Nakagami.ratio_mean_bound", lambda b: Nakagami(0.5, 1.0).ratio_mean_bound(b),
     dict(b=1.0), dict(b=(NAN, NEG))),
    ("fading.Nakagami.inverse_mean", lambda b: Nakagami(0.5, 1.0).inverse_mean(b), dict(b=1.0),
     dict(b=VAR)),
    ("fading.Nakagami.pdf", lambda r: Nakagami(2.0, 1.0).pdf(r), dict(r=1.0), dict(r=(NAN,))),
    ("fading.expected_posterior", fading.expected_posterior,
     dict(p=1.0, sigma_v2=1.0, sigma_n2=1.0, channel=_ch()),
     dict(p=VAR, sigma_v2=VAR, sigma_n2=VAR)),
    ("fading.scalar_bounds", fading.scalar_bounds, SC, SC_BAD),
    ("fading.scalar_bound_limits", fading.scalar_bound_limits,
     {k: v for k, v in SC.items() if k not in ("p0", "steps")},
     {k: v for k, v in SC_BAD.items() if k not in ("p0", "steps")}),
    ("fading.scalar_mc", fading.scalar_mc, dict(SC, n_paths=4, seed=0),
     dict(SC_BAD, n_paths=INT, seed=INT)),
    ("fading.scalar_paths", fading.scalar_paths, dict(SC, n_paths=4, seed=0),
     dict(SC_BAD, n_paths=INT, seed=INT)),
    ("fading.nakagami_q_as_printed", fading.nakagami_q_as_printed,
     dict(a=0.9, sigma_w2=1.0, sigma_v2=2.0, sigma_n2=3.0, lam=1.0, p0=1.0, steps=3),
     dict(a=NUM, sigma_w2=VAR, sigma_v2=VAR, sigma_n2=VAR, lam=VAR, p0=VAR, steps=INT)),
    ("fading.multisensor_bounds", fading.multisensor_bounds, MS, MS_BAD),
    ("fading.multisensor_bound_limits", fading.multisensor_bound_limits,
     {k: v for k, v in MS.items() if k not in ("p0", "steps")},
     {k: v for k, v in MS_BAD.items() if k not in ("p0", "steps")}),
    ("fading.multisensor_mc", fading.multisensor_mc, dict(MS, n_paths=4, seed=0),
     dict(MS_BAD, n_paths=INT, seed=INT)),
    ("fading.multisensor_paths", fading.multisensor_paths, dict(MS, n_paths=4, seed=0),
     dict(MS_BAD, n_paths=INT, seed=INT)),
    ("fading.vector_bound", fading.vector_bound, VEC, VEC_BAD),
    ("fading.vector_mc", fading.vector_mc, dict(VEC, n_paths=4, seed=0),
     dict(VEC_BAD, n_paths=INT, seed=INT)),
    ("fading.vector_paths", fading.vector_paths, dict(VEC, n_paths=4, seed=0),
     dict(VEC_BAD, n_paths=INT, seed=INT)),
    ("fading.triu_to_symmetric", fading.triu_to_symmetric, dict(x=[1.0, 0.5, 2.0], n=2),
     dict(x=NUM, n=INT)),
    ("power.stationary_variance", power.stationary_variance, dict(a=0.5, sigma_w2=1.0),
     dict(a=NUM, sigma_w2=VAR)),
    ("power.kappa", power.kappa, dict(a=0.5, sigma_w2=1.0, c=C3, sigma_v2=V3),
     dict(a=NUM, sigma_w2=VAR, c=NUM, sigma_v2=VAR)),
    ("power.transmit_power", power.transmit_power,
     dict(alpha=[1.0, 1.0, 1.0], a=0.5, sigma_w2=1.0, c=C3, sigma_v2=V3),
     dict(alpha=NUM, a=NUM, sigma_w2=VAR, c=NUM, sigma_v2=VAR)),
    ("power.steady_state", power.steady_state, dict(a=0.5, sigma_w2=1.0, S=2.0),
     dict(a=NUM, sigma_w2=VAR, S=VAR)),
    ("power.steady_recursion", power.steady_recursion, dict(P=1.0, a=0.5, sigma_w2=1.0, S=2.0),
     dict(P=VAR, a=NUM, sigma_w2=VAR, S=VAR)),
    ("power.required_snr", power.required_snr, dict(D=1.2, a=0.5, sigma_w2=1.0),
     dict(D=VAR, a=NUM, sigma_w2=VAR)),
    ("power.snr", power.snr, dict(access="orthogonal", alpha=[1.0, 1.0, 1.0], h=H3, c=C3,
                                  sigma_v2=V3, sigma_n2=1.0),
     dict(alpha=NUM, h=VAR, c=NUM, sigma_v2=VAR, sigma_n2=VAR)),
    ("power.symmetric_asymptotics", power.symmetric_asymptotics,
     dict(access="orthogonal", scaling="sqrt", a=0.5, sigma_w2=1.0, h=1.0, c=1.0, sigma_v2=1.0,
          sigma_n2=1.0), dict(a=NUM, sigma_w2=VAR, h=VAR, c=NUM, sigma_v2=VAR, sigma_n2=VAR)),
    ("power.lemma4_bounds", power.lemma4_bounds,
     dict(M=4, a=0.5, sigma_w2=1.0, sigma_n2=1.0, h_range=(0.5, 1.0), c_range=(0.5, 1.0),
          sigma_v2_range=(1.0, 2.0)),
     dict(M=VAR, a=NUM, sigma_w2=VAR, sigma_n2=VAR, h_range=VAR, c_range=VAR,
          sigma_v2_range=VAR)),
    ("power.coherent_min_power", power.coherent_min_power, dict(GEN, x=0.1, y=0.5),
     dict(GEN_BAD, x=VAR, y=VAR)),
    ("power.orthogonal_min_power", power.orthogonal_min_power, dict(GEN, x=0.1, y=0.5),
     dict(GEN_BAD, x=VAR, y=VAR)),
    ("power.coherent_max_snr", power.coherent_max_snr, dict(GEN, gamma_total=1.0),
     dict(GEN_BAD, gamma_total=VAR)),
    ("power.coherent_max_snr_printed", power.coherent_max_snr_printed,
     dict(GEN, gamma_total=1.0), dict(GEN_BAD, gamma_total=VAR)),
    ("power.orthogonal_max_snr", power.orthogonal_max_snr, dict(GEN, gamma_total=1.0),
     dict(GEN_BAD, gamma_total=VAR)),
    ("power.general_min_power", power.general_min_power,
     dict(GEN, access="multi-access", x=0.1, y=0.5), dict(GEN_BAD, x=VAR, y=VAR)),
    ("power.general_max_snr", power.general_max_snr,
     dict(GEN, access="orthogonal", gamma_total=1.0), dict(GEN_BAD, gamma_total=VAR)),
    ("power.solve_numerically", lambda **kw: power.solve_numerically("orthogonal-max-snr", **kw),
     dict(GEN, gamma_total=1.0, starts=1, seed=0),
     dict(GEN_BAD, gamma_total=VAR, starts=INT, seed=INT)),
    ("power.static_coefficients", power.static_coefficients,
     {k: v for k, v in ST.items() if k != "sigma_n2"},
     {k: v for k, v in ST_BAD.items() if k != "sigma_n2"}),
    ("power.min_power", power.min_power, dict(ST, access="orthogonal", D=1.1),
     dict(ST_BAD, D=VAR)),
    ("power.min_error", power.min_error, dict(ST, access="orthogonal", gamma_total=1.0),
     dict(ST_BAD, gamma_total=VAR)),
    ("power.equal_power", power.equal_power,
     dict(a=0.5, sigma_w2=1.0, c=C3, sigma_v2=V3, gamma_total=1.0),
     dict(a=NUM, sigma_w2=VAR, c=NUM, sigma_v2=VAR, gamma_total=VAR)),
    ("power.equal_power_min_power", power.equal_power_min_power,
     dict(ST, access="orthogonal", D=1.1), dict(ST_BAD, D=VAR)),
    ("power.csi_min_power_step", power.csi_min_power_step,
     dict(ST, access="orthogonal", P=1.2, D=1.1), dict(ST_BAD, P=VAR, D=VAR)),
    ("power.csi_min_error_step", power.csi_min_error_step,
     dict(ST, access="orthogonal", gamma_total=1.0), dict(ST_BAD, gamma_total=VAR)),
    ("power.greedy_min_power", power.greedy_min_power,
     dict(ST, access="orthogonal", D=1.1, h=np.ones((2, 3))), dict(ST_BAD, D=VAR)),
    ("power.greedy_min_error", power.greedy_min_error,
     dict(ST, access="orthogonal", gamma_total=1.0, h=np.ones((2, 3))),
     dict(ST_BAD, gamma_total=VAR)),
    ("power.beamformed", power.beamformed, dict(alpha=[1.0, 1.0], h_mean=[1.0, 0.8]),
     dict(alpha=NUM, h_mean=NUM)),
    ("power.lmmse_matrices", power.lmmse_matrices,
     dict(NOCSI, access="multi-access", alpha_t=[1.0, 1.0]), NOCSI_BAD),
    ("power.lmmse_snr", power.lmmse_snr, dict(Cbar=_CBAR, Rbar=_RBAR),
     dict(Cbar=NUM, Rbar=COV)),
    ("power.lmmse_coefficients", power.lmmse_coefficients,
     {k: v for k, v in NOCSI.items() if k != "sigma_n2"},
     {k: v for k, v in NOCSI_BAD.items() if k != "sigma_n2"}),
    ("power.lmmse_steady_state", power.lmmse_steady_state,
     dict(NOCSI, access="multi-access", alpha=[1.0, 1.0]), NOCSI_BAD),
    ("power.lmmse_min_power", power.lmmse_min_power, dict(NOCSI, access="orthogonal", D=1.2),
     dict(NOCSI_BAD, D=VAR)),
    ("power.lmmse_min_error", power.lmmse_min_error,
     dict(NOCSI, access="orthogonal", gamma_total=1.0), dict(NOCSI_BAD, gamma_total=VAR)),
    ("power.lmmse_filter", power.lmmse_filter,
     dict(z=np.ones((3, 2)), a=0.5, sigma_w2=1.0, Cbar=_CBAR, Rbar=_RBAR),
     dict(z=NUM, a=NUM, sigma_w2=VAR, Cbar=NUM, Rbar=COV)),
    ("power.simulate_nocsi", lambda **kw: power.simulate_nocsi(RNG(0), **kw),
     dict(NOCSI, n=2, steps=3, access="multi-access", alpha_t=[1.0, 1.0]),
     dict(NOCSI_BAD, n=INT, steps=INT)),
    ("event.trigger_probability", event.trigger_probability, dict(s=1.0, delta=1.0, mu=0.5),
     dict(s=VAR, delta=VAR, mu=NUM)),
    ("event.communication_rate", event.communication_rate,
     {k: EV[k] for k in ("Sigma", "C", "R", "delta")},
     dict(Sigma=COV, C=NUM, R=VAR, delta=VAR)),
    ("event.delta_for_rate", event.delta_for_rate, dict(rate=0.5, s=1.0, mu=0.5),
     dict(rate=VAR, s=VAR, mu=NUM)),
    ("event.sample_trigger", lambda **kw: event.sample_trigger(RNG(0), **kw),
     dict(y=np.ones(2), delta=1.0), dict(y=NUM, delta=VAR)),
    ("event.posterior", event.posterior, EV,
     dict(xbar=NUM, Sigma=COV, C=NUM, R=VAR, delta=VAR, y=(NAN, INF))),
    ("event.steady_state_delta", lambda **kw: event.steady_state_delta(TRK, **kw),
     dict(rate=0.5), dict(rate=VAR)),
    ("event.calibrate_delta", lambda **kw: event.calibrate_delta(TRK, **kw),
     dict(rate=0.5, n_trials=8, steps=6, burn_in=2, seed=0, max_iter=2, tol=0.5),
     dict(rate=VAR, steps=INT, burn_in=INT, seed=INT, n_trials=INT)),
    ("event.event_kf_run", lambda **kw: event.event_kf_run(TRK, rng=RNG(0), **kw),
     dict(steps=3, scheme="stochastic", n_trials=2, delta=1.0),
     dict(steps=INT, n_trials=INT, delta=VAR)),
    ("event.event_kf_chunk", lambda **kw: event.event_kf_chunk(RNG(0), model=TRK, **kw),
     dict(n=2, steps=3, scheme="stochastic", delta=1.0), dict(n=INT, steps=INT, delta=VAR)),
    ("comparison.outage_threshold", comparison.outage_threshold, dict(outage=0.1),
     dict(outage=VAR)),
    ("comparison.energy_matched_outage", comparison.energy_matched_outage,
     dict(outage_full=0.1, rate=0.5), dict(outage_full=VAR, rate=VAR)),
    ("kalman.kalman_step",
     lambda x, P, innov, C, R: kalman.kalman_step(
         np.asarray(x, float), np.asarray(P, float), np.asarray(innov, float),
         np.asarray(C, float), np.asarray(R, float), 0.9 * E2, E2, check=True),
     dict(x=np.zeros((3, 2)), P=P2, innov=np.ones((3, 1)), C=[[1.0, 0.0]], R=[[1.0]]),
     dict(P=COV0, R=COV0)),
    ("models.wna_model", models.wna_model, dict(dt=1.0), dict(dt=VAR)),
    ("comparison.kf_filter", _kf_filter, {}, dict(z=NUM, xi=NUM, delta=VAR)),
    # issue 29: shapes of the Kalman step and the Riccati step, named with the expected shape
    ("kalman.kalman_step(shapes)",
     lambda x, innov, A, Q: kalman.kalman_step(
         np.asarray(x), P2, np.asarray(innov), np.array([[1.0, 0.0]]), np.eye(1),
         np.asarray(A), np.asarray(Q), check=True),
     dict(x=np.zeros((3, 2)), innov=np.ones((3, 1)), A=0.9 * E2, Q=E2),
     dict(x=(SHAPE,), innov=(SHAPE,), A=(SHAPE,), Q=(SHAPE,))),
    ("riccati.riccati_step(shapes)",
     lambda A, Q: riccati.riccati_step(P2, A, Q, [[1.0, 0.0]], [[1.0]]),
     dict(A=0.9 * E2, Q=E2), dict(A=(SHAPE,), Q=(SHAPE,))),
    # the nonlinear censoring (zheng2014 Section VI) and its likelihoods
    ("censoring.nonlinear.log_silent_probability", nonlinear.log_silent_probability,
     dict(m=[0.5, -1.0], h=[1.0, 2.0]), dict(m=NUM + (SHAPE,), h=(NAN, NEG, TEXT, SHAPE))),
    ("censoring.nonlinear.amplitude", lambda pos: nonlinear.amplitude(NL, pos),
     dict(pos=[1.0, -2.0]), dict(pos=(NAN, TEXT, SHAPE))),
    ("censoring.nonlinear.jacobian", lambda x: nonlinear.jacobian(NL, x),
     dict(x=[1.0, 0.5, -2.0, 0.1]), dict(x=NUM + (SHAPE,))),
    ("censoring.nonlinear.ekf_covariance_step", nonlinear.ekf_covariance_step,
     dict(P=np.eye(4), g=[0.5, 0.0, -0.2, 0.0], F=np.eye(4), Q=np.eye(4), r=1.0),
     dict(P=COV + (SHAPE,), g=NUM + (SHAPE,), F=NUM + (SHAPE,), Q=COV + (SHAPE,), r=VAR)),
    ("censoring.nonlinear.silent_terms", nonlinear.silent_terms,
     dict(a=np.array([[0.0, 0.5, 1.0]]), h=np.array([1.5])), dict(a=VAR, h=VAR + (SHAPE,))),
    ("censoring.nonlinear.log_likelihood", nonlinear.log_likelihood, LL,
     dict(z=(NAN, INF, TEXT, SHAPE), hx=NUM, hx_pred=NUM, s=VAR, r=VAR, eta=VAR)),
    ("censoring.log_likelihood_feedback", censoring.log_likelihood_feedback, LL,
     dict(z=(NAN, INF, TEXT, SHAPE), hx=NUM, hx_pred=NUM, s=VAR, r=VAR, eta=VAR)),
    # the censoring probabilities (checked entry points of the filters' kernels)
    ("censoring.probability.log_prob_inside", cprob.log_prob_inside,
     dict(m=[0.5, -1.0], h=[1.0, 2.0]), dict(m=NUM + (SHAPE,), h=(NAN, NEG, TEXT))),
    ("censoring.probability.prob_inside", lambda m, h: cprob.prob_inside(m, h, log=False),
     dict(m=[0.5, -1.0], h=[1.0, 2.0]), dict(m=NUM, h=(NAN, NEG, TEXT))),
    ("censoring.probability.truncated_normal", cprob.truncated_normal,
     dict(u=[0.2, 0.7], lo=[-1.0, 0.5], hi=[1.0, 3.0]), dict(u=VAR, lo=(NAN, TEXT))),
    ("censoring.probability.log_silent_constant", cprob.log_silent_constant,
     dict(Vcov=P2, a=[1.0, 2.0]), dict(Vcov=COV, a=VAR)),
    ("censoring.probability.log_region_probability", cprob.log_region_probability,
     dict(c=[0.5, -0.5], cov=P2, a=[1.0, 2.0], outside=(True, False)),
     dict(c=NUM, cov=COV, a=VAR)),
    # the particle helpers: ancestor indices and weighted statistics
    ("particle.resample", lambda x, idx: particle.resample(x, idx),
     dict(x=np.arange(12.0).reshape(2, 3, 2), idx=np.array([[0, 2, 2], [1, 1, 0]])),
     dict(idx=IDX)),
    ("particle.weighted_mean", particle.weighted_mean,
     dict(x=np.arange(6.0).reshape(3, 2), logw=[0.0, -1.0, -2.0]), dict(x=NUM, logw=(SHAPE,))),
    ("particle.weighted_mean_cov", particle.weighted_mean_cov,
     dict(x=np.arange(6.0).reshape(3, 2), logw=[0.0, -1.0, -2.0]), dict(x=NUM, logw=(SHAPE,))),
]

#: Public names deliberately not in the table: constants, result containers, and what other
#: modules own (the particle filters of synthesis belong to the censoring engine's helper).
NOT_ENTRY_POINTS = {
    "riccati.PINV_RCOND", "fading.ACCESS_SCHEMES", "power.ACCESS", "power.InfeasibleError",
    "event.SCHEMES", "kalman.KalmanStep",
    "event.Calibration", "event.EventKFRun", "event.split_summary",
    "comparison.KF_SCHEMES", "comparison.PF_SCHEMES", "comparison.RECEIVERS", "comparison.Draw",
    "comparison.KFOutput", "comparison.KFRun", "comparison.Summary", "comparison.run_pf",
    "comparison.summary_from_censoring", "comparison.scenario_model", "comparison.draw",
    "comparison.kf_chunk", "comparison.run_kf", "comparison.kf_flops", "comparison.pf_flops",
}
@pytest.fixture(scope="module", autouse=True)
def _report_examples():
    """After the module: how many examples each property tried (shown with ``-s``)."""
    yield
    print(f"\nhypothesis suite: {len(ENTRY_POINTS)} entry points, {len(_CASES)} invalid-input "
          f"cases; examples tried: {dict(EXAMPLES)} (total {sum(EXAMPLES.values())})")


def _good_args(name):
    for e in ENTRY_POINTS:
        if e[0] == name:
            fn, good = e[1], e[2]
    if name == "kalman.LinearGaussianModel":
        good = dict(A=0.9 * E2, Q=E2, C=[[1.0, 0.0]], R=[[1.0]], m0=[0.0, 1.0], P0=P2)
    if name == "comparison.kf_filter":
        good = dict(z=_DRAW.z, xi=_DRAW.xi, delta=1.0)
    return fn, good


def _draw():
    from fusioncenter import censoring
    return comparison.draw(RNG(0), 2, censoring.LinearScenario())


_DRAW = _draw()
_CASES = [(name, arg, kind) for name, _, _, bad in ENTRY_POINTS for arg, kinds in bad.items()
          for kind in kinds
          if not (kind == ASYM and np.shape(_good_args(name)[1][arg])[-1:] == (1,))]


#: Entry points whose measurement argument is checked only where a sensor sent (the first).
_SENT_FIRST = {("event.posterior", "y"), ("censoring.nonlinear.log_likelihood", "z"),
               ("censoring.log_likelihood_feedback", "z")}


def test_every_public_function_is_covered():
    names = {e[0] for e in ENTRY_POINTS}
    for mod in (riccati, kalman, models, fading, power, event, comparison):
        short = mod.__name__.rsplit(".", 1)[1]
        for attr in mod.__all__:
            if inspect.ismodule(getattr(mod, attr)):  # a package's submodule
                continue
            qual = f"{short}.{attr}"
            assert qual in names or qual in NOT_ENTRY_POINTS, f"{qual} is not covered"
    for name, fn, good, _ in ENTRY_POINTS:  # every valid call is valid and finite
        out = fn(**good)
        leaves = out if isinstance(out, tuple | list) else [out]
        for leaf in leaves:
            if isinstance(leaf, dict):
                leaf = list(leaf.values())
            if isinstance(leaf, np.ndarray | float | int | list):
                assert np.all(np.isfinite(np.asarray(leaf))), name


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(_CASES), where=st.integers(0, 10),
       size=fl(1e-3, 1e300))
def test_invalid_input_raises_value_error_naming_the_argument(case, where, size):
    name, arg, kind = case
    fn, good = _good_args(name)
    if (name, arg) in _SENT_FIRST:
        where = 0  # y of a silent sensor (gamma = 0) is ignored and may be NaN (documented)
    EXAMPLES["invalid"] += 1
    args = {**good, arg: _bad(kind, good[arg], where, size)}
    with pytest.raises(ValueError) as info:
        fn(**args)
    msg = str(info.value)
    # the message names the argument (for a range: its stem)
    stem = arg.replace("_range", "")
    assert re.search(rf"\b{re.escape(stem)}", msg), f"{name}({arg}={kind}): {msg!r}"


@pytest.mark.parametrize("case", _CASES, ids=lambda c: f"{c[0]}-{c[1]}-{c[2]}")
def test_each_invalid_input_case_once(case):
    """Every (entry point, argument, kind) once, with the simplest bad value."""
    name, arg, kind = case
    fn, good = _good_args(name)
    EXAMPLES["invalid"] += 1
    with pytest.raises(ValueError) as info:
        fn(**{**good, arg: _bad(kind, good[arg])})
    stem = arg.replace("_range", "")
    assert re.search(rf"\b{re.escape(stem)}", str(info.value)), (name, arg, kind,
                                                                  str(info.value))


# ============================================================================ valid inputs
var = fl(1e-6, 1e6)
var0 = st.one_of(st.just(0.0), var)
#: gains: 0 or of magnitude >= 1e-100 (below, c^2 underflows; tested in test_properties_rule)
gain = st.one_of(st.just(0.0), fl(1e-100, 1e3), fl(-1e3, -1e-100))
stable = fl(-0.999, 0.999)


def _spd(seed, n, rank=None):
    rng = RNG(seed)
    M = rng.standard_normal((n, rank or n))
    return M @ M.T + (0.0 if rank else 1e-3) * np.eye(n)


def _psd_draw(S, rng):
    """A draw of ``N(0, S)`` for a PSD (possibly singular) ``S``."""
    w, V = np.linalg.eigh(S)
    return V @ (np.sqrt(np.clip(w, 0.0, None)) * rng.standard_normal(len(w)))


def _is_psd(M, rtol=1e-9, scale=None):
    """Symmetric PSD up to ``rtol * scale`` (``scale``: of the prior a posterior came from)."""
    M = np.asarray(M)
    scale = max(np.abs(M).max(), 1e-300) if scale is None else scale
    return (np.abs(M - np.swapaxes(M, -1, -2)).max() <= 1e-12 * scale
            and np.linalg.eigvalsh(M).min() >= -rtol * scale)


@SETTINGS
@given(p=var0, c=gain, r=var0, a=fl(-3, 3), q=var0)
def test_riccati_scalar_invariants(p, c, r, a, q):
    EXAMPLES["riccati"] += 1
    post = riccati.scalar_update(p, c, r)
    assert np.isfinite(post) and 0.0 <= post <= p * (1 + 2.3e-16)  # p r / r: one rounding
    nxt = riccati.scalar_step(p, a, q, c, r)
    assert np.isfinite(nxt) and nxt >= q
    if c != 0 or abs(a) < 1:
        pinf = riccati.scalar_steady_state(a, q, c, r)
        assert np.isfinite(pinf) and pinf >= q * (1 - 1e-12)
        assert riccati.scalar_step(pinf, a, q, c, r) == pytest.approx(pinf, rel=1e-6, abs=1e-9)
    else:  # no information and |a| >= 1: no steady state, a ValueError (never inf)
        with pytest.raises(ValueError, match="^no steady state: c = 0"):
            riccati.scalar_steady_state(a, q, c, r)


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), m=st.integers(1, 3),
       rank_p=st.booleans(), zero_r=st.booleans())
def test_riccati_matrix_invariants(seed, n, m, rank_p, zero_r):
    EXAMPLES["riccati"] += 1
    rng = RNG(seed)
    P = _spd(seed, n, 1 if rank_p else None)
    R = np.zeros((m, m)) if zero_r else _spd(seed + 1, m)
    C = rng.standard_normal((m, n))
    post = riccati.measurement_update(P, C, R)
    assert np.all(np.isfinite(post)) and _is_psd(post, 1e-7, np.abs(P).max())
    assert np.linalg.eigvalsh(P - post).min() >= -1e-7 * np.abs(P).max()  # never above prior
    A = 0.9 * rng.standard_normal((n, n)) / max(1.0, np.abs(np.linalg.eigvals(
        rng.standard_normal((n, n)))).max())
    Q = _spd(seed + 2, n)
    nxt = riccati.riccati_step(P, A, Q, C, R if not zero_r else _spd(seed + 3, m))
    assert _is_psd(nxt, 1e-7)


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), m=st.integers(1, 2))
def test_riccati_steady_state_is_a_psd_fixed_point(seed, n, m):
    EXAMPLES["riccati"] += 1
    rng = RNG(seed)
    A = rng.standard_normal((n, n))
    Q, R = _spd(seed, n), _spd(seed + 1, m)
    C = rng.standard_normal((m, n))
    P = riccati.steady_state(A, Q, C, R)
    assert _is_psd(P)
    np.testing.assert_allclose(riccati.riccati_step(P, A, Q, C, R), P, rtol=1e-6,
                               atol=1e-8 * np.abs(P).max())


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), r=var0, q=st.one_of(st.just(0.0), fl(1e-100, 10)),
       n=st.integers(1, 4))
def test_kalman_filter_covariances_are_psd(seed, r, q, n):
    EXAMPLES["kalman"] += 1
    model = models.tracking_model(n, sigma2=q, r=r, P0=_spd(seed, 2))
    x, y = model.sample(RNG(seed), 3, 4)
    xhat, P = model.filter(y)
    assert np.all(np.isfinite(xhat))
    assert all(_is_psd(Pk, 1e-6, np.abs(model.P0).max() + 1e3 * (1 + q)) for Pk in P)
    L = particle.psd_factor(model.Q)
    np.testing.assert_allclose(L @ L.T, model.Q, rtol=1e-9, atol=1e-12 * (1 + q))


@SETTINGS
@given(x=fl(1e-300, 1e300), b=fl(0, 1e12), lam=fl(1e-3, 1e3),
       m=fl(0.5, 6.0))
def test_fading_special_function_invariants(x, b, lam, m):
    EXAMPLES["fading"] += 1
    e = fading.exp_e1(x)
    assert 1.0 / (x + 1.0) * 0.5 <= e <= 1.0 / x * (1 + 1e-12)  # 1/(x+2) < e^x E1(x) < 1/x
    for ch in (Rayleigh(lam), Nakagami(m, lam), Nakagami(0.5, lam)):
        g = ch.ratio_mean(b)
        assert 0.0 <= g <= 1.0 + 1e-12
    assert Rayleigh(lam).ratio_mean_bound(b) >= Rayleigh(lam).ratio_mean(b) * (1 - 1e-12)
    assert Nakagami(0.5, lam).ratio_mean_bound(b) >= Nakagami(0.5, lam).ratio_mean(b) * (1 - 1e-9)


@settings(max_examples=25, deadline=None)
@given(a=fl(-1.3, 1.3), sw2=fl(0, 10), sv2=fl(0, 10),
       sn2=fl(1e-3, 10), lam=fl(0.1, 10), p0=fl(0, 10),
       nak=st.booleans())
def test_fading_bounds_invariants(a, sw2, sv2, sn2, lam, p0, nak):
    """E[posterior] <= p; s <= q; the Monte Carlo mean stays below s (Theorem, within 5 se)."""
    EXAMPLES["fading"] += 1
    ch = Nakagami(0.5, lam) if nak else Rayleigh(lam)
    post = fading.expected_posterior(p0, sv2, sn2, ch)
    assert 0.0 <= post <= p0 * (1 + 1e-12)
    b = fading.scalar_bounds(a, sw2, sv2, sn2, ch, p0, 8)
    assert np.all(np.isfinite(b["s"])) and np.all(b["s"] <= b["q"] * (1 + 1e-9) + 1e-12)
    mean, se = fading.scalar_mc(a, sw2, sv2, sn2, ch, p0, 8, 400, 0)
    assert np.all(np.isfinite(mean))
    assert np.all(mean <= b["s"] + 5 * se + 1e-9 * (1 + b["s"]))


@settings(max_examples=20, deadline=None)
@given(access=st.sampled_from(fading.ACCESS_SCHEMES), a=fl(-1.2, 1.2),
       n=st.integers(1, 3), seed=st.integers(0, 1000))
def test_fading_multisensor_bounds_above_monte_carlo(access, a, n, seed):
    EXAMPLES["fading"] += 1
    rng = RNG(seed)
    c = rng.uniform(0.5, 2.0, n)
    sv2, lams = rng.uniform(0.5, 3.0, n), rng.uniform(0.5, 3.0, n)
    args = (access, a, c, sv2, 2.0, lams, 1.0, 1.0, 6)
    b = fading.multisensor_bounds(*args)
    mean, se = fading.multisensor_mc(*args, 300, seed)
    assert np.all(np.isfinite(b["s"])) and np.all(np.isfinite(b["t"]))
    assert np.all(mean <= b["s"] + 5 * se + 1e-9 * b["s"])


@settings(max_examples=25, deadline=None)
@given(a=stable, sw2=fl(0, 1e3), S=fl(0, 1e300), S2=fl(0, 1e300))
def test_power_steady_state_bracketed_and_decreasing(a, sw2, S, S2):
    EXAMPLES["power"] += 1
    p, p2 = power.steady_state(a, sw2, S), power.steady_state(a, sw2, S2)
    top = sw2 / (1 - a * a)
    assert np.isfinite(p) and sw2 * (1 - 1e-12) <= p <= top * (1 + 1e-12)
    if S <= S2:
        assert p >= p2 * (1 - 1e-12)


@settings(max_examples=30, deadline=None)
@given(access=st.sampled_from(power.ACCESS), M=st.integers(1, 4), seed=st.integers(0, 10**6),
       g=fl(0, 1e3), sn2=st.one_of(st.just(0.0), fl(1e-6, 10)),
       scale=fl(-200, 200))
def test_power_allocations_invariants(access, M, seed, g, sn2, scale):
    """The optimal SNR is at most sum c^2 / sigma_v2 (Cauchy-Schwarz) and at least that of equal
    power; it spends exactly the budget; snr stays finite whatever the scale of alpha."""
    EXAMPLES["power"] += 1
    rng = RNG(seed)
    h, c, sv = rng.uniform(0.1, 2, M), rng.uniform(-2, 2, M), rng.uniform(0.1, 3, M)
    a, sw2 = 0.7, 1.0
    best = power.min_error(access, g, a, sw2, h, c, sv, sn2)
    S = power.snr(access, best, h, c, sv, sn2)
    ceiling = np.sum(c**2 / sv)
    assert np.isfinite(S) and -1e-12 <= S <= ceiling * (1 + 1e-9)
    spent = power.transmit_power(best, a, sw2, c, sv).sum()
    assert spent == pytest.approx(g, rel=1e-9, abs=1e-300)
    eq = power.equal_power(a, sw2, c, sv, gamma_total=g)
    assert S >= power.snr(access, eq, h, c, sv, sn2) * (1 - 1e-9) - 1e-300
    alpha = rng.standard_normal(M) * 10.0**scale
    S_any = power.snr(access, alpha, h, c, sv, sn2)
    assert np.isfinite(S_any) and -1e-12 <= S_any <= ceiling * (1 + 1e-9)


@SETTINGS
@given(s=var0, delta=var, mu=fl(-1e3, 1e3), rate=fl(1e-6, 1 - 1e-6))
def test_event_probabilities_and_inverse(s, delta, mu, rate):
    EXAMPLES["event"] += 1
    pr = event.trigger_probability(s, delta, mu)
    assert 0.0 <= pr <= 1.0
    if s > 0:
        d = event.delta_for_rate(rate, s)
        assert event.trigger_probability(s, d) == pytest.approx(rate, rel=1e-9)


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), m=st.integers(1, 3),
       rank=st.booleans(), zero_r=st.booleans())
def test_event_posterior_and_rates_invariants(seed, n, m, rank, zero_r):
    EXAMPLES["event"] += 1
    rng = RNG(seed)
    Sigma = _spd(seed, n, 1 if rank else None)
    C = rng.standard_normal((m, n))
    r = np.zeros(m) if zero_r else rng.uniform(0.1, 2, m)
    delta = rng.uniform(0.1, 3, m)
    rate = event.communication_rate(Sigma, C, r, delta)
    assert np.all((rate >= 0) & (rate <= 1))
    gamma = rng.random(m) < 0.5
    # y drawn from the model: with noise-free sensors an arbitrary y may contradict it (more
    # sensors than states, or a singular Sigma), and posterior then refuses it (issue 29)
    x = _psd_draw(Sigma, rng)
    y = C @ x + np.sqrt(r) * rng.standard_normal(m)
    xhat, P = event.posterior(np.zeros(n), Sigma, C, r, delta, gamma, y)
    assert np.all(np.isfinite(xhat)) and _is_psd(P, 1e-7, np.abs(Sigma).max())
    assert np.linalg.eigvalsh(Sigma - P).min() >= -1e-7 * np.abs(Sigma).max()




# ================================================= issue 29: singular innovation covariances
@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), m=st.integers(1, 3),
       off=st.one_of(fl(-1e3, -1e-3), fl(1e-3, 1e3)))
def test_noise_free_measurement_of_a_known_state_must_match_it(seed, n, m, off):
    """R = 0 and Sigma = 0: a sent y_i must equal c_i xbar; otherwise ValueError naming y (it
    returned numbers). The Kalman step of the same numbers refuses the innovation."""
    EXAMPLES["event"] += 1
    rng = RNG(seed)
    C = rng.standard_normal((m, n))
    C[0, 0] += 1.0 + np.abs(C[0]).sum()  # a measurement row that is not zero
    xbar = rng.standard_normal(n)
    y = C @ xbar
    gamma = np.ones(m, dtype=bool)
    xhat, P = event.posterior(xbar, np.zeros((n, n)), C, np.zeros(m), 1.0, gamma, y)
    np.testing.assert_allclose(xhat, xbar, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(P, 0.0)
    y[0] += off
    with pytest.raises(ValueError, match="^y contradicts the model"):
        event.posterior(xbar, np.zeros((n, n)), C, np.zeros(m), 1.0, gamma, y)
    with pytest.raises(ValueError, match="^innov contradicts the model"):
        kalman.kalman_step(xbar[None], np.zeros((n, n)), (y - C @ xbar)[None], C,
                           np.zeros((m, m)), np.eye(n), np.eye(n))


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), r=var0, zero_g=st.booleans())
def test_ekf_covariance_step_is_psd_and_never_above_the_prediction(seed, r, zero_g):
    """Including s = 0 (r = 0 and a zero gradient: no information, P_upd = P_pred)."""
    EXAMPLES["nonlinear"] += 1
    rng = RNG(seed)
    P, Q = _spd(seed, 4), _spd(seed + 1, 4)
    g = np.zeros(4) if zero_g else rng.standard_normal(4)
    Pp, s, Pu = nonlinear.ekf_covariance_step(P, g, np.eye(4) + 0.1 * np.eye(4, k=1), Q, r)
    assert np.isfinite(s) and s >= 0
    assert np.all(np.isfinite(Pu)) and _is_psd(Pu, 1e-7, np.abs(Pp).max())
    assert np.linalg.eigvalsh(Pp - Pu).min() >= -1e-7 * np.abs(Pp).max()
    if s == 0:
        np.testing.assert_array_equal(Pu, 0.5 * (Pp + Pp.T))


@SETTINGS
@given(m=fl(-40, 40), h=st.one_of(st.just(0.0), fl(1e-6, 50), st.just(np.inf)))
def test_log_silent_probability_is_a_log_probability(m, h):
    EXAMPLES["nonlinear"] += 1
    v = float(nonlinear.log_silent_probability(m, h))
    assert v <= 0.0 and not np.isnan(v)
    assert (v == -np.inf) == (h == 0.0)
