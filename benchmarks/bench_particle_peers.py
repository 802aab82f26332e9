"""zheng2014 Section VII.A.1: our particle filter against two peer libraries, `particles` and
Stone Soup.

Workload: that of ``bench_particle_floor.py`` (the linear scenario's defaults: ``N = 2``
sensors measuring the position, ``r = 1``, white-noise acceleration, ``x_0`` known, ``T = 20``;
1000 particles), on 16 trials (the peers are slow): every variant filters the SAME
measurements ``z`` (:func:`bench_particle_floor.data`).

Variants, timed in ONE interleaved run (each round runs every variant once, in turn; the
median over rounds of each variant's CPU time, ``time.process_time``, is reported as ns per
particle-step, with the ratios of each peer to ours all-send and to ours CFwMD):

* ``ours all-send`` and ``ours CFwMD`` (state feedback): :func:`bench_particle_floor.ours`
  (every trial in one call, as ``censoring.run`` runs a sub-block);
* ``particles``: N. Chopin's SMC library, a bootstrap filter (``state_space_models.Bootstrap``) of a
  :class:`particles.state_space_models.StateSpaceModel` written here for this model
  (:func:`_particles_model`), run by ``particles.SMC`` with systematic resampling at every
  step (``ESSrmin=1``) and ``collect=[Moments()]``; one trial at a time (the package filters
  one data set per ``SMC``);
* ``Stone Soup``: ``stonesoup``'s ``ParticlePredictor`` (a
  ``LinearGaussianTimeInvariantTransitionModel`` with ``F`` and the white-noise acceleration's
  rank-one ``Q``), ``ParticleUpdater`` (a ``LinearGaussian`` measurement model, both sensors
  measuring the position, ``R = r I``) and ``SystematicResampler``, with 1000 particles, one
  trial at a time. The estimate of a step is the weighted mean after the update and BEFORE
  resampling, as ours and `particles` report it (the updater is built without a resampler
  and the resampler is called right after: the same work as the updater calling it, but the
  mean of the weighted particles, not the noisier mean of the resampled ones).

The transition noise is rank one (``Q = L L^T`` with ``L`` a column), so the state has no
transition density; a bootstrap filter needs none (it only samples the transition and
evaluates the sensors' likelihood). Both peers draw from NumPy's global ``RandomState``
(seeded once per call, so every run is reproducible); ours from its SFC64 stream.

Checks before timing (the run prints them), on 64 trials: the position and velocity RMSE of
each variant against the truth and the RMS distance of its estimate to the exact Kalman filter
(:func:`bench_particle_floor.kalman_means`; all-send is linear-Gaussian, so the KF is the Bayes
filter and a particle filter's estimate is a Monte Carlo approximation of it). A variant
agrees with the KF when (1) its RMS distance to the KF is below ``MAX_TO_KF`` = 10 % of the
KF's RMSE, for the position and the velocity (the Monte Carlo error then adds at most 1 % to
the KF's mean squared error; 1000 particles give about 8 % here); and, for a peer, paired
trial by trial against ours all-send (the same algorithm: bootstrap proposal, systematic
resampling at every step, the weighted mean), (2) the mean difference of the per-trial
squared distances to the KF and (3) that of the per-trial squared errors against the truth are
within 4 standard errors of zero. (A difference of squared errors against the truth alone
cannot tell a filter from the KF: by the orthogonality of the Bayes estimate it equals the
squared distance to the KF in expectation; (2) is the sharp test.) Model errors planted in a
peer's model fail (2) by 10 to 25 SE: the measurement variance times 1.5 or 2, the transition
noise's covariance times 1.5 (velocity), ``X_0`` at ``x_0`` instead of ``x_1`` (a time
shift, also 28x the bound (1)). Taking Stone Soup's mean after resampling instead of before
passes (systematic resampling adds little noise), but is not what the others compute.
CFwMD filters the censored data (the silent sensors' measurements are not received), so its
estimate is not the all-send KF's: its numbers are printed for reference, not tested.

Peers whose package is not importable are skipped with the reason printed (the project's own
environment has neither): install them in a separate venv, outside the repository::

    python3.11 -m venv /tmp/peers-venv
    /tmp/peers-venv/bin/pip install -c requirements/lock.txt particles stonesoup -e .

Run: ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 /tmp/peers-venv/bin/python
benchmarks/bench_particle_peers.py`` (or ``benchmarks/run.py peers``).
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import datetime  # noqa: E402
import importlib.util  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402


def _load_floor():
    """``bench_particle_floor.py`` (the workload, ``ours``, ``data``, ``kalman_means``)."""
    path = Path(__file__).resolve().parent / "bench_particle_floor.py"
    spec = importlib.util.spec_from_file_location("bench_particle_floor", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


floor = _load_floor()
SC, PARTICLES, SEED = floor.SC, floor.PARTICLES, floor.SEED
TRIALS = 16
CHECK_TRIALS = 64
#: a particle filter's RMS distance to the KF, as a fraction of the KF's RMSE, must stay below
#: this (its Monte Carlo error then adds at most 1 % to the KF's mean squared error)
MAX_TO_KF = 0.1
ROUNDS = 5
LQ = floor.particle.psd_factor(SC.Q)  # Q = LQ LQ^T, (2, 1): the noise is rank one


# ----------------------------------------------------------------------------- particles
def _particles_model():
    """The `particles` bootstrap filter's model class, or the reason it cannot be built."""
    try:
        import particles
        from particles import distributions as dists
        from particles import state_space_models as ssm
    except ImportError as e:
        return None, f"`particles` not importable ({e})"

    F, m0, H, rvec = SC.F, SC.dynamics.m0, SC.H, SC.rvec

    class Transition(dists.ProbDist):
        """``F xp + LQ g``, ``g ~ N(0, I)``: the law of ``x_t`` given ``x_{t-1} = xp`` (rank-one
        noise: sampled, no density, which a bootstrap filter does not need)."""

        dim = 2

        def __init__(self, xp):
            self.xp = xp

        def rvs(self, size=None):
            g = dists.random.standard_normal((size, LQ.shape[1]))  # the package's RNG
            return self.xp @ F.T + g @ LQ.T

    class WhiteNoiseAcceleration(ssm.StateSpaceModel):
        """zheng2014 VII.A.1: ``X_0`` is the law of ``x_1`` (``x_0`` known), ``Y_t`` the ``N``
        sensors' measurements ``H x_t + v``, ``v ~ N(0, diag(r))``."""

        def PX0(self):
            return Transition(m0)

        def PX(self, t, xp):
            return Transition(xp)

        def PY(self, t, xp, x):
            return dists.IndepProd(*[dists.Normal(loc=x @ H[i], scale=math.sqrt(rvec[i]))
                                     for i in range(len(rvec))])

    return (particles, ssm.Bootstrap, WhiteNoiseAcceleration), f"particles {particles.__version__}"


