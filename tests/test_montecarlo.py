"""The Monte Carlo runner: reproducible, and independent of chunking and executor."""

from __future__ import annotations

import functools
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from fusioncenter.montecarlo import simulate


def walk(rng: np.random.Generator, n: int, steps: int = 5) -> np.ndarray:
    """A vectorized toy trial: random walks, shaped (n, steps)."""
    return np.cumsum(rng.standard_normal((n, steps)), axis=1)


def uniform_scalar(rng, n):
    return rng.uniform(size=n)


def _identical(a, b):
    return a.samples.tobytes() == b.samples.tobytes() and (
        a.mean.tobytes() == b.mean.tobytes() and a.stderr.tobytes() == b.stderr.tobytes()
    )


def test_mean_and_stderr_are_correct():
    res = simulate(uniform_scalar, 4000, seed=1)
    assert res.n_trials == 4000
    assert res.samples.shape == (4000,)
    assert res.mean == pytest.approx(np.mean(res.samples))
    assert res.stderr == pytest.approx(np.std(res.samples, ddof=1) / np.sqrt(4000))
    # U(0,1): mean 1/2, sd 1/sqrt(12); the estimate is within 4 standard errors
    assert abs(res.mean - 0.5) < 4 * res.stderr
    assert res.stderr == pytest.approx(1 / np.sqrt(12 * 4000), rel=0.05)


@pytest.mark.parametrize("chunk_size", [1, 7, 256, 1000, 5000])
def test_bitwise_identical_for_every_chunk_size(chunk_size):
    ref = simulate(walk, 1234, seed=42)
    assert _identical(ref, simulate(walk, 1234, seed=42, chunk_size=chunk_size))


def test_different_seeds_differ_and_same_seed_repeats():
    a = simulate(walk, 300, seed=1)
    assert _identical(a, simulate(walk, 300, seed=1))
    assert not np.array_equal(a.samples, simulate(walk, 300, seed=2).samples)


def test_prefix_property():
    """The first trials do not depend on how many trials follow (blocks are fixed)."""
    small = simulate(walk, 300, seed=5, block_size=100)
    big = simulate(walk, 1000, seed=5, block_size=100)
    assert np.array_equal(small.samples, big.samples[:300])


def test_thread_and_process_pools_are_bitwise_identical():
    ref = simulate(walk, 2000, seed=3)
    with ThreadPoolExecutor(2) as ex:
        assert _identical(ref, simulate(walk, 2000, seed=3, executor=ex, chunk_size=300))
    with ProcessPoolExecutor(2) as ex:
        assert _identical(ref, simulate(walk, 2000, seed=3, executor=ex))
        part = functools.partial(walk, steps=5)
        assert _identical(ref, simulate(part, 2000, seed=3, executor=ex, chunk_size=513))


def test_dask_distributed_executor_is_bitwise_identical():
    distributed = pytest.importorskip("dask.distributed", reason="the dask extra is in the lock")
    ref = simulate(walk, 1500, seed=9)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            res = simulate(walk, 1500, seed=9, executor=client.get_executor(), chunk_size=256)
    assert _identical(ref, res)


def test_progress_bar_goes_to_stderr(capsys):
    simulate(walk, 600, seed=1, progress=True, block_size=100)
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "600/600" in captured.err


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_trials": 0}, "n_trials"),
        ({"n_trials": 2.5}, "n_trials"),
        ({"seed": -1}, "seed"),
        ({"chunk_size": 0}, "chunk_size"),
        ({"block_size": 0}, "block_size"),
        ({"executor": object()}, "executor"),
    ],
)
def test_bad_arguments_raise_value_error(kwargs, match):
    args = {"chunk_fn": walk, "n_trials": 10, "seed": 0, **kwargs}
    with pytest.raises(ValueError, match=match):
        simulate(args.pop("chunk_fn"), args.pop("n_trials"), args.pop("seed"), **args)


def test_chunk_fn_with_wrong_shape_is_reported():
    with pytest.raises(ValueError, match=r"shaped \(n, \.\.\.\)"):
        simulate(lambda rng, n: rng.uniform(size=n + 1), 10, seed=0)
    with pytest.raises(ValueError, match="callable"):
        simulate("not a function", 10, seed=0)
