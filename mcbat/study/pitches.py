"""Real pitches: a game study's pitch (and swing) drawn from the rows of a Statcast table.

A game study with a ``[pitches]`` section resamples real pitches with replacement::

    [pitches]
    file = "../data/statcast_example.parquet"  # relative to the study file: mcbat's tidy
                                               # table (.parquet or .csv) or a Savant CSV
    pitch_type = ["FF", "SI"]                  # filters, each one value or a list:
    p_throws = "R"                             #   pitch_type, p_throws, pitcher, batter,
    game_year = 2024                           #   game_year, bb_type (balls in play:
                                               #   ground_ball, line_drive, fly_ball, popup)
    swing = true                               # also bat_speed, attack_angle and
                                               # attack_direction from the rows (default false)
    swing_plane = true                         # with swing: the vertical bat angle from
                                               # swing_path_tilt (default false)
    [pitches.fallback]                         # for rows that lack a value: a number or a
    spin_axis = { dist = "uniform", low = 180, high = 240, unit = "deg" }  # distribution
    [pitches.swing_error]                      # with swing = true: the measurement error
    attack_angle = { value = 4, unit = "deg" } # (sd) of a drawn swing key (below)
    [pitches.swing_shift]                      # with swing = true, a what-if: added to
    bat_speed = { value = 2, unit = "mph" }    # every drawn swing (mcbat.study.swing_shift)
    [pitches.player_levels]                    # with swing = true: each batter's and
    batter_launch_speed = ...                  # pitcher's own contact, from his other
                                               # games (mcbat.study.player_levels)

The drawn keys are ``PITCH_KEYS`` (and ``SWING_KEYS`` with ``swing = true``); ``[pitch]``
and ``[swing]`` then hold only the other keys (spin efficiency, vertical bat angle, ...),
drawn from their distributions as always. With ``swing_plane = true`` a row's measured
``swing_path_tilt`` and its attack angle set its vertical bat angle
(``mcbat.study.swing_plane``); rows without a tilt keep ``[swing] vertical_bat_angle``. A
row that lacks a drawn value (NaN: older exports have no spin axis, bat tracking starts in
2024, a pitch not swung at) takes the key's fallback when ``[pitches.fallback]`` has one;
otherwise it is left out of the draw and counted. Rows with values outside the ranges of
``ROW_RANGES`` (those a study's own values are checked against, and at most what was ever
measured: pitch and bat speeds up to 150 mph, spins up to 10,000 rpm) are left out and
counted too, and so are the copies of a pitch the file gives twice (the same ``game_pk``,
``at_bat_number`` and ``pitch_number``: two overlapping downloads concatenated), flagged by
the runner in ``DUPLICATE_COLUMN``.

**Swing measurement error** (``[pitches.swing_error]``, with ``swing = true``): a drawn
swing key measured with a Gaussian error of sd ``s`` is replaced by a draw of the true value
given the measured one (``z`` a standard normal of stream ``"pitches.swing_error.<key>"``;
with ``[pitches.swing_error.bat_speed_outliers]`` a share of the bat speeds measured far too
fast), as ``mcbat.study.swing_errors`` describes; ``s = 0`` leaves the measured values.

This module knows only plain numpy columns: reading the file (pandas, pyarrow, the Savant
reader) is the runner's (``mcbat.runner.pitches``), which hands a ``PitchTable`` to
``mcbat.study.game.GameStudy.with_pitch_table``. Until then the study is valid but
cannot be sampled.

Sampling: sample ``i`` takes selected row ``floor(u * M)`` (``M`` selected rows), ``u`` the
Philox uniform of stream ``"pitches.row"`` for sample ``i``, like every random input of a
study (``mcbat.core.sampling``): the draw depends on the seed, the sample index and the
selection alone, not on threads, chunks, engine or resumption.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from mcbat.checks import check_keys, integer
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.distributions import Uniform, parse
from mcbat.study.pitch_messages import present, what_would_help
from mcbat.study.player_levels import PlayerLevels, parse_player_levels
from mcbat.study.random_program import draw_stream
from mcbat.study.swing_errors import parse_swing_errors
from mcbat.study.swing_plane import measured_tilt, parse_swing_plane
from mcbat.study.swing_shift import parse_swing_shift

__all__ = ["BUNT_COLUMN", "DUPLICATE_COLUMN", "FILTERS", "IDENTIFIERS", "PITCH_KEYS",
           "PITCH_SOURCE_COLUMNS", "ROW_RANGES", "ROW_STREAM", "SWING_ERROR_STREAM",
           "SWING_KEYS", "TABLE_UNITS", "TILT_COLUMN", "PitchRows", "PitchSource",
           "PitchTable", "parse_pitches"]

#: Study keys of ``[pitch]`` drawn from the rows -> the tidy table's column.
PITCH_KEYS = {"speed": "pitch_speed",
              "vertical_approach_angle": "vertical_approach_angle",
              "horizontal_approach_angle": "horizontal_approach_angle",
              "spin_rate": "spin_rate", "spin_axis": "spin_axis"}
#: Study keys of ``[swing]`` drawn from the rows with ``swing = true`` (bat tracking).
SWING_KEYS = {"bat_speed": "bat_speed", "attack_angle": "attack_angle",
              "attack_direction": "attack_direction"}
#: Units of the tidy table's numeric columns (Statcast's): quantity and unit.
TABLE_UNITS = {"pitch_speed": (u.SPEED, "mph"), "vertical_approach_angle": (u.ANGLE, "deg"),
               "horizontal_approach_angle": (u.ANGLE, "deg"), "spin_rate": (u.SPIN, "rpm"),
               "spin_axis": (u.ANGLE, "deg"), "bat_speed": (u.SPEED, "mph"),
               "attack_angle": (u.ANGLE, "deg"), "attack_direction": (u.ANGLE, "deg")}
#: The identifiers of a pitch, copied into the dataset.
IDENTIFIERS = ("game_pk", "at_bat_number", "pitch_number", "pitcher", "batter")
#: The dataset columns that trace a row to its real pitch: the row of the file (from 0,
#: in the file's order, before any filter) and the pitch's identifiers.
PITCH_SOURCE_COLUMNS = ("source_row", *IDENTIFIERS)
#: Filters: key -> the type of its values (``bb_type``: Statcast's batted-ball type, which
#: only balls in play have).
FILTERS = {"pitch_type": str, "p_throws": str, "pitcher": int, "batter": int,
           "game_year": int, "bb_type": str}
#: Column of a ``PitchTable`` flagging bunts (1.0) with ``swing = true``: left out.
BUNT_COLUMN = "bunt"
#: Column of a ``PitchTable`` flagging (1.0) a row that repeats an earlier pitch: left
#: out and counted as "duplicate pitches".
DUPLICATE_COLUMN = "duplicate"
#: The largest value a drawn key may take, in the table's unit (beyond: the row is left
#: out): the fastest pitch measured is near 106 mph, the fastest swing near 90 mph, the
#: highest spin near 3,800 rpm. With the signs and angle limits of ``_in_range``.
ROW_RANGES = {"pitch.speed": (150.0, "mph"), "swing.bat_speed": (150.0, "mph"),
              "pitch.spin_rate": (10_000.0, "rpm"), "pitch.spin_axis": (720.0, "deg")}
#: The tidy column of the swing plane's tilt (``[pitches] swing_plane``).
TILT_COLUMN = "swing_path_tilt"
#: The Philox stream of the row draw (as an input named so; no study key has the name).
ROW_STREAM = "pitches.row"

#: The Philox stream prefix of the swing measurement errors' draws (+ ".<key>").
SWING_ERROR_STREAM = "pitches.swing_error"

_HAND = {"R": 1.0, "L": -1.0}
_RIGHT_ANGLE = math.pi / 2.0


def _study_key(key):
    """``"speed"`` -> ``"pitch.speed"``, ``"bat_speed"`` -> ``"swing.bat_speed"``."""
    return f"pitch.{key}" if key in PITCH_KEYS else f"swing.{key}"


@dataclass(frozen=True)
class PitchSource:
    """The validated ``[pitches]`` section (no rows yet).

    Attributes
    ----------
    file : str
        The file as written.
    path : Path
        The file, resolved against the study file's directory (the working directory for
        a study without a file).
    filters : mapping
        Filter key -> tuple of accepted values, in ``FILTERS`` order.
    swing : bool
        Draw ``SWING_KEYS`` from the rows too.
    fallback : mapping
        Study input name (``"pitch.spin_axis"``) -> its fallback distribution.
    swing_error : mapping
        Study input name (``"swing.attack_angle"``) -> the sd of its measurement error
        (SI: m/s or rad); empty without ``[pitches.swing_error]``.
    bat_speed_outliers : tuple or None
        ``(fraction, excess m/s, spread m/s)`` of ``[pitches.swing_error.bat_speed_outliers]``:
        the share of bat speeds measured ``excess`` too fast (with sd ``spread``).
    swing_plane : bool
        Each row's vertical bat angle from its ``swing_path_tilt``
        (``mcbat.study.swing_plane``).
    swing_shift : mapping
        Study input name -> the amount added to every drawn swing's value (SI), a what-if
        (``mcbat.study.swing_shift``); empty without ``[pitches.swing_shift]``.
    player_levels : PlayerLevels or None
        ``[pitches.player_levels]`` (``mcbat.study.player_levels``).
    """

    file: str
    path: Path
    filters: MappingProxyType
    swing: bool
    fallback: MappingProxyType
    swing_error: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    bat_speed_outliers: tuple | None = None
    swing_plane: bool = False
    swing_shift: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    player_levels: PlayerLevels | None = None

    @property
    def keys(self) -> dict:
        """The drawn study keys (``"pitch.speed"``, ...) -> the table's column."""
        keys = {f"pitch.{k}": c for k, c in PITCH_KEYS.items()}
        if self.swing:
            keys.update({f"swing.{k}": c for k, c in SWING_KEYS.items()})
        return keys

    def needed_columns(self, handedness_from_rows: bool, location=()) -> tuple:
        """The table columns the study reads (``location``: ``"plate_x"``, ``"plate_z"``,
        where the contact follows the pitch's location, ``[contact.plate_x_trend]``,
        ``[contact.plate_z_trend]``)."""
        names = [*self.keys.values(), *IDENTIFIERS, *self.filters]
        if self.swing_plane:
            names.append(TILT_COLUMN)
        if handedness_from_rows:
            names.append("handedness")
        names.extend(location)
        return tuple(dict.fromkeys(names))


