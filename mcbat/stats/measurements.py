"""Measurement tables: the format, validation, and synthetic tables drawn from the model.

Format (CSV with a header line, ``#`` comment lines allowed, or Parquet). A bat-frame study
(a drop test) takes any subset of:

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

A game study (a pitch and a swing) takes Statcast's names and units where Statcast has the
quantity (``docs/batting.md`` defines them):

========================  ========  ==============================================
column                    unit      meaning
========================  ========  ==============================================
``launch_speed``          mph       batted-ball speed
``launch_angle``          deg       its elevation
``spray_angle``           deg       its direction, positive towards right field
``spin_rate``             rpm       its spin; ``backspin``, ``sidespin`` (rpm) its parts
``pitch_speed``           mph       measured input: the pitch's speed (the study's
                                    ``pitch.speed``)
``bat_speed``             mph       measured input: the swing's bat speed
``attack_angle``          deg       measured input: the swing's attack angle
``undercut``              m         measured input: how far under the ball's centre it
                                    was hit (high-speed video, a lab)
``from_barrel_end``       m         measured input: the contact's distance from the
                                    barrel end
``<column>_err``          as above  optional 1-sigma uncertainty of that column
========================  ========  ==============================================

A Baseball Savant (Statcast) export, or the tidy table ``mcbat statcast --out`` writes,
is read as a game table: its balls in play with a measured launch, the columns above that
Statcast has (``mcbat.statcast.measured`` says which rows are dropped and counts them in
``table.attrs["statcast"]``).

The fixed setup (bat, ball, and for a drop test the incoming speed) comes from a study TOML.
Every value must be a finite number; uncertainties must be > 0; an ``_err`` column needs its
value column. Errors name the file, the column and the data row (1-based) with the offending
value. Observables without an ``_err`` column get ``DEFAULT_ERRORS``: one error per
column, from the table's mean magnitude (``table_error``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from mcbat.errors import InputError
from mcbat.stats.columns import BAT_FRAME_COLUMNS, GAME_TABLE_COLUMNS, GAME_WRITTEN
from mcbat.stats.models.simulate import solve_study

__all__ = ["COLUMNS", "DEFAULT_ERRORS", "default_errors", "measured_fraction",
           "read_measurements", "synthesize", "table_error",
           "write_table_atomic"]

COLUMNS = {**{c: u for c, (u, _) in BAT_FRAME_COLUMNS.items()},
           **{c: u for c, (u, _) in GAME_TABLE_COLUMNS.items()}}
"""Measured quantities and their units (bat-frame and game tables)."""
DEFAULT_ERRORS = {
    "exit_speed": (0.05, 0.0), "scattering_angle": (0.0, 3.0), "spin_out": (0.10, 1.0),
    "launch_speed": (0.0, 1.0), "launch_angle": (0.0, 1.0), "spray_angle": (0.0, 1.0),
    "spin_rate": (0.10, 50.0), "backspin": (0.10, 50.0), "sidespin": (0.10, 50.0),
}
"""1-sigma error of an observable without an ``_err`` column, as ``(relative, floor)``: one
error for every row of the table, ``table_error`` (``max(relative x mean |y|, floor)``,
the mean over the table's rows, in the column's unit): 5 % of a drop test's mean exit speed,
3 deg, 10 % of its mean spin with a 1 rad/s floor; 1 mph of launch speed, 1 deg of launch
and spray angle, 10 % of the mean spin with a 50 rpm floor (assumed typical, not from a
published calibration of a tracking system). Not a fraction of each row's own value: that
would tell the fit which rows lie above the model's mean (docs/fitting.md)."""


