"""The column contract of mcbat datasets: names, units and order.

Every solver input is a column, so each row is a self-contained case; every output of the
kernel is a column; a few quantities are derived from the outgoing ball (``mcbat.solving.derived``,
the one place they are computed: datasets, ``mcbat.solve_frame``, the single-case API,
the fits and the synthetic measurements all call it).

Columns (SI units, see ``UNITS``; the lab frame of ``docs/physics.md``):

* inputs: ``mu``, ``e`` (energetic e*), ``e_x``, ``axial``, ``from_barrel_end`` (the
  contact's distance from the barrel end, ``cm_from_barrel_end - axial``; NaN for a bat
  without one), ``angle``, ``impact_parameter``, ``ball_mass``, ``ball_radius``,
  ``ball_inertia_factor``, ``bat_mass``, ``bat_radius``, ``bat_slope``, ``bat_transverse_inertia``,
  ``bat_axial_inertia``, ``ball_vx_in`` ... ``ball_wz_in``, ``bat_vx_in`` ... ``bat_wz_in``;
* outputs: ``ball_vx`` ... ``ball_wz``, ``bat_vx`` ... ``bat_wz``, ``normal_impulse``,
  ``stick_impulse`` (NaN if none), ``compression_impulse``, ``tangential_impulse_1/2``,
  ``compression_work``, ``normal_work``, ``friction_work``, ``stick_criterion``,
  ``energy_in``, ``energy_out``, ``rk4_steps``, ``end_state`` (int8: 0 sliding, 1 stuck),
  ``status`` (int8: 0 ok, see ``mcbat.core.status``);
* derived: ``exit_speed``, ``scattering_angle`` (degrees, ``atan2(v_y, v_x)``),
  ``spin_axial`` (ball spin about the bat axis), ``spin`` (magnitude);
* bookkeeping: ``sample_id`` (int64), ``chunk`` (int32);
* optional simulated measurements (a study's ``[noise]``): ``<derived>_measured``.

Game datasets (a study with ``[pitch]``/``[swing]``, ``docs/batting.md``) have every
column above (the bat-frame case each row solved, so any row re-solves in the bat frame
alone) and, in ``GAME_COLUMNS`` only, the game inputs (``GAME_INPUT_COLUMNS``),
the field-frame velocities and spins of ball and bat before and after, the collision
efficiency (``GAME_OUTPUT_COLUMNS``), and the batted ball in the field's conventions
(``derive_game``: ``launch_speed`` mph, ``launch_angle``, ``spray_angle`` deg,
``spin_rate``, ``backspin``, ``sidespin``, ``gyrospin`` rpm).

Game datasets of a study with ``[pitches]`` (real pitches, ``docs/batting.md``) end with
``PITCH_SOURCE_COLUMNS`` (int64): ``source_row``, the row of the study's file the
sample's pitch was drawn from (from 0, in the file's order, before any filter), and that
pitch's Statcast identifiers ``game_pk``, ``at_bat_number``, ``pitch_number``, ``pitcher``,
``batter``.

A row whose status is not 0 has NaN outputs: it is flagged, never passed off as a result.
"""

from __future__ import annotations

import numpy as np

from mcbat.solving import GAME_INPUT_FIELDS, GAME_OUTPUT_FIELDS, INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.study import units as study_units
from mcbat.study.pitches import PITCH_SOURCE_COLUMNS

__all__ = ["COLUMNS", "DERIVED_COLUMNS", "FLIGHT_COLUMNS", "GAME_COLUMNS",
           "GAME_DERIVED_COLUMNS", "GAME_INPUT_COLUMNS", "GAME_OUTPUT_COLUMNS",
           "INPUT_COLUMNS", "MEASURED_SUFFIX", "OUTPUT_COLUMNS", "PITCH_SOURCE_COLUMNS",
           "SCHEMA_VERSION", "STATCAST_UNIT_INPUTS", "UNITS",
           "si_units", "statcast_units"]

