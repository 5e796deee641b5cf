"""Mergeable binned statistics for summary scans: count, mean, std, min, max, quantiles.

A scan of 10^9 rows is summarised chunk by chunk: ``accumulate`` turns one chunk into a
*partial* (``SummaryPartial``, per bin and per value column), ``merge_into`` adds
partials in chunk order, ``finalize`` gives the statistics. Everything is exact or
nearly so, so that the result does not depend on how the rows were cut into chunks, on the
thread count, or on the order of the engine's tasks:

* counts, minima, maxima and histograms are exact;
* sums of ``x`` and ``x^2`` are kept in double-double arithmetic (Knuth's TwoSum and
  Dekker's TwoProduct: ~106 bits), so the mean and ``M2 = S2 - S1^2/N`` lose nothing to
  the order of summation or to cancellation (the relative error of the variance is about
  ``2^-104 (1 + mean^2/variance)``), and the final rounding to a double gives the same
  number whatever the chunking (barring a tie at the last of 106 bits);
* quantiles come from per-bin log-bucket histograms (DDSketch's buckets): a value
  ``MIN_MAGNITUDE <= |x| <= MAX_MAGNITUDE`` goes into bucket ``ceil(log|x| / log gamma)``
  with ``gamma = (1 + ALPHA) / (1 - ALPHA)``, whose representative ``2 gamma^i / (gamma +
  1)`` is within ``ALPHA`` (relative) of every value in it; ``|x| < MIN_MAGNITUDE`` counts
  as 0. Quantile ``q`` of ``N`` values is the value of rank ``floor(q (N - 1))`` (0-based;
  pandas' ``interpolation="lower"``), estimated to within ``ALPHA`` relative (plus
  rounding), or within ``MIN_MAGNITUDE`` absolute for smaller values, and clamped into
  ``[min, max]`` of the bin. Values beyond ``MAX_MAGNITUDE`` share the last bucket.

NaN values (failed rows) are skipped, as pandas does; ``count`` counts every row of a bin,
``n`` the non-NaN values of each column. A row whose ``by`` value is NaN or outside
``[low, high)`` on any axis is counted in ``outside``.

Source: Masson, Rim & Lee, "DDSketch: a fast and fully-mergeable quantile sketch with
relative-error guarantees", PVLDB 12, 2195 (2019); Dekker, Numer. Math. 18, 224 (1971).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from mcbat.core.jit import njit

__all__ = ["ALPHA", "MAX_MAGNITUDE", "MIN_MAGNITUDE", "SummaryPartial", "SummaryStats",
           "accumulate", "allocate_partial", "bin_rows", "finalize", "merge_into",
           "n_buckets", "partial_bytes"]

#: Relative accuracy of the quantiles.
ALPHA = 0.005
#: Magnitudes below this count as 0 in the quantile histograms; above MAX_MAGNITUDE they
#: share the last bucket. (Columns are SI values, degrees, rpm or mph: far inside.)
MIN_MAGNITUDE = 1e-9
MAX_MAGNITUDE = 1e9

_GAMMA = (1.0 + ALPHA) / (1.0 - ALPHA)
_LOG_GAMMA = math.log(_GAMMA)
_I_MIN = math.ceil(math.log(MIN_MAGNITUDE) / _LOG_GAMMA)
#: Buckets per sign.
_K = math.ceil(math.log(MAX_MAGNITUDE) / _LOG_GAMMA) - _I_MIN + 1


def n_buckets() -> int:
    """Histogram buckets per bin and column: ``K`` negative, one zero, ``K`` positive, in
    ascending order of value."""
    return 2 * _K + 1


class SummaryPartial(NamedTuple):
    """Partial statistics of some rows (struct of arrays; ``B`` bins, ``m`` columns,
    ``H`` buckets, 0 without quantiles)."""

    count: np.ndarray    # int64[B]: rows in each bin
    outside: np.ndarray  # int64[1]: rows in no bin
    n: np.ndarray        # int64[B, m]: non-NaN values
    sum_hi: np.ndarray   # float64[B, m]: sum of x, double-double (hi + lo)
    sum_lo: np.ndarray
    sq_hi: np.ndarray    # float64[B, m]: sum of x^2, double-double
    sq_lo: np.ndarray
    min: np.ndarray      # float64[B, m] (+inf when empty)
    max: np.ndarray      # float64[B, m] (-inf when empty)
    hist: np.ndarray     # int64[B, m, H]


class SummaryStats(NamedTuple):
    """The statistics of ``finalize`` (NaN where a bin has no value; ``std`` needs 2)."""

    n: np.ndarray          # int64[B, m]
    mean: np.ndarray       # float64[B, m]
    std: np.ndarray        # float64[B, m], ddof = 1
    min: np.ndarray        # float64[B, m]
    max: np.ndarray        # float64[B, m]
    quantiles: np.ndarray  # float64[B, m, len(probabilities)]


def allocate_partial(n_bins: int, n_values: int, n_hist: int) -> SummaryPartial:
    """An empty partial (``n_hist`` = ``n_buckets``, or 0 without quantiles)."""
    shape = (n_bins, n_values)
    return SummaryPartial(np.zeros(n_bins, np.int64), np.zeros(1, np.int64),
                          np.zeros(shape, np.int64), np.zeros(shape), np.zeros(shape),
                          np.zeros(shape), np.zeros(shape), np.full(shape, np.inf),
                          np.full(shape, -np.inf), np.zeros((*shape, n_hist), np.int64))


def partial_bytes(n_bins: int, n_values: int, n_hist: int) -> int:
    """Memory of one partial, bytes."""
    return 8 * (n_bins + 1 + n_bins * n_values * (7 + n_hist))


# ---------------------------------------------------------------- double-double


@njit(inline="always")
def _two_sum(a, b):
    """``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@njit(inline="always")