def parse_pitches(table, source) -> PitchSource:
    """Validate a ``[pitches]`` section; ``source`` is the study file (or None)."""
    check_keys(table, "pitches", ("file",),
               (*FILTERS, "swing", "swing_plane", "fallback", "swing_error", "swing_shift",
                "player_levels"))
    quantities = {k: TABLE_UNITS[c][0] for k, c in SWING_KEYS.items()}
    file = table["file"]
    if not isinstance(file, str) or not file.strip():
        raise InputError("pitches.file", f"must be a file name (a string), got {file!r}")
    path = Path(file).expanduser()
    if not path.is_absolute():
        base = Path(source).parent if source else Path.cwd()
        path = base / path
    path = Path(os.path.abspath(path))
    swing = table.get("swing", False)
    if not isinstance(swing, bool):
        raise InputError("pitches.swing", f"must be true or false, got {swing!r}")
    swing_plane = parse_swing_plane(table, swing)
    filters = {}
    for key, kind in FILTERS.items():
        if key in table:
            filters[key] = _filter_values(table[key], f"pitches.{key}", kind)
    fallback_table = table.get("fallback", {})
    allowed = (*PITCH_KEYS, *(SWING_KEYS if swing else ()))
    if not isinstance(fallback_table, dict):
        raise InputError("pitches.fallback", f"must be a table ([pitches.fallback]), got "
                         f"{fallback_table!r}")
    if not swing:
        for key in fallback_table:
            if key in SWING_KEYS:
                raise InputError(f"pitches.fallback.{key}", "only with pitches.swing = true "
                                 f"(without it, {key} is a key of [swing])")
    check_keys(fallback_table, "pitches.fallback", (), allowed)
    fallback = {}
    for key, spec in fallback_table.items():
        quantity = TABLE_UNITS[{**PITCH_KEYS, **SWING_KEYS}[key]][0]
        fallback[_study_key(key)] = parse(spec, f"pitches.fallback.{key}", quantity)
    return PitchSource(file, path, MappingProxyType(filters), swing,
                       MappingProxyType(fallback),
                       *parse_swing_errors(table, swing, quantities), swing_plane,
                       parse_swing_shift(table, swing, quantities),
                       parse_player_levels(table, swing))


