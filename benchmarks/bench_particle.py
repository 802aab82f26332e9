"""zheng2014 (Part IV(a)): the fusion centre's particle filter, vectorized vs per-trial loops.

Workload: Section VII.A, N = 2 sensors, l = 1, 32 trials x 1000 particles x 20 steps.

Group 1 -- CFwMD with feedback of the predicted state (Proposition 1).
Group 2 -- CFoMD without feedback: every sensor runs its own Kalman filter on all of its
measurements and censors its own innovation.

The baselines are straightforward per-trial reproductions: for every trial, each sensor is a
``filterpy.kalman.KalmanFilter`` (``predict`` / ``update`` every step; it gives the innovation
variance ``s_k^i`` and, without feedback, the innovation itself), the particles of that trial are
a ``(P, 2)`` array, the likelihood is computed sensor by sensor (the silent factor with the
public, careful ``censoring.log_censored_probability``), and systematic resampling uses
``np.searchsorted``. They replay the random numbers of :func:`fusioncenter.censoring.run` (block
0: the truth and measurements from the data stream; per step the particles' noise and one
uniform per trial from the filter's stream, sub-block by sub-block), so their per-trial squared
errors and transmissions are checked equal (to 1e-9 relative) to ``censoring.run`` before
timing. The target ratio is >= 10x for the CFwMD filter (measured on the project's 2-core
machine: about 11x with state feedback since the fused filter's table, moments and resampling
loops are compiled, 8x before; about 6x for CFoMD without feedback, whose per-trial loop has no
silent factor to evaluate: both loops are vectorized over the 1000 particles of a trial, and
the vectorized filter spends a third of its time drawing the particles' normal noise). The
paper-scale timing of Fig. 1 is in ``bench_censoring.py``.
"""

from __future__ import annotations

import numpy as np
from filterpy.kalman import KalmanFilter

from fusioncenter import censoring as cs
from fusioncenter import particle

TRIALS, PARTICLES, L = 32, 1000, 1.0
SCENARIO = cs.LinearScenario()
SEED = 2014


def _sensors(sc: cs.LinearScenario) -> list[KalmanFilter]:
    out = []
    for i in range(sc.N):
        kf = KalmanFilter(dim_x=2, dim_z=1)
        kf.F, kf.Q = sc.F.copy(), sc.Q.copy()
        kf.H, kf.R = sc.H[i:i + 1].copy(), np.array([[sc.rvec[i]]])
        kf.x = np.asarray(sc.x0, dtype=float).reshape(2, 1)
        kf.P = sc.dynamics.P0.copy()
        out.append(kf)
    return out


def _streams(sc: cs.LinearScenario, n: int, P: int, seed: int):
    """The random numbers of ``censoring.run``'s first block (see ``censoring.dispatch._chunk``)."""
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    rng_data, rng_pf = rng.spawn(2)
    rng_pf = np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))
    x, z = sc.sample(rng_data, n)
    rng_data.random(z.shape)  # random-selection uniforms (unused here)
    LQ = particle.psd_factor(sc.Q)
    # the filter draws sub-block by sub-block (x_0 known: no initial draws), per step the
    # particles' noise then one uniform per trial
    noise = np.empty((sc.T, n, P, LQ.shape[1]))
    u = np.empty((sc.T, n))
    for R in cs.fusion.sub_blocks(n, P):
        for t in range(sc.T):
            noise[t, R] = rng_pf.standard_normal((R.stop - R.start, P, LQ.shape[1]))
            u[t, R] = rng_pf.random(R.stop - R.start)
    return x, z, LQ, list(zip(noise, u, strict=True))


def _systematic(w: np.ndarray, u: float) -> np.ndarray:
    P = w.size
    c = np.cumsum(w)
    c /= c[-1]
    c[-1] = 1.0
    return np.searchsorted(c, (u + np.arange(P)) / P, side="right")


def loop(feedback: str = "state", sc: cs.LinearScenario = SCENARIO, n: int = TRIALS,
         P: int = PARTICLES, l: float = L, seed: int = SEED) -> np.ndarray:
    """Per trial: CFwMD with state feedback, or CFoMD without feedback. ``(n, T, 3)``:
    squared position and velocity errors, number of sensors that sent."""
    eta = cs.threshold(l, sc.N)
    x, z, LQ, draws = _streams(sc, n, P, seed)
    F, H, r = sc.F, sc.H, sc.rvec
    x0 = np.asarray(sc.x0, dtype=float)
    out = np.empty((n, sc.T, 3))
    for b in range(n):
        kfs = _sensors(sc)
        parts = np.tile(x0, (P, 1))  # P0 = 0: x_0 known
        pred = F @ x0
        for t in range(sc.T):
            noise, u = draws[t]
            parts = parts @ F.T + noise[b] @ LQ.T
            sent = np.zeros(sc.N, dtype=bool)
            s = np.empty(sc.N)
            for i, kf in enumerate(kfs):
                kf.predict()
                s[i] = (kf.H @ kf.P @ kf.H.T + kf.R)[0, 0]
                # with feedback the innovation is against the FC's broadcast prediction
                ref = H[i] @ pred if feedback == "state" else (kf.H @ kf.x)[0, 0]
                sent[i] = (z[b, t, i] - ref) ** 2 >= eta * s[i]
                kf.update(z[b, t, i])
            logw = np.zeros(P)
            for i in range(sc.N):
                y = parts @ H[i]
                if sent[i]:
                    logw += -0.5 * np.log(2 * np.pi * r[i]) - 0.5 * (z[b, t, i] - y) ** 2 / r[i]
                elif feedback == "state":  # CFwMD: Proposition 1's silent factor
                    logw += cs.log_censored_probability(y - H[i] @ pred, s[i], r[i], eta)
            w = np.exp(logw - logw.max())
            w /= w.sum()
            mean = w @ parts
            out[b, t, :2] = (mean - x[b, t + 1]) ** 2
            out[b, t, 2] = sent.sum()
            pred = F @ mean
            parts = parts[_systematic(w, u[b])]
    return out


def vectorized(feedback: str = "state", sc: cs.LinearScenario = SCENARIO, n: int = TRIALS,
               P: int = PARTICLES, l: float = L, seed: int = SEED) -> np.ndarray:
    scheme = "cfwmd" if feedback == "state" else "cfomd"
    res = cs.run(sc, scheme, l=l, n_trials=n, n_particles=P, seed=seed, feedback=feedback,
                 block_size=max(n, 1))
    return res.mc.samples[..., :3]


_REF = {}


def _checked(fn, feedback):
    def setup():
        if feedback not in _REF:
            _REF[feedback] = loop(feedback)
        ref = _REF[feedback]
        got = fn(feedback)
        assert np.array_equal(got[..., 2], ref[..., 2])  # the same sensors sent
        np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-12)
        return lambda: fn(feedback)
    return setup


REPEATS = 3
_G1 = "CFwMD, state feedback, 32 trials x 1000 particles x 20 steps"
_G2 = "CFoMD, no feedback (local KFs), 32 trials x 1000 particles x 20 steps"
CASES = [
    (_G1, "per-trial loop (filterpy sensors)", _checked(loop, "state")),
    (_G1, "vectorized (censoring.run)", _checked(vectorized, "state")),
    (_G2, "per-trial loop (filterpy sensors)", _checked(loop, "none")),
    (_G2, "vectorized (censoring.run)", _checked(vectorized, "none")),
]
