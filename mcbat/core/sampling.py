"""Counter-based random draws: the jitted, parallel sampler of a study's random inputs.

Every random number of a study is a pure function of ``(seed, sample index, stream)``:
the Philox4x32-10 block cipher of Salmon, Moraes, Dror & Shaw ("Parallel random numbers:
as easy as 1, 2, 3", SC '11) maps the 128-bit counter ``(index low, index high, stream,
domain)`` under the 64-bit key ``(seed low, seed high)`` to 128 random bits (the domain
keeps families of draws apart: 0 for a study's inputs, 1 for simulated measurement
noise). There is no generator state to carry from one sample to the next, so any range of
samples is drawn in parallel, in any order, by any number of threads, and gives the same
bits: the sample index alone fixes the draw.

One block per sample and input gives two uniforms on (0, 1) of 52 bits each (never 0 or
1): ``u_select`` picks a mixture component and ``u_value`` draws its value. Normal values
use the inverse CDF (Wichura's AS241, ~1e-16 relative), so a normal draw costs one uniform
and its tails reach 8.2 standard deviations (the smallest uniform, 2**-53).

A study is compiled (``mcbat.study.random_program``) into a ``DrawProgram``:
struct-of-arrays tables of its inputs and their components, which
``draw_random_inputs`` reads. Kernels here are pure: arrays in, ``out`` written.
"""

import math
from typing import NamedTuple

import numba
import numpy as np

from mcbat.core.jit import njit

__all__ = ["CHOICE", "FIXED", "NORMAL", "PARAMS", "TRUNCNORMAL", "UNIFORM", "DrawProgram",
           "draw_random_inputs", "philox4x32_10", "standard_normal_quantile", "unit_uniform"]

# Component kinds of a DrawProgram, and what their ``param`` row holds.
FIXED = 0        # (value,)
UNIFORM = 1      # (low, high)
NORMAL = 2       # (mean, std)
TRUNCNORMAL = 3  # (mean, std, low, high, cdf_low, cdf_high, flip) (see study.distributions)
CHOICE = 4       # values and cumulative weights in the program's choice tables
#: Columns of ``DrawProgram.param``.
PARAMS = 7

_MASK32 = np.uint64(0xFFFFFFFF)
_SHIFT32 = np.uint64(32)
_SHIFT12 = np.uint64(12)
# Philox4x32 multipliers and Weyl key increments (Salmon et al. 2011, Random123).
_PHILOX_M0 = np.uint64(0xD2511F53)
_PHILOX_M1 = np.uint64(0xCD9E8D57)
_PHILOX_W0 = np.uint64(0x9E3779B9)
_PHILOX_W1 = np.uint64(0xBB67AE85)


class DrawProgram(NamedTuple):
    """A study's random inputs as tables for ``draw_random_inputs``.

    Input ``k`` is drawn into row ``row[k]`` of ``out`` from Philox stream ``stream[k]``
    of ``domain``.
    Its components are ``first[k] .. first[k] + count[k] - 1``; with more than one,
    ``u_select`` picks component ``j`` with probability proportional to the weights whose
    running sums are ``cum[first[k]:first[k] + count[k]]`` (``last[k]``: the last component
    with a positive weight). Component ``j`` has kind ``kind[j]`` and parameters
    ``param[j]``; a choice component's values and running weight sums are
    ``choice_value``/``choice_cum[choice_first[j]:choice_first[j] + choice_count[j]]``
    (``choice_last[j]``: its last value with a positive weight).
    """

    row: np.ndarray           # int64[k]
    stream: np.ndarray        # uint64[k], < 2**32
    first: np.ndarray         # int64[k]
    count: np.ndarray         # int64[k]
    last: np.ndarray          # int64[k]
    cum: np.ndarray           # float64[c]
    kind: np.ndarray          # int64[c]
    param: np.ndarray         # float64[c, PARAMS]
    choice_first: np.ndarray  # int64[c]
    choice_count: np.ndarray  # int64[c]
    choice_last: np.ndarray   # int64[c]
    choice_value: np.ndarray  # float64[v]
    choice_cum: np.ndarray    # float64[v]
    domain: np.uint64         # the counter's last word