#: Version of the column contract; stored in every manifest and chunk file.
#: 3: game datasets (``GAME_COLUMNS``); the bat-frame columns are those of version 2.
#: 4: ``from_barrel_end`` in every dataset (after ``axial``); ``[output]`` column selection
#: and float32 outputs; ``[summary]`` tables; float columns stored uncompressed by default.
#: 5: the same columns; the random inputs come from the counter-based sampler (study format
#: 2: Philox4x32-10, see ``mcbat.core.sampling``), so a seed gives other rows than in 4.
#: 6: the same columns and rows; every Parquet column is REQUIRED (non-nullable: no column
#: holds nulls, NaN marks a failed row), which encodes faster. Version-5 files are
#: OPTIONAL, and pyarrow does not concatenate the two: a version-5 dataset is not resumed.
#: 7: the same rows; a game dataset's pitch and swing columns that have a Statcast
#: counterpart (``STATCAST_UNIT_INPUTS``) are in Statcast's units (mph, deg, rpm), as
#: its batted-ball columns already were; lengths stay in m.
SCHEMA_VERSION = 7

_LINEAR = {"v": "m/s", "w": "rad/s"}
STATCAST_UNIT_INPUTS = {
    "pitch_speed": "mph", "pitch_vertical_approach_angle": "deg",
    "pitch_horizontal_approach_angle": "deg", "pitch_spin_rate": "rpm", "pitch_spin_axis": "deg",
    "bat_speed": "mph", "attack_angle": "deg", "attack_direction": "deg",
    "vertical_bat_angle": "deg",
}
"""The game inputs a dataset writes in Statcast's units (the kernel takes them in SI): the
pitch at the plate and the swing, as a Savant export and Statcast's bat tracking give them
(``bat_speed > 70`` selects fast swings in mph)."""
UNITS = {
    "mu": "1", "e": "1", "e_x": "1", "axial": "m", "angle": "rad", "impact_parameter": "m",
    "ball_mass": "kg", "ball_radius": "m", "ball_inertia_factor": "1",
    "bat_mass": "kg", "bat_radius": "m", "bat_slope": "1",
    "bat_transverse_inertia": "kg m^2", "bat_axial_inertia": "kg m^2",
    **{f"{body}_{q}{c}_in": _LINEAR[q] for body in ("ball", "bat") for q in "vw" for c in "xyz"},
    **{f"{body}_{q}{c}": _LINEAR[q] for body in ("ball", "bat") for q in "vw" for c in "xyz"},
    "normal_impulse": "kg m/s", "stick_impulse": "kg m/s", "compression_impulse": "kg m/s",
    "tangential_impulse_1": "kg m/s", "tangential_impulse_2": "kg m/s",
    "compression_work": "J", "normal_work": "J", "friction_work": "J",
    "stick_criterion": "J", "energy_in": "J", "energy_out": "J", "rk4_steps": "1",
    "end_state": "code", "status": "code",
    "exit_speed": "m/s", "scattering_angle": "deg", "spin_axial": "rad/s", "spin": "rad/s",
    "sample_id": "1", "chunk": "1",
    "exit_speed_measured": "m/s", "scattering_angle_measured": "deg",
    "spin_axial_measured": "rad/s", "spin_measured": "rad/s",
    # game datasets
    **STATCAST_UNIT_INPUTS,
    "bat_length": "m", "bat_cm_from_knob": "m", "handedness": "1 (+1 R, -1 L)",
    "pitch_spin_efficiency": "1", "pitch_gyro_sign": "1",
    "pivot": "m", "from_barrel_end": "m", "undercut": "m",
    "e_ref": "1", "e_slope": "s/m", "e_speed_ref": "m/s", "e_location_factor": "1",
    "collision_efficiency": "1",
    **{f"field_{body}_{q}{c}{sfx}": _LINEAR[q] for body in ("ball", "bat") for q in "vw"
       for c in "xyz" for sfx in ("_in", "")},
    "launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg", "spin_rate": "rpm",
    "backspin": "rpm", "sidespin": "rpm", "gyrospin": "rpm",
    # game datasets with a [flight] section
    "hit_distance": "ft", "hang_time": "s", "apex": "ft", "landing_x": "ft", "landing_y": "ft",
    "hit_distance_m": "m", "apex_m": "m", "landing_x_m": "m", "landing_y_m": "m",
    "flight_status": "code (0 ok, 1 no flight: invalid launch, 2 step limit)",
    # game datasets with [pitches]: the real pitch of each row
    "source_row": "1 (row of the [pitches] file, from 0)", "game_pk": "id (MLB game)",
    "at_bat_number": "1", "pitch_number": "1", "pitcher": "id (MLBAM)",
    "batter": "id (MLBAM)",
}
"""Unit of every column."""