def _dd_add(hi, lo, x_hi, x_lo):
    """``(hi, lo) + (x_hi, x_lo)`` in double-double."""
    s, e = _two_sum(hi, x_hi)
    e += lo + x_lo
    return _two_sum(s, e)


@njit(inline="always")
def _split(a):
    """Dekker's split of ``a`` into two 26-bit halves."""
    c = 134217729.0 * a  # 2^27 + 1
    high = c - (c - a)
    return high, a - high


@njit(inline="always")
def _two_prod(a, b):
    """``a * b = p + e`` exactly (Dekker; no FMA needed, no overflow for our values)."""
    p = a * b
    a1, a2 = _split(a)
    b1, b2 = _split(b)
    e = ((a1 * b1 - p) + a1 * b2 + a2 * b1) + a2 * b2
    return p, e


@njit(inline="always")
def _bucket(x):
    """Histogram bucket of ``x`` (ascending in value; see ``n_buckets``)."""
    a = abs(x)
    if a < MIN_MAGNITUDE:
        return _K
    # (an infinite value would make the ceil's integer meaningless: test it first)
    k = _K - 1 if a >= MAX_MAGNITUDE else math.ceil(math.log(a) / _LOG_GAMMA) - _I_MIN
    k = min(max(k, 0), _K - 1)
    return _K + 1 + k if x > 0.0 else _K - 1 - k


# ---------------------------------------------------------------- kernels


@njit(parallel=True)
def bin_rows(by_values, lows, highs, nbins, out_index):
    """Flat bin index of every row (row-major over the axes), -1 outside.

    Parameters
    ----------
    by_values : float64[k, n]
        The ``by`` columns (k = 1..3), in the units of ``lows`` and ``highs``.
    lows, highs : float64[k]
        Each axis covers ``[low, high)``.
    nbins : int64[k]
        Bins per axis.
    out_index : int64[n]
        Output: the bin of each row, or -1 (a NaN or out-of-range value on any axis).
    """
    k, n = by_values.shape
    for r in numba.prange(n):
        flat = 0
        for d in range(k):
            x = by_values[d, r]
            if not (x >= lows[d] and x < highs[d]):  # (False for NaN)
                flat = -1
                break
            i = int((x - lows[d]) / (highs[d] - lows[d]) * nbins[d])
            if i >= nbins[d]:  # rounding just below high
                i = nbins[d] - 1
            flat = flat * nbins[d] + i
        out_index[r] = flat