@njit(inline="always")
def _philox_round(c0, c1, c2, c3, k0, k1):
    """One Philox4x32 round: two 32x32 -> 64-bit products, their halves xor-ed across."""
    product0 = _PHILOX_M0 * c0
    product1 = _PHILOX_M1 * c2
    return (((product1 >> _SHIFT32) ^ c1 ^ k0) & _MASK32, product1 & _MASK32,
            ((product0 >> _SHIFT32) ^ c3 ^ k1) & _MASK32, product0 & _MASK32)


@njit(inline="always")
def _bump(k0, k1):
    """The Weyl step of the key between rounds."""
    return (k0 + _PHILOX_W0) & _MASK32, (k1 + _PHILOX_W1) & _MASK32


@njit(inline="always")
def _round_and_bump(state):
    """A round, then the key's Weyl step: ``state`` is the counter's and the key's words
    ``(c0, c1, c2, c3, k0, k1)``, and so is the result, for the next round."""
    c0, c1, c2, c3, k0, k1 = state
    c0, c1, c2, c3 = _philox_round(c0, c1, c2, c3, k0, k1)
    k0, k1 = _bump(k0, k1)
    return c0, c1, c2, c3, k0, k1


@njit(inline="always")
def _three_rounds(state):
    """Three rounds, each followed by the key's Weyl step (``state`` as ``_round_and_bump``)."""
    return _round_and_bump(_round_and_bump(_round_and_bump(state)))


@njit(inline="always")
def philox4x32_10(c0, c1, c2, c3, k0, k1):
    """Philox4x32-10: 128 random bits from a 128-bit counter and a 64-bit key.

    Parameters
    ----------
    c0, c1, c2, c3, k0, k1 : uint64
        The counter's and the key's 32-bit words (each < 2**32).

    Returns
    -------
    tuple of 4 uint64
        The output's 32-bit words, in Random123's order (its known-answer vectors are
        checked by the tests).
    """
    # The ten rounds as nested inlined calls, three times three rounds and a last one: as
    # a loop, numba keeps the tuple shuffle and the generator is 4x slower (9 ns a block
    # against 2.2 ns).
    c0, c1, c2, c3, k0, k1 = _three_rounds(_three_rounds(_three_rounds((c0, c1, c2, c3,
                                                                      k0, k1))))
    return _philox_round(c0, c1, c2, c3, k0, k1)


@njit(inline="always")
def unit_uniform(high_word, low_word):
    """A uniform on the open interval (0, 1) from two 32-bit words: their top 52 bits,
    centred in their cell, ``(m + 1/2) 2**-52``, exact in a double, so that neither 0 nor
    1 ever comes out (the extremes are ``2**-53`` and ``1 - 2**-53``)."""
    bits = ((high_word << _SHIFT32) | low_word) >> _SHIFT12
    # (through int64, exact below 2**52: converting a uint64 to float takes a branch)
    return (float(np.int64(bits)) + 0.5) * 2.220446049250313e-16  # 2**-52