def table_error(values, relative, floor):
    """One 1-sigma error for a whole column: ``max(relative * mean |y|, floor)``, the mean
    over the finite values (0 if there are none).

    The rule of the errors a table does not state (``DEFAULT_ERRORS``) and of the errors
    ``synthesize`` states. The same error for every row, on purpose: an error computed
    from each row's own value (true or measured) tells the fit which rows lie above the
    model's mean (they get larger errors, less weight), which its likelihood, taking the
    errors as given, does not model: game fits came out low by a third of their error and
    more (docs/fitting.md).
    """
    magnitude = np.abs(np.asarray(values, dtype=float))
    magnitude = magnitude[np.isfinite(magnitude)]
    typical = float(magnitude.mean()) if magnitude.size else 0.0
    return max(relative * typical, floor)


MEASURED_FRACTION_SPREAD = 0.02
"""Stated errors are read as a fraction of each row's measured value when their ratio to
it varies by less than this share over the rows above any floor (printed errors rounded
to three figures vary by up to 1 %)."""


def measured_fraction(values, errors):
    """The fraction of each row's measured value that a column of stated errors is, or None
    when it is not one.

    A column qualifies when, over the rows whose error lies above the column's smallest
    (a floor, as in ``max(8 % |y|, 2 rad/s)``), at least five, the errors vary by more
    than 10 % and their ratio to ``|y|`` by less than
    ``MEASURED_FRACTION_SPREAD`` of its median. Such an error tells the fit which rows
    lie above the model's mean (they weigh less), which a likelihood that takes the errors
    as given does not model: the fit is biased, by more of its errors the more rows (the
    drop test's ``e*`` low by 0.35 of its errors at 60 rows: docs/fit-checks.md).

    Parameters
    ----------
    values, errors : array_like
        A column's measured values and their stated 1-sigma errors (its unit).

    Returns
    -------
    float or None
        The median ratio ``error / |value|``.
    """
    values, errors = np.abs(np.asarray(values, float)), np.asarray(errors, float)
    good = np.isfinite(values) & np.isfinite(errors) & (values > 0) & (errors > 0)
    values, errors = values[good], errors[good]
    if errors.size < 5:
        return None
    above = errors > errors.min() * (1 + 1e-6)
    if above.sum() < 5:
        return None
    values, errors = values[above], errors[above]
    ratio = errors / values
    typical = float(np.median(ratio))
    if errors.max() < 1.1 * errors.min() or np.ptp(ratio) > MEASURED_FRACTION_SPREAD * typical:
        return None
    return typical


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

    from mcbat.statcast.measured import is_statcast, measurement_table

    path = Path(path)
    source = str(path)
    if is_statcast(path):  # a Savant export or mcbat's tidy Statcast table
        table = measurement_table(path)
        _check_columns(table.columns, required, source)
        if len(table) == 0:
            raise InputError(None, "the Statcast export has no ball in play with a measured "
                             "launch speed, launch angle and spray angle", source)
        return table
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
    """The raw table (strings for CSV), or ``InputError`` naming the file."""
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


#: Largest magnitude of a measured value (and its uncertainty) by unit: an angle within a
#: turn, anything else within 10^6 of its unit (mph, m/s, rpm, rad/s, m). Larger values are
#: typos that would overflow the likelihood's squares.
VALUE_LIMITS = {"deg": 360.0, None: 1e6}


def _numbers(name, values, source):
    """Column ``name`` as finite floats (uncertainties > 0), naming the first bad row."""
    numbers = np.empty(len(values))
    unit = COLUMNS.get(name[:-4] if name.endswith("_err") else name, "")
    limit = VALUE_LIMITS.get(unit, VALUE_LIMITS[None])
    for i, value in enumerate(values):
        try:
            numbers[i] = float(value)
        except (TypeError, ValueError):
            raise InputError(name, f"row {i + 1}: not a number: {value!r}", source) from None
        if not math.isfinite(numbers[i]):
            raise InputError(name, f"row {i + 1}: must be finite, got {value!r}", source)
        if not abs(numbers[i]) <= limit:
            raise InputError(name, f"row {i + 1}: must be within +-{limit:g} {unit}, got "
                             f"{value!r}", source)
        if name.endswith("_err") and not numbers[i] > 0.0:
            raise InputError(name, f"row {i + 1}: an uncertainty must be > 0, got {value!r}",
                             source)
    return numbers