@njit(parallel=True)
def _accumulate(index, values, count, outside, n, sum_hi, sum_lo, sq_hi, sq_lo, vmin, vmax,
                hist):
    rows = index.shape[0]
    n_bins, n_hist = count.shape[0], hist.shape[2]
    for r in range(rows):  # counts: one pass, exact
        b = index[r]
        if b < 0:
            outside[0] += 1
        else:
            count[b] += 1
    # One thread per column, rows in order (so the result does not depend on the thread
    # count). Each thread sums into arrays of its own: the [bin, column] sums of
    # neighbouring columns share cache lines, and threads writing them in place were slower
    # than one thread.
    for j in numba.prange(values.shape[0]):
        n_j = n[:, j].copy()
        sum_hi_j, sum_lo_j = sum_hi[:, j].copy(), sum_lo[:, j].copy()
        sq_hi_j, sq_lo_j = sq_hi[:, j].copy(), sq_lo[:, j].copy()
        min_j, max_j = vmin[:, j].copy(), vmax[:, j].copy()
        for r in range(rows):
            b = index[r]
            x = values[j, r]
            if b < 0 or x != x:
                continue
            n_j[b] += 1
            sum_hi_j[b], sum_lo_j[b] = _dd_add(sum_hi_j[b], sum_lo_j[b], x, 0.0)
            p, e = _two_prod(x, x)
            sq_hi_j[b], sq_lo_j[b] = _dd_add(sq_hi_j[b], sq_lo_j[b], p, e)
            if x < min_j[b]:
                min_j[b] = x
            if x > max_j[b]:
                max_j[b] = x
            if n_hist:
                hist[b, j, _bucket(x)] += 1
        for b in range(n_bins):
            n[b, j] = n_j[b]
            sum_hi[b, j], sum_lo[b, j] = sum_hi_j[b], sum_lo_j[b]
            sq_hi[b, j], sq_lo[b, j] = sq_hi_j[b], sq_lo_j[b]
            vmin[b, j], vmax[b, j] = min_j[b], max_j[b]


def accumulate(index: np.ndarray, values: np.ndarray, partial: SummaryPartial) -> None:
    """Add rows to ``partial`` (in place).

    Parameters
    ----------
    index : int64[n]
        Each row's bin (``bin_rows``; -1 outside).
    values : float64[m, n]
        The summarised columns (NaN values are skipped).
    partial : SummaryPartial
        Of ``B`` bins and ``m`` columns.
    """
    _accumulate(index, np.ascontiguousarray(values, np.float64), *partial)


@njit
def _merge(count, outside, n, sum_hi, sum_lo, sq_hi, sq_lo, vmin, vmax, hist,
           p_count, p_outside, p_n, p_sum_hi, p_sum_lo, p_sq_hi, p_sq_lo, p_min, p_max,
           p_hist):
    outside[0] += p_outside[0]
    bins, m = n.shape
    for b in range(bins):
        count[b] += p_count[b]
        for j in range(m):
            n[b, j] += p_n[b, j]
            sum_hi[b, j], sum_lo[b, j] = _dd_add(sum_hi[b, j], sum_lo[b, j], p_sum_hi[b, j],
                                                 p_sum_lo[b, j])
            sq_hi[b, j], sq_lo[b, j] = _dd_add(sq_hi[b, j], sq_lo[b, j], p_sq_hi[b, j],
                                               p_sq_lo[b, j])
            vmin[b, j] = min(vmin[b, j], p_min[b, j])
            vmax[b, j] = max(vmax[b, j], p_max[b, j])
            if p_n[b, j] == 0 or hist.shape[2] == 0:
                continue
            # The partial's values lie between the buckets of its min and max (buckets
            # ascend with the value; one more each side in case the logarithm's rounding
            # is not monotone): merge those, not all ~8,000.
            for h in range(max(_bucket(p_min[b, j]) - 1, 0),
                           min(_bucket(p_max[b, j]) + 2, hist.shape[2])):
                hist[b, j, h] += p_hist[b, j, h]


