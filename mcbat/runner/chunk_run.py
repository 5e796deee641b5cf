"""The one step every engine executes: ``run_chunk`` draws one chunk's inputs
(deterministic in the sample index), solves them with the parallel kernel, computes its
share of the summary and writes its Parquet file atomically.

Errors name the Python parameters (``out``); the CLI maps them to flags.
"""

from __future__ import annotations

import contextlib
import os
import socket

import numba
import numpy as np

from mcbat.core import status as st
from mcbat.dataset import chunks
from mcbat.dataset.summary import summarise
from mcbat.errors import InputError
from mcbat.runner.job import ChunkJob, ChunkSummary
from mcbat.solving import (
    GAME_INPUT_FIELDS,
    INPUT_FIELDS,
    solve_and_fly,
    solve_games,
    solve_impacts,
)

__all__ = ["run_chunk", "study_inputs", "warm_kernel", "write_columns", "write_error"]


def write_columns(table_args, path, compression="none") -> dict:
    """Build a chunk's table from its columns and write it atomically (see
    ``run_chunk``); returns its manifest record."""
    return chunks.write_chunk(chunks.to_table(*table_args), path, compression)


def run_chunk(study, job: ChunkJob, index: int, *, write=None,
              solve_lock=None) -> ChunkSummary:
    """Compute chunk ``index`` of a run: write its Parquet file atomically (unless the run
    is summary-only) and compute its share of the ``[summary]`` statistics.

    The chunk's inputs are drawn from ``(seed, sample index)`` alone
    (``mcbat.study.Study.sample``), so the file is the same wherever and however
    often it is computed: a rerun overwrites it with identical content.

    Parameters
    ----------
    study : mcbat.study.Study
        The validated study (its solver settings are used).
    job : ChunkJob
        The run's output location, sample count, seed, chunk size, metadata, columns and
        summary.
    index : int
        The chunk.
    write : callable, optional
        ``write(write_columns, table_args, path, compression)`` writes the file and
        returns its record. Default: write it now, before returning. The local engine
        hands it to its writer thread instead (and returns None: the record comes with the
        write's result).
    solve_lock : context manager, optional
        Held while the chunk is sampled and solved (the Dask engine serialises kernel calls
        of a worker's threads with it).

    Returns
    -------
    ChunkSummary
    """
    start, stop = job.bounds(index)
    solve = _solve_game_chunk if getattr(study, "kind", "impact") == "game" else _solve_chunk
    with solve_lock if solve_lock is not None else contextlib.nullcontext():
        threads = numba.get_num_threads()
        names, cols = solve(study, start, stop, job.seed, _derived_needed(job))
        partial = None if job.summary is None else summarise(job.summary, cols)
    counts = np.bincount(cols["status"], minlength=len(st.STATUS_NAMES))
    record = None
    if not job.summary_only:
        table_args = (names, cols, start, index, job.output, job.metadata)
        record = (write or _write_now)(write_columns, table_args, job.path(index),
                                       job.output.compression)
    return ChunkSummary(index, stop - start, tuple(int(c) for c in counts), threads,
                        f"{socket.gethostname()}:{os.getpid()}", record, partial)


def _derived_needed(job: ChunkJob):
    """The derived columns a chunk must compute: a summary-only run stores no rows, so it
    needs only those its ``[summary]`` reads (None: every one)."""
    if not job.summary_only:
        return None
    return {*job.summary.columns, *(axis.name for axis in job.summary.by)}


def _solve_chunk(study, start, stop, seed, derived=None):
    """Sample and solve an impact chunk; ``(names, cols)`` of
    ``mcbat.dataset.chunks.impact_columns`` (``derived``: as there)."""
    columns = study.sample(start, stop, seed)
    inputs = study_inputs(columns)
    out_arr, status, end_state = solve_impacts(inputs, study.solver_settings)
    barrel = study.bat.cm_from_barrel_end
    extra = {"impact_parameter": columns["impact_parameter"],
             "from_barrel_end": (np.full(stop - start, np.nan) if barrel is None
                                 else barrel - columns["axial"])}
    return chunks.impact_columns(inputs, out_arr, status, end_state, extra,
                                 study.measurement_noise(start, stop, seed), derived)


def study_inputs(columns) -> np.ndarray:
    """The kernel's input array from ``mcbat.study.Study.sample``'s columns: the first
    rows of the array they are views of (no copy), else a stacked copy."""
    n_fields = len(INPUT_FIELDS)
    base = columns[INPUT_FIELDS[0]].base
    if (isinstance(base, np.ndarray) and base.ndim == 2 and base.dtype == np.float64
            and base.shape[0] >= n_fields and base.flags.c_contiguous
            and all(columns[name].ctypes.data == base[i].ctypes.data
                    and columns[name].shape == base[i].shape
                    for i, name in enumerate(INPUT_FIELDS))):
        return base[:n_fields]
    return np.stack([np.asarray(columns[name], np.float64) for name in INPUT_FIELDS])


def _solve_game_chunk(study, start, stop, seed, derived=None):
    """Sample and solve a game chunk (and fly it, with ``[flight]``); ``(names, cols)`` of
    ``mcbat.dataset.chunks.game_columns`` (``derived``: as there)."""
    game_inputs = study.sample_inputs(start, stop, seed)  # rows: GAME_INPUT_FIELDS
    if study.flight is None:
        solved, flight = solve_games(game_inputs, study.solver_settings), None
    else:  # the batted balls fly too, each in the study's one air
        flown = solve_and_fly(game_inputs, study.solver_settings,
                              study.flight.params(study.ball.mass, study.ball.radius),
                              study.flight.start)
        solved, flight = flown.game, flown.flight
    frame, out_arr, game_out, status, end_state = solved
    return chunks.game_columns(game_inputs, frame, out_arr, game_out, status, end_state,
                               flight, derived, study.pitch_identifiers(start, stop, seed))


def _write_now(function, *args):
    return function(*args)


def warm_kernel(study, seed: int = 0) -> None:
    """Load (or compile) the kernels a chunk of ``study`` calls, by drawing and solving
    (and flying) its first sample as a chunk does, nothing written: the sampler, and the
    game or the bat-frame kernel, whichever the study uses."""
    game = getattr(study, "kind", "impact") == "game"
    # The solver first, on a row of zeros (a status code, no answer), then the first
    # sample as a chunk computes it: on a fresh install the largest kernel group is
    # compiled first, while a helper process compiles the sampler and the flight
    # (mcbat.cli.precompile).
    if game:
        solve_games(np.zeros((len(GAME_INPUT_FIELDS), 1)), study.solver_settings)
    else:
        solve_impacts(np.zeros((len(INPUT_FIELDS), 1)), study.solver_settings)
    (_solve_game_chunk if game else _solve_chunk)(study, 0, 1, seed)


def write_error(err: OSError, out) -> InputError:
    """The error for a chunk file that could not be written (names ``out``)."""
    reason = os.strerror(err.errno) if err.errno else str(err)
    return InputError("out", f"cannot write a chunk file: {reason}; complete chunk "
                      "files are kept, free space (or fix permissions) and rerun to resume",
                      str(out))