def run_particles(z, seed: int = SEED) -> np.ndarray:
    """The `particles` bootstrap filter's estimates ``(n, T, 2)``, one trial at a time."""
    (particles, bootstrap, model), _ = _PARTICLES
    from particles.collectors import Moments
    np.random.seed(seed)  # noqa: NPY002 (the peers draw from NumPy's global RandomState)
    n, T, _ = z.shape
    out = np.empty((n, T, 2))
    for b in range(n):
        fk = bootstrap(ssm=model(), data=z[b])
        pf = particles.SMC(fk=fk, N=PARTICLES, resampling="systematic", ESSrmin=1.0,
                           collect=[Moments()])
        pf.run()
        out[b] = [m["mean"] for m in pf.summaries.moments]
    return out


# ----------------------------------------------------------------------------- Stone Soup
def _stonesoup_parts():
    """Stone Soup's predictor, updater and resampler for this model, or the reason."""
    try:
        import stonesoup
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.models.transition.linear import (
            LinearGaussianTimeInvariantTransitionModel,
        )
        from stonesoup.predictor.particle import ParticlePredictor
        from stonesoup.resampler.particle import SystematicResampler
        from stonesoup.types.detection import Detection
        from stonesoup.types.hypothesis import SingleHypothesis
        from stonesoup.types.state import ParticleState, StateVector, StateVectors
        from stonesoup.updater.particle import ParticleUpdater
    except ImportError as e:
        return None, f"Stone Soup not importable ({e})"
    # every sensor measures the position: H's rows select state component 0
    mapping = tuple(int(np.flatnonzero(h)[0]) for h in SC.H)
    assert np.array_equal(SC.H, np.eye(2)[list(mapping)])
    tm = LinearGaussianTimeInvariantTransitionModel(transition_matrix=SC.F,
                                                    covariance_matrix=SC.Q)
    mm = LinearGaussian(ndim_state=2, mapping=mapping, noise_covar=np.diag(SC.rvec))
    parts = dict(predictor=ParticlePredictor(transition_model=tm),
                 updater=ParticleUpdater(measurement_model=mm),  # resampled below, see module
                 resampler=SystematicResampler(), mm=mm, Detection=Detection,
                 SingleHypothesis=SingleHypothesis, ParticleState=ParticleState,
                 StateVector=StateVector, StateVectors=StateVectors)
    return parts, f"stonesoup {stonesoup.__version__}"


