"""Measurement tables: the format, validation, and synthetic tables drawn from the model.

Format (CSV with a header line, ``#`` comment lines allowed, or Parquet); any subset of:

========================  ========  ==============================================
column                    unit      meaning
========================  ========  ==============================================
``impact_parameter``      m         offset of the ball's incoming line from the bat axis
``spin_in``               rad/s     incoming ball spin about the bat axis
``exit_speed``            m/s       outgoing ball speed
``scattering_angle``      deg       ``atan2(v_y, v_x)`` of the outgoing ball
``spin_out``              rad/s     outgoing ball spin about the bat axis
``<column>_err``          as above  optional 1-sigma uncertainty of that column
========================  ========  ==============================================

The fixed setup (bat, ball, incoming speed) comes from a study TOML. Every value must be a
finite number; uncertainties must be > 0; an ``_err`` column needs its value column.
Errors name the file, the column and the data row (1-based) with the offending value.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.dataset.schema import derive
from mcbat.errors import InputError

__all__ = ["COLUMNS", "MEASURED_INPUTS", "OBSERVABLES", "UNITS_HINT", "read_measurements",
           "synthesize", "write_table_atomic"]

COLUMNS = {"impact_parameter": "m", "spin_in": "rad/s", "exit_speed": "m/s",
           "scattering_angle": "deg", "spin_out": "rad/s"}
"""Measured quantities and their units."""
OBSERVABLES = ("exit_speed", "scattering_angle", "spin_out")
"""The columns a fit compares with the model."""
MEASURED_INPUTS = ("impact_parameter", "spin_in")
"""Measured inputs: a fit uses their values, and marginalises their ``_err`` (1 sigma)."""
UNITS_HINT = {
    "exit_speed": ("m/s", "wrong unit? exit_speed is in m/s (mph would be 2.24 times "
                          "larger, km/h 3.6 times)"),
    "scattering_angle": ("deg", "wrong unit? scattering_angle is in degrees (radians would "
                                "be 57 times smaller)"),
    "spin_out": ("rad/s", "wrong unit or sign convention? spin_out is in rad/s about the bat "
                          "axis (rpm would be 9.55 times larger)"),
}
"""Units of the observables, and the hint given when a table's values are far outside the
model's range."""


def read_measurements(path, required=()):
    """Read and validate a measurement table (CSV or Parquet) into a pandas DataFrame.

    Parameters
    ----------
    path : str or Path
        ``.csv`` or ``.parquet`` file.
    required : sequence of str
        Columns that must be present.

    Raises
    ------
    InputError
        Naming the file, the column and the row, for any malformed content.
    """
    import pandas as pd

    path = Path(path)
    source = str(path)
    df = _read_table(path, source)
    df.columns = [str(c).strip() for c in df.columns]
    _check_columns(df.columns, required, source)
    if len(df) == 0:
        raise InputError(None, "the table has no data rows", source)
    out = pd.DataFrame(index=range(len(df)))
    for name in df.columns:
        out[name] = _numbers(name, df[name].to_numpy(), source)
    for name in out.columns:
        if name.endswith("_err") and name[:-4] not in out.columns:
            raise InputError(name, f"uncertainty without its value column {name[:-4]!r}",
                             source)
    out.attrs["source"] = source
    return out


def _read_table(path, source):
    """The raw table (strings for CSV), or :class:`InputError` naming the file."""
    import pandas as pd

    if not path.is_file():
        raise InputError(None, "no such file", source)
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".parquet", ".pq"):
        raise InputError(None, f"unknown table format {suffix!r} (use .csv or .parquet)",
                         source)
    try:
        if suffix == ".csv":
            table = pd.read_csv(path, comment="#", skipinitialspace=True, dtype=str)
        else:
            return pd.read_parquet(path)
    except Exception as err:  # noqa: BLE001 - any parser failure is the file's fault
        raise InputError(None, f"cannot read the table: {err}", source) from None
    _refuse_duplicate_header(path, source)
    return table


def _refuse_duplicate_header(path, source):
    """A CSV header naming a column twice is an error naming it: pandas would rename the
    second one (``exit_speed.1``), and the message would blame a column the file lacks."""
    import csv

    with open(path, newline="", encoding="utf-8-sig", errors="replace") as lines:
        for row in csv.reader(lines, skipinitialspace=True):
            names = []
            for cell in row:  # a '#' starts a comment, to the end of the line
                names.append(cell.split("#", 1)[0].strip())
                if "#" in cell:
                    break
            if any(names):
                break
        else:
            return
    seen = set()
    for name in names:
        if name in seen:
            raise InputError(name, f"duplicate column: appears {names.count(name)} times "
                             "in the header", source)
        seen.add(name)


def _check_columns(columns, required, source):
    """Known, unique column names, with every ``required`` one present."""
    allowed = set(COLUMNS) | {f"{c}_err" for c in COLUMNS}
    for name in columns:
        if name not in allowed:
            raise InputError(name, f"unknown column (expected any of: "
                             f"{', '.join(COLUMNS)}, each optionally with a _err column)",
                             source)
    if len(set(columns)) != len(columns):
        raise InputError(None, "duplicate column names", source)
    for name in required:
        if name not in columns:
            raise InputError(name, "missing required column", source)


