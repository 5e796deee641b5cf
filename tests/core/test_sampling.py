"""The counter-based sampler (mcbat.core.sampling, mcbat.study.random_program): Philox
against Random123's known answers, AS241 against scipy, each distribution against its CDF,
and the draws' independence of threads, chunking and the other inputs."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from scipy import special, stats

from mcbat.core.sampling import philox4x32_10, standard_normal_quantile, unit_uniform
from mcbat.study.distributions import parse
from mcbat.study.random_program import compile_program, draw

# Random123's kat_vectors, the three "philox4x32 10" lines: (counter, key, output).
PHILOX_KNOWN_ANSWERS = [
    ((0, 0, 0, 0), (0, 0), (0x6627E8D5, 0xE169C58D, 0xBC57AC4C, 0x9B00DBD8)),
    ((0xFFFFFFFF,) * 4, (0xFFFFFFFF,) * 2, (0x408F276D, 0x41C83B0E, 0xA20BC7C6, 0x6D5451FD)),
    ((0x243F6A88, 0x85A308D3, 0x13198A2E, 0x03707344), (0xA4093822, 0x299F31D0),
     (0xD16CFE09, 0x94FDCCEB, 0x5001E420, 0x24126EA1)),
]


@pytest.mark.parametrize("counter,key,expected", PHILOX_KNOWN_ANSWERS)
def test_philox_matches_random123_known_answers(counter, key, expected):
    words = [np.uint64(w) for w in counter + key]
    assert tuple(int(w) for w in philox4x32_10(*words)) == expected


@numba.njit
def _uniforms(high, low):
    return unit_uniform(high, low)


def test_unit_uniforms_stay_strictly_inside_zero_one():
    zero, ones = np.uint64(0), np.uint64(0xFFFFFFFF)
    assert _uniforms(zero, zero) == 2.0**-53
    assert _uniforms(ones, ones) == 1.0 - 2.0**-53
    assert 0.0 < _uniforms(zero, zero) < _uniforms(ones, ones) < 1.0


@numba.njit
def _quantiles(p):
    out = np.empty_like(p)
    for i in range(p.size):
        out[i] = standard_normal_quantile(p[i])
    return out


def test_normal_quantile_matches_scipy_ndtri_to_rounding():
    p = np.concatenate([np.linspace(1e-6, 1 - 1e-6, 100_001), np.logspace(-300, -1, 2000),
                        1.0 - np.logspace(-16, -1, 2000), [2.0**-53, 1.0 - 2.0**-53]])
    ours, scipys = _quantiles(p), special.ndtri(p)
    tolerance = 4e-15 * np.abs(scipys) + 1e-300
    assert np.all(np.abs(ours - scipys) <= tolerance)
    assert np.all(np.diff(_quantiles(np.linspace(0.001, 0.999, 9999))) > 0)


def _program(specs, seed=11, n=200_000, start=0):
    """Draw ``{name: spec}`` (TOML-like dicts, SI) for samples ``start .. start + n - 1``."""
    dists = [(name, parse(spec, name, "dimensionless")) for name, spec in specs.items()]
    out = np.full((len(dists), n), np.nan)
    draw(compile_program(dists, {name: i for i, (name, _) in enumerate(dists)}), seed,
         start, out)
    return {name: out[i] for i, (name, _) in enumerate(dists)}


def test_each_distribution_follows_its_cdf():
    specs = {
        "a.uniform": {"dist": "uniform", "low": -2.0, "high": 5.0},
        "a.normal": {"dist": "normal", "mean": 1.5, "std": 0.25},
        "a.truncnormal": {"dist": "truncnormal", "mean": 0.0, "std": 1.0, "low": 0.5,
                          "high": 3.0},
    }
    x = _program(specs)
    # Kolmogorov-Smirnov at n = 200,000: the statistic of a correct sampler is ~0.002;
    # a wrong scale, shift or truncation is 0.01 or more.
    checks = {"a.uniform": stats.uniform(-2.0, 7.0).cdf,
              "a.normal": stats.norm(1.5, 0.25).cdf,
              "a.truncnormal": stats.truncnorm(0.5, 3.0).cdf}
    for name, cdf in checks.items():
        result = stats.kstest(x[name], cdf)
        assert result.statistic < 0.005 and result.pvalue > 1e-4, (name, result)
    assert x["a.uniform"].min() > -2.0 and x["a.uniform"].max() < 5.0
    assert x["a.truncnormal"].min() >= 0.5 and x["a.truncnormal"].max() <= 3.0


def test_mixture_and_choice_frequencies_match_their_weights():
    specs = {
        "b.mixture": {"dist": "mixture", "weights": [0.2, 0.5, 0.3],
                      "components": [0.0, {"dist": "uniform", "low": 10.0, "high": 11.0},
                                     {"dist": "choice", "values": [-1.0, -2.0],
                                      "weights": [3.0, 1.0]}]},
        "b.choice": {"dist": "choice", "values": [1.0, 2.0, 3.0], "weights": [1.0, 0.0, 4.0]},
    }
    n = 200_000
    x = _program(specs, n=n)
    mixture = x["b.mixture"]
    observed = [np.mean(mixture == 0.0), np.mean((mixture >= 10.0) & (mixture <= 11.0)),
                np.mean(mixture == -1.0), np.mean(mixture == -2.0)]
    expected = [0.2, 0.5, 0.3 * 0.75, 0.3 * 0.25]
    for got, want in zip(observed, expected):
        assert abs(got - want) < 5 * np.sqrt(want * (1 - want) / n), (observed, expected)
    assert sum(observed) == 1.0
    uniform_part = mixture[mixture >= 10.0] - 10.0
    assert stats.kstest(uniform_part, "uniform").pvalue > 1e-4
    choice = x["b.choice"]
    assert not np.any(choice == 2.0)  # zero weight: never drawn
    assert abs(np.mean(choice == 3.0) - 0.8) < 5 * np.sqrt(0.16 / n)


def test_inputs_are_independent_streams():
    specs = {f"c.x{i}": {"dist": "uniform", "low": 0.0, "high": 1.0} for i in range(4)}
    x = np.array(list(_program(specs, n=100_000).values()))
    correlations = np.corrcoef(x)[np.triu_indices(4, 1)]
    assert np.all(np.abs(correlations) < 5 / np.sqrt(100_000))
    # and consecutive samples of one input
    assert abs(np.corrcoef(x[0, :-1], x[0, 1:])[0, 1]) < 5 / np.sqrt(100_000)


def test_a_draw_depends_on_the_sample_index_seed_and_name_alone():
    spec = {"dist": "mixture", "weights": [0.5, 0.5],
            "components": [{"dist": "normal", "mean": 0.0, "std": 1.0}, 2.0]}
    other = {"dist": "uniform", "low": 0.0, "high": 1.0}
    # any piece, any thread count (the whole on two threads, the pieces on one), with or
    # without (or before) other inputs
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    whole = _program({"d.x": spec, "d.y": other}, n=10_000)
    numba.set_num_threads(1)
    try:
        piece = _program({"d.y": other, "d.x": spec}, start=1234, n=5000)
        alone = _program({"d.x": spec}, start=1234, n=5000)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert np.array_equal(piece["d.x"], whole["d.x"][1234:6234])
    assert np.array_equal(alone["d.x"], whole["d.x"][1234:6234])
    assert np.array_equal(piece["d.y"], whole["d.y"][1234:6234])
    # and changes with the seed, the name and the index
    assert not np.array_equal(_program({"d.x": spec}, seed=12, n=10_000)["d.x"], whole["d.x"])
    assert not np.array_equal(_program({"d.z": spec}, n=10_000)["d.z"], whole["d.x"])
    assert not np.array_equal(whole["d.x"][1:], whole["d.x"][:-1])


def test_indices_beyond_32_bits_and_large_seeds_draw_distinct_values():
    spec = {"e.x": {"dist": "uniform", "low": 0.0, "high": 1.0}}
    low = _program(spec, start=5, n=1000)["e.x"]
    high = _program(spec, start=5 + 2**32, n=1000)["e.x"]
    big_seed = _program(spec, seed=2**63 - 1, start=5, n=1000)["e.x"]
    assert not np.array_equal(low, high) and not np.array_equal(low, big_seed)
    assert stats.kstest(high, "uniform").pvalue > 1e-4


@pytest.mark.parametrize("count", [2, 4, 5, 7])
def test_mixtures_of_any_size_pick_components_by_weight(count):
    """Up to four components are selected in one vectorised pass, more one sum at a time:
    both paths give the weights' frequencies (a zero weight is never drawn)."""
    weights = [float(j + 1) for j in range(count)]
    weights[-2] = 0.0
    spec = {"f.x": {"dist": "mixture", "weights": weights,
                    "components": [float(j) for j in range(count)]}}
    n = 100_000
    x = _program(spec, n=n)["f.x"]
    total = sum(weights)
    for j, w in enumerate(weights):
        p = w / total
        assert abs(np.mean(x == j) - p) <= 5 * np.sqrt(p * (1 - p) / n) + 1e-12, (j, count)