def run_stonesoup(z, seed: int = SEED) -> np.ndarray:
    """Stone Soup's particle filter's estimates ``(n, T, 2)``, one trial at a time."""
    s, _ = _STONESOUP
    np.random.seed(seed)  # noqa: NPY002 (the peers draw from NumPy's global RandomState)
    n, T, _ = z.shape
    dt = datetime.timedelta(seconds=float(SC.F[0, 1]))
    t0 = datetime.datetime(2014, 1, 1)
    out = np.empty((n, T, 2))
    x0 = np.tile(np.asarray(SC.dynamics.m0, float)[:, None], PARTICLES)
    lw0 = np.full(PARTICLES, -math.log(PARTICLES))
    for b in range(n):
        state = s["ParticleState"](s["StateVectors"](x0.copy()), log_weight=lw0.copy(),
                                   timestamp=t0)
        for t in range(T):
            ts = t0 + (t + 1) * dt
            pred = s["predictor"].predict(state, timestamp=ts)
            det = s["Detection"](s["StateVector"](z[b, t]), timestamp=ts,
                                 measurement_model=s["mm"])
            post = s["updater"].update(s["SingleHypothesis"](pred, det))
            out[b, t] = np.asarray(post.mean, float).ravel()
            state = s["resampler"].resample(post)
    return out


_PARTICLES = _particles_model()
_STONESOUP = _stonesoup_parts()


# ----------------------------------------------------------------------------- variants
def variants() -> tuple[dict, list[str]]:
    """The importable variants (name -> function of ``(x, z, sel_u, state)``) and the reasons
    for the skipped ones."""
    v = {"ours all-send": lambda d: floor.ours("all-send", *d),
         "ours CFwMD": lambda d: floor.ours("cfwmd", *d)}
    skipped = []
    for name, (obj, why), fn in (("particles", _PARTICLES, run_particles),
                                 ("Stone Soup", _STONESOUP, run_stonesoup)):
        if obj is None:
            skipped.append(f"{name}: skipped, {why}")
        else:
            v[name] = lambda d, fn=fn: fn(d[1])
    return v, skipped


def versions() -> str:
    import numba
    import scipy
    out = [f"numpy {np.__version__}", f"scipy {scipy.__version__}", f"numba {numba.__version__}"]
    return ", ".join(out + [why for obj, why in (_PARTICLES, _STONESOUP) if obj is not None])