INPUT_COLUMNS = ("mu", "e", "e_x", "axial", "from_barrel_end", "angle", "impact_parameter",
                 "ball_mass", "ball_radius", "ball_inertia_factor", "bat_mass", "bat_radius",
                 "bat_slope", "bat_transverse_inertia", "bat_axial_inertia",
                 *(f for f in INPUT_FIELDS if f.endswith("_in")))
"""The inputs of a row: the kernel's ``mcbat.core.batch.INPUT_FIELDS``, the contact's
distance from the barrel end and the impact parameter (second descriptions of the contact's
position and angle)."""
OUTPUT_COLUMNS = (*OUTPUT_FIELDS, "end_state", "status")
DERIVED_COLUMNS = ("exit_speed", "scattering_angle", "spin_axial", "spin")
COLUMNS = (*INPUT_COLUMNS, *OUTPUT_COLUMNS, *DERIVED_COLUMNS, "sample_id", "chunk")
"""All columns, in file order."""
MEASURED_SUFFIX = "_measured"

GAME_INPUT_COLUMNS = tuple(f for f in GAME_INPUT_FIELDS if f not in INPUT_COLUMNS)
"""The game inputs that are not bat-frame columns."""
GAME_OUTPUT_COLUMNS = tuple(f for f in GAME_OUTPUT_FIELDS if f not in INPUT_COLUMNS)
"""Collision efficiency and the field-frame velocities and spins."""
GAME_DERIVED_COLUMNS = ("launch_speed", "launch_angle", "spray_angle", "spin_rate",
                        "backspin", "sidespin", "gyrospin")
GAME_COLUMNS = (*INPUT_COLUMNS, *GAME_INPUT_COLUMNS, *OUTPUT_COLUMNS, *GAME_OUTPUT_COLUMNS,
                *DERIVED_COLUMNS, *GAME_DERIVED_COLUMNS, "sample_id", "chunk")
"""All columns of a game dataset, in file order."""
FLIGHT_COLUMNS = ("hit_distance", "hang_time", "apex", "landing_x", "landing_y",
                  "hit_distance_m", "apex_m", "landing_x_m", "landing_y_m", "flight_status")
"""The flight columns of a game dataset with a ``[flight]`` section (after
``GAME_COLUMNS``): Statcast's ft and s, then SI."""



def _statcast_factor(unit):
    quantity = "speed" if unit == "mph" else "spin" if unit == "rpm" else "angle"
    return study_units.UNITS[quantity][unit]


def statcast_units(cols):
    """``cols`` (a dict of SI arrays by name) with the columns of ``STATCAST_UNIT_INPUTS``
    replaced by new arrays in Statcast's units."""
    for name, unit in STATCAST_UNIT_INPUTS.items():
        if name in cols:
            cols[name] = np.asarray(cols[name], np.float64) / _statcast_factor(unit)
    return cols


def si_units(cols):
    """The inverse of ``statcast_units``: ``cols`` (a dict, or a dataset row as a
    mapping) with the columns of ``STATCAST_UNIT_INPUTS`` back in SI, e.g. to solve a
    game dataset's row again with ``mcbat.api.GameCase`` (which takes SI). Each value
    is one division and one multiplication away from the kernel's input: equal to it within
    a unit in the last place or two."""
    cols = dict(cols)
    for name, unit in STATCAST_UNIT_INPUTS.items():
        if name in cols:
            cols[name] = np.asarray(cols[name], np.float64) * _statcast_factor(unit)
    return cols
