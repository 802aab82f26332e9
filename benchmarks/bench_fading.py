"""dey2009 (Part II): vectorized Monte Carlo of the random Riccati equation vs a per-path loop,
and the four paper figures at paper scale.

Group 1 -- the scalar recursion (15) under Rayleigh fading (a = 1.25, sigma_w2 = 1,
sigma_v2 = 1, sigma_n2 = 4, lambda = 100), 5000 paths x 100 steps: a plain Python loop over
paths and steps against ``fading.scalar_mc`` (vectorized across paths, through the one runner).
Both use the same channel draws (the runner's first block stream) and agree to 1e-12 before
timing. The issue's target: at least 30x.

Group 2 -- ``compute("paper")`` of dey2009-fig1 ... fig4 (50 000 paths x 100 steps each, several
noise levels or channel settings per figure). The issue's target: <= 20 s. Timed once.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import fading, figures

A, SW2, SV2, SN2, LAM, P0, STEPS, PATHS = 1.25, 1.0, 1.0, 4.0, 100.0, 1.0, 100, 5000
CHANNEL = fading.Rayleigh(LAM)
SEED = 7
BLOCK = PATHS  # one block: the loop can replay exactly the runner's draws


def _draws() -> np.ndarray:
    ss = np.random.SeedSequence(SEED).spawn(1)[0]
    return CHANNEL.sample(np.random.default_rng(ss), (STEPS, PATHS))


R = _draws()


def loop() -> np.ndarray:
    total = np.zeros(STEPS + 1)
    for i in range(PATHS):
        p = P0
        total[0] += p
        for k in range(STEPS):
            r = R[k, i]
            p = SW2 + A * A * p * (r * SV2 + SN2) / (r * (p + SV2) + SN2)
            total[k + 1] += p
    return total / PATHS


def vectorized() -> np.ndarray:
    mean, _ = fading.scalar_mc(A, SW2, SV2, SN2, CHANNEL, P0, STEPS, PATHS, SEED,
                               block_size=BLOCK)
    return mean


def _checked(fn):
    def setup():
        assert np.allclose(fn(), loop(), rtol=1e-12), "vectorized and loop differ"
        return fn
    return setup


IDS = ["dey2009-fig1", "dey2009-fig2", "dey2009-fig3", "dey2009-fig4"]


def four_figures() -> None:
    for entry_id in IDS:
        figures.get(entry_id).run_compute("paper")


def _figures_setup():
    for entry_id in IDS:
        assert figures.get(entry_id).compute is not None
    return four_figures


REPEATS = 3
CASES = [
    ("scalar (15), 5000 paths x 100 steps", "python loop over paths", _checked(loop)),
    ("scalar (15), 5000 paths x 100 steps", "vectorized (fading.scalar_mc)",
     _checked(vectorized)),
    ("dey2009 Figs. 1-4, paper profile", "vectorized (four entries)", _figures_setup),
]
