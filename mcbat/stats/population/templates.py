"""The simulated side of a population fit (``mcbat.stats.population.fit``): the study
rewritten to meet the table's own pitches, its draws solved (and, for ``hit_distance``,
flown) in this process or on an engine, and simulated tables for injection tests."""

from __future__ import annotations

import copy
import tempfile
from pathlib import Path

import numpy as np

from mcbat.bodies.restitution import GAME_RESTITUTION
from mcbat.core.status import ImpactStatus
from mcbat.errors import InputError
from mcbat.solving import FLIGHT_FIELDS, GAME_INPUT_FIELDS, FlightStatus, solve_and_fly
from mcbat.solving.derived import derive_game
from mcbat.stats.models.simulate import solve_game_inputs
from mcbat.stats.population.parameters import PHYSICS, parse_free
from mcbat.stats.population.table import (
    FLIGHT_OBSERVABLES,
    MEASURED_NAMES,
    OBSERVABLES,
    PITCH_COLUMNS,
    SWING_COLUMNS,
    write_pitches,
)
from mcbat.study import units as u
from mcbat.study.game_keys import KEYS
from mcbat.study.spec import Study

__all__ = ["ENGINES", "TemplateSimulator", "simulate_table"]

ENGINES = ("memory", "local", "dask")
#: The drawn inputs a trend of ``[contact]`` may move after the draw.
MOVED_COLUMNS = ("from_barrel_end", "undercut", "vertical_bat_angle")


class TemplateSimulator:
    """The study rewritten for the table (its pitches, proposals, physics nodes), solved
    on an engine; returns the draws' free-key columns and observables. With ``flight``
    the study's ``[flight]`` is kept and every draw is flown (``hit_distance``)."""

    def __init__(self, study, table, draws, seed, engine, workdir, flight=False):
        if engine not in ENGINES:
            raise InputError("engine", f"must be one of {', '.join(ENGINES)}, got {engine!r}")
        self.draws, self.seed, self.engine = draws, seed, engine
        self._tmp = tempfile.TemporaryDirectory(prefix="mcbat-population-")
        self.workdir = Path(workdir) if workdir is not None else Path(self._tmp.name)
        self.workdir.mkdir(parents=True, exist_ok=True)
        pitches = self.workdir / "pitches.csv"
        write_pitches(table, pitches)
        self.base = _conditioned_definition(study, pitches, flight)
        self.source = study.source
        self.runs = 0

    def run(self, proposal, physics, columns, observables):
        """Draws of the study with the free keys' ``proposal`` ({key: (FreeKey, mean, std)})
        and ``physics`` ({name: value}): ``(inputs, observed, ok)``."""
        data = copy.deepcopy(self.base)
        for key, (k, mean, std) in proposal.items():
            section, name = key.split(".", 1)
            data.setdefault(section, {})[name] = k.spec(mean, std)
        for name, value in physics.items():
            section, key = PHYSICS[name]
            if name == "e" and "e" in data.get("restitution", {}):
                key = "e"  # a study with a constant e*
            data.setdefault(section, {})[key] = float(value)
        study = Study.from_dict(data, source=self.source)
        self.runs += 1
        if self.engine == "memory":
            return _solve_memory(study, self.draws, self.seed, columns, observables)
        return self._solve_engine(study, columns, observables)

    def _solve_engine(self, study, columns, observables):
        from mcbat.dataset.load import load
        from mcbat.dataset.schema import si_units
        from mcbat.runner.study_run import run_study

        if set(MOVED_COLUMNS) & set(columns) and _moves_contact(study):
            raise InputError("engine", "a fit of the contact with a trend of [contact] "
                             "(bat_speed_trend, plate_x_trend, plate_z_trend, "
                             "swing_length_trend) runs on engine 'memory' only (the "
                             "datasets hold the contact after the trend moved it)")

        out = self.workdir / f"templates_{self.runs}"
        run_study(study, out, samples=self.draws, seed=self.seed, engine=self.engine,
                  progress=False, overwrite=True)
        flown = any(o in FLIGHT_OBSERVABLES for o in observables)
        df = load(out, columns=[*columns, *observables, "status",
                                *(["flight_status"] if flown else [])])
        ok = df["status"].to_numpy() == 0
        if flown:
            ok &= df["flight_status"].to_numpy() == 0
        # The dataset holds the pitch and the swing in Statcast's units; the proposal's
        # densities are in the kernel's SI, as the in-process draws are.
        inputs = si_units({c: df[c].to_numpy(float) for c in columns})
        return inputs, {c: df[c].to_numpy(float) for c in observables}, ok

    def close(self):
        """Remove the temporary files."""
        self._tmp.cleanup()