def _filter_values(value, name, kind) -> tuple:
    """A filter's accepted values: one value or a non-empty list, all of ``kind``."""
    values = value if isinstance(value, list) else [value]
    if not values:
        raise InputError(name, "must not be an empty list")
    out = []
    for i, item in enumerate(values):
        where = name if not isinstance(value, list) else f"{name}[{i}]"
        if kind is str:
            if not isinstance(item, str) or not item:
                raise InputError(where, f"must be a non-empty string, got {item!r}")
            if name.endswith("p_throws") and item not in _HAND:
                raise InputError(where, f'must be "R" or "L", got {item!r}')
            out.append(item)
        else:
            out.append(integer(item, where, minimum=0))
    return tuple(dict.fromkeys(out))


@dataclass(frozen=True)
class PitchTable:
    """A Statcast table as plain numpy columns (what the runner reads from the file).

    Attributes
    ----------
    columns : mapping
        Column name -> 1-d array, every one of length ``rows``, in the tidy table's
        units (``TABLE_UNITS``): float64 for the measured values (NaN where missing),
        float64 for identifiers and ``game_year`` (NaN where missing; integers otherwise),
        ``str`` objects for ``pitch_type``, ``p_throws`` and ``handedness`` (``""`` where
        missing).
    rows : int
        Rows of the file.
    sha256 : str
        SHA-256 (hex) of the file's bytes: part of the study's identity.
    name : str
        The file's name, for messages and the study's config.
    """

    columns: dict
    rows: int
    sha256: str
    name: str