def _numbers(name, values, source):
    """Column ``name`` as finite floats (uncertainties > 0), naming the first bad row."""
    numbers = np.empty(len(values))
    for i, value in enumerate(values):
        try:
            numbers[i] = float(value)
        except (TypeError, ValueError):
            raise InputError(name, f"row {i + 1}: not a number: {value!r}", source) from None
        if not math.isfinite(numbers[i]):
            raise InputError(name, f"row {i + 1}: must be finite, got {value!r}", source)
        if name.endswith("_err") and not numbers[i] > 0.0:
            raise InputError(name, f"row {i + 1}: an uncertainty must be > 0, got {value!r}",
                             source)
    return numbers


def synthesize(study, rows, seed=0, *, e=None, mu=None, e_x=None, speed_noise=0.05,
               angle_noise=3.0, spin_noise=0.10, spin_floor=1.0, impact_parameter_noise=0.0,
               spin_in_noise=0.0):
    """A noisy synthetic measurement table drawn from the model (what an experiment yields).

    Parameters
    ----------
    study : mcbat.study.Study
        The setup and the nuisance scatter (impact point, incoming spin, ...).
    rows : int
        Number of rows (impacts); rows the solver cannot finish are dropped.
    seed : int
        Seed of the draws and of the noise (deterministic in it).
    e, mu, e_x : float, optional
        ``e*``, the friction coefficient and the tangential restitution (Cross & Nathan
        2006), overriding the study's values.
    speed_noise : float
        Relative 1-sigma error of the exit speed.
    angle_noise : float
        1-sigma error of the scattering angle, deg.
    spin_noise, spin_floor : float
        Relative 1-sigma error of the outgoing spin, with a floor of ``spin_floor`` rad/s
        (so spins near zero keep an error).
    impact_parameter_noise : float
        1-sigma error (m) of the written impact parameter: the impact is solved at the true
        value, the table gets the true value plus noise and an ``impact_parameter_err``
        column (none when 0, the default: exact).
    spin_in_noise : float
        Likewise for the incoming spin (rad/s) and ``spin_in_err``.

    Returns
    -------
    pandas.DataFrame
        Columns ``impact_parameter``, ``spin_in``, the observables and their ``_err``
        columns (the sigmas used), plus the input ``_err`` columns when noise was added.
    """
    import pandas as pd

    rows = _count(rows, "rows", 1)
    seed = _count(seed, "seed", 0)
    limits = {"e": (e, 0.0, 1.0), "mu": (mu, 0.0, math.inf), "e_x": (e_x, 0.0, 1.0),
              "speed_noise": (speed_noise, 0.0, math.inf),
              "angle_noise": (angle_noise, 0.0, math.inf),
              "spin_noise": (spin_noise, 0.0, math.inf),
              "impact_parameter_noise": (impact_parameter_noise, 0.0, 0.05),
              "spin_in_noise": (spin_in_noise, 0.0, math.inf)}
    for name, (value, low, high) in limits.items():
        if value is not None and not (isinstance(value, (int, float, np.floating))
                                      and low <= value <= high):
            raise InputError(name, f"must be in [{low:g}, {high:g}], got {value!r}")
    cols = study.sample(0, rows, seed)
    for name, value in (("e", e), ("mu", mu), ("e_x", e_x)):
        if value is not None:
            cols[name] = np.full(rows, float(value))
    inputs = np.stack([np.asarray(cols[name], np.float64) for name in INPUT_FIELDS])
    out, status, _ = allocate_outputs(rows)
    solver = study.solver
    solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"], out, status,
                _)
    o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
    ok = status == 0
    derived = derive([o[f"ball_v{c}"] for c in "xyz"], [o[f"ball_w{c}"] for c in "xyz"])
    speed, angle = derived["exit_speed"], derived["scattering_angle"]
    spin = derived["spin_axial"]
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 7,)))
    speed_err = speed_noise * speed
    angle_err = np.full(rows, float(angle_noise))
    spin_err = np.maximum(spin_noise * np.abs(spin), spin_floor)
    # Input noise from its own stream: the tables with and without it share every draw.
    in_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 9,)))
    b_noise = impact_parameter_noise * in_rng.standard_normal(rows)
    w_noise = spin_in_noise * in_rng.standard_normal(rows)
    table = pd.DataFrame({
        "impact_parameter": cols["impact_parameter"] + b_noise,
        "spin_in": cols["ball_wz_in"] + w_noise,
        "exit_speed": speed + speed_err * rng.standard_normal(rows),
        "exit_speed_err": speed_err,
        "scattering_angle": angle + angle_err * rng.standard_normal(rows),
        "scattering_angle_err": angle_err,
        "spin_out": spin + spin_err * rng.standard_normal(rows),
        "spin_out_err": spin_err,
    })
    if impact_parameter_noise > 0:
        table.insert(1, "impact_parameter_err", np.full(rows, float(impact_parameter_noise)))
    if spin_in_noise > 0:
        table.insert(table.columns.get_loc("spin_in") + 1, "spin_in_err",
                     np.full(rows, float(spin_in_noise)))
    return table[ok].reset_index(drop=True)


def _count(value, name, minimum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(name, f"must be an integer >= {minimum}, got {value!r}")
    return int(value)


def write_table_atomic(table, path):
    """Write a measurement table as CSV (or Parquet by suffix) via a temporary file."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        if path.suffix.lower() in (".parquet", ".pq"):
            table.to_parquet(tmp, index=False)
        else:
            table.to_csv(tmp, index=False, float_format="%.10g")
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
