"""A study's random inputs compiled for the jitted sampler (``mcbat.core.sampling``).

Each random input has its own Philox stream, numbered by the CRC-32 of its dotted name
(``"ball_velocity.x"``): adding, removing or reordering inputs leaves every other input's
draws unchanged, and the sample index alone fixes a row's values.
"""

from __future__ import annotations

import zlib

import numpy as np

from mcbat.core.jit import await_group
from mcbat.core.sampling import (
    CHOICE,
    FIXED,
    NORMAL,
    PARAMS,
    TRUNCNORMAL,
    UNIFORM,
    DrawProgram,
    draw_random_inputs,
)
from mcbat.study.distributions import (
    Choice,
    Fixed,
    Mixture,
    Normal,
    TruncNormal,
    Uniform,
)

__all__ = ["INPUTS", "NOISE", "compile_program", "draw", "draw_stream", "stream_id"]


def stream_id(name: str) -> int:
    """The Philox stream of the random input (or noise output) ``name``: CRC-32 of the
    name's UTF-8 bytes."""
    return zlib.crc32(name.encode("utf-8"))


def _component_row(dist, choices) -> tuple[int, list, list]:
    """``(kind, params, choice slot)`` of one component; a choice's values and running
    weight sums are appended to ``choices``, and its slot is ``(first, count, last)``
    there (``(0, 0, 0)`` for the other kinds)."""
    none = [0, 0, 0]
    if isinstance(dist, Fixed):
        return FIXED, [dist.value], none
    if isinstance(dist, Uniform):
        return UNIFORM, [dist.low, dist.high], none
    if isinstance(dist, Normal):
        return NORMAL, [dist.mean, dist.std], none
    if isinstance(dist, TruncNormal):
        return TRUNCNORMAL, [dist.mean, dist.std, dist.low, dist.high, dist._pa, dist._pb,
                             float(dist._flip)], none
    if isinstance(dist, Choice):
        first = sum(len(values) for values, _ in choices)
        choices.append((dist._values, dist._cum))
        return CHOICE, [], [first, len(dist._values), dist._last]
    raise TypeError(f"{type(dist).__name__} is not drawn by the random sampler")


#: Counter domains: a study's random inputs, and its simulated measurement noise.
INPUTS, NOISE = 0, 1


def compile_program(inputs, rows, domain=INPUTS) -> DrawProgram:
    """The ``mcbat.core.sampling.DrawProgram`` of random ``inputs``.

    Parameters
    ----------
    inputs : list of (str, Dist)
        Random inputs (``family == "random"``) by dotted name.
    rows : dict of str -> int
        The row of the output table each input is drawn into.
    domain : int
        ``INPUTS`` or ``NOISE`` (the counter's last word).
    """
    row, stream, first, count, last, cum = [], [], [], [], [], []
    kind, param, choice_slot, choices = [], [], [], []
    for name, dist in inputs:
        components = dist.components if isinstance(dist, Mixture) else (dist,)
        row.append(rows[name])
        stream.append(stream_id(name))
        first.append(len(kind))
        count.append(len(components))
        if isinstance(dist, Mixture):
            last.append(dist._last)
            cum.extend(dist._cum)
        else:
            last.append(0)
            cum.append(1.0)
        for component in components:
            k, p, slot = _component_row(component, choices)
            kind.append(k)
            param.append(p + [0.0] * (PARAMS - len(p)))
            choice_slot.append(slot)
    if len(set(stream)) != len(stream):  # (CRC-32 of a handful of names: never in practice)
        raise ValueError(f"two random inputs share a stream: {[n for n, _ in inputs]}")
    slots = np.asarray(choice_slot, np.int64).reshape(-1, 3)
    values = [np.asarray(v, np.float64) for v, _ in choices]
    cums = [np.asarray(c, np.float64) for _, c in choices]
    return DrawProgram(
        row=np.asarray(row, np.int64), stream=np.asarray(stream, np.uint64),
        first=np.asarray(first, np.int64), count=np.asarray(count, np.int64),
        last=np.asarray(last, np.int64), cum=np.asarray(cum, np.float64),
        kind=np.asarray(kind, np.int64),
        param=np.asarray(param, np.float64).reshape(-1, PARAMS),
        choice_first=slots[:, 0].copy(), choice_count=slots[:, 1].copy(),
        choice_last=slots[:, 2].copy(),
        choice_value=np.concatenate(values) if values else np.zeros(0),
        choice_cum=np.concatenate(cums) if cums else np.zeros(0), domain=np.uint64(domain))


def draw(program: DrawProgram, seed: int, start: int, out: np.ndarray) -> None:
    """Draw ``program``'s inputs for samples ``start .. start + out.shape[1] - 1`` into
    their rows of ``out`` (float64, C-contiguous rows)."""
    if program.row.size and out.shape[1]:
        await_group("sampling")
        draw_random_inputs(program, np.uint64(seed), np.int64(start), out)


def draw_stream(name: str, dist, seed: int, start: int, n: int) -> np.ndarray:
    """The draws of one named stream from ``dist`` for samples ``start .. start + n - 1``
    (float64[n]): a study's extra random numbers (the row draw, the swing errors)."""
    out = np.empty((1, n))
    draw(compile_program([(name, dist)], {name: 0}), seed, start, out)
    return out[0]