def test_the_truncated_normal_cdf_matches_scipy_ndtr():
    """TruncNormal's bounds go through its own normal CDF (no scipy.special at start-up):
    scipy's ndtr to 1e-13 relative, deep into the lower tail (the C library's erfc and
    cephes' differ by up to ~6e-14 in the far tail)."""
    from mcbat.study.dist_types import _normal_cdf

    x = np.concatenate([np.linspace(-38.0, 9.0, 20_001), [0.0, -0.0, 1e-300, -1e-300]])
    ours = np.array([_normal_cdf(v) for v in x])
    scipys = special.ndtr(x)
    assert np.all(np.abs(ours - scipys) <= 1e-13 * scipys + 1e-300)
    assert np.all(np.diff(ours[:20_001]) >= 0.0)


def test_noise_draws_are_a_domain_apart_from_the_inputs():
    """The same stream number in the noise domain gives other values: simulated
    measurement noise can never repeat an input's draws."""
    from mcbat.study.random_program import INPUTS, NOISE

    dist = parse({"dist": "normal", "mean": 0.0, "std": 1.0}, "g.x", "dimensionless")
    out = np.empty((2, 50_000))
    for row, domain in enumerate((INPUTS, NOISE)):
        draw(compile_program([("g.x", dist)], {"g.x": row}, domain), 5, 0, out)
    assert abs(np.corrcoef(out)[0, 1]) < 5 / np.sqrt(50_000)
    assert stats.kstest(out[1], "norm").pvalue > 1e-4