@njit
def standard_normal_quantile(p):
    """The standard normal quantile (inverse CDF) of ``p`` in (0, 1).

    Wichura's rational approximations, Algorithm AS 241 (Applied Statistics 37, 477-484,
    1988; PPND16, relative error about 1e-16); checked against ``scipy.special.ndtri``.
    """
    q = p - 0.5
    if abs(q) <= 0.425:
        r = 0.180625 - q * q
        num = (((((((2.5090809287301226727e+3 * r + 3.3430575583588128105e+4) * r
                    + 6.7265770927008700853e+4) * r + 4.5921953931549871457e+4) * r
                  + 1.3731693765509461125e+4) * r + 1.9715909503065514427e+3) * r
                + 1.3314166789178437745e+2) * r + 3.3871328727963666080e+0)
        den = (((((((5.2264952788528545610e+3 * r + 2.8729085735721942674e+4) * r
                    + 3.9307895800092710610e+4) * r + 2.1213794301586595867e+4) * r
                  + 5.3941960214247511077e+3) * r + 6.8718700749205790830e+2) * r
                + 4.2313330701600911252e+1) * r + 1.0)
        return q * num / den
    r = math.sqrt(-math.log(p if q < 0.0 else 1.0 - p))
    if r <= 5.0:
        r -= 1.6
        num = (((((((7.74545014278341407640e-4 * r + 2.27238449892691845833e-2) * r
                    + 2.41780725177450611770e-1) * r + 1.27045825245236838258e+0) * r
                  + 3.64784832476320460504e+0) * r + 5.76949722146069140550e+0) * r
                + 4.63033784615654529590e+0) * r + 1.42343711074968357734e+0)
        den = (((((((1.05075007164441684324e-9 * r + 5.47593808499534494600e-4) * r
                    + 1.51986665636164571966e-2) * r + 1.48103976427480074590e-1) * r
                  + 6.89767334985100004550e-1) * r + 1.67638483018380384940e+0) * r
                + 2.05319162663775882187e+0) * r + 1.0)
    else:
        r -= 5.0
        num = (((((((2.01033439929228813265e-7 * r + 2.71155556874348757815e-5) * r
                    + 1.24266094738807843860e-3) * r + 2.65321895265761230930e-2) * r
                  + 2.96560571828504891230e-1) * r + 1.78482653991729133580e+0) * r
                + 5.46378491116411436990e+0) * r + 6.65790464350110377720e+0)
        den = (((((((2.04426310338993978564e-15 * r + 1.42151175831644588870e-7) * r
                    + 1.84631831751005468180e-5) * r + 7.86869131145613259100e-4) * r
                  + 1.48753612908506148525e-2) * r + 1.36929880922735805310e-1) * r
                + 5.99832206555887937690e-1) * r + 1.0)
    x = num / den
    return -x if q < 0.0 else x


@njit(inline="always")
def _select(cum, first, count, last, u):
    """The index (from 0) drawn by the uniform ``u`` with probabilities proportional to
    the weights whose running sums are ``cum[first:first + count]``: the number of sums
    ``<= u * total``, capped at ``last`` (the last positive weight)."""
    x = u * cum[first + count - 1]
    index = 0
    for j in range(count):
        if x >= cum[first + j]:
            index += 1
    return min(index, last)


@njit(inline="always")
def _finish(program, j, values, which, component, lo, hi, every=False):
    """Turn the uniforms ``values[lo:hi]`` into values of component ``j`` where
    ``which[i] == component`` (everywhere with ``every``: an input of one component,
    ``which`` unread). The kind is tested once per block and the loops of the common kinds
    are branch-free selects, so they vectorise."""
    kind = program.kind[j]
    p = program.param
    if kind == FIXED:
        value = p[j, 0]
        for i in range(lo, hi):
            values[i] = value if every or which[i] == component else values[i]
    elif kind == UNIFORM:
        low, span = p[j, 0], p[j, 1] - p[j, 0]
        for i in range(lo, hi):
            values[i] = (low + span * values[i] if every or which[i] == component
                         else values[i])
    elif kind == NORMAL:
        for i in range(lo, hi):
            if every or which[i] == component:
                values[i] = p[j, 0] + p[j, 1] * standard_normal_quantile(values[i])
    elif kind == TRUNCNORMAL:
        for i in range(lo, hi):
            if every or which[i] == component:
                x = standard_normal_quantile(p[j, 4] + (p[j, 5] - p[j, 4]) * values[i])
                if p[j, 6] != 0.0:
                    x = -x
                values[i] = min(max(p[j, 0] + p[j, 1] * x, p[j, 2]), p[j, 3])
    else:  # CHOICE
        first, count = program.choice_first[j], program.choice_count[j]
        for i in range(lo, hi):
            if every or which[i] == component:
                values[i] = program.choice_value[first + _select(
                    program.choice_cum, first, count, program.choice_last[j], values[i])]


