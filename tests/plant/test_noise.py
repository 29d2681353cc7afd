"""Tests of it2track.plant.noise: noise scaling, per-run seeding, sample holding."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from it2track.plant import (
    HeadingNoise,
    held_sample_index,
    noise_samples_needed,
    run_generator,
    standard_noise,
)


def test_band_limited_power_of_the_paper():
    # Simulink Band-Limited White Noise: variance = power / sample time.
    noise = HeadingNoise.from_band_limited_power(0.1, 0.01)
    assert noise.std == math.sqrt(10.0)  # 0.1 W at 100 Hz -> ~3.162 rad
    assert noise.std == pytest.approx(3.1623, abs=1e-4)
    assert noise.rate == 100.0
    assert HeadingNoise.from_band_limited_power(0.0, 0.02) == HeadingNoise(std=0.0, rate=50.0)


def test_defaults_and_frozen():
    noise = HeadingNoise()
    assert (noise.std, noise.rate) == (0.0, 100.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        noise.std = 1.0  # type: ignore[misc]
    assert isinstance(HeadingNoise(std=1, rate=20).std, float)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"std": -0.1}, "std"),
        ({"std": math.nan}, "std"),
        ({"std": math.inf}, "std"),
        ({"std": "0.1"}, "std"),
        ({"rate": 0.0}, "rate"),
        ({"rate": -100.0}, "rate"),
        ({"rate": math.inf}, "rate"),
    ],
)
def test_bad_noise_params_raise(kwargs, field):
    with pytest.raises(ValueError, match=field):
        HeadingNoise(**kwargs)


@pytest.mark.parametrize(
    ("power", "sample_time", "field"),
    [(-0.1, 0.01, "power"), (0.1, 0.0, "sample_time"), (0.1, -0.01, "sample_time")],
)
def test_bad_band_limited_arguments_raise(power, sample_time, field):
    with pytest.raises(ValueError, match=field):
        HeadingNoise.from_band_limited_power(power, sample_time)


@pytest.mark.parametrize("seed", [0, 1, 12345, 2**40 + 3])
def test_run_generator_equals_spawned_child(seed):
    children = np.random.SeedSequence(seed).spawn(10)
    for index in (0, 3, 9):
        expected = np.random.default_rng(children[index]).standard_normal(50)
        assert np.array_equal(run_generator(seed, index).standard_normal(50), expected)
    # different runs and different seeds give different streams
    assert not np.array_equal(
        run_generator(seed, 0).standard_normal(5), run_generator(seed, 1).standard_normal(5)
    )
    assert not np.array_equal(
        run_generator(seed, 0).standard_normal(5), run_generator(seed + 1, 0).standard_normal(5)
    )


def test_standard_noise_rows_do_not_depend_on_the_other_indices():
    alone = standard_noise(7, [3], 1001)
    together = standard_noise(7, [0, 1, 2, 3], 1001)
    shuffled = standard_noise(7, np.array([3, 250, 0]), 1001)
    assert alone.shape == (1, 1001) and together.shape == (4, 1001)
    assert np.array_equal(alone[0], together[3])
    assert np.array_equal(alone[0], shuffled[0])
    assert np.array_equal(together[0], shuffled[2])
    assert np.array_equal(alone[0], run_generator(7, 3).standard_normal(1001))
    assert not np.array_equal(together[0], together[1])
    # a longer horizon extends the same sequence
    assert np.array_equal(standard_noise(7, [3], 2000)[0, :1001], alone[0])
    assert standard_noise(7, [], 5).shape == (0, 5)


def test_standard_noise_is_standard_normal():
    z = standard_noise(2024, np.arange(20), 5000)
    assert abs(z.mean()) < 0.01  # 1e5 samples: standard error 0.003
    assert abs(z.std() - 1.0) < 0.01


@pytest.mark.parametrize(
    ("indices", "match"),
    [([[0, 1]], "1-D"), ([-1], "indices"), ([0.5], "indices")],
)
def test_standard_noise_rejects_bad_indices(indices, match):
    with pytest.raises(ValueError, match=match):
        standard_noise(0, indices, 3)


@pytest.mark.parametrize(
    ("args", "match"),
    [((-1, 0), "seed"), ((0, -1), "index"), ((0.5, 0), "seed"), ((0, True), "index")],
)
def test_run_generator_rejects_bad_arguments(args, match):
    with pytest.raises(ValueError, match=match):
        run_generator(*args)


def test_held_index_at_noise_rate_equal_to_control_rate():
    ts = 0.01
    times = np.arange(1001) * ts  # control instants t_k = k ts over 10 s
    assert np.array_equal(held_sample_index(times, 100.0), np.arange(1001))
    # accumulated time (rounding drifts both ways) still lands on the right sample
    acc = np.cumsum(np.full(1000, ts))
    assert np.array_equal(held_sample_index(acc, 100.0), np.arange(1, 1001))
    assert held_sample_index(times, 100.0).dtype == np.int64


def test_held_index_at_half_rate_holds_each_sample_two_steps():
    idx = held_sample_index(np.arange(1001) * 0.01, 50.0)
    assert np.array_equal(idx, np.arange(1001) // 2)
    values, counts = np.unique(idx[:-1], return_counts=True)
    assert np.array_equal(values, np.arange(500)) and np.all(counts == 2)


@given(
    k=st.integers(min_value=0, max_value=10**6),
    q=st.sampled_from([10, 20, 50, 100, 200, 1000]),  # control rate 1/ts, Hz
    p=st.sampled_from([1, 5, 10, 25, 50, 100, 400]),  # noise rate, Hz
)
def test_held_index_is_exact_floor_on_the_control_grid(k, q, p):
    t = k * (1.0 / q)  # t_k = k ts as a simulation computes it
    assert int(held_sample_index(t, float(p))) == (k * p) // q


def test_held_index_shapes_and_errors():
    assert held_sample_index(0.0, 100.0).shape == ()
    assert held_sample_index(np.zeros((2, 3)), 100.0).shape == (2, 3)
    with pytest.raises(ValueError, match="times"):
        held_sample_index([-0.01], 100.0)
    with pytest.raises(ValueError, match="times"):
        held_sample_index([math.nan], 100.0)
    with pytest.raises(ValueError, match="rate"):
        held_sample_index([0.0], 0.0)


def test_noise_samples_needed():
    assert noise_samples_needed(10.0, 100.0) == 1001
    assert noise_samples_needed(10.0, 50.0) == 501
    assert noise_samples_needed(0.0, 100.0) == 1
    assert noise_samples_needed(0.29, 100.0) == 30  # 0.29 * 100 = 28.999999999999996
    assert noise_samples_needed(10.0, 30.0) == 301
    with pytest.raises(ValueError, match="duration"):
        noise_samples_needed(-1.0, 100.0)
    # enough samples for every control instant
    idx = held_sample_index(np.arange(1001) * 0.01, 30.0)
    assert idx.max() == noise_samples_needed(10.0, 30.0) - 1


def test_common_random_numbers_scale_with_std():
    z = standard_noise(11, [4], 1001)[0]
    idx = held_sample_index(np.arange(1001) * 0.01, 100.0)
    small, large = HeadingNoise(std=0.05), HeadingNoise(std=0.2)
    n_small, n_large = small.std * z[idx], large.std * z[idx]
    assert np.allclose(n_large, 4.0 * n_small, rtol=1e-15, atol=0)
