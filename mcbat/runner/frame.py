"""Solve a DataFrame of impacts in memory: ``solve_frame``."""

from __future__ import annotations

import numba
import numpy as np

from mcbat.core.geometry import impact_parameters_from_angles
from mcbat.dataset.chunks import build_table
from mcbat.dataset.load import units_of
from mcbat.errors import InputError
from mcbat.runner.plan import positive_int
from mcbat.solving import (
    DEFAULT_MAX_STEPS,
    DEFAULT_STEPS,
    DEFAULT_TOLERANCE,
    INPUT_FIELDS,
    SolverSettings,
    solve_impacts,
)

__all__ = ["solve_frame"]


def solve_frame(frame, *, steps=DEFAULT_STEPS, tolerance=DEFAULT_TOLERANCE,
                max_steps=DEFAULT_MAX_STEPS, threads=None):
    """Solve every row of a DataFrame of inputs with the parallel kernel; no files.

    The rows are those ``mcbat run`` writes for the same inputs, bit for bit (the same
    kernel, the same table builder), without ``chunk``.

    Parameters
    ----------
    frame : pandas.DataFrame
        One impact per row, with a column for every kernel input of
        ``mcbat.solving.INPUT_FIELDS`` (SI units, the names of the dataset schema;
        a dataset loaded with ``mcbat.load`` has them). ``impact_parameter`` is
        computed from ``angle`` (approach azimuth 0) when absent; ``from_barrel_end`` and
        ``sample_id`` are kept when present (else NaN, and numbered from 0). Other columns
        are ignored.
    steps, tolerance, max_steps
        The kernel's accuracy settings (see ``mcbat.api.SolverSettings``; ``tolerance``
        finite with ``0 < tolerance < 1``, as everywhere).
    threads : int, optional
        Numba threads for the kernel (default: the current setting).

    Returns
    -------
    pandas.DataFrame
        The dataset columns (``mcbat.dataset.schema.COLUMNS`` but ``chunk``), with
        ``frame``'s index; ``df.attrs["units"]`` gives every column's unit. Rows that
        cannot be solved are flagged in ``status`` with NaN outputs.

    Raises
    ------
    InputError
        A missing input column, named.
    """
    missing = [name for name in INPUT_FIELDS if name not in frame.columns]
    if missing:
        raise InputError(missing[0], "missing column of the input frame (the kernel needs "
                         f"{', '.join(INPUT_FIELDS)})")
    steps = positive_int(steps, "steps")
    max_steps = positive_int(max_steps, "max_steps")
    # The one rule of every tolerance (studies, SolverSettings, mcbat impact --tolerance).
    settings = SolverSettings(steps, tolerance, max_steps)
    n = len(frame)
    inputs = np.stack([np.asarray(frame[name], np.float64) for name in INPUT_FIELDS]) \
        if n else np.empty((len(INPUT_FIELDS), 0))
    if "impact_parameter" in frame.columns:
        impact_parameter = np.asarray(frame["impact_parameter"], np.float64)
    else:
        row = {name: inputs[i] for i, name in enumerate(INPUT_FIELDS)}
        impact_parameter = np.empty(n)
        impact_parameters_from_angles(row["angle"], row["ball_radius"], row["bat_radius"],
                                      row["bat_slope"], np.zeros(n), impact_parameter)
    previous = numba.get_num_threads()
    if threads is not None:
        numba.set_num_threads(positive_int(threads, "threads"))
    try:
        out, status, end_state = solve_impacts(inputs, settings)
    finally:
        numba.set_num_threads(previous)
    extra = {"impact_parameter": impact_parameter}
    if "from_barrel_end" in frame.columns:  # (the frame's bat; else NaN: unknown here)
        extra["from_barrel_end"] = np.asarray(frame["from_barrel_end"], np.float64)
    table = build_table(0, 0, inputs, out, status, end_state, extra, None)
    df = table.drop_columns(["chunk"]).to_pandas()
    if "sample_id" in frame.columns:
        df["sample_id"] = np.asarray(frame["sample_id"], np.int64)
    df.index = frame.index
    df.attrs["units"] = units_of(df.columns)
    return df