@dataclass(frozen=True)
class PitchRows:
    """The rows a study draws from: its filters and exclusions applied to a
    ``PitchTable``.

    Attributes
    ----------
    index : int64[M]
        The selected rows of the file.
    values : float64[k, M]
        The drawn keys' values (SI; NaN where the key's fallback applies), one row per key
        of ``keys``.
    keys : tuple of str
        Study input names (``"pitch.speed"``, ...), the rows of ``values``.
    handedness : float64[M] or None
        +1 (R) / -1 (L) from the batter's side, or None when the study fixes it.
    identifiers : int64[5, M]
        ``IDENTIFIERS`` of the selected rows.
    summary : dict
        Rows in the file, selected by the filters, left out (reason -> count), drawn from.
    location : mapping
        Where each pitch crossed the front of the plate, as the study asked for it:
        ``"plate_x"`` (m along the field's ``x``, towards first base) and ``"plate_z"`` (m
        above the ground), Statcast's, float64[M], NaN where the file lacks a value.
    tilt : float64[M] or None
        With ``swing_plane``: the swing plane's measured tilt (rad; NaN where the row has
        none, or a vertical plane).
    """

    index: np.ndarray
    values: np.ndarray
    keys: tuple
    handedness: np.ndarray | None
    identifiers: np.ndarray
    summary: dict = field(default_factory=dict)
    location: dict = field(default_factory=dict)
    tilt: np.ndarray | None = None

    def config(self, source: PitchSource, table: PitchTable) -> dict:
        """The identity of the rows for the study's config: the file's content hash, the
        filters, the drawn keys and what was selected."""
        return {"file": table.name, "sha256": table.sha256,
                "filters": {k: list(v) for k, v in source.filters.items()},
                "swing": source.swing, "keys": list(self.keys),
                "fallback": sorted(source.fallback),
                **({"swing_error": dict(source.swing_error)} if source.swing_error else {}),
                **({"bat_speed_outliers": dict(zip(("fraction", "excess", "spread"),
                                                   source.bat_speed_outliers))}
                   if source.bat_speed_outliers else {}),
                **({"swing_plane": True} if source.swing_plane else {}),
                **({"swing_shift": dict(source.swing_shift)} if source.swing_shift else {}),
                **({"player_levels": source.player_levels.config()}
                   if source.player_levels else {}),
                "handedness": "rows" if self.handedness is not None else "study",
                "draw": f"row = floor(u M), u the Philox uniform of stream {ROW_STREAM!r}",
                **self.summary}

    def draw_rows(self, seed: int, start: int, n: int) -> np.ndarray:
        """Indices into the selection (0 .. M - 1) of samples ``start .. start + n - 1``."""
        m = self.index.size
        dist = Uniform(ROW_STREAM, u.DIMENSIONLESS, None, low=0.0, high=float(m),
                       raw={"low": 0, "high": m})
        # u < 1, but u M may round up to M: the last row then.
        return np.minimum(draw_stream(ROW_STREAM, dist, seed, start, n).astype(np.int64),
                          m - 1)


