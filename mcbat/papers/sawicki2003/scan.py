"""The optimal-swing scan: undercut x attack angle, with Monte Carlo scatter, per pitch and model.

Sawicki, Hubbard & Stronge (Am. J. Phys. 71, 1152 (2003)) choose the undercut and the swing
angle that maximise the range of a batted fastball and curveball. This module poses the
same question to mcbat's impact model: the bundled game studies (``game_fastball``,
``game_curveball``) give the pitch, the swing and their scatter; the undercut and the
attack angle become a grid; every cell gets ``PER_CELL`` Monte Carlo samples; the game
kernel solves the impacts and the flight kernel carries the balls to the ground. It is run
twice per pitch: with the rigid model (``e_x = 0``) and with tangential compliance
(``e_x`` of the game preset, ``mcbat.bodies.restitution.GAME_E_X``).

The scan is a game study built in memory (``scan_study``), so it samples and solves
exactly like ``mcbat run``; nothing is written here.
"""

from __future__ import annotations

import copy
import tomllib
from dataclasses import dataclass
from importlib import resources

import numpy as np

from mcbat.bodies.restitution import GAME_RESTITUTION
from mcbat.core import status as st
from mcbat.solving import batted_ball_vectors, solve_games
from mcbat.solving.derived import derive_game
from mcbat.study import Study
from mcbat.study.game import COLUMNS as GAME_COLUMNS

__all__ = ["ATTACK_ANGLES_DEG", "MODELS", "PER_CELL", "PITCHES", "UNDERCUTS_IN", "Scan",
           "centre", "run_scan", "scan_study"]

#: The pitches: name -> bundled game study.
PITCHES = {"fastball": "game_fastball.toml", "curveball": "game_curveball.toml"}
#: The impact models: name -> e_x (rigid: none; compliant: the game preset's).
MODELS = {"rigid": 0.0, "compliant": GAME_RESTITUTION.e_x}
#: The undercut grid (in): start, stop, number of points (0.05 in apart).
UNDERCUTS_IN = (-0.25, 2.25, 51)
#: The attack-angle grid (deg): start, stop, number of points.
ATTACK_ANGLES_DEG = (0.0, 36.0, 10)
#: Monte Carlo samples per (undercut, attack angle) cell.
PER_CELL = 120
#: The scan's seed (the same draws for every pitch and model: common random numbers).
SEED = 2003

# Scatter kept from the game studies: the pitch (speed, spin, axis, approach angles), the
# bat speed and vertical bat angle, mu. Narrowed here: where on the bat (a hitter aiming
# at the sweet spot) and the attack direction (balls to the middle of the field).
_NARROWED = {
    ("contact", "from_barrel_end"): {"dist": "truncnormal", "mean": 6.0, "std": 0.5,
                                     "low": 4.5, "high": 7.5, "unit": "in"},
    ("swing", "attack_direction"): {"dist": "truncnormal", "mean": 0.0, "std": 3.0,
                                    "low": -9.0, "high": 9.0, "unit": "deg"},
}


def _grid(values, unit):
    start, stop, num = values
    return {"dist": "grid", "start": start, "stop": stop, "num": num, "unit": unit}


def grid_points(values):
    """The points of a ``(start, stop, num)`` grid."""
    return np.linspace(*values)


def centre(spec):
    """The centre of a study value: a (truncated) normal's ``mean`` parameter, a uniform's
    midpoint, a fixed value unchanged (a scan without scatter puts every input there)."""
    if not isinstance(spec, dict) or "dist" not in spec:
        return spec
    unit = {"unit": spec["unit"]} if "unit" in spec else {}
    if spec["dist"] in ("truncnormal", "normal"):
        return {"value": spec["mean"], **unit}
    if spec["dist"] == "uniform":
        return {"value": 0.5 * (spec["low"] + spec["high"]), **unit}
    raise ValueError(f"no centre for a {spec['dist']} distribution")


