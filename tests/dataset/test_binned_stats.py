"""Mergeable binned statistics (mcbat.dataset.binned_stats): exact counts and extremes,
means and standard deviations to 1e-12 of pandas whatever the chunking, quantiles within
the stated resolution, the same result on 1 or 2 threads and for any cut into chunks."""

import numba
import numpy as np
import pandas as pd
import pytest

from mcbat.dataset import binned_stats as bs

LOW, HIGH, BINS = np.array([0.0]), np.array([1.0]), np.array([10], np.int64)
QUANTILES = np.array([0.05, 0.5, 0.95])


def _data(n=1_000_000, seed=1):
    rng = np.random.default_rng(seed)
    by = rng.uniform(-0.1, 1.1, n)
    by[rng.random(n) < 0.001] = np.nan
    by[:3] = [0.0, np.nextafter(1.0, 0.0), 1.0]  # edges: first bin, last bin, outside
    values = np.stack([
        rng.normal(1e4, 3.0, n),                  # a large mean over a small spread
        rng.standard_cauchy(n),                   # heavy tails, both signs
        np.where(rng.random(n) < 0.01, np.nan,    # failed rows, zeros, tiny values
                 np.where(rng.random(n) < 0.05, 0.0, rng.uniform(-90, 90, n) * 1e-3)),
    ])
    return by, values


def _summarise(by, values, cuts, n_hist=None):
    n_hist = bs.n_buckets() if n_hist is None else n_hist
    total = bs.allocate_partial(int(BINS[0]), values.shape[0], n_hist)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        index = np.empty(hi - lo, np.int64)
        bs.bin_rows(by[None, lo:hi], LOW, HIGH, BINS, index)
        part = bs.allocate_partial(int(BINS[0]), values.shape[0], n_hist)
        bs.accumulate(index, values[:, lo:hi], part)
        bs.merge_into(total, part)
    return total


def test_bin_rows_edges_and_three_axes():
    index = np.empty(5, np.int64)
    bs.bin_rows(np.array([[0.0, 0.1, np.nextafter(1.0, 0), 1.0, np.nan]]), LOW, HIGH, BINS,
                index)
    assert index.tolist() == [0, 1, 9, -1, -1]
    rng = np.random.default_rng(0)
    by = rng.uniform(-0.2, 1.2, (3, 10_000))
    lows, highs, nbins = np.zeros(3), np.ones(3), np.array([4, 3, 5], np.int64)
    index = np.empty(10_000, np.int64)
    bs.bin_rows(by, lows, highs, nbins, index)
    inside = ((by >= 0) & (by < 1)).all(axis=0)
    digit = [np.minimum((by[d] * nbins[d]).astype(int), nbins[d] - 1) for d in range(3)]
    expected = np.where(inside, (digit[0] * 3 + digit[1]) * 5 + digit[2], -1)
    assert index.tolist() == expected.tolist()


def test_statistics_match_pandas_and_do_not_depend_on_the_chunking():
    by, values = _data()
    n = by.size
    cuttings = [[0, n], [0, 250_000, 500_000, 750_000, n],
                [*range(0, n, 37_000), n], [0, 1, 2, 999_000, n]]
    results = [bs.finalize(_summarise(by, values, cuts), QUANTILES) for cuts in cuttings]
    for other in results[1:]:
        for a, b in zip(results[0], other):
            np.testing.assert_array_equal(a, b)  # bit for bit
    stats = results[0]
    frame = pd.DataFrame({"by": by, **{f"x{j}": values[j] for j in range(3)}})
    inside = (frame.by >= 0) & (frame.by < 1)
    groups = frame[inside].groupby(np.minimum((frame.by[inside] * 10).astype(int), 9))
    total = _summarise(by, values, cuttings[0])
    assert total.outside[0] == (~inside).sum() and total.count.sum() + total.outside[0] == n
    assert total.count.tolist() == groups.size().tolist()
    for j in range(3):
        col = groups[f"x{j}"]
        np.testing.assert_array_equal(stats.n[:, j], col.count())
        np.testing.assert_array_equal(stats.min[:, j], col.min())
        np.testing.assert_array_equal(stats.max[:, j], col.max())
        np.testing.assert_allclose(stats.mean[:, j], col.mean(), rtol=1e-12, atol=0)
        np.testing.assert_allclose(stats.std[:, j], col.std(), rtol=1e-12, atol=0)
        for k, q in enumerate(QUANTILES):
            exact = col.quantile(q, interpolation="lower").to_numpy()
            error = np.abs(stats.quantiles[:, j, k] - exact)
            # ALPHA relative (the 1e-9 is the rounding of log() at a bucket edge)
            bound = bs.ALPHA * np.abs(exact) * (1 + 1e-9) + bs.MIN_MAGNITUDE
            assert (error <= bound).all(), (j, q, error.max())


def test_the_same_bits_on_one_and_two_threads():
    by, values = _data(200_000, seed=3)
    previous = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = _summarise(by, values, [0, 200_000])
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = _summarise(by, values, [0, 200_000])
    finally:
        numba.set_num_threads(previous)
    for a, b in zip(one, two):
        np.testing.assert_array_equal(a, b)


def test_empty_and_single_value_bins():
    by = np.array([0.05, 0.55, 0.56])  # bin 0: one value; bin 5: two; the rest empty
    values = np.array([[2.0, 1.0, 3.0]])
    stats = bs.finalize(_summarise(by, values, [0, 3]), QUANTILES)
    assert stats.n[:, 0].tolist() == [1, 0, 0, 0, 0, 2, 0, 0, 0, 0]
    assert stats.mean[0, 0] == 2.0 and np.isnan(stats.std[0, 0])
    assert stats.mean[5, 0] == 2.0 and stats.std[5, 0] == pytest.approx(np.sqrt(2.0))
    assert np.isnan(stats.mean[1, 0]) and np.isnan(stats.quantiles[1, 0]).all()
    assert stats.quantiles[5, 0].tolist() == pytest.approx([1.0, 1.0, 1.0], rel=bs.ALPHA)


def test_quantiles_need_histograms_and_partials_have_a_size():
    total = bs.allocate_partial(3, 2, 0)
    with pytest.raises(ValueError, match="histograms"):
        bs.finalize(total, QUANTILES)
    assert bs.finalize(total, np.array([])).quantiles.shape == (3, 2, 0)
    assert bs.partial_bytes(40, 2, bs.n_buckets()) == sum(
        a.nbytes for a in bs.allocate_partial(40, 2, bs.n_buckets()))


def test_merged_histograms_keep_every_value_even_infinite_ones():
    """Merging adds only the buckets between a partial's min and max: every value of every
    chunk must still be in the merged histogram, and infinite or huge values go into the
    last bucket of their sign (the first and last buckets), not a random one."""
    by, values = _data(200_000, seed=3)
    values[1, :50] = [np.inf, -np.inf, 1e300, -1e300, 2e9] * 10
    cuts = [0, 7, 50_000, 50_001, 123_457, 200_000]
    total = _summarise(by, values, cuts)
    assert (total.hist.sum(axis=2) == total.n).all()
    whole = _summarise(by, values, [0, by.size])
    np.testing.assert_array_equal(total.hist, whole.hist)
    index = np.empty(by.size, np.int64)
    bs.bin_rows(by[None], LOW, HIGH, BINS, index)
    column = values[1]
    for sign, bucket in ((1, -1), (-1, 0)):
        huge = (index >= 0) & (sign * column >= bs.MAX_MAGNITUDE)
        assert huge.sum() > 0
        assert total.hist[:, 1, bucket].sum() >= huge.sum()