@njit(inline="always")
def _four_sums(cum, first, count):
    """The running weight sums ``cum[first:first + count]`` (``count <= 4``), padded with
    +inf to four."""
    t0 = cum[first]
    t1 = cum[first + 1] if count > 1 else math.inf
    t2 = cum[first + 2] if count > 2 else math.inf
    t3 = cum[first + 3] if count > 3 else math.inf
    return t0, t1, t2, t3


#: Samples per block of the parallel loop: its inner loops run over a block (L1-sized).
_BLOCK = 1024


@njit(parallel=True)
def draw_random_inputs(program, seed, start, out):
    """Draw every input of ``program`` for samples ``start .. start + n - 1``.

    Parameters
    ----------
    program : DrawProgram
        The study's random inputs.
    seed : uint64
        The study's seed (the Philox key).
    start : int
        The index of the first sample.
    out : float64[m, n]
        Written in the rows ``program.row`` (other rows are left alone).
    """
    key0 = seed & _MASK32
    key1 = seed >> _SHIFT32
    n = out.shape[1]
    selector = np.empty(n)         # u_select of the current input (read by mixtures)
    which = np.empty(n, np.int64)  # the component it picks
    for block in numba.prange((n + _BLOCK - 1) // _BLOCK):
        lo, hi = block * _BLOCK, min(n, (block + 1) * _BLOCK)
        for k in range(program.row.shape[0]):
            _draw_block(program, k, key0, key1, start, lo, hi, out[program.row[k]], selector,
                        which)


@njit
def _draw_block(program, k, key0, key1, start, lo, hi, values, selector, which):
    """Input ``k`` of samples ``start + lo .. start + hi - 1`` into ``values[lo:hi]``.

    A function of its own, not the body of the parallel loop: numba compiles a ``prange``
    body so that LLVM does not vectorise its inner loops, and the generator ran 3x slower
    there (10.7 ns a block against 3.3 ns)."""
    stream = program.stream[k]
    first, count = program.first[k], program.count[k]
    # The uniforms first, in a loop of nothing else (it vectorises).
    if count == 1:  # (no component to select)
        for i in range(lo, hi):
            index = np.uint64(start + i)
            _, _, w2, w3 = philox4x32_10(index & _MASK32, index >> _SHIFT32, stream,
                                         program.domain, key0, key1)
            values[i] = unit_uniform(w2, w3)
        _finish(program, first, values, which, 0, lo, hi, True)
        return
    for i in range(lo, hi):
        index = np.uint64(start + i)
        w0, w1, w2, w3 = philox4x32_10(index & _MASK32, index >> _SHIFT32, stream,
                                       program.domain, key0, key1)
        selector[i] = unit_uniform(w0, w1)
        values[i] = unit_uniform(w2, w3)
    # which = the number of running weight sums <= u * total, capped at the last positive
    # weight (as _select); up to 4 components in one pass that vectorises (the missing sums
    # are +inf), more one sum at a time.
    total = program.cum[first + count - 1]
    last = program.last[k]
    if count <= 4:
        t0, t1, t2, t3 = _four_sums(program.cum, first, count)
        for i in range(lo, hi):
            x = selector[i] * total
            which[i] = min((x >= t0) + (x >= t1) + (x >= t2) + (x >= t3), last)
    else:
        for i in range(lo, hi):
            which[i] = 0
        for c in range(count):
            threshold = program.cum[first + c]
            for i in range(lo, hi):
                which[i] += selector[i] * total >= threshold
        for i in range(lo, hi):
            which[i] = min(which[i], last)
    for component in range(count):
        _finish(program, first + component, values, which, component, lo, hi)