def merge_into(total: SummaryPartial, partial: SummaryPartial) -> None:
    """Add ``partial`` to ``total`` (in place). Merge partials in chunk order."""
    _merge(*total, *partial)


@njit
def _representative(h):
    """The value that stands for histogram bucket ``h``."""
    if h == _K:
        return 0.0
    k = h - _K - 1 if h > _K else _K - 1 - h
    value = 2.0 * math.exp((k + _I_MIN) * _LOG_GAMMA) / (_GAMMA + 1.0)
    return value if h > _K else -value


@njit
def _finalize(n, sum_hi, sum_lo, sq_hi, sq_lo, vmin, vmax, hist, probabilities, mean, std,
              out_min, out_max, quantiles):
    bins, m = n.shape
    for b in range(bins):
        for j in range(m):
            count = n[b, j]
            if count == 0:
                mean[b, j] = np.nan
                std[b, j] = np.nan
                out_min[b, j] = np.nan
                out_max[b, j] = np.nan
                quantiles[b, j, :] = np.nan
                continue
            out_min[b, j], out_max[b, j] = vmin[b, j], vmax[b, j]
            # mean = S1 / N and M2 = S2 - S1^2 / N in double-double.
            q_hi = sum_hi[b, j] / count
            p, e = _two_prod(q_hi, count)
            q_lo = ((sum_hi[b, j] - p) - e + sum_lo[b, j]) / count
            mean[b, j] = q_hi + q_lo
            if count < 2:
                std[b, j] = np.nan
            else:
                # S1^2 / N = mean * S1 (double-double product, the small terms added)
                p, e = _two_prod(q_hi, sum_hi[b, j])
                e += q_hi * sum_lo[b, j] + q_lo * sum_hi[b, j]
                m2_hi, m2_lo = _dd_add(sq_hi[b, j], sq_lo[b, j], -p, -e)
                m2 = max(m2_hi + m2_lo, 0.0)
                std[b, j] = math.sqrt(m2 / (count - 1))
            for k in range(probabilities.shape[0]):
                rank = int(math.floor(probabilities[k] * (count - 1)))
                seen = 0
                value = np.nan
                for h in range(hist.shape[2]):
                    seen += hist[b, j, h]
                    if seen > rank:
                        value = _representative(h)
                        break
                quantiles[b, j, k] = min(max(value, vmin[b, j]), vmax[b, j])


def finalize(total: SummaryPartial, probabilities: np.ndarray) -> SummaryStats:
    """The statistics of a merged partial; ``probabilities`` in (0, 1) (quantiles need
    histograms: a partial allocated with ``n_hist = n_buckets()``)."""
    shape = total.n.shape
    probabilities = np.asarray(probabilities, np.float64)
    if probabilities.size and total.hist.shape[2] == 0:
        raise ValueError("quantiles need a partial with histograms")
    mean, std, vmin, vmax = (np.empty(shape) for _ in range(4))
    quantiles = np.empty((*shape, probabilities.size))
    _finalize(total.n, total.sum_hi, total.sum_lo, total.sq_hi, total.sq_lo, total.min,
              total.max, total.hist, probabilities, mean, std, vmin, vmax, quantiles)
    return SummaryStats(total.n.copy(), mean, std, vmin, vmax, quantiles)
