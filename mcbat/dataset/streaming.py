"""Exact percentiles of columns too large to hold in memory: ``streamed_percentiles``.

A dataset's closing report (the batted-ball medians and 5-95 % ranges of a game run) needs
percentiles of columns of every row. Concatenating them grows with ``--samples`` (8
columns of 10^7 rows are 640 MB); this reads the chunks a few times instead and keeps at
most one chunk and a few small histograms in memory.

The method is a selection by histograms: a first pass counts the values and finds their
range; each later pass bins the values still in contention for a wanted order statistic
into ``BINS`` equal bins of the current range, keeps the one bin holding that rank,
and, once that bin holds at most ``COLLECT`` values, collects them and picks the
value. A value's bin is ``floor((v - lo) * BINS / (hi - lo))``, which is monotone in
``v``, so the values outside the chosen bin are all below or all above it whatever the
rounding. Three passes for any smooth distribution; a cluster of equal values ends as
soon as its minimum equals its maximum. The answer is numpy's default percentile
(``method="linear"``) of the same values: the order statistics are exact, and the
interpolation between them is numpy's.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BINS", "COLLECT", "streamed_percentiles"]

#: Bins of each refining pass.
BINS = 4096
#: A bin with at most this many values is collected and sorted.
COLLECT = 1 << 16
#: Refining passes before the values of the chosen bin are collected whatever their number
#: (reached only by pathological spreads, e.g. values 1e-300 apart around a 1e300 range).
MAX_PASSES = 10


class _Target:
    """The search for order statistic ``rank`` (0-based) of the values of ``key``."""

    def __init__(self, key, rank, lo, hi):
        self.key, self.rank = key, rank
        self.levels = []  # (lo, scale, bin) of each narrowing, outermost first
        self.lo, self.hi = lo, hi  # the range the next pass bins
        self.below = 0  # values known to rank below the candidates
        self.collect = False
        self.value = lo if lo == hi else None
        self._reset()

    def _reset(self):
        self.counts = np.zeros(BINS, np.int64)
        self.parts = []
        self.cmin, self.cmax = math.inf, -math.inf

    def _scale(self):
        width = self.hi - self.lo
        return BINS / width if width > 0 and math.isfinite(BINS / width) else 0.0

    def candidates(self, values):
        """The values still in contention (inside every chosen bin so far)."""
        mask = None
        for lo, scale, chosen in self.levels:
            inside = _bin_of(values, lo, scale) == chosen
            mask = inside if mask is None else mask & inside
        return values if mask is None else values[mask]

    def feed(self, values):
        candidates = self.candidates(values)
        if not candidates.size:
            return
        self.cmin = min(self.cmin, float(candidates.min()))
        self.cmax = max(self.cmax, float(candidates.max()))
        if self.collect:
            self.parts.append(candidates.copy())
        else:
            self.counts += np.bincount(_bin_of(candidates, self.lo, self._scale()),
                                       minlength=BINS)

    def finish_pass(self, last: bool):
        """After a pass over every value: the answer, or the next narrower range."""
        if self.cmin == self.cmax:  # every candidate is one value
            self.value = self.cmin
        elif self.collect:
            values = np.sort(np.concatenate(self.parts))
            self.value = float(values[self.rank - self.below])
        else:
            scale = self._scale()
            cumulative = np.cumsum(self.counts)
            chosen = int(np.searchsorted(cumulative, self.rank - self.below, side="right"))
            self.below += int(cumulative[chosen - 1]) if chosen else 0
            self.levels.append((self.lo, scale, chosen))
            if scale > 0:
                lo = self.lo
                self.lo, self.hi = lo + chosen / scale, lo + (chosen + 1) / scale
            self.collect = last or scale == 0 or int(self.counts[chosen]) <= COLLECT
        self._reset()


def _bin_of(values, lo, scale):
    """The bin of each value: ``floor((v - lo) * scale)`` clipped to the bins."""
    index = np.floor((values - lo) * scale)
    return np.clip(index, 0, BINS - 1).astype(np.int64)


def _count(read_pass, wanted):
    """The first pass: ``(count, min, max)`` of each key's values, as dicts."""
    count = dict.fromkeys(wanted, 0)
    low = dict.fromkeys(wanted, math.inf)
    high = dict.fromkeys(wanted, -math.inf)
    for part in read_pass():
        for key in wanted:
            values = part[key]
            if values.size:
                count[key] += values.size
                low[key] = min(low[key], float(values.min()))
                high[key] = max(high[key], float(values.max()))
    return count, low, high


def streamed_percentiles(read_pass, wanted: dict) -> dict:
    """Exact percentiles of value streams read in parts.

    Parameters
    ----------
    read_pass : callable
        ``read_pass()`` returns a fresh iterable over parts: dicts ``{key: values}`` of
        1-D float arrays of finite values (each call must yield the same values).
    wanted : dict
        ``{key: percentiles}``, percentiles in [0, 100].

    Returns
    -------
    dict
        ``{key: (count, tuple of the percentiles)}``; NaN percentiles when ``key`` has no
        value. Equal to ``np.percentile`` of all the values (its default, linear
        interpolation).
    """
    count, low, high = _count(read_pass, wanted)
    targets = {}
    for key, percentiles in wanted.items():
        for q in percentiles:
            if count[key]:
                position = q / 100 * (count[key] - 1)
                for rank in (math.floor(position), math.ceil(position)):
                    targets.setdefault((key, rank), _Target(key, rank, low[key], high[key]))
    for round_ in range(MAX_PASSES + 1):
        open_ = [t for t in targets.values() if t.value is None]
        if not open_:
            break
        for part in read_pass():
            for target in open_:
                target.feed(part[target.key])
        for target in open_:
            target.finish_pass(last=round_ >= MAX_PASSES - 1)
    result = {}
    for key, percentiles in wanted.items():
        out = []
        for q in percentiles:
            if not count[key]:
                out.append(math.nan)
                continue
            position = q / 100 * (count[key] - 1)
            a = targets[(key, math.floor(position))].value
            b = targets[(key, math.ceil(position))].value
            out.append(float(np.percentile(np.array([a, b]), (position % 1) * 100)))
        result[key] = (count[key], tuple(out))
    return result
