"""The fusion centre's particle filter (zheng2014 CFwMD, state feedback): vectorized vs a loop.

Workload: Section VII.A (N = 2 sensors, l = 1), 32 trials x 1000 particles x 20 steps.

* baseline: a straightforward per-trial reproduction -- for every trial and step, the particles of
  that trial as a ``(P, 2)`` array, the likelihood sensor by sensor with the public
  ``censoring.log_censored_probability``, ``np.searchsorted`` systematic resampling;
* vectorized: :func:`fusioncenter.censoring.run` (all trials of a block at once, shape
  ``(trials, particles, 2)``).

Both draw the same random numbers (the baseline replays ``run``'s streams: the truth from the
first spawned generator, then per step the particles' noise and one uniform per trial from the
second), so their per-trial squared errors and transmissions are checked equal before timing.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import particle

TRIALS, PARTICLES, L = 32, 1000, 1.0
SCENARIO = cs.LinearScenario()
SEED = 2014


def loop(sc: cs.LinearScenario = SCENARIO, n: int = TRIALS, P: int = PARTICLES, l: float = L,
         seed: int = SEED) -> np.ndarray:
    """Per-trial CFwMD with state feedback; returns ``(n, T, 3)``: squared errors, #sent."""
    eta = cs.threshold(l, sc.N)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])  # run's block 0
    rng_data, rng_pf = rng.spawn(2)
    x, z = sc.sample(rng_data, n)
    rng_data.random(z.shape)  # random-selection uniforms (unused by CFwMD)
    LQ = particle.psd_factor(sc.Q)
    draws = [(rng_pf.standard_normal((n, P, LQ.shape[1])), rng_pf.random(n))
             for _ in range(sc.T)]
    s_loc = sc.local_filters()["s"]
    F, H, r = sc.F, sc.H, sc.rvec
    out = np.empty((n, sc.T, 3))
    for b in range(n):
        parts = np.tile(np.asarray(sc.x0, dtype=float), (P, 1))  # P0 = 0: x_0 known
        pred = F @ np.asarray(sc.x0, dtype=float)
        for t in range(sc.T):
            noise, u = draws[t]
            parts = parts @ F.T + noise[b] @ LQ.T
            nu = z[b, t] - H @ pred
            sent = nu**2 >= eta * s_loc[t]
            logw = np.zeros(P)
            for i in range(sc.N):
                y = parts @ H[i]
                if sent[i]:
                    logw += -0.5 * np.log(2 * np.pi * r[i]) - 0.5 * (z[b, t, i] - y) ** 2 / r[i]
                else:
                    logw += cs.log_censored_probability(y - H[i] @ pred, s_loc[t, i], r[i], eta)
            w = np.exp(logw - logw.max())
            w /= w.sum()
            mean = w @ parts
            out[b, t, :2] = (mean - x[b, t + 1]) ** 2
            out[b, t, 2] = sent.sum()
            pred = F @ mean
            c = np.cumsum(w)
            c /= c[-1]
            c[-1] = 1.0
            parts = parts[np.searchsorted(c, (u[b] + np.arange(P)) / P, side="right")]
    return out


def vectorized(sc: cs.LinearScenario = SCENARIO, n: int = TRIALS, P: int = PARTICLES,
               l: float = L, seed: int = SEED) -> np.ndarray:
    res = cs.run(sc, "cfwmd", l=l, n_trials=n, n_particles=P, seed=seed, feedback="state",
                 block_size=max(n, 1))
    return res.mc.samples[..., :3]


def _checked(fn):
    def setup():
        got = fn()
        assert np.array_equal(got[..., 2], loop_result[..., 2])  # the same sensors sent
        assert np.allclose(got, loop_result, rtol=1e-9, atol=1e-12)
        return fn
    return setup


loop_result = loop()
REPEATS = 3
CASES = [
    ("CFwMD filter 32 trials x 1000 particles x 20 steps", "python loop over trials",
     _checked(loop)),
    ("CFwMD filter 32 trials x 1000 particles x 20 steps", "vectorized (censoring.run)",
     _checked(vectorized)),
]