def scan_study(pitch: str, model: str, per_cell: int = PER_CELL, *, centred: bool = False,
               edits=(), undercuts=UNDERCUTS_IN, attack_angles=ATTACK_ANGLES_DEG) -> Study:
    """The scan of ``pitch`` with ``model`` as a game study (in memory).

    The attack angle is the outer grid, the undercut the inner one; sample ``i`` is in
    cell ``i % cells`` (``mcbat.study.distributions.Grid`` order), so every cell
    gets ``per_cell`` samples. ``centred``: every scattered input at its centre
    (``centre``), one deterministic case per cell. ``edits``: ``(section, key,
    value)`` triples applied last (``value`` None removes the key), for variants of the
    scan (``mcbat.papers.sawicki2003.steps``). ``undercuts`` (in) and
    ``attack_angles`` (deg): ``(start, stop, num)`` grids."""
    with resources.files("mcbat.studies").joinpath(PITCHES[pitch]).open("rb") as fh:
        data = tomllib.load(fh)
    data = copy.deepcopy(data)
    cells = attack_angles[2] * undercuts[2]
    data["study"] = {"name": f"sawicki2003_{pitch}_{model}", "samples": cells * per_cell,
                     "seed": SEED,
                     "description": f"optimal-swing scan, {pitch}, {model} impact model"}
    for (section, key), spec in _NARROWED.items():
        data[section][key] = dict(spec)
    rest = GAME_RESTITUTION
    data["restitution"] = {"e_ref": rest.e_ref, "e_slope": rest.e_slope,
                           "e_speed_ref": rest.e_speed_ref, "e_x": MODELS[model]}
    if centred:
        for section in ("pitch", "swing", "contact", "friction"):
            data[section] = {k: centre(v) for k, v in data[section].items()}
    data["swing"]["attack_angle"] = _grid(attack_angles, "deg")
    data["contact"]["undercut"] = _grid(undercuts, "in")
    for section, key, value in edits:
        if value is None:
            data[section].pop(key, None)
        else:
            data.setdefault(section, {})[key] = copy.deepcopy(value)
    return Study.from_dict(data, source=f"sawicki2003 scan ({pitch}, {model})")


@dataclass(frozen=True)
class Scan:
    """One scan's rows (struct of arrays, SI unless the name says otherwise).

    ``attack_angle`` (deg) and ``undercut`` (in) are the grid values of each row;
    ``batted`` has the batted ball in Statcast's conventions (``derive_game``);
    ``flight`` the landing (``mcbat.papers.sawicki2003.carry.fly``)."""

    pitch: str
    model: str
    attack_angle: np.ndarray
    undercut: np.ndarray
    batted: dict
    flight: dict
    ok: np.ndarray


def run_scan(pitch: str, model: str, fly, per_cell: int = PER_CELL, *, study=None,
             cell=None) -> Scan:
    """Solve the scan of ``pitch`` with ``model`` (or ``study``, a variant from
    ``scan_study``); ``fly(v, w)`` carries the batted balls (field-frame velocity and
    spin, ``float64[3, n]``) and returns the flight columns. ``cell``: ``(attack angle
    (deg), undercut (in))``, solve only that cell's samples (the same draws as in the
    whole scan)."""
    if study is None:
        study = scan_study(pitch, model, per_cell)
    inputs = study.sample_inputs(0, study.samples, study.seed)
    if cell is not None:
        col = {name: i for i, name in enumerate(GAME_COLUMNS)}
        keep = (np.isclose(np.degrees(inputs[col["attack_angle"]]), cell[0], atol=1e-9)
                & np.isclose(inputs[col["undercut"]] / 0.0254, cell[1], atol=1e-9))
        if not keep.any():
            raise ValueError(f"no cell at attack angle {cell[0]} deg, undercut {cell[1]} in")
        inputs = np.ascontiguousarray(inputs[:, keep])
    solved = solve_games(inputs, study.solver_settings)
    v, w = batted_ball_vectors(solved)
    col = {name: i for i, name in enumerate(GAME_COLUMNS)}
    return Scan(pitch=pitch, model=model,
                attack_angle=np.round(np.degrees(inputs[col["attack_angle"]]), 9),
                undercut=np.round(inputs[col["undercut"]] / 0.0254, 9),
                batted=derive_game(tuple(v), tuple(w)), flight=fly(v, w),
                ok=solved.status == st.OK)