def synthesize(study, rows, seed=0, *, e=None, mu=None, e_x=None, speed_noise=None,
               angle_noise=None, spin_noise=0.10, spin_floor=None, impact_parameter_noise=0.0,
               spin_in_noise=0.0, input_noise=None):
    """A noisy synthetic measurement table drawn from the model (what an experiment yields).

    Parameters
    ----------
    study : mcbat.study.Study or mcbat.study.game.GameStudy
        The setup and the nuisance scatter (impact point, incoming spin, ...).
    rows : int
        Number of rows (impacts); rows the solver cannot finish are dropped.
    seed : int
        Seed of the draws and of the noise (deterministic in it).
    e, mu, e_x : float, optional
        ``e*`` (a game's ``e*`` at its reference speed), the friction coefficient and the
        tangential restitution (Cross & Nathan 2006), overriding the study's values.
    speed_noise : float, optional
        Relative 1-sigma error of the exit (launch) speed, relative to the table's mean
        (one error for every row); default 0.05 for a drop test, 0.01 (about 1 mph) for a
        game.
    angle_noise : float, optional
        1-sigma error of the scattering angle (a game's launch and spray angles), deg;
        default 3 for a drop test, 1 for a game.
    spin_noise, spin_floor : float
        Relative 1-sigma error of the outgoing spin (relative to the table's mean
        magnitude, one error for every row), with a floor: default 1 rad/s for a drop test,
        50 rpm for a game's spin rate.
    impact_parameter_noise, spin_in_noise : float
        A drop test's ``input_noise`` for ``impact_parameter`` (m) and ``spin_in`` (rad/s).
    input_noise : dict, optional
        1-sigma error of written measured inputs, in the table's units (``{"undercut":
        0.005}``): the impact is solved at the true value, the table gets the true value
        plus noise and an ``<input>_err`` column (none for an input without noise: exact).
        A drop test writes ``impact_parameter`` and ``spin_in``; a game ``pitch_speed``,
        ``bat_speed``, ``attack_angle`` and ``undercut``.

    Returns
    -------
    pandas.DataFrame
        The measured inputs, the observables (a drop test: ``exit_speed``,
        ``scattering_angle``, ``spin_out``; a game: ``launch_speed``, ``launch_angle``,
        ``spray_angle``, ``spin_rate``) with their ``_err`` columns (the sigmas used), and
        the inputs' ``_err`` columns where noise was added.
    """
    import pandas as pd

    game = getattr(study, "kind", None) == "game"
    rows = _count(rows, "rows", 1, MAX_SYNTH_ROWS)
    seed = _count(seed, "seed", 0, 2**63 - 1)
    noise = dict(input_noise or {})
    for name, value in (("impact_parameter", impact_parameter_noise),
                        ("spin_in", spin_in_noise)):
        if value:
            noise[name] = value
    written = GAME_WRITTEN if game else ("impact_parameter", "spin_in")
    for name in noise:
        if name not in written:
            raise InputError("input_noise", f"{name!r} is not a measured input a "
                             f"{'game' if game else 'drop-test'} table carries (one of "
                             f"{', '.join(written)})")
    speed_noise = (0.01 if game else 0.05) if speed_noise is None else speed_noise
    angle_noise = (1.0 if game else 3.0) if angle_noise is None else angle_noise
    spin_floor = (50.0 if game else 1.0) if spin_floor is None else spin_floor
    # Finite bounds on every number: an infinite or absurd noise would write inf and NaN
    # into the table, and a friction coefficient of 1e10 leaves no impact the solver can
    # finish. The bounds are far beyond any experiment's.
    limits = {"e": (e, 0.0, 1.0), "mu": (mu, 0.0, MAX_MU), "e_x": (e_x, 0.0, 1.0),
              "speed_noise": (speed_noise, 0.0, 10.0),
              "angle_noise": (angle_noise, 0.0, 180.0),
              "spin_noise": (spin_noise, 0.0, 10.0),
              "spin_floor": (spin_floor, 0.0, 1e6),
              "impact_parameter_noise": (impact_parameter_noise, 0.0, 0.05),
              "spin_in_noise": (spin_in_noise, 0.0, 1e4)}
    limits.update({("input_noise", k): (v, 0.0, 1e3) for k, v in (input_noise or {}).items()})
    for name, (value, low, high) in limits.items():
        if value is not None and not (isinstance(value, (int, float, np.floating))
                                      and not isinstance(value, bool) and low <= value <= high):
            field, what = (name[0], f"{name[1]}: ") if isinstance(name, tuple) else (name, "")
            raise InputError(field, f"{what}must be in [{low:g}, {high:g}], got {value!r}")
    params = {"e": e, "mu": mu, "e_x": e_x}
    inputs, observed, ok = solve_study(study, rows, seed, params)
    if not ok.any():
        raise InputError(None, f"none of the {rows:,} impacts could be solved with these "
                         "parameters (e, mu, e_x and the study's setup): nothing written")
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 7,)))
    errors = {}
    for name, value in observed.items():
        # One error per table (table_error: relative to the mean over the impacts, the same
        # for every row), never a fraction of each row's true value.
        if name in ("exit_speed", "launch_speed"):
            rule = (speed_noise, 0.0)
        elif name in ("scattering_angle", "launch_angle", "spray_angle"):
            rule = (0.0, float(angle_noise))
        else:
            rule = (spin_noise, spin_floor)
        errors[name] = np.full(rows, table_error(value[ok], *rule))
    # Input noise from its own stream: the tables with and without it share every draw.
    in_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 9,)))
    columns = {}
    for name, value in inputs.items():
        columns[name] = value + noise.get(name, 0.0) * in_rng.standard_normal(rows)
        if noise.get(name, 0.0) > 0:
            columns[f"{name}_err"] = np.full(rows, float(noise[name]))
    for name, value in observed.items():
        columns[name] = value + errors[name] * rng.standard_normal(rows)
        columns[f"{name}_err"] = errors[name]
    table = pd.DataFrame(columns)[ok].reset_index(drop=True)
    bad = [name for name in table.columns if not np.isfinite(table[name]).all()]
    if bad:  # never a table with inf or NaN (a measurement table refuses them)
        raise InputError(None, f"the synthetic table's {bad[0]!r} is not finite with these "
                         "settings: nothing written")
    return table


#: Most rows of one synthetic table.
MAX_SYNTH_ROWS = 10_000_000
#: Largest friction coefficient ``synthesize`` accepts (Coulomb friction of a ball on a bat
#: is ~0.2-0.6; beyond a few every contact sticks at once).
MAX_MU = 10.0


def _count(value, name, minimum, maximum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(name, f"must be an integer >= {minimum}, got {value!r}")
    if value > maximum:
        raise InputError(name, f"must be <= {maximum:,}, got {value:,}")
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


def default_errors(column, values):
    """1-sigma errors of an observable without an ``_err`` column, one per row of
    ``values`` (the column's measured values), all equal: ``max(relative x mean |y|,
    floor)`` with ``DEFAULT_ERRORS`` (``mcbat.stats.measurements.table_error``; the
    mean over the finite values). Not ``relative |y|`` row by row: a row's error would then
    grow with its measured value and tell the fit which rows lie above the model's mean,
    biasing the estimates (docs/fitting.md)."""
    relative, floor = DEFAULT_ERRORS[column]
    values = np.asarray(values, dtype=float)
    return np.full(values.shape, table_error(values, relative, floor))
