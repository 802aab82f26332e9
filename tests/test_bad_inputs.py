"""Issue 48, part 5: bad and boundary inputs on the public functions, one parametrized case each.

Every case calls one public function with warnings turned into errors and classifies what it
does against the project's rule (a finite, meaningful result, or a ``ValueError`` naming the
parameter):

* a *bad* input (NaN, inf, a negative variance, an empty array, a 0x0 state matrix, a
  mismatched shape, a measurement that contradicts a singular innovation covariance) must raise
  ``ValueError`` whose message names the parameter. Returning anything is *silent*; any other
  exception, or a NumPy warning, is *obscure*;
* a *limit* (a zero noise variance, ``a = 0``, one sensor, a singular but valid covariance)
  must return the closed form; raising is *rejected*, a different number is *wrong*.

The failure message starts with the class (``SILENT``, ``OBSCURE``, ``REJECTED``, ``WRONG``), so
``pytest -q tests/test_bad_inputs.py`` counts what is left.

The mathematics of the two singular cases the issue names:

* Kalman update with ``P = 0`` and ``R = 0`` along a measured direction: ``S = C P C^T + R`` is
  singular there and the predicted measurement is exact. A measurement equal to the prediction
  (innovation 0) carries no information: the posterior is the prior (the limit ``R -> 0`` of
  the gain, applied to a zero innovation). Any other measurement has probability zero under the
  model: no posterior exists, ``ValueError`` naming the innovation. The covariance update alone
  (:func:`fusioncenter.riccati.measurement_update`) does not see the data: ``P_post = P``.
* EKF step with ``s = g P g^T + r = 0``: the same, for one scalar measurement; the covariance
  step returns ``P_upd = P_pred`` (documented), and a filter that meets a non-zero innovation
  with ``s = 0`` raises.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field

import numpy as np
import pytest

from fusioncenter import (
    censoring,
    comparison,
    event,
    fading,
    kalman,
    models,
    montecarlo,
    particle,
    power,
    riccati,
)
from fusioncenter.censoring import nonlinear_model as nlm
from fusioncenter.fading import Nakagami, Rayleigh

NAN, INF = float("nan"), float("inf")


@dataclass
class Case:
    label: str
    fn: object
    args: tuple = ()
    kwargs: dict = field(default_factory=dict)
    name: str | tuple | None = None  # bad input: the parameter(s) the ValueError may name
    expect: object = None  # limit: a value (compared with allclose) or a predicate

    def __str__(self):
        return self.label


CASES: list[Case] = []


def bad(label, name, fn, *args, **kwargs):
    CASES.append(Case(label, fn, args, kwargs, name=name))


def limit(label, expect, fn, *args, **kwargs):
    CASES.append(Case(label, fn, args, kwargs, expect=expect))


def _variant(value, kind):
    arr = np.asarray(value)
    arr = arr if arr.dtype.kind == "c" else arr.astype(float)
    if kind == "nan":
        return np.full(arr.shape, NAN)[()]
    if kind == "inf":
        return np.full(arr.shape, INF)[()]
    if kind == "neg":
        return (-np.abs(arr) - 1.0)[()]
    if kind == "zero":
        return np.zeros(arr.shape)[()]
    if kind == "empty":
        return np.zeros((0,) * max(arr.ndim, 1))
    if kind == "shape":  # one more entry along the last axis (a scalar becomes a 3-vector)
        if arr.ndim == 0:
            return np.full(3, float(arr))
        return np.concatenate([arr, arr[..., -1:]], axis=-1)
    if kind == "text":
        return "1"
    raise AssertionError(kind)


def sweep(prefix, fn, base: dict, specs: dict):
    """Bad cases: each parameter of ``specs`` replaced by each of its kinds, the others at
    ``base`` (``base`` itself must be valid: it is checked as a limit with any finite result)."""
    CASES.append(Case(f"{prefix}[base]", fn, (), dict(base), expect=_finite))
    for pname, kinds in specs.items():
        for kind in kinds:
            if isinstance(kind, tuple):
                tag, value = kind
            else:
                tag, value = kind, _variant(base.get(pname, 1.0), kind)
            CASES.append(Case(f"{prefix}[{pname}={tag}]", fn, (), {**base, pname: value},
                              name=pname))


def _flat(out):
    if isinstance(out, dict):
        return [v for x in out.values() for v in _flat(x)]
    if isinstance(out, tuple | list):
        return [v for x in out for v in _flat(x)]
    if hasattr(out, "__dataclass_fields__"):
        return [v for k in out.__dataclass_fields__ for v in _flat(getattr(out, k))]
    if isinstance(out, str | type(None) | bool) or callable(out):
        return []
    arr = np.asarray(out)
    return [arr] if arr.dtype.kind in "biufc" else []


def _finite(out):
    return all(np.all(np.isfinite(a)) for a in _flat(out))


def _close(expected, rtol=1e-12, atol=1e-14):
    def check(out):
        return np.allclose(np.asarray(out, dtype=float), expected, rtol=rtol, atol=atol)
    return check


def run_case(case: Case):
    """``(verdict, detail)``: ``"ok"``, or ``SILENT`` / ``OBSCURE`` / ``REJECTED`` / ``WRONG``."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            out = case.fn(*case.args, **case.kwargs)
        except ValueError as err:
            if case.name is None:
                return "REJECTED", f"ValueError: {err}"
            names = case.name if isinstance(case.name, tuple) else (case.name,)
            if any(re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", str(err)) for n in names):
                return "ok", ""
            return "OBSCURE", f"ValueError not naming {case.name}: {err}"
        except Exception as err:  # noqa: BLE001 - the point is to classify it
            return "OBSCURE", f"{type(err).__name__}: {err}"
    if case.name is not None:
        return "SILENT", f"returned {str(out)[:200]}"
    ok = case.expect(out) if callable(case.expect) else np.allclose(out, case.expect)
    return ("ok", "") if ok else ("WRONG", f"returned {str(out)[:200]}")


# ===================================================================================== riccati
I1, Z1 = np.eye(1), np.zeros((1, 1))
I2, Z2 = np.eye(2), np.zeros((2, 2))
E0 = np.zeros((0, 0))
SCAL = ["nan", "inf", "text"]
VAR = SCAL + ["neg"]

sweep("riccati.scalar_update", riccati.scalar_update, dict(p=1.0, c=1.0, r=1.0),
      dict(p=VAR, c=SCAL, r=VAR))
sweep("riccati.scalar_step", riccati.scalar_step, dict(p=1.0, a=0.5, q=1.0, c=1.0, r=1.0),
      dict(p=VAR, a=SCAL, q=VAR, r=VAR))
sweep("riccati.scalar_sequence", riccati.scalar_sequence,
      dict(p0=1.0, a=0.5, q=1.0, c=1.0, r=1.0, steps=3),
      dict(p0=VAR, a=SCAL, q=VAR, steps=[("neg", -1), ("float", 2.5), ("bool", True)]))
sweep("riccati.scalar_steady_state", riccati.scalar_steady_state,
      dict(a=0.5, q=1.0, c=1.0, r=1.0), dict(a=SCAL, q=VAR, c=SCAL, r=VAR))
MAT = ["nan", "inf", "text", ("empty", E0), ("1x2", np.ones((1, 2)))]
COV = MAT + [("negdef", -I1), ("asym", np.array([[1.0, 1.0], [0.0, 1.0]]))]
sweep("riccati.measurement_update", riccati.measurement_update, dict(P=I1, C=I1, R=I1),
      dict(P=COV, C=["nan", "inf", ("2x2", I2)], R=COV))
sweep("riccati.riccati_step", riccati.riccati_step, dict(P=I1, A=I1 * .5, Q=I1, C=I1, R=I1),
      dict(P=COV, A=MAT, Q=COV, C=["nan", ("2x2", I2)], R=COV))
sweep("riccati.riccati_sequence", riccati.riccati_sequence,
      dict(P0=I1, A=I1 * .5, Q=I1, C=I1, R=I1, steps=2),
      dict(P0=COV, A=MAT, Q=COV, R=COV, steps=[("neg", -1)]))
sweep("riccati.steady_state", riccati.steady_state, dict(A=I1 * .5, Q=I1, C=I1, R=I1),
      dict(A=MAT, Q=COV, C=["nan", ("2x2", I2)], R=COV))
sweep("riccati.solve_psd", riccati.solve_psd, dict(S=I1, B=I1),
      dict(S=COV, B=["nan", "inf", ("3x1", np.ones((3, 1)))]))
sweep("riccati.singular", riccati.singular, dict(R=I1), dict(R=["nan", "inf", "text"]))
bad("riccati.steady_state[0x0 state]", "A", riccati.steady_state, E0, E0, E0, E0)
bad("riccati.riccati_step[0x0 state]", ("P", "A"), riccati.riccati_step, E0, E0, E0, E0, E0)
bad("riccati.measurement_update[0x0 state]", "P", riccati.measurement_update, E0, E0, E0)
bad("riccati.riccati_sequence[0x0 state]", "P0", riccati.riccati_sequence, E0, E0, E0, E0, E0, 2)
# limits: zero noise, a = 0, singular but valid covariances (closed forms)
limit("riccati.scalar_update[r=0]", 0.0, riccati.scalar_update, 2.0, 1.0, 0.0)
limit("riccati.scalar_update[c=0]", 2.0, riccati.scalar_update, 2.0, 0.0, 1.0)
limit("riccati.scalar_update[p=0,r=0]", 0.0, riccati.scalar_update, 0.0, 1.0, 0.0)
limit("riccati.scalar_step[a=0]", 3.0, riccati.scalar_step, 2.0, 0.0, 3.0, 1.0, 1.0)
limit("riccati.scalar_steady_state[r=0]", 3.0, riccati.scalar_steady_state, 0.5, 3.0, 1.0, 0.0)
limit("riccati.scalar_steady_state[a=0]", 3.0, riccati.scalar_steady_state, 0.0, 3.0, 1.0, 1.0)
limit("riccati.scalar_steady_state[q=0,a=2]", 3.0, riccati.scalar_steady_state, 2.0, 0.0, 1.0,
      1.0)
limit("riccati.measurement_update[P=0,R=0]", Z1, riccati.measurement_update, Z1, I1, Z1)
limit("riccati.measurement_update[R=0]", np.diag([0.0, 1.0]), riccati.measurement_update, I2,
      np.array([[1.0, 0.0]]), Z1)
limit("riccati.steady_state[R=0]", I1 * 2.0, riccati.steady_state, I1 * .5, I1 * 2, I1, Z1)
limit("riccati.steady_state[a=0]", I1 * 2.0, riccati.steady_state, Z1, I1 * 2, I1, I1)
limit("riccati.riccati_step[P=0,R=0]", I1, riccati.riccati_step, Z1, I1, I1, I1, Z1)
limit("riccati.solve_psd[S=0,singular]", Z1, riccati.solve_psd, Z1, I1, singular=True)

# ====================================================================================== kalman
x0, in1 = np.zeros((1, 1)), np.ones((1, 1))
KS = dict(x=x0, P=I1, innov=in1, C=I1, R=I1, A=I1, Q=I1)
sweep("kalman.kalman_step", kalman.kalman_step, KS,
      dict(x=["nan", "inf", ("1x2", np.zeros((1, 2)))], P=["nan", "inf", ("1x2", np.ones((1, 2)))],
           innov=["nan", "inf", ("1x2", np.ones((1, 2)))], C=["nan", "inf", ("2x2", I2)],
           R=["nan", "inf", ("2x2", I2)], A=["nan", "inf", ("2x2", I2)],
           Q=["nan", "inf", ("2x2", I2)]))
bad("kalman.kalman_step[R=-1,check]", "R", kalman.kalman_step, **{**KS, "R": -I1}, check=True)
bad("kalman.kalman_step[P=-1,check]", "P", kalman.kalman_step, **{**KS, "P": -I1}, check=True)
bad("kalman.kalman_step[R=-1]", "R", kalman.kalman_step, **{**KS, "R": -I1})
bad("kalman.kalman_step[P=-2]", "P", kalman.kalman_step, **{**KS, "P": -2 * I1})
bad("kalman.kalman_step[P=0,R=0,innov=1]", "innov", kalman.kalman_step,
    **{**KS, "P": Z1, "R": Z1})
bad("kalman.kalman_step[P=0,R=0,innov=1,per trial]", "innov", kalman.kalman_step,
    **{**KS, "P": Z1[None], "R": Z1[None], "C": I1[None]})
bad("kalman.kalman_step[0x0 state]", "P", kalman.kalman_step, np.zeros((1, 0)), E0,
    np.zeros((1, 0)), E0, E0, E0, E0)
limit("kalman.kalman_step[P=0,R=0,innov=0]", lambda s: s.x_post[0, 0] == 0 and s.P_post[0, 0] == 0
      and s.P_pred[0, 0] == 1, kalman.kalman_step, **{**KS, "P": Z1, "R": Z1, "innov": Z1})
limit("kalman.kalman_step[R=0]", lambda s: s.x_post[0, 0] == 1 and s.P_post[0, 0] == 0,
      kalman.kalman_step, **{**KS, "R": Z1})
limit("kalman.kalman_step[a=0]", lambda s: s.x_pred[0, 0] == 0 and s.P_pred[0, 0] == 1,
      kalman.kalman_step, **{**KS, "A": Z1})
LGM = dict(A=I1, Q=I1, C=I1, R=I1, m0=np.zeros(1), P0=I1)
sweep("kalman.LinearGaussianModel", kalman.LinearGaussianModel, LGM,
      dict(A=MAT, Q=COV, C=["nan", "inf", ("1x2", np.ones((1, 2)))], R=COV,
           m0=["nan", "inf", "shape"], P0=COV))
bad("kalman.LinearGaussianModel[0x0 state]", "A", kalman.LinearGaussianModel, E0, E0, E0, E0,
    np.zeros(0), E0)
# no sensor (C with 0 rows) is a legitimate model: the filter only predicts, x_k = 2^k x_0,
# P_k = 4 P_{k-1} + 1 from P_0 = 1
_blind = kalman.LinearGaussianModel(2 * I1, I1, np.zeros((0, 1)), E0, np.ones(1), I1)
limit("kalman.LinearGaussianModel.filter[no sensor: prediction only]",
      lambda o: np.array_equal(o[0][0, :, 0], [1.0, 2.0, 4.0])
      and np.array_equal(o[1][:, 0, 0], [1.0, 5.0, 21.0]), _blind.filter, np.zeros((1, 3, 0)))
_lgm = kalman.LinearGaussianModel(**LGM)
bad("kalman.LinearGaussianModel.filter[y=nan]", "y", _lgm.filter, np.full((1, 2, 1), NAN))
bad("kalman.LinearGaussianModel.filter[y 2-D]", "y", _lgm.filter, np.zeros((2, 1)))
limit("kalman.LinearGaussianModel.filter[y no time points: empty]",
      lambda o: o[0].shape == (1, 0, 1) and o[1].shape == (0, 1, 1), _lgm.filter,
      np.zeros((1, 0, 1)))
bad("kalman.LinearGaussianModel.sample[n=-1]", "n", _lgm.sample, np.random.default_rng(0), -1, 2)
bad("kalman.LinearGaussianModel.sample[steps=1.5]", "steps", _lgm.sample,
    np.random.default_rng(0), 1, 1.5)
_known = kalman.LinearGaussianModel(A=I1, Q=Z1, C=I1, R=Z1, m0=np.zeros(1), P0=Z1)
bad("kalman.LinearGaussianModel.filter[P0=0,R=0,y!=m0]", "y", _known.filter,
    np.ones((1, 1, 1)))
limit("kalman.LinearGaussianModel.filter[P0=0,R=0,y=m0]",
      lambda o: np.all(o[0] == 0) and np.all(o[1] == 0), _known.filter, np.zeros((1, 3, 1)))
sweep("kalman.constant_velocity", kalman.constant_velocity, dict(dt=1.0, q=1.0, r=1.0),
      dict(dt=VAR + ["zero"], q=VAR, r=VAR))
limit("kalman.constant_velocity[r=0]", lambda m: m.R[0, 0] == 0, kalman.constant_velocity, r=0.0)

# ======================================================================================= event
sweep("event.trigger_probability", event.trigger_probability, dict(s=1.0, delta=1.0, mu=0.0),
      dict(s=VAR, delta=VAR + ["zero"], mu=SCAL))
limit("event.trigger_probability[s=0,mu=0]", 0.0, event.trigger_probability, 0.0, 1.0, 0.0)
limit("event.trigger_probability[s=0,mu=2]", 1 - math.exp(-2.0), event.trigger_probability,
      0.0, 1.0, 2.0)
CR = dict(Sigma=I2, C=np.eye(2), R=np.ones(2), delta=1.0)
sweep("event.communication_rate", event.communication_rate, CR,
      dict(Sigma=COV[:4] + [("negdef", -I2)], C=["nan", "inf", ("2x3", np.ones((2, 3)))],
           R=["nan", "inf", "neg", "shape"], delta=VAR + ["zero", "shape"],
           xbar=["nan", ("3", np.zeros(3))]))
bad("event.communication_rate[0x0 state]", ("Sigma", "C"), event.communication_rate, E0,
    np.zeros((1, 0)), np.ones(1), 1.0)
limit("event.communication_rate[Sigma=0,R=0]", [0.0, 0.0], event.communication_rate, Z2,
      np.eye(2), np.zeros(2), 1.0)
sweep("event.delta_for_rate", event.delta_for_rate, dict(rate=0.5, s=1.0, mu=0.0),
      dict(rate=SCAL + ["neg", "zero", ("one", 1.0), ("two", 2.0)], s=VAR, mu=SCAL))
sweep("event.sample_trigger", event.sample_trigger,
      dict(rng=np.random.default_rng(0), y=np.zeros((3, 2)), delta=1.0),
      dict(y=["nan", "inf", "text"], delta=VAR + ["zero", "shape"],
           rng=[("int", 0), ("none", None)]))
PO = dict(xbar=np.zeros(2), Sigma=I2, C=np.eye(2), R=np.ones(2), delta=1.0,
          gamma=np.array([1, 0]), y=np.array([0.5, NAN]))
sweep("event.posterior", event.posterior, PO,
      dict(xbar=["nan", "inf", ("3", np.zeros(3))], Sigma=["nan", ("negdef", -I2)],
           C=["nan", "inf"], R=["nan", "neg", "shape"], delta=["nan", "neg", "zero"],
           gamma=[("2", np.array([2, 0])), ("float", np.array([0.5, 0.0])), ("3", np.ones(3))],
           y=[("nan sent", np.array([NAN, 0.0])), ("inf sent", np.array([INF, 0.0])),
              ("3", np.zeros(3))]))
bad("event.posterior[Sigma=0,R=0,y!=xbar]", "y", event.posterior, np.zeros(1), Z1, I1,
    np.zeros(1), 1.0, np.ones(1), np.ones(1))
bad("event.posterior[0x0 state]", ("Sigma", "C"), event.posterior, np.zeros(0), E0,
    np.zeros((1, 0)), np.ones(1), 1.0, np.ones(1), np.ones(1))
limit("event.posterior[Sigma=0,R=0,y=xbar]", lambda o: np.all(np.asarray(o[0]) == 0)
      and np.all(np.asarray(o[1]) == 0), event.posterior, np.zeros(1), Z1, I1, np.zeros(1), 1.0,
      np.ones(1), np.zeros(1))
_ev = models.tracking_model(2, r=1.0, P0=I2)
bad("event.event_kf_run[steps=-1]", "steps", event.event_kf_run, _ev, -1, "stochastic",
    np.random.default_rng(0), 2, delta=1.0)
bad("event.event_kf_run[n_trials=0]", "n_trials", event.event_kf_run, _ev, 2, "stochastic",
    np.random.default_rng(0), 0, delta=1.0)
bad("event.event_kf_run[delta=nan]", "delta", event.event_kf_run, _ev, 2, "stochastic",
    np.random.default_rng(0), 2, delta=NAN)
bad("event.event_kf_run[delta=0]", "delta", event.event_kf_run, _ev, 2, "stochastic",
    np.random.default_rng(0), 2, delta=0.0)
bad("event.event_kf_run[p=1.5]", "p", event.event_kf_run, _ev, 2, "random",
    np.random.default_rng(0), 2, p=1.5)
bad("event.event_kf_run[p=nan]", "p", event.event_kf_run, _ev, 2, "random",
    np.random.default_rng(0), 2, p=NAN)
bad("event.event_kf_run[scheme]", "scheme", event.event_kf_run, _ev, 2, "nope",
    np.random.default_rng(0), 2)
bad("event.steady_state_delta[rate=0]", "rate", event.steady_state_delta, _ev, 0.0)
bad("event.steady_state_delta[rate=nan]", "rate", event.steady_state_delta, _ev, NAN)
bad("event.steady_state_delta[rate=1.5]", "rate", event.steady_state_delta, _ev, 1.5)
bad("event.steady_state_delta[rate shape]", "rate", event.steady_state_delta, _ev,
    np.full(3, 0.5))
bad("event.steady_state_delta[tol=nan]", "tol", event.steady_state_delta, _ev, 0.5, tol=NAN)
bad("event.steady_state_delta[tol=-1]", "tol", event.steady_state_delta, _ev, 0.5, tol=-1.0)
bad("event.steady_state_delta[max_iter=0]", "max_iter", event.steady_state_delta, _ev, 0.5,
    max_iter=0)
bad("event.split_summary[nx=0]", "nx", event.split_summary, np.zeros(10), 0)
bad("event.split_summary[text]", "arr", event.split_summary, ["1"] * 6, 1)
limit("event.split_summary[NaN stderr of one trial: views, as they are]",
      lambda d: np.all(np.isnan(d["gamma"])), event.split_summary, np.full(6, NAN), 1)
bad("event.calibrate_delta[rate=0]", "rate", event.calibrate_delta, _ev, 0.0)
bad("event.calibrate_delta[tol=0]", "tol", event.calibrate_delta, _ev, 0.5, tol=0.0)
bad("event.calibrate_delta[burn_in>steps]", "burn_in", event.calibrate_delta, _ev, 0.5,
    steps=5, burn_in=10)

# ====================================================================================== models
sweep("models.wna_model", models.wna_model, dict(dt=1.0), dict(dt=VAR + ["zero"]))
sweep("models.tracking_model", models.tracking_model,
      dict(n_sensors=2, dt=1.0, sigma2=4.0, r=1.0, x0=(0.0, 10.0)),
      dict(n_sensors=[("zero", 0), ("float", 2.0), ("bool", True)], dt=VAR + ["zero"],
           sigma2=VAR, r=VAR, x0=["nan", "inf", "shape"],
           P0=[("nan", np.full((2, 2), NAN)), ("negdef", -I2), ("1x1", I1)]))
limit("models.tracking_model[one sensor]", lambda m: m.C.shape == (1, 2),
      models.tracking_model, 1)
limit("models.tracking_model[sigma2=0,r=0]", lambda m: np.all(m.Q == 0) and np.all(m.R == 0),
      models.tracking_model, 2, sigma2=0.0, r=0.0)

# ================================================================================== montecarlo
def _chunk(rng, n):
    return rng.standard_normal((n, 2))


bad("montecarlo.simulate[n_trials=0]", "n_trials", montecarlo.simulate, _chunk, 0, 0)
bad("montecarlo.simulate[seed=-1]", "seed", montecarlo.simulate, _chunk, 4, -1)
bad("montecarlo.simulate[seed=nan]", "seed", montecarlo.simulate, _chunk, 4, NAN)
bad("montecarlo.simulate[block_size=0]", "block_size", montecarlo.simulate, _chunk, 4, 0,
    block_size=0)
bad("montecarlo.simulate[chunk_size=0]", "chunk_size", montecarlo.simulate, _chunk, 4, 0,
    chunk_size=0)
bad("montecarlo.simulate[chunk_fn]", "chunk_fn", montecarlo.simulate, None, 4, 0)
limit("montecarlo.simulate[one trial]", lambda r: r.samples.shape == (1, 2),
      montecarlo.simulate, _chunk, 1, 0)

# ===================================================================================== fading
RAY = Rayleigh(1.0)
bad("fading.Rayleigh[lam=0]", "lam", Rayleigh, 0.0)
bad("fading.Rayleigh[lam=nan]", "lam", Rayleigh, NAN)
bad("fading.Rayleigh[lam=inf]", "lam", Rayleigh, INF)
bad("fading.Nakagami[m=0]", "m", Nakagami, 0.0, 1.0)
bad("fading.Nakagami[m=nan]", "m", Nakagami, NAN, 1.0)
bad("fading.Nakagami[lam=-1]", "lam", Nakagami, 0.5, -1.0)
sweep("fading.exp_e1", fading.exp_e1, dict(x=1.0), dict(x=["nan", "neg", "text"]))
limit("fading.exp_e1[inf]", 0.0, fading.exp_e1, INF)
limit("fading.exp_e1[0: returns inf (documented)]", lambda v: v == INF, fading.exp_e1, 0.0)
sweep("fading.expected_posterior", fading.expected_posterior,
      dict(p=1.0, sigma_v2=1.0, sigma_n2=1.0, channel=RAY),
      dict(p=VAR, sigma_v2=VAR, sigma_n2=VAR + ["zero"], channel=[("none", None)]))
limit("fading.expected_posterior[p=0]", 0.0, fading.expected_posterior, 0.0, 1.0, 1.0, RAY)
SB = dict(a=0.9, sigma_w2=1.0, sigma_v2=1.0, sigma_n2=1.0, channel=RAY, p0=1.0, steps=3)
sweep("fading.scalar_bounds", fading.scalar_bounds, SB,
      dict(a=SCAL, sigma_w2=VAR, sigma_v2=VAR, sigma_n2=VAR + ["zero"], p0=VAR,
           steps=[("neg", -1), ("float", 1.5)], channel=[("str", "rayleigh")]))
sweep("fading.scalar_bound_limits", fading.scalar_bound_limits,
      {k: SB[k] for k in ("a", "sigma_w2", "sigma_v2", "sigma_n2", "channel")},
      dict(a=SCAL, sigma_w2=VAR, sigma_v2=VAR, sigma_n2=VAR + ["zero"]))
limit("fading.scalar_bounds[a=0]", lambda d: all(np.allclose(np.asarray(v)[1:], 1.0)
      for k, v in d.items() if np.ndim(v) == 1 and len(v) == 4), fading.scalar_bounds,
      **{**SB, "a": 0.0})
SMC = dict(**SB, n_paths=4, seed=0)
sweep("fading.scalar_mc", fading.scalar_mc, SMC,
      dict(n_paths=[("zero", 0)], seed=[("neg", -1), ("bool", True)], p0=["nan", "neg"],
           sigma_n2=["zero"]))
sweep("fading.scalar_paths", fading.scalar_paths, SMC,
      dict(n_paths=[("zero", 0)], sigma_v2=["neg"], a=["inf"]))
sweep("fading.nakagami_q_as_printed", fading.nakagami_q_as_printed,
      dict(a=0.9, sigma_w2=1.0, sigma_v2=1.0, sigma_n2=1.0, lam=1.0, p0=1.0, steps=3),
      dict(a=SCAL, sigma_w2=VAR, sigma_v2=VAR, sigma_n2=VAR + ["zero"],
           lam=VAR + ["zero"], p0=VAR))
MS = dict(access="orthogonal", a=0.9, c=np.ones(2), sigma_v2=np.ones(2), sigma_n2=1.0,
          lams=np.ones(2), sigma_w2=1.0, p0=1.0, steps=3)
sweep("fading.multisensor_bounds", fading.multisensor_bounds, MS,
      dict(access=[("bad", "tdma")], a=SCAL, c=["nan", "inf", "shape", "empty"],
           sigma_v2=["nan", "neg", "shape"], sigma_n2=["nan", "neg", "zero"],
           lams=["nan", "neg", "zero", "shape"], sigma_w2=VAR, p0=VAR,
           steps=[("neg", -1)]))
bad("fading.multisensor_bounds[multi-access c=0]", "c", fading.multisensor_bounds,
    **{**MS, "access": "multi-access", "c": np.array([1.0, 0.0])})
bad("fading.multisensor_bounds[last_sensor=5]", "last_sensor", fading.multisensor_bounds,
    **{**MS, "access": "multi-access"}, last_sensor=5)
sweep("fading.multisensor_bound_limits", fading.multisensor_bound_limits,
      {k: v for k, v in MS.items() if k not in ("p0", "steps")},
      dict(a=["nan"], c=["empty"], sigma_n2=["zero"], lams=["zero"]))
sweep("fading.multisensor_mc", fading.multisensor_mc, dict(**MS, n_paths=4, seed=0),
      dict(n_paths=[("zero", 0)], seed=[("neg", -1)], c=["nan"], sigma_v2=["neg"]))
VB = dict(A=I2 * .9, c=np.array([1.0, 0.0]), Sigma_w=I2, sigma_v2=1.0, sigma_n2=1.0,
          channel=RAY, P0=I2, steps=3)
sweep("fading.vector_bound", fading.vector_bound, VB,
      dict(A=["nan", "inf", ("2x3", np.ones((2, 3))), ("empty", E0)], c=["nan", "shape"],
           Sigma_w=["nan", ("negdef", -I2), ("3x3", np.eye(3))], sigma_v2=VAR,
           sigma_n2=VAR + ["zero"], P0=["nan", ("negdef", -I2)], steps=[("neg", -1)]))
bad("fading.vector_bound[0x0 state]", "A", fading.vector_bound, E0, np.zeros(0), E0, 1.0, 1.0,
    RAY, E0, 3)
sweep("fading.vector_mc", fading.vector_mc, dict(**VB, n_paths=4, seed=0),
      dict(n_paths=[("zero", 0)], c=["nan"], P0=[("negdef", -I2)]))
sweep("fading.triu_to_symmetric", fading.triu_to_symmetric, dict(x=np.ones(3), n=2),
      dict(x=["nan", "inf", "shape"], n=[("zero", 0), ("float", 2.0)]))

# ====================================================================================== power
AW = dict(a=0.5, sigma_w2=1.0)
AWBAD = dict(a=SCAL + [("one", 1.0), ("two", 2.0)], sigma_w2=VAR)
sweep("power.stationary_variance", power.stationary_variance, AW, AWBAD)
limit("power.stationary_variance[a=0]", 1.0, power.stationary_variance, 0.0, 1.0)
M2 = np.ones(2)
sweep("power.kappa", power.kappa, dict(AW, c=M2, sigma_v2=M2),
      dict(AWBAD, c=["nan", "inf"], sigma_v2=["nan", "neg", "zero", "shape"]))
sweep("power.transmit_power", power.transmit_power, dict(AW, alpha=M2, c=M2, sigma_v2=M2),
      dict(alpha=["nan", "inf", "shape"], c=["nan"], sigma_v2=["zero", "neg"], a=["nan"]))
sweep("power.steady_state", power.steady_state, dict(AW, S=1.0),
      dict(a=SCAL, sigma_w2=VAR, S=VAR))
limit("power.steady_state[S=1e300: the limit sigma_w2]", 1.0, power.steady_state, 0.5, 1.0,
      1e300)
sweep("power.required_snr", power.required_snr, dict(AW, D=1.2),
      dict(D=SCAL + [("below", 0.5), ("above", 2.0)], a=["nan", ("one", 1.0)],
           sigma_w2=["nan", "neg", "zero"]))
SNR = dict(access="orthogonal", alpha=M2, h=M2, c=M2, sigma_v2=M2, sigma_n2=1.0)
sweep("power.snr", power.snr, SNR,
      dict(access=[("bad", "tdma")], alpha=["nan", "inf", "shape"], h=["nan", "neg", "zero"],
           c=["nan"], sigma_v2=["neg", "zero"], sigma_n2=VAR))
limit("power.snr[sigma_n2=0,one sensor]", 1.0, power.snr, "orthogonal", np.ones(1), np.ones(1),
      np.ones(1), np.ones(1), 0.0)
RT = dict(rho=M2, tau=M2, kappa=M2, sigma_n2=1.0)
RTBAD = dict(rho=["nan", "inf", ("zeros", np.zeros(2)), "empty"], tau=["nan", "neg", "zero"],
             kappa=["nan", "neg", "zero", "shape"], sigma_n2=["nan", "neg"])
sweep("power.coherent_min_power", power.coherent_min_power, dict(RT, x=1.0, y=1.0),
      dict(RTBAD, x=VAR + ["zero"], y=VAR + ["zero"], sigma_n2=["zero"],
           infeasible=[("bad", "ignore")]))
sweep("power.coherent_max_snr", power.coherent_max_snr, dict(RT, gamma_total=1.0),
      dict(RTBAD, gamma_total=VAR))
limit("power.coherent_max_snr[gamma_total=0]", 0.0, power.coherent_max_snr, gamma_total=0.0,
      **RT)
sweep("power.orthogonal_min_power", power.orthogonal_min_power, dict(RT, x=1.0, y=1.0),
      dict(RTBAD, x=VAR, y=VAR + ["zero"]))
sweep("power.orthogonal_max_snr", power.orthogonal_max_snr, dict(RT, gamma_total=1.0),
      dict(RTBAD, gamma_total=VAR))
limit("power.orthogonal_max_snr[gamma_total=0]", 0.0, power.orthogonal_max_snr,
      gamma_total=0.0, **RT)
sweep("power.general_min_power", power.general_min_power,
      dict(RT, access="orthogonal", x=1.0, y=1.0), dict(access=[("bad", "x")], x=["nan"]))
sweep("power.general_max_snr", power.general_max_snr,
      dict(RT, access="multi-access", gamma_total=1.0),
      dict(access=[("bad", "x")], gamma_total=["neg"], rho=["nan"]))
sweep("power.coherent_max_snr_printed", power.coherent_max_snr_printed,
      dict(RT, gamma_total=1.0), dict(rho=["nan"], gamma_total=["zero", "neg"],
                                     sigma_n2=["zero"]))
sweep("power.static_coefficients", power.static_coefficients,
      dict(AW, h=M2, c=M2, sigma_v2=M2),
      dict(a=["nan", ("one", 1.0)], h=["nan", "zero", "neg", "shape"], c=["nan"],
           sigma_v2=["zero"]))
PWR = dict(access="orthogonal", D=1.2, a=0.5, sigma_w2=1.0, h=M2, c=M2, sigma_v2=M2,
           sigma_n2=1.0)
sweep("power.min_power", power.min_power, PWR,
      dict(D=["nan", ("below", 0.5)], a=["nan"], h=["zero"], sigma_n2=["zero", "nan"],
           access=[("bad", "x")]))
sweep("power.min_error", power.min_error,
      {**{k: v for k, v in PWR.items() if k != "D"}, "gamma_total": 1.0},
      dict(gamma_total=VAR, a=["nan", ("one", 1.0)], sigma_v2=["zero"], h=["shape"]))
sweep("power.equal_power", power.equal_power, dict(a=0.5, sigma_w2=1.0, c=M2, sigma_v2=M2,
                                                  gamma=1.0),
      dict(gamma=VAR, c=["nan"], a=["nan"]))
sweep("power.equal_power_min_power", power.equal_power_min_power, PWR,
      dict(D=["nan", ("above", 2.0)], sigma_n2=["zero"]))
sweep("power.csi_min_power_step", power.csi_min_power_step, dict(PWR, P=1.0),
      dict(P=VAR, D=["nan"], h=["zero"]))
sweep("power.csi_min_error_step", power.csi_min_error_step,
      {**{k: v for k, v in PWR.items() if k != "D"}, "gamma_total": 1.0},
      dict(gamma_total=["nan", "neg"], h=["zero"]))
sweep("power.greedy_min_error", power.greedy_min_error,
      {**{k: v for k, v in PWR.items() if k != "D"}, "gamma_total": 1.0,
       "h": np.ones((3, 2))},
      dict(gamma_total=["nan", "neg"], h=["nan", ("zero", np.zeros((3, 2)))],
           P0=["nan", "neg"]))
sweep("power.greedy_min_power", power.greedy_min_power, dict(PWR, h=np.ones((3, 2))),
      dict(D=["nan"], P0=["nan", "neg"], h=[("zero", np.zeros((3, 2)))]))
sweep("power.steady_recursion", power.steady_recursion, dict(P=1.0, a=0.5, sigma_w2=1.0,
                                                             S=1.0),
      dict(P=VAR, a=SCAL, sigma_w2=VAR, S=VAR))
sweep("power.beamformed", power.beamformed, dict(alpha=M2, h_mean=M2 + 0j),
      dict(alpha=["nan", "inf", "shape"], h_mean=[("nan", np.full(2, NAN + 0j))]))
LM = dict(access="orthogonal", alpha=M2, a=0.5, sigma_w2=1.0, c=M2, sigma_v2=M2,
          sigma_n2=1.0, h_mean=M2 + 0j, h_var_re=M2 * .1, h_var_im=M2 * .1)
sweep("power.lmmse_steady_state", power.lmmse_steady_state, LM,
      dict(alpha=["nan", "shape", ("complex", M2 + 1j)], a=["nan", ("one", 1.0)],
           sigma_w2=["neg"], sigma_v2=["zero", "neg"], sigma_n2=["zero", "nan"],
           h_mean=[("zero", np.zeros(2, complex))], h_var_re=["neg", "nan"],
           h_var_im=["neg"]))
sweep("power.lmmse_coefficients", power.lmmse_coefficients,
      {k: LM[k] for k in ("a", "sigma_w2", "c", "sigma_v2", "h_mean", "h_var_re", "h_var_im")},
      dict(a=["nan"], h_var_re=["neg"], h_mean=[("nan", np.full(2, NAN + 0j))]))
sweep("power.lmmse_min_power", power.lmmse_min_power,
      {**{k: v for k, v in LM.items() if k != "alpha"}, "D": 1.2},
      dict(D=["nan", ("below", 0.5)], sigma_n2=["zero"], h_var_im=["neg"]))
sweep("power.lmmse_min_error", power.lmmse_min_error,
      {**{k: v for k, v in LM.items() if k != "alpha"}, "gamma_total": 1.0},
      dict(gamma_total=["nan", "neg"], h_var_re=["nan"]))
sweep("power.lmmse_snr", power.lmmse_snr, dict(Cbar=M2, Rbar=I2),
      dict(Cbar=["nan", "shape"], Rbar=["nan", ("negdef", -I2),
                                                        ("asym", np.array([[1, 1], [0, 1.]]))]))
sweep("power.lmmse_filter", power.lmmse_filter,
      dict(z=np.zeros((3, 4, 2)), a=0.5, sigma_w2=1.0, Cbar=M2, Rbar=I2),
      dict(z=["nan", "inf", ("shape", np.zeros((3, 4, 3)))], a=["nan"], sigma_w2=["neg"],
           Cbar=["nan"], Rbar=[("negdef", -I2), ("singular", Z2)], P0=["nan", "neg"]))
sweep("power.simulate_nocsi", power.simulate_nocsi,
      dict(rng=np.random.default_rng(0), n=2, steps=3, **{k: v for k, v in LM.items()
                                                          if k != "alpha"}, alpha_t=M2 + 0j),
      dict(n=[("zero", 0)], steps=[("zero", 0)], sigma_n2=["zero"], h_var_re=["neg"],
           alpha_t=[("nan", np.full(2, NAN + 0j))]))
sweep("power.symmetric_asymptotics", power.symmetric_asymptotics,
      dict(access="orthogonal", scaling="sqrt", a=0.5, sigma_w2=1.0, h=1.0, c=1.0,
           sigma_v2=1.0, sigma_n2=1.0),
      dict(scaling=[("bad", "log")], a=["nan"], h=["zero", "nan"], c=["zero"],
           sigma_v2=["zero"], sigma_n2=["neg"]))
sweep("power.lemma4_bounds", power.lemma4_bounds,
      dict(M=4, a=0.5, sigma_w2=1.0, sigma_n2=1.0, h_range=(1.0, 2.0), c_range=(1.0, 2.0),
           sigma_v2_range=(1.0, 2.0)),
      dict(M=[("zero", 0), ("nan", NAN)], h_range=[("reversed", (2.0, 1.0)),
                                                   ("zero", (0.0, 1.0))],
           sigma_v2_range=[("nan", (NAN, 1.0))], a=["nan"]))
sweep("power.solve_numerically", power.solve_numerically,
      dict(problem="coherent-max-snr", **RT, gamma_total=1.0, starts=1),
      dict(problem=[("bad", "x")], gamma_total=["nan", "neg"], starts=[("zero", 0)],
           seed=[("neg", -1)]))

# =================================================================================== particle
LW = np.log(np.array([[0.2, 0.3, 0.5]]))
sweep("particle.log_normalize", particle.log_normalize, dict(logw=LW),
      dict(logw=["nan", "inf", "empty"]))
limit("particle.log_normalize[all -inf: uniform weights, log_sum -inf (documented)]",
      lambda o: np.allclose(np.exp(o[0]), 1 / 3) and o[1][0] == -INF, particle.log_normalize,
      np.full((1, 3), -INF))
sweep("particle.ess", particle.ess, dict(logw=LW), dict(logw=["nan", "inf", "empty"]))
limit("particle.ess[one particle]", 1.0, particle.ess, np.zeros((1, 1)))
sweep("particle.systematic_counts", particle.systematic_counts, dict(logw=LW, u=np.array([.5])),
      dict(logw=["nan"], u=["nan", ("one", np.array([1.0])), "neg", ("2", np.array([.1, .2]))]))
sweep("particle.systematic_resample", particle.systematic_resample,
      dict(logw=LW, u=np.array([.5])), dict(logw=["nan"], u=["nan", ("one", np.array([1.0]))]))
X = np.arange(6.0).reshape(1, 3, 2)
sweep("particle.resample", particle.resample, dict(x=X, idx=np.array([[0, 1, 2]])),
      dict(idx=[("3", np.array([[0, 1, 3]])), ("neg", np.array([[0, -1, 2]])),
                ("float", np.array([[0.5, 1, 2]])), ("text", "0")]))
limit("particle.resample[K=2 of 3 particles (documented)]", X[:, [2, 0]], particle.resample, X,
      np.array([[2, 0]]))
limit("particle.resample[x NaN: a gather copies values]", lambda o: np.isnan(o[0, 0, 0]),
      particle.resample, np.full((1, 3, 2), NAN), np.array([[0, 1, 2]]))
sweep("particle.weighted_mean", particle.weighted_mean, dict(x=X, logw=LW),
      dict(x=["nan", "inf"], logw=["nan", ("2", np.zeros((1, 2)))]))
sweep("particle.weighted_mean_cov", particle.weighted_mean_cov, dict(x=X, logw=LW),
      dict(x=["nan"], logw=["nan", "inf"]))
sweep("particle.by_component", particle.by_component, dict(x=X),
      dict(x=[("2-D", np.zeros((3, 2))), "text"]))
limit("particle.by_component[x NaN: a layout copies values]", lambda o: np.isnan(o[0, 0, 0]),
      particle.by_component, np.full((1, 3, 2), NAN))
sweep("particle.psd_factor", particle.psd_factor, dict(M=I2),
      dict(M=["nan", ("negdef", -I2), ("asym", np.array([[1, 1], [0, 1.]])), ("empty", E0)],
           rtol=[("neg", -1.0), ("one", 1.0), ("nan", NAN)]))
limit("particle.psd_factor[singular]", lambda L: np.allclose(L @ L.T, np.diag([1.0, 0.0])),
      particle.psd_factor, np.diag([1.0, 0.0]))
sweep("particle.LinearGaussianDynamics", particle.LinearGaussianDynamics,
      dict(A=I2, Q=I2, m0=np.zeros(2), P0=I2),
      dict(A=["nan", ("2x3", np.ones((2, 3)))], Q=["nan", ("negdef", -I2)],
           m0=["nan", "shape"], P0=[("negdef", -I2)]))
bad("particle.LinearGaussianDynamics[0x0 state]", "A", particle.LinearGaussianDynamics, E0, E0,
    np.zeros(0), E0)

# ================================================================================== censoring
sweep("censoring.threshold", censoring.threshold, dict(l=1.0, N=2),
      dict(l=["nan", "neg", "zero", ("above N", 3.0)], N=[("zero", 0), ("float", 2.5)],
           dof=[("zero", 0)]))
MSRE = dict(mu=0.0, s=1.0, r=1.0, eta=1.0)
MSREBAD = dict(mu=["nan", "inf"], s=VAR, r=VAR + ["zero"], eta=["nan", "neg"])
sweep("censoring.censored_probability", censoring.censored_probability, MSRE, MSREBAD)
sweep("censoring.log_censored_probability", censoring.log_censored_probability, MSRE,
      MSREBAD)
limit("censoring.censored_probability[s=0]", lambda p: 0 <= p <= 1,
      censoring.censored_probability, 0.0, 0.0, 1.0, 1.0)
sweep("censoring.bivariate_normal_cdf", censoring.bivariate_normal_cdf,
      dict(h=0.0, k=0.0, rho=0.5), dict(h=["nan"], k=["nan"], rho=["nan", ("2", 2.0)]))
limit("censoring.bivariate_normal_cdf[rho=1]", 0.5, censoring.bivariate_normal_cdf, 0.0, 0.0,
      1.0)
sweep("censoring.bivariate_rectangle", censoring.bivariate_rectangle,
      dict(l1=-1.0, u1=1.0, l2=-1.0, u2=1.0, rho=0.0),
      dict(l1=["nan"], u2=["nan"], rho=["nan", ("-2", -2.0)]))
LF = dict(sent=np.array([True, False]), z=np.array([0.5, 0.0]), hx=np.zeros(2),
          hx_pred=np.zeros(2), s=np.ones(2), r=np.ones(2), eta=1.0)
sweep("censoring.log_likelihood_feedback", censoring.log_likelihood_feedback, LF,
      dict(z=[("nan sent", np.array([NAN, 0.0]))], hx=["nan", "inf"], hx_pred=["nan"],
           s=["nan", "neg"], r=["nan", "neg", "zero", "shape"], eta=["nan", "neg"],
           sent=[("float", np.array([0.5, 0.0]))]))
LN = dict(sent=np.array([True, False]), z=np.array([0.5, 0.0]), hx=np.zeros(2), C=I2,
          r=np.ones(2), eta=1.0)
sweep("censoring.log_likelihood_no_feedback", censoring.log_likelihood_no_feedback, LN,
      dict(hx=["nan"], C=["nan", ("negdef", -I2)], r=["nan", "neg", "zero"],
           eta=["nan", "neg"], version=[("bad", "x")]))
bad("censoring.LinearScenario[N=0]", "N", censoring.LinearScenario, N=0)
bad("censoring.LinearScenario[r=-1]", "r", censoring.LinearScenario, r=-1.0)
bad("censoring.LinearScenario[r=nan]", "r", censoring.LinearScenario, r=NAN)
bad("censoring.LinearScenario[sigma2=nan]", "sigma2", censoring.LinearScenario, sigma2=NAN)
bad("censoring.LinearScenario[dt=0]", "dt", censoring.LinearScenario, dt=0.0)
bad("censoring.LinearScenario[T=0]", "T", censoring.LinearScenario, T=0)
bad("censoring.LinearScenario[x0=nan]", "x0", censoring.LinearScenario, x0=(NAN, 0.0))
bad("censoring.LinearScenario[h=nan]", "h", censoring.LinearScenario, h=(NAN, 0.0))
bad("censoring.LinearScenario[P0 negdef]", "P0", censoring.LinearScenario,
    P0=((-1.0, 0.0), (0.0, 1.0)))
limit("censoring.LinearScenario[one sensor]", lambda s: s.N == 1, censoring.LinearScenario, N=1)
_sc = censoring.LinearScenario(T=3)
bad("censoring.run[l=0]", "l", censoring.run, _sc, "cfwmd", l=0.0, n_trials=1, n_particles=10,
    seed=0)
bad("censoring.run[l=nan]", "l", censoring.run, _sc, "cfwmd", l=NAN, n_trials=1,
    n_particles=10, seed=0)
bad("censoring.run[n_particles=0]", "n_particles", censoring.run, _sc, "cfwmd", l=1.0,
    n_trials=1, n_particles=0, seed=0)
bad("censoring.run[ess_threshold=2]", "ess_threshold", censoring.run, _sc, "cfwmd", l=1.0,
    n_trials=1, n_particles=10, seed=0, ess_threshold=2.0)
bad("censoring.run[scheme]", "scheme", censoring.run, _sc, "x", l=1.0, n_trials=1,
    n_particles=10, seed=0)

# EKF step and the sensors' EKFs (zheng2014 Section VII.C)
EK = dict(P=I2, g=np.array([1.0, 0.0]), F=I2, Q=I2, r=1.0)
sweep("censoring.nonlinear.ekf_covariance_step", nlm.ekf_covariance_step, EK,
      dict(P=["nan", ("negdef", -I2), ("empty", E0)], g=["nan", "inf", "shape"],
           F=["nan", ("3x3", np.eye(3))], Q=["nan", ("negdef", -I2)], r=VAR))
bad("censoring.nonlinear.ekf_covariance_step[0x0 state]", "P", nlm.ekf_covariance_step, E0,
    np.zeros(0), E0, E0, 1.0)
limit("censoring.nonlinear.ekf_covariance_step[s=0: g=0, r=0]",
      lambda o: o[1] == 0 and np.array_equal(o[2], 2 * I2), nlm.ekf_covariance_step,
      **{**EK, "g": np.zeros(2), "r": 0.0})
limit("censoring.nonlinear.ekf_covariance_step[r=0]",
      lambda o: o[1] == 2 and np.allclose(o[2], np.diag([0.0, 2.0])), nlm.ekf_covariance_step,
      **{**EK, "r": 0.0})
_nsc0 = nlm.NonlinearScenario(T=2, r=1.0)
bad("censoring.nonlinear.local_ekf[z=nan]", "z", nlm.local_ekf, _nsc0,
    np.full((1, 2, 9), NAN))
bad("censoring.nonlinear.local_ekf[z shape]", "z", nlm.local_ekf, _nsc0, np.zeros((1, 2, 8)))
bad("censoring.nonlinear.NonlinearScenario[r=-1]", "r", nlm.NonlinearScenario, r=-1.0)
bad("censoring.nonlinear.NonlinearScenario[r=nan]", "r", nlm.NonlinearScenario, r=NAN)
# r = 0 would make s = g P g^T + r = 0 possible in the sensors' EKFs (a zero gradient) and leave
# the particle filter's likelihood without a density: the scenario documents r > 0
bad("censoring.nonlinear.NonlinearScenario[r=0]", "r", nlm.NonlinearScenario, r=0.0)
bad("censoring.nonlinear.NonlinearScenario[sigma2=-1]", "sigma2", nlm.NonlinearScenario,
    sigma2=-1.0)
bad("censoring.nonlinear.amplitude[pos=nan]", "pos", nlm.amplitude, _nsc0, np.full(2, NAN))
bad("censoring.nonlinear.jacobian[x shape]", "x", nlm.jacobian, _nsc0, np.zeros(3))

# vector and nonlinear censoring (zheng2014 Sections V-VII)
from fusioncenter.censoring import ellipse as ell  # noqa: E402
from fusioncenter.censoring import nonlinear as cnl  # noqa: E402
from fusioncenter.censoring import vector as cvec  # noqa: E402
from fusioncenter.censoring import vector_likelihood as vlik  # noqa: E402

sweep("censoring.ellipse.log_censored_probability", ell.log_censored_probability,
      dict(mean=np.zeros(2), cov=I2, eta=1.0),
      dict(mean=["nan", "inf", "shape"], cov=["nan", ("negdef", -I2),
                                               ("asym", np.array([[1, 1], [0, 1.]]))],
           eta=["nan", "neg"]))
limit("censoring.ellipse.log_censored_probability[cov=0, inside]", 0.0,
      ell.log_censored_probability, np.zeros(2), Z2, 1.0)
limit("censoring.ellipse.log_censored_probability[cov=0, outside]", -INF,
      ell.log_censored_probability, np.full(2, 3.0), Z2, 1.0)
sweep("censoring.ellipse.log_silent_probability", ell.log_silent_probability,
      dict(mu=np.zeros(2), S=I2, R=I2, eta=1.0),
      dict(mu=["nan", "shape"], S=["nan", ("singular", Z2), ("negdef", -I2)],
           R=["nan", ("negdef", -I2)], eta=["nan", "neg"]))
sweep("censoring.ellipse.canonical_map", ell.canonical_map, dict(S=I2, R=I2),
      dict(S=["nan", ("singular", Z2)], R=["nan", ("negdef", -I2)]))
sweep("censoring.ellipse.log_canon", ell.log_canon, dict(b1=0.0, b2=0.0, a1=1.0, a2=1.0),
      dict(b1=["nan", "inf"], a1=["nan", "neg", "zero"], a2=["neg"], K=[("zero", 0)]))
sweep("censoring.ellipse.log_inside_1d", ell.log_inside_1d, dict(b=0.0, a=1.0),
      dict(b=["nan"], a=["nan", "neg"]))
sweep("censoring.vector.whitening", cvec.whitening, dict(R=I2),
      dict(R=["nan", ("singular", Z2), ("negdef", -I2), ("empty", E0)]))
sweep("censoring.vector.log_all_silent", cvec.log_all_silent,
      dict(cov=np.eye(4), S=np.stack([I2, I2]), eta=1.0),
      dict(cov=["nan", ("negdef", -np.eye(4)), ("3x3", np.eye(3))],
           S=["nan", ("negdef", -np.stack([I2, I2]))], eta=["nan", "neg"], K=[("zero", 0)]))
bad("censoring.vector.VectorScenario[R singular]", "R", cvec.VectorScenario, R=((1.0, 0.0),
                                                                             (0.0, 0.0)))
bad("censoring.vector.VectorScenario[R nan]", "R", cvec.VectorScenario, R=((NAN, 0.0),
                                                                         (0.0, 1.0)))
bad("censoring.vector.VectorScenario[H nan]", "H", cvec.VectorScenario, H=((NAN, 0.0),
                                                                         (0.0, 1.0)))
bad("censoring.vector.VectorScenario[N=0]", "N", cvec.VectorScenario, N=0)
sweep("censoring.nonlinear.log_silent_probability", cnl.log_silent_probability,
      dict(m=0.0, h=1.0), dict(m=["nan"], h=["nan", "neg"]))
NL = dict(sent=np.array([True, False]), z=np.array([0.5, 0.0]), hx=np.zeros(2),
          hx_pred=np.zeros(2), s=np.ones(2), r=np.ones(2), eta=1.0)
sweep("censoring.nonlinear.log_likelihood", cnl.log_likelihood, NL,
      dict(z=[("nan sent", np.array([NAN, 0.0]))], hx=["nan"], s=["nan", "neg"],
           r=["nan", "neg", "zero"], eta=["nan", "neg"], scheme=[("bad", "x")]))
VL = dict(sent=np.array([True, False]), z=np.zeros((2, 2)), Hx=np.zeros((2, 2)),
          Hx_pred=np.zeros((2, 2)), S=np.stack([I2, I2]), R=np.stack([I2, I2]), eta=1.0)
sweep("censoring.vector_likelihood.log_likelihood_feedback", vlik.log_likelihood_feedback, VL,
      dict(z=[("nan sent", np.array([[NAN, 0.0], [0.0, 0.0]]))], Hx=["nan"],
           S=["nan", ("negdef", -np.stack([I2, I2]))], R=[("singular", np.stack([Z2, Z2]))],
           eta=["nan", "neg"]))
sweep("censoring.likelihood.log_gauss", censoring.likelihood.log_gauss,
      dict(z=0.0, mean=0.0, r=1.0), dict(z=["nan"], mean=["inf"], r=["neg", "zero", "nan"]))

# ================================================================================== synthesis
bad("comparison.outage_threshold[outage=1]", "outage", comparison.outage_threshold, 1.0)
bad("comparison.outage_threshold[outage=-0.1]", "outage", comparison.outage_threshold, -0.1)
bad("comparison.outage_threshold[outage=nan]", "outage", comparison.outage_threshold, NAN)
bad("comparison.outage_threshold[channel]", "channel", comparison.outage_threshold, 0.1, "x")
limit("comparison.outage_threshold[outage=0]", 0.0, comparison.outage_threshold, 0.0)
bad("comparison.energy_matched_outage[rate=2]", "rate", comparison.energy_matched_outage, 0.1,
    2.0)
bad("comparison.energy_matched_outage[rate=nan]", "rate", comparison.energy_matched_outage, 0.1,
    NAN)
bad("comparison.energy_matched_outage[outage_full=1]", "outage_full",
    comparison.energy_matched_outage, 1.0, 0.5)
limit("comparison.energy_matched_outage[rate=1]", 0.1, comparison.energy_matched_outage, 0.1, 1.0)
_ssc = censoring.LinearScenario(T=3)
bad("comparison.draw[n=-1]", "n", comparison.draw, np.random.default_rng(0), -1, _ssc)
bad("comparison.draw[rng]", "rng", comparison.draw, 0, 2, _ssc)
_d = comparison.draw(np.random.default_rng(0), 2, _ssc)
_lost = np.zeros(_d.z.shape, bool)
KF = dict(scenario=_ssc, z=_d.z, xi=_d.xi, lost=_lost, scheme="stochastic", delta=1.0)
sweep("comparison.kf_filter", comparison.kf_filter, KF,
      dict(z=[("nan", np.full(_d.z.shape, NAN)), ("shape", _d.z[:, :2])],
           xi=[("nan", np.full(_d.xi.shape, NAN)), ("two", _d.xi + 2.0)],
           lost=[("float", _lost + 0.5)], scheme=[("bad", "x")],
           delta=["nan", "neg", "zero"], receiver=[("bad", "x")]))
bad("comparison.kf_filter[p=1.5]", "p", comparison.kf_filter, _ssc, _d.z, _d.xi, _lost, "random",
    p=1.5)
# KFRun is validated when run (documented): run_kf names the field
bad("comparison.run_kf[KFRun scheme]", "scheme", comparison.run_kf, _ssc, (comparison.KFRun("x"),),
    n_trials=2, seed=0)
bad("comparison.run_kf[KFRun outage=1]", "outage", comparison.run_kf, _ssc,
    (comparison.KFRun("all-send", outage=1.0),), n_trials=2, seed=0)
bad("comparison.run_kf[KFRun delta=nan]", "delta", comparison.run_kf, _ssc,
    (comparison.KFRun("stochastic", delta=NAN),), n_trials=2, seed=0)
bad("comparison.run_kf[n_trials=0]", "n_trials", comparison.run_kf, _ssc,
    (comparison.KFRun("all-send"),), n_trials=0, seed=0)
bad("comparison.run_kf[runs empty]", "runs", comparison.run_kf, _ssc, (), n_trials=2, seed=0)
bad("comparison.kf_flops[n=0]", "n", comparison.kf_flops, 0, 2)
bad("comparison.pf_flops[n_particles=0]", "n_particles", comparison.pf_flops, 2, 2, 0)
bad("comparison.pf_flops[scheme]", "scheme", comparison.pf_flops, 2, 2, 10, "x")
bad("comparison.run_pf[outage=1]", "outage", comparison.run_pf, _ssc, "cfwmd", l=1.0, n_trials=1,
    n_particles=10, seed=0, outage=1.0)

_LABELS = [c.label for c in CASES]
assert len(set(_LABELS)) == len(_LABELS), "duplicate case labels"


@pytest.mark.parametrize("case", CASES, ids=_LABELS)
def test_input(case):
    verdict, detail = run_case(case)
    assert verdict == "ok", f"{verdict}: {case.label}: {detail}"
