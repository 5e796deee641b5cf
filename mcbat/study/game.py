"""Game studies: a pitch, a swing and a contact in the field frame (``docs/batting.md``).

A study file is a game study when it has a ``[pitch]``, ``[swing]`` or ``[pitches]``
section::

    handedness = "R"              # optional, "R" (default) or "L": the mirror image in x
    [study]  ...                  # as in every study
    [ball]   preset = "baseball"
    [bat]    preset = "r161"      # or mass, radius, length, cm_from_knob (or
                                  # cm_from_barrel_end), transverse_inertia, axial_inertia
    [pitch]                       # speed (required), vertical_approach_angle (0),
    speed = { value = 94, unit = "mph" }   # horizontal_approach_angle (0), spin_rate (0),
    spin_axis = { value = 180, unit = "deg" }  # spin_axis (180 deg), spin_efficiency (1),
                                  # gyro_sign (+1)
    [swing]                       # bat_speed (required), attack_angle (0),
    bat_speed = { value = 72, unit = "mph" }  # attack_direction (0), vertical_bat_angle
                                  # (0), pivot (6 in from the knob)
    [contact]                     # from_barrel_end (6 in), undercut (0)
    [contact.bat_speed_trend]     # optional: the contact moves with the bat speed
    reference = { value = 70, unit = "mph" }   # (mcbat.study.contact_moves), along the
    per = { value = 10, unit = "mph" }         # bat, under the ball's centre, or both
    from_barrel_end = { value = 1, unit = "in" }
    undercut = { value = 0.3, unit = "in" }
    [contact.plate_x_trend]       # optional, with [pitches]: the contact moves with where
    reference = { value = 2, unit = "in" }     # the pitch crosses the plate
    dead_zone = { value = 4, unit = "in" }     # (mcbat.study.contact_moves)
    per = { value = 1, unit = "ft" }
    from_barrel_end = { value = -8, unit = "in" }
    [contact.plate_z_trend]       # optional, with [pitches]: the undercut (and the bat's
    reference = { value = 2.5, unit = "ft" }   # angle, rows without a swing plane) move
    per = { value = 1, unit = "ft" }           # with the pitch's height
    undercut = { value = 0.4, unit = "in" }    # (mcbat.study.contact_moves)
    vertical_bat_angle = { value = 7, unit = "deg" }
    [contact.swing_length_trend]  # optional, with [pitches]: the undercut moves with the
                                  # measured swing_length (the height's keys, no bat angle)
    [friction]  mu = 0.5          # required
    [restitution]                 # optional; default: the game preset (mcbat.bodies.
                                  # restitution.GAME_RESTITUTION). e (constant) or e_ref,
                                  # e_slope, e_speed_ref; with either, location and e_x.

    [pitches]                     # optional: real pitches, resampled with replacement
    file = "statcast.parquet"     # (mcbat.study.pitches); then [pitch] and [swing] hold only
                                  # the keys not drawn from the rows, and handedness, if
                                  # given, replaces the batter's side of every row

Every numeric key takes a number or a distribution, with units, as in bat-frame studies.
Samples are the float64 columns of ``COLUMNS``, the inputs of
``mcbat.core.swing.solve_game_batch``; the contact's trends: ``mcbat.study.contact_moves``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from types import MappingProxyType

import numpy as np

from mcbat.bodies.restitution import GAME_RESTITUTION, LOCATION_TABLES, Restitution
from mcbat.checks import check_keys, check_string
from mcbat.errors import InputError
from mcbat.solving.names import GAME_INPUT_FIELDS, SWEET_SPOT_FROM_BARREL_END
from mcbat.solving.settings import SolverSettings
from mcbat.study import contact_moves as moves
from mcbat.study import units as u
from mcbat.study.dist_types import Normal, Uniform
from mcbat.study.distributions import check_range, parse
from mcbat.study.flight import parse_flight
from mcbat.study.game_keys import (
    GAME_SECTIONS,
    HANDEDNESS,
    KEYS,
    check_bat_angle_trend,
    check_sections,
    check_swing_angles,
    is_game,
    largest_magnitude,
    parse_handedness,
    parse_plate_x_trend,
    parse_plate_z_trend,
    parse_swing_length_trend,
    parse_trend,
)
from mcbat.study.impact import Study
from mcbat.study.pitches import (
    IDENTIFIERS,
    SWING_ERROR_STREAM,
    PitchRows,
    PitchTable,
    parse_pitches,
    select_rows,
)
from mcbat.study.player_levels import apply_player_contact, check_contact
from mcbat.study.random_program import draw_stream
from mcbat.study.sections import check_solver, fill_bodies, parse_ball, parse_bat
from mcbat.study.swing_errors import clip_true, outlier_population, true_values
from mcbat.study.swing_plane import fill_vertical_bat_angle
from mcbat.study.swing_shift import apply_swing_shift

__all__ = ["COLUMNS", "GAME_SECTIONS", "GameStudy", "KEYS", "is_game"]

#: Columns returned by ``GameStudy.sample``: the game kernel's inputs.
COLUMNS = GAME_INPUT_FIELDS
#: The ``[contact]`` tables that move each drawn contact, and the columns of the
#: ``[pitches]`` rows the last three follow.
CONTACT_TRENDS = ("bat_speed_trend", "plate_x_trend", "plate_z_trend", "swing_length_trend")
ROW_TRENDS = ("plate_x", "plate_z", "swing_length")


class GameStudy(Study):
    """A validated game study (see the module docstring). Sampling, overrides and the
    config hash work as for ``mcbat.study.impact.Study``."""

    kind = "game"
    marker_sections = ("pitch", "swing", "pitches")

    def _parse(self, data):
        check_sections(data)
        real = "pitches" in data
        self._parse_study_section(data["study"])
        self.pitches = parse_pitches(data["pitches"], self.source) if real else None
        self._pitch_rows = self._pitch_table = self._player_contact = None
        self._outlier_cache = {}
        # With real pitches and no handedness key, each row's batter side (None here).
        self.handedness = data.get("handedness", None if real else "R")
        if self.handedness is not None:
            parse_handedness(self.handedness)
        self.ball = parse_ball(data["ball"])
        self.bat = parse_bat(data["bat"])
        if self.bat.length is None or self.bat.cm_from_barrel_end is None:
            raise InputError("bat.length", "a game needs the bat's length and its CM "
                             "(cm_from_knob or cm_from_barrel_end), or a bat preset")
        self._solver = check_solver(data.get("solver", {}))
        self.flight = parse_flight(data["flight"]) if "flight" in data else None
        self._parse_output(data)
        self.noise = MappingProxyType({})
        self._axial_key, self._angle_key = "from_barrel_end", "undercut"

        inputs = {}
        location = None
        drawn = self.pitches.keys if real else {}
        self._parse_trends(data.get("contact", {}), real)
        for section, keys in KEYS.items():
            table = data.get(section, {})
            if section == "contact":
                table = {k: v for k, v in table.items()
                         if k not in CONTACT_TRENDS}
            optional = tuple(keys) + (("location",) if section == "restitution" else ())
            required = tuple(k for k, (_, default, _) in keys.items()
                             if default is None and section != "restitution"
                             and f"{section}.{k}" not in drawn)
            for key in table:
                if f"{section}.{key}" in drawn:
                    raise InputError(f"{section}.{key}", "drawn from the rows of [pitches]; "
                                     "a value for rows that lack it goes in "
                                     f"[pitches.fallback] ({key} = ...)")
            check_keys(table, section, required, optional)
            for key, spec in table.items():
                if key == "location":
                    location = check_string(spec, "restitution.location")
                    if location not in LOCATION_TABLES:
                        raise InputError("restitution.location", f"unknown table "
                                         f"{location!r} (expected one of: "
                                         f"{', '.join(LOCATION_TABLES)})")
                    continue
                inputs[f"{section}.{key}"] = parse(spec, f"{section}.{key}", keys[key][0])
        rest = data.get("restitution")
        if rest is None:
            self.restitution = GAME_RESTITUTION
        else:
            has_e, has_ref = "e" in rest, "e_ref" in rest
            if has_e == has_ref:
                raise InputError("restitution", "give exactly one of 'e' (a constant e*) "
                                 "or 'e_ref' (with e_slope and e_speed_ref)")
            if has_e and ("e_slope" in rest or "e_speed_ref" in rest):
                key = "e_slope" if "e_slope" in rest else "e_speed_ref"
                raise InputError(f"restitution.{key}", "only with 'e_ref', not with 'e'")
            self.restitution = Restitution(location=location)
        if real:
            inputs.update(self.pitches.fallback)
        self.inputs = MappingProxyType(inputs)
        self._check_ranges()
        if self.pitches is not None and self.pitches.player_levels is not None:
            check_contact(self.inputs)
        self._plan()

    def _parse_trends(self, contact, real) -> None:
        """The ``[contact]`` tables that move each drawn contact: with the bat speed, and
        (with ``[pitches]`` rows, ``real``) with the pitch's location."""
        self.contact_trend = parse_trend(contact.get("bat_speed_trend"))
        self.plate_x_trend = parse_plate_x_trend(contact.get("plate_x_trend"))
        self.plate_z_trend = parse_plate_z_trend(contact.get("plate_z_trend"))
        self.swing_length_trend = parse_swing_length_trend(contact.get("swing_length_trend"))
        for name in ROW_TRENDS:
            if getattr(self, f"{name}_trend") is not None and not real:
                raise InputError(f"contact.{name}_trend", f"needs the rows of [pitches] "
                                 f"(each row's {name}); a study without them has no "
                                 f"{name}")

    # ------------------------------------------------------------ real pitches

    def with_pitch_table(self, table: PitchTable) -> GameStudy:
        """A copy that draws its pitches from ``table`` (the rows of the ``[pitches]``
        file, read by ``mcbat.runner.pitches.load_pitches``): the filters and
        exclusions applied, ready to sample.

        Raises
        ------
        InputError
            A filter that selects no row (naming it), or no row left to draw from.
        """
        if self.pitches is None:
            raise ValueError("this study has no [pitches] section")
        try:
            rows = select_rows(self.pitches, table, self.handedness, self.inputs,
                               self.pitches.file, self.location_columns)
        except InputError as err:
            raise err.within(source=self.source) from None
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new._pitch_table, new._pitch_rows = table, rows
        new._outlier_cache, new._player_contact = {}, None
        return new

    def with_player_contact(self, spread, shift, summary=None) -> GameStudy:
        """A copy whose rows meet their players' own contact (``[pitches.player_levels]``,
        estimated by ``mcbat.runner.player_levels``): ``spread`` and ``shift`` (m), one per
        row drawn from (``mcbat.study.player_levels``); ``summary``: what the config records
        of the estimate."""
        m = self._need_rows().index.size
        spread, shift = (np.asarray(v, np.float64) for v in (spread, shift))
        if spread.shape != (m,) or shift.shape != (m,):
            raise ValueError(f"need one spread and one shift per row drawn from ({m})")
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new._player_contact = (spread, shift, dict(summary or {}))
        return new

    @property
    def player_contact(self) -> tuple | None:
        """``(spread, shift, summary)`` of the rows' players (None: the league's)."""
        return self._player_contact

    @property
    def pitch_table(self) -> PitchTable | None:
        """The ``[pitches]`` file's columns (None until loaded)."""
        return self._pitch_table

    @property
    def pitch_rows(self) -> PitchRows | None:
        """The rows drawn from (None: no ``[pitches]``, or the file not loaded yet)."""
        return self._pitch_rows

    def _need_rows(self) -> PitchRows:
        if self._pitch_rows is None:
            raise RuntimeError(f"the rows of {self.pitches.file} ([pitches]) are not "
                               "loaded: mcbat.runner.pitches.load_pitches(study) reads them")
        return self._pitch_rows

    def pitch_identifiers(self, start=0, stop=None, seed=None) -> dict[str, np.ndarray]:
        """The real pitch each of samples ``start .. stop - 1`` comes from: int64 columns
        ``mcbat.study.pitches.PITCH_SOURCE_COLUMNS`` (``source_row``: the row of the
        file, from 0, before any filter). Empty without ``[pitches]``."""
        if self.pitches is None:
            return {}
        rows = self._need_rows()
        stop = self.samples if stop is None else stop
        seed = self.seed if seed is None else seed
        j = rows.draw_rows(int(seed), int(start), int(stop) - int(start))
        out = {"source_row": rows.index[j]}
        out.update({name: rows.identifiers[k, j] for k, name in enumerate(IDENTIFIERS)})
        return out

    def _fill_pitches(self, cols, start, n, seed) -> dict:
        """Overwrite the drawn keys' columns with the sampled rows' values (where a row
        lacks one, the fallback drawn there stays), and the handedness from the rows.
        Returns the samples' values the trends need: ``{"away": plate_x away from the
        batter, "plate_z": ..., "swing_length": ...}`` (m), the keys the rows keep, and
        ``"row"``: each sample's index into the rows drawn from."""
        rows = self._need_rows()
        j = rows.draw_rows(seed, start, n)
        targets = {f"{s}.{k}": spec[2] for s, keys in KEYS.items() for k, spec in keys.items()}
        vertical = self.inputs.get("swing.vertical_bat_angle")
        support = vertical.support() if vertical is not None else None
        for k, key in enumerate(rows.keys):
            values = rows.values[k, j]
            column = cols[targets[key]]
            if key in self.pitches.fallback:
                np.copyto(column, values, where=np.isfinite(values))
            else:
                column[:] = values
            if self.pitches.swing_error.get(key, 0.0) > 0.0:
                # (a value drawn from the key's fallback is no measurement: left as drawn)
                self._true_swing(key, rows.values[k], column, (start, n, seed),
                                 np.isfinite(values), support)
        apply_swing_shift(cols, self.pitches.swing_shift, targets, support)
        if self.plate_z_trend is not None and self.plate_z_trend[2] != 0.0:
            moves.bat_angle_move(cols["vertical_bat_angle"], rows.location["plate_z"][j],
                                 self.plate_z_trend, support)
        if rows.tilt is not None:  # (after the attack angle's true value is drawn)
            fill_vertical_bat_angle(cols, rows.tilt[j])
        if rows.handedness is not None:
            cols["handedness"][:] = rows.handedness[j]
        location = {"row": j}
        if "plate_x" in rows.location:
            # the batter stands on the side away from which "away" counts: a right-handed
            # batter (handedness +1) on the third-base side, so away is +x for him
            location["away"] = rows.location["plate_x"][j] * cols["handedness"]
        for name in ("plate_z", "swing_length"):
            if name in rows.location:
                location[name] = rows.location[name][j]
        return location

    def _true_swing(self, key, measured, column, draws, where, support) -> None:
        """Replace the measured values of swing key ``key`` in ``column`` (where ``where``;
        the others took the key's fallback) by draws of the true values given them
        (``mcbat.study.swing_errors``; ``measured``: the selected rows' values, SI;
        ``draws``: ``(start, n, seed)``; ``support``: the vertical bat angle's, or None)."""
        s = self.pitches.swing_error[key]
        start, n, seed = draws
        finite = measured[np.isfinite(measured)]
        if not finite.size:  # (every row took the key's fallback: nothing was measured)
            return
        name = f"{SWING_ERROR_STREAM}.{key.split('.', 1)[1]}"
        z = draw_stream(name, Normal(name, u.DIMENSIONLESS, None, mean=0.0, std=1.0,
                                     raw={"mean": 0, "std": 1}), seed, start, n)
        outliers = self.pitches.bat_speed_outliers if key == "swing.bat_speed" else None
        pick = population = None
        if outliers and outliers[0] > 0.0:
            label = f"{name}.outlier"
            pick = draw_stream(label, Uniform(label, u.DIMENSIONLESS, None, low=0.0, high=1.0,
                                              raw={"low": 0, "high": 1}), seed, start, n)
            cache_key = (id(self._pitch_rows), key, s, outliers)
            if self._outlier_cache.get("key") != cache_key:
                # (the deconvolved population is the same for every chunk of the rows)
                self._outlier_cache.update(key=cache_key, population=outlier_population(
                    finite, s, outliers))
            population = self._outlier_cache["population"]
        true = true_values(column, finite, s, z, outliers, pick, population)
        true = clip_true(key, true, support)
        np.copyto(column, true, where=where)

    def _check_ranges(self):
        inp, bat = self.inputs, self.bat
        right = math.pi / 2.0
        check_bat_angle_trend(self.plate_z_trend, inp.get("swing.vertical_bat_angle"))

        def need(key, **kw):
            if key in inp:
                check_range(inp[key], **kw)

        need("pitch.speed", minimum=0.0, strict_minimum=True, what="the pitch speed")
        for key in ("pitch.vertical_approach_angle", "pitch.horizontal_approach_angle"):
            need(key, minimum=-right, maximum=right, strict_minimum=True, strict_maximum=True,
                 what="an approach angle (a pitch moving towards the plate)")
        need("pitch.spin_rate", minimum=0.0, what="the spin rate")
        need("pitch.spin_efficiency", minimum=0.0, maximum=1.0, what="the spin efficiency")
        if "pitch.gyro_sign" in inp:
            dist = inp["pitch.gyro_sign"]
            if dist.family != "fixed" or dist.value not in (1.0, -1.0):
                raise InputError("pitch.gyro_sign", "must be a fixed +1 or -1")
        need("swing.bat_speed", minimum=0.0, what="the bat speed")
        for key in ("swing.attack_angle", "swing.attack_direction",
                    "swing.vertical_bat_angle"):
            need(key, minimum=-right, maximum=right, strict_minimum=True, strict_maximum=True,
                 what="a swing angle")
        if "swing.attack_angle" in inp and "swing.vertical_bat_angle" in inp:
            check_swing_angles(largest_magnitude(inp["swing.attack_angle"]),
                               largest_magnitude(inp["swing.vertical_bat_angle"]))
        sweet_from_knob = bat.length - SWEET_SPOT_FROM_BARREL_END
        need("swing.pivot", minimum=0.0, maximum=sweet_from_knob, strict_maximum=True,
             what="the pivot (from the knob, short of the sweet spot)")
        need("contact.from_barrel_end", minimum=0.0, maximum=bat.length + 1e-12,
             what="the contact's distance from the barrel end (on the bat)")
        d_low, d_high = (inp["contact.from_barrel_end"].support()
                         if "contact.from_barrel_end" in inp
                         else (SWEET_SPOT_FROM_BARREL_END,) * 2)
        reach = bat.min_reach(self.ball.radius, bat.axial_from_barrel_end(d_high),
                              bat.axial_from_barrel_end(d_low))
        need("contact.undercut", minimum=-reach, maximum=reach,
             what="the undercut (within the reach r + R of barrel and ball; beyond it the "
                  "ball misses)")
        need("friction.mu", minimum=0.0, what="mu")
        for key in ("restitution.e", "restitution.e_ref", "restitution.e_x"):
            need(key, minimum=0.0, maximum=1.0, what=key.split(".")[1])
        need("restitution.e_speed_ref", minimum=0.0, what="e_speed_ref")

    def config(self) -> dict:
        """As ``Study.config``, with ``kind = "game"``, the handedness and the
        restitution's form."""
        out = super().config()
        out.update(kind="game",
                   handedness=self.handedness if self.handedness is not None else "rows",
                   restitution=self.restitution.config()
                   if any(k.startswith("restitution.") for k in self.inputs)
                   else {"preset": "game", **GAME_RESTITUTION.config()})
        out["contact"] = {"position": "from_barrel_end", "offset": "undercut",
                          **moves.trends_config(self)}
        if self.flight is not None:
            out["flight"] = self.flight.config()
        if self.pitches is not None:
            # The file's content hash, the filters and the selection: a changed file is a
            # different study (never resumed into the old dataset).
            out["pitches"] = self._need_rows().config(self.pitches, self._pitch_table)
            if self._player_contact is not None:
                out["pitches"]["player_levels"].update(self._player_contact[2])
        return out

    def definition(self) -> dict:
        """As ``Study.definition``, with the ``[pitches]`` file as an absolute path
        (a Dask worker rebuilds the study without the study file's directory)."""
        data = super().definition()
        if self.pitches is not None:
            data["pitches"]["file"] = str(self.pitches.path)
        return data

    def sample(self, start=0, stop=None, seed=None) -> dict[str, np.ndarray]:
        """Game-kernel inputs of samples ``start .. stop - 1`` (``COLUMNS``, SI), as
        views of the rows of ``sample_inputs``."""
        table = self.sample_inputs(start, stop, seed)
        return {name: table[i] for i, name in enumerate(COLUMNS)}

    def sample_inputs(self, start=0, stop=None, seed=None) -> np.ndarray:
        """The game kernel's input array of samples ``start .. stop - 1``:
        ``float64[len(COLUMNS), n]``, one row per column of ``COLUMNS`` (SI)."""
        stop = self.samples if stop is None else stop
        seed = self.seed if seed is None else seed
        for label, value in (("start", start), ("stop", stop), ("seed", seed)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise TypeError(f"{label} must be an integer, got {value!r}")
        if not 0 <= start <= stop:
            raise ValueError(f"need 0 <= start <= stop, got start={start}, stop={stop}")
        start, stop, seed = int(start), int(stop), int(seed)
        n = stop - start
        table = np.empty((len(COLUMNS), n))
        cols = {name: table[i] for i, name in enumerate(COLUMNS)}
        if n == 0:
            return table
        targets = {f"{s}.{k}": spec[2] for s, keys in KEYS.items() for k, spec in keys.items()}
        row = {name: i for i, name in enumerate(COLUMNS)}
        self._draw(start, stop, seed, table, {name: row[targets[name]] for name in self.inputs})
        defaults = {spec[2]: spec[1] for keys in KEYS.values() for spec in keys.values()
                    if spec[1] is not None}
        rest = (GAME_RESTITUTION if not any(k.startswith("restitution.") for k in self.inputs)
                else None)
        if rest is not None:
            defaults.update(e_ref=rest.e_ref, e_slope=rest.e_slope,
                            e_speed_ref=rest.e_speed_ref, e_x=rest.e_x)
        drawn = {targets[name] for name in self.inputs}
        for column, value in defaults.items():
            if column not in drawn:
                cols[column][:] = value
        ball, bat = self.ball, self.bat
        fill_bodies(cols, ball, bat)
        cols["bat_length"][:] = bat.length
        cols["bat_cm_from_knob"][:] = bat.length - bat.cm_from_barrel_end
        if self.handedness is not None:
            cols["handedness"][:] = HANDEDNESS[self.handedness]
        location = {}
        if self.pitches is not None:
            location = self._fill_pitches(cols, start, n, seed)
        if self._player_contact is not None:
            apply_player_contact(cols, location["row"], self._player_contact, self.inputs)
        if self.contact_trend is not None or self.plate_x_trend is not None:
            moves.move_contact(self, cols, location.get("away"))
        if (self.plate_z_trend is not None or self.contact_trend is not None
                or self.swing_length_trend is not None):
            moves.move_undercut(self, cols, location)
        self.fill_contact(cols)
        return table

    @property
    def solver_settings(self) -> SolverSettings:
        """The ``[solver]`` table as the kernels take it, with the flight integrator's
        tolerance (``[flight] tolerance``) where the study flies its balls."""
        settings = super().solver_settings
        return settings if self.flight is None else replace(
            settings, flight_tolerance=self.flight.tolerance)

    @property
    def location_columns(self) -> tuple:
        """The columns its trends need from the ``[pitches]`` rows (the pitch's location,
        the swing's length)."""
        return tuple(name for name in ROW_TRENDS
                     if getattr(self, f"{name}_trend") is not None)

    def fill_contact(self, cols):
        """Write the columns that follow from the contact's place on the bat: the barrel's
        ``bat_radius`` and ``bat_slope`` there and the restitution's ``e_location_factor``,
        from ``cols["from_barrel_end"]`` (``cols``: column name -> float64 array, as the
        rows of ``sample_inputs``; a fit that measures ``from_barrel_end`` per row
        calls it after setting that column)."""
        bat = self.bat
        axial = bat.clip_axial(bat.axial_from_barrel_end(cols["from_barrel_end"]))
        cols["bat_radius"][:], cols["bat_slope"][:] = bat.surface(axial)
        own = any(k.startswith("restitution.") for k in self.inputs)
        location = (self.restitution if own else GAME_RESTITUTION).location
        cols["e_location_factor"][:] = Restitution(location=location).location_factor(
            cols["from_barrel_end"])