def select_rows(source: PitchSource, table: PitchTable, fixed_handedness, inputs,
                where, location=()) -> PitchRows:
    """Apply ``source``'s filters to ``table``, leave out (and count) the rows that lack a
    value without a fallback or hold one outside the physical range, and convert the drawn
    values to SI.

    Parameters
    ----------
    fixed_handedness : str or None
        The study's ``handedness``; None: from the rows' batter side.
    inputs : mapping
        The study's other inputs (``swing.vertical_bat_angle`` bounds the attack angles).
    where : str
        The file as the study names it, for messages.
    location : sequence of str
        The columns of the pitch's location to keep (``"plate_x"``, ``"plate_z"``:
        ``PitchRows.location``).

    Raises
    ------
    InputError
        On ``pitches.<filter>`` when a filter leaves no row, on ``pitches`` when the
        exclusions leave none.
    """
    cols = table.columns
    mask = np.ones(table.rows, bool)
    for key, accepted in source.filters.items():
        column = cols[key]
        if FILTERS[key] is int:
            hit = np.isin(column, np.asarray(accepted, np.float64))
        else:
            hit = np.isin(column, np.asarray(accepted, object))
        before = mask.copy()
        mask &= hit
        if not mask.any():
            shown = accepted[0] if len(accepted) == 1 else list(accepted)
            count = int(before.sum())
            context = ("" if count == table.rows else
                       f" among the {count:,} rows the filters before it select")
            which = "those rows have" if context else "the file has"
            raise InputError(f"pitches.{key}", f"selects no row of {where}: no {key} "
                             f"= {shown!r}{context}; {which} {key} "
                             f"{present(column[before])}")
    selected = int(mask.sum())
    # (a file of the seasons before bat tracking: no selected row has a bat speed)
    untracked = source.swing and "bat_speed" in cols and not np.isfinite(
        np.asarray(cols["bat_speed"], np.float64)[mask]).any()
    excluded = {}

    def leave_out(bad, reason):
        bad = bad & mask
        count = int(bad.sum())
        if count:
            excluded[reason] = excluded.get(reason, 0) + count
            mask[bad] = False

    for name in IDENTIFIERS:
        leave_out(~np.isfinite(cols[name]), f"without {name}")
    if DUPLICATE_COLUMN in cols:
        leave_out(np.asarray(cols[DUPLICATE_COLUMN]) > 0.0, "duplicate pitches")
    if source.swing and BUNT_COLUMN in cols:
        leave_out(np.asarray(cols[BUNT_COLUMN]) > 0.0, "bunts")
    handedness = None
    if fixed_handedness is None:
        side = cols["handedness"]
        leave_out(~np.isin(side, np.asarray(["R", "L"], object)),
                  "without the batter's side (stand)")
    keys = tuple(source.keys)
    si = {}
    for key in keys:
        column = source.keys[key]
        quantity, unit = TABLE_UNITS[column]
        values = np.asarray(cols[column], np.float64) * u.UNITS[quantity][unit]
        missing = ~np.isfinite(values)
        if key not in source.fallback:
            leave_out(missing, f"without {column}")
        leave_out(~missing & ~_in_range(key, values, inputs), f"{column} out of range")
        si[key] = values
    if not mask.any():
        reasons = ", ".join(f"{n:,} {r}" for r, n in excluded.items())
        raise InputError("pitches", f"no row of {where} is left to draw from: of the "
                         f"{selected:,} rows the filters select, {reasons}"
                         f"{what_would_help(source, keys, excluded, untracked)}")
    index = np.flatnonzero(mask).astype(np.int64)
    if fixed_handedness is None:
        handedness = np.where(cols["handedness"][index] == "R", 1.0, -1.0)
    values = np.stack([si[k][index] for k in keys]) if keys else np.zeros((0, index.size))
    identifiers = np.stack([cols[n][index].astype(np.int64) for n in IDENTIFIERS])
    summary = {"rows_in_file": table.rows, "selected": selected, "excluded": excluded,
               "drawn_from": int(index.size)}
    kept = {name: np.asarray(cols[name], np.float64)[index] * u.UNITS["length"]["ft"]
            for name in location}
    tilt = None
    if source.swing_plane:
        tilt = measured_tilt(cols[TILT_COLUMN], index)
        summary["swing_plane_measured"] = int(np.isfinite(tilt).sum())
    return PitchRows(index, values, keys, handedness, identifiers, summary, kept, tilt)


def _in_range(key, values, inputs) -> np.ndarray:
    """Rows whose value of ``key`` (SI) lies where the study's range checks put it."""
    with np.errstate(invalid="ignore"):
        if key in ROW_RANGES:
            most, unit = ROW_RANGES[key]
            quantity = TABLE_UNITS[{**PITCH_KEYS, **SWING_KEYS}[key.split(".")[1]]][0]
            below = np.abs(values) <= most * u.UNITS[quantity][unit]
        if key == "pitch.speed":
            return (values > 0.0) & below
        if key in ("pitch.spin_rate", "swing.bat_speed"):
            return (values >= 0.0) & below
        if key == "pitch.spin_axis":
            return np.isfinite(values) & below
        ok = np.abs(values) < _RIGHT_ANGLE
        if key == "swing.attack_angle":
            # The bat axis must be perpendicular to the sweet spot's velocity:
            # |tan(attack) tan(vertical_bat_angle)| < 1 for every vertical bat angle drawn.
            vertical = inputs.get("swing.vertical_bat_angle")
            if vertical is not None:
                low, high = vertical.support()
                largest = max(abs(low), abs(high))
                ok &= np.abs(np.tan(values)) * math.tan(largest) < 1.0 - 1e-9
        return ok