def _conditioned_definition(study, pitches, flight=False):
    """The study's definition with its pitches drawn from ``pitches`` (the table's rows),
    each row's batter side, no summary, and its flight only with ``flight``."""
    data = study.definition()
    own = data.get("pitches", {})
    for section in ("summary", "output", "pitches", *(() if flight else ("flight",))):
        data.pop(section, None)
    data.pop("handedness", None)  # each pitch meets the batter who saw it
    pitch = data.get("pitch", {})
    fallback = {}
    for key in PITCH_COLUMNS:
        name = key.split(".", 1)[1]
        if name in pitch:
            fallback[name] = pitch.pop(name)
        elif own.get("fallback", {}).get(name) is not None:  # the study's own fallback
            fallback[name] = own["fallback"][name]
        elif KEYS["pitch"][name][1] is not None:  # the game's default, for rows without
            default, quantity = KEYS["pitch"][name][1], KEYS["pitch"][name][0]
            fallback[name] = {"value": default, "unit": u.SI_UNITS[quantity]}
        # (no default: the speed and approach angles, which every row used has)
    data["pitch"] = pitch
    data["pitches"] = {"file": str(pitches), "fallback": fallback}
    if own.get("swing"):  # the measured swings too, with their errors and fallbacks
        data["pitches"]["swing"] = True
        fallback.update({k: v for k, v in own.get("fallback", {}).items()
                         if f"swing.{k}" in SWING_COLUMNS})
        for key in ("swing_error", "swing_plane"):
            if own.get(key):
                data["pitches"][key] = own[key]
    if "restitution" not in data:  # the game preset, written out so e and e_x can be set
        r = GAME_RESTITUTION
        data["restitution"] = {"e_ref": r.e_ref, "e_slope": r.e_slope,
                               "e_speed_ref": {"value": r.e_speed_ref, "unit": "m/s"},
                               "e_x": r.e_x}
    return data


def _solve_memory(study, draws, seed, columns, observables):
    """Sample and solve the draws in this process (what an engine's chunk does)."""
    from mcbat.runner.pitches import load_pitches

    study = load_pitches(study, player_levels=False)
    inputs = study.sample_inputs(0, draws, seed)
    if any(o in FLIGHT_OBSERVABLES for o in observables):
        batted, ok = _solve_and_fly(study, inputs)
    else:
        batted, ok = solve_game_inputs(study, inputs)
    row = {name: i for i, name in enumerate(GAME_INPUT_FIELDS)}
    drawn = {c: inputs[row[c]].copy() for c in columns}
    moved = [c for c in MOVED_COLUMNS if c in drawn]
    if moved and _moves_contact(study):
        # The weights are densities of the drawn contact (and bat angle), before the trends
        # moved it (the same random numbers without the trends).
        plain = copy.copy(study)
        plain.contact_trend = plain.plate_x_trend = plain.plate_z_trend = None
        plain.swing_length_trend = None
        inputs = plain.sample_inputs(0, draws, seed)
        for c in moved:
            drawn[c] = inputs[row[c]]
    return drawn, {c: np.asarray(batted[c], float) for c in observables}, ok


def _moves_contact(study) -> bool:
    """Whether the study moves each drawn contact (a trend of ``[contact]``)."""
    return any(getattr(study, f"{name}_trend", None) is not None
               for name in ("contact", "plate_x", "plate_z", "swing_length"))


def _solve_and_fly(study, inputs):
    """The batted balls of a game kernel's input rows and their flight (the study's
    ``[flight]``), as an engine's chunk solves and flies them: the Statcast outputs with
    ``hit_distance`` (ft), and the rows both solved and flown."""
    solved = solve_and_fly(inputs, study.solver_settings,
                           study.flight.params(study.ball.mass, study.ball.radius),
                           study.flight.start)
    batted = derive_game(list(solved.velocity), list(solved.spin))
    distance = solved.flight.out[FLIGHT_FIELDS.index("hit_distance")]
    batted["hit_distance"] = distance / u.UNITS["length"]["ft"]
    return batted, ((solved.game.status == ImpactStatus.OK)
                    & (solved.flight.status == FlightStatus.OK))


def simulate_table(study, pitches, rows, seed, values=None):
    """A table of ``rows`` batted balls of ``study`` with its distributions' parameters
    set to ``values`` (``{"swing.bat_speed.mean": 70, "e": 0.5, ...}``, reporting units:
    the study's), each ball meeting a pitch of ``pitches`` (a tidy Statcast table) drawn
    with replacement: the measured pitch columns and the observables, for injection
    tests. A study with a ``[flight]`` flies every ball and writes its distance as
    Statcast's ``hit_distance_sc`` (ft; and as ``hit_distance`` if ``pitches`` has that
    column); without one they are NaN (the resampled pitch row's measured distance belongs
    to another ball)."""
    values = dict(values or {})
    keys, params, physics = parse_free(study, tuple(values)) if values else ({}, [], [])
    flight = study.flight is not None
    observables = tuple(o for o in OBSERVABLES if flight or o not in FLIGHT_OBSERVABLES)
    sim = TemplateSimulator(study, pitches.reset_index(drop=True), rows, seed, "memory", None,
                            flight)
    try:
        proposal = {key: (k, k.mean, k.std) for key, k in keys.items()}
        for name, key, what in params:
            k, mean, std = proposal[key]
            proposal[key] = (k, values[name], std) if what == "mean" else (k, mean,
                                                                            values[name])
        phys = {p: values[p] for p in physics if p in values}
        inputs, observed, ok = sim.run(proposal, phys, ["pitch_speed"], observables)
        from mcbat.runner.pitches import load_pitches

        rewritten = load_pitches(Study.from_dict(sim.base, source=study.source),
                                 player_levels=False)
        ids = rewritten.pitch_identifiers(0, rows, seed)["source_row"]
    finally:
        sim.close()
    table = pitches.reset_index(drop=True).iloc[ids].reset_index(drop=True).copy()
    for o in OBSERVABLES:
        value = observed[o] if o in observed else np.nan
        table[MEASURED_NAMES.get(o, o)] = value  # (Statcast's name: the table is read as one)
        if o in table.columns:  # no measured value of the resampled pitch's ball stays
            table[o] = value
    return table.loc[ok].reset_index(drop=True)