# ----------------------------------------------------------------------------- checks
def check(n: int = CHECK_TRIALS, seed: int = SEED) -> None:
    """Print the RMSEs and distances to the KF and test the agreement (see the module)."""
    vs, _ = variants()
    d = floor.data(n, seed)
    x, z = d[0], d[1]
    kf = floor.kalman_means(z)
    truth = x[:, 1:]
    est = {name: fn(d) for name, fn in vs.items()}
    kf_rm = np.sqrt(((kf - truth) ** 2).mean(axis=(0, 1)))
    print(f"  checks on {n} trials x {PARTICLES} particles x {SC.T} steps (the same z for all):")
    print(f"  {'variant':<22} {'RMSE pos':>9} {'RMSE vel':>9} {'RMS to KF pos':>14} "
          f"{'vel':>7}")
    print(f"  {'exact Kalman filter':<22} {kf_rm[0]:9.4f} {kf_rm[1]:9.4f}")
    for name, m in est.items():
        rm = np.sqrt(((m - truth) ** 2).mean(axis=(0, 1)))
        to_kf = np.sqrt(((m - kf) ** 2).mean(axis=(0, 1)))
        note = "  (censored data: reference only)" if name == "ours CFwMD" else ""
        print(f"  {name:<22} {rm[0]:9.4f} {rm[1]:9.4f} {to_kf[0]:14.4f} {to_kf[1]:7.4f}{note}")

    def within(dd):  # per-trial differences (n, 2): mean, SE, |mean| <= 4 SE
        dm, se = dd.mean(axis=0), dd.std(axis=0, ddof=1) / math.sqrt(dd.shape[0])
        return dm, se, bool(np.all(np.abs(dm) <= 4 * se))

    def mse(a, b):
        return ((a - b) ** 2).mean(axis=1)  # (n, 2) per trial

    ours_ = est["ours all-send"]
    for name in est:
        if name == "ours CFwMD":
            continue
        to_kf = np.sqrt(mse(est[name], kf).mean(axis=0))
        small = bool(np.all(to_kf < MAX_TO_KF * kf_rm))
        line = (f"  {name}: RMS to KF / KF's RMSE pos {to_kf[0] / kf_rm[0]:.3f}, "
                f"vel {to_kf[1] / kf_rm[1]:.3f} (bound {MAX_TO_KF})")
        oka = okb = True
        if name != "ours all-send":
            db, sb, okb = within(mse(est[name], kf) - mse(ours_, kf))
            da, sa, oka = within(mse(est[name], truth) - mse(ours_, truth))
            line += (f"; minus ours all-send, per trial: MSE to KF pos {db[0]:+.1e} "
                     f"(SE {sb[0]:.1e}), vel {db[1]:+.1e} (SE {sb[1]:.1e}); MSE to truth pos "
                     f"{da[0]:+.1e} (SE {sa[0]:.1e}), vel {da[1]:+.1e} (SE {sa[1]:.1e})")
        print(line + f": {'agree' if small and oka and okb else 'DISAGREE'}")
        assert small and oka and okb, name


# ----------------------------------------------------------------------------- timing
def timing(rounds: int = ROUNDS, n: int = TRIALS) -> dict[str, float]:
    """Interleaved CPU times; returns the median ns per particle-step of each variant."""
    vs, _ = variants()
    d = floor.data(n, SEED)
    for fn in vs.values():
        fn(d)  # warm-up (compilation, imports, caches)
    times: dict[str, list[float]] = {k: [] for k in vs}
    for _ in range(rounds):
        for name, fn in vs.items():
            t0 = time.process_time()
            fn(d)
            times[name].append(time.process_time() - t0)
    ps = n * PARTICLES * SC.T
    med = {k: statistics.median(v) / ps * 1e9 for k, v in times.items()}
    print(f"  timing: {rounds} interleaved rounds of {n} trials x {PARTICLES} particles x "
          f"{SC.T} steps, CPU time, medians (load average {os.getloadavg()[0]:.2f})")
    print(f"  {'variant':<22} {'ns/particle-step':>17} {'min':>8} {'max':>8} "
          f"{'/ all-send':>11} {'/ CFwMD':>8}")
    for k, v in med.items():
        lo, hi = min(times[k]) / ps * 1e9, max(times[k]) / ps * 1e9
        print(f"  {k:<22} {v:17.1f} {lo:8.1f} {hi:8.1f} {v / med['ours all-send']:10.2f}x "
              f"{v / med['ours CFwMD']:7.2f}x")
    return med


def main() -> None:
    _, skipped = variants()
    print(f"  {versions()}")
    for s in skipped:
        print(f"  {s}")
    check()
    timing()


REPEATS = 1
CASES = [("particle peers (zheng2014 VII.A.1, 16 x 1000 x 20)", "ours vs particles, Stone Soup",
          lambda: main)]

if __name__ == "__main__":
    main()
