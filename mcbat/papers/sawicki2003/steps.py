"""Why mcbat's optimal undercut is smaller than Sawicki et al.'s: one change at a time.

mcbat's optimum (``mcbat reproduce sawicki2003``) sits at an undercut of ~1 cm; Sawicki,
Hubbard & Stronge (2003) report ~2.6 cm. This module re-runs the optimal-swing scan with
one ingredient at a time moved from mcbat's setup towards theirs, and reports where the
optimum goes. Their abstract and their lift (mcbat's ``sawicki2003`` flight model) give
the direction of each step:
no Monte Carlo scatter (they optimise one deterministic case), a level bat in a vertical
plane (their model is planar; mcbat's bat is tilted 30 deg down, so its undercut is
measured in a tilted plane), their lift ``C_L = 1.5 S`` / ``0.09 + 0.6 S`` without spin
decay, the coefficient of friction (their post-impact state does not depend on it), the
coefficient of restitution and the bat radius (their values are not in the sources the
project holds: the steps bracket mcbat's by a plausible margin).

Every step but the first is deterministic (every scattered input at its centre, one case
per cell) on a finer grid than the reproduction's (0.025 in x 1 deg), so its optimum is
the grid's best case, not a noisy cell mean. Rigid impacts (``e_x = 0``), as theirs.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass

import numpy as np

from mcbat.bodies import bat_preset
from mcbat.papers.sawicki2003.carry import SETTINGS, fly
from mcbat.papers.sawicki2003.scan import (
    ATTACK_ANGLES_DEG,
    PER_CELL,
    PITCHES,
    UNDERCUTS_IN,
    run_scan,
    scan_study,
)
from mcbat.study.flight import FlightSettings

__all__ = ["FINE_ATTACK_ANGLES_DEG", "FINE_UNDERCUTS_IN", "STEPS", "THEIR_UNDERCUT_IN", "Step",
           "format_markdown", "markdown_row", "run_step", "run_steps", "to_json"]

#: The deterministic steps' grids: undercut (in) 0.025 in apart, attack angle (deg) 1 deg.
FINE_UNDERCUTS_IN = (-0.25, 2.25, 101)
FINE_ATTACK_ANGLES_DEG = (0.0, 36.0, 37)
#: The impact model of every step: rigid, as Sawicki et al.'s.
MODEL = "rigid"

_CM_PER_IN = 2.54


def _cylinder_bat(radius_m):
    """The R161's mass, length, CM and inertias on a cylinder of ``radius_m``."""
    r161 = bat_preset("r161")
    return {"mass": r161.mass, "length": r161.length,
            "cm_from_barrel_end": r161.cm_from_barrel_end,
            "transverse_inertia": r161.transverse_inertia,
            "axial_inertia": r161.axial_inertia, "radius": radius_m}


#: The R161's barrel radius at the sweet spot, 6 in from the barrel end (m).
R161_SWEET_SPOT_RADIUS = bat_preset("r161").surface_at(
    bat_preset("r161").axial_from_barrel_end(6 * 0.0254))[0]


@dataclass(frozen=True)
class Step:
    """One variant of the scan: ``name`` (the table's row), ``change`` (what moves,
    towards Sawicki et al.), ``edits`` (see ``mcbat.papers.sawicki2003.scan.
    scan_study``), ``flight`` (None: the reproduction's) and ``scatter`` (the
    reproduction's Monte Carlo scan instead of the deterministic one)."""

    name: str
    change: str
    edits: tuple = ()
    flight: FlightSettings | None = None
    scatter: bool = False


_NO_DECAY = FlightSettings(spin_decay_time=None)
_SAWICKI_LIFT = FlightSettings(model="sawicki2003", spin_decay_time=None)
_LEVEL = ("swing", "vertical_bat_angle", {"value": 0.0, "unit": "deg"})

#: The steps, in the table's order.
STEPS = (
    Step("mcbat reproduce sawicki2003", "the reproduction's Monte Carlo scan "
         "(0.05 in x 4 deg cells of 120 samples)", scatter=True),
    Step("no scatter", "every scattered input at its centre (one case per cell)"),
    Step("level bat", "vertical bat angle 0 deg instead of -30 deg: the undercut in the "
         "vertical plane, as in their planar model", edits=(_LEVEL,)),
    Step("mu = 0.2", "friction 0.2 instead of 0.5",
         edits=(("friction", "mu", 0.2),)),
    Step("mu = 0.8", "friction 0.8 instead of 0.5",
         edits=(("friction", "mu", 0.8),)),
    Step("e* + 0.05", "restitution 0.05 higher at every speed",
         edits=(("restitution", "e_ref", 0.605),)),
    Step("e* - 0.05", "restitution 0.05 lower at every speed",
         edits=(("restitution", "e_ref", 0.505),)),
    Step("bat radius + 10 %", "a cylinder with the R161's mass and inertias, radius 10 % "
         "above the R161's at the sweet spot",
         edits=(("bat", "preset", None),)
         + tuple(("bat", k, v) for k, v in
                 _cylinder_bat(1.1 * R161_SWEET_SPOT_RADIUS).items())),
    Step("no spin decay", "the flight's spin kept constant (Nathan's 30 s decay off)",
         flight=_NO_DECAY),
    Step("their lift", "Sawicki et al.'s lift C_L = 1.5 S (S < 0.1), 0.09 + 0.6 S, "
         "no spin decay", flight=_SAWICKI_LIFT),
    Step("level bat + their lift", "both", edits=(_LEVEL,), flight=_SAWICKI_LIFT),
)


#: Sawicki et al.'s optimal undercut, as the comparison point: ~2.6 cm (in).
THEIR_UNDERCUT_IN = 2.6 / 2.54


def run_step(step: Step, pitch: str, *, per_cell: int = PER_CELL, fly_fn=None) -> dict:
    """The optimum of ``step`` for ``pitch``: the best cell's undercut (in and cm),
    attack angle, launch speed and angle, backspin and carry (mean over the cell's
    samples; one sample without scatter); ``loss_at_theirs``: how much shorter the best
    ball is at the grid's undercut nearest Sawicki et al.'s (ft, at its own best attack
    angle). ``fly_fn(v, w)``: a flight instead of the step's."""
    from mcbat.papers.sawicki2003.reproduce import cell_means, optimum

    if step.scatter:
        study = scan_study(pitch, MODEL, per_cell, edits=step.edits)
    else:
        study = scan_study(pitch, MODEL, 1, centred=True, edits=step.edits,
                           undercuts=FINE_UNDERCUTS_IN, attack_angles=FINE_ATTACK_ANGLES_DEG)
    settings = step.flight or SETTINGS
    scan = run_scan(pitch, MODEL, fly_fn or (lambda v, w: fly(v, w, settings)), study=study)
    means = cell_means(scan)
    best = optimum(means)
    out = {k: best[k] for k in ("undercut", "attack_angle", "launch_speed", "launch_angle",
                                "backspin", "distance")}
    out["undercut_cm"] = out["undercut"] * _CM_PER_IN
    cuts = np.unique(means["undercut"])
    theirs = cuts[np.argmin(np.abs(cuts - THEIR_UNDERCUT_IN))]
    out["their_undercut_in"] = float(theirs)
    out["loss_at_theirs"] = best["distance"] - float(
        np.nanmax(means["distance"][means["undercut"] == theirs]))
    return out


def run_steps(steps=STEPS, pitches=tuple(PITCHES), *, per_cell: int = PER_CELL,
              echo=print) -> dict:
    """Every step for every pitch: JSON-ready ``{"steps": [{"name", "change",
    "optimum": {pitch: ...}}], ...}``."""
    t0 = time.perf_counter()
    rows = []
    for step in steps:
        optima = {pitch: run_step(step, pitch, per_cell=per_cell) for pitch in pitches}
        rows.append({"name": step.name, "change": step.change, "optimum": optima})
        echo(f"{step.name}: " + ", ".join(f"{p} {o['undercut_cm']:.2f} cm, "
                                           f"{o['attack_angle']:.0f} deg"
                                           for p, o in optima.items()))
    return {"model": MODEL, "per_cell": per_cell,
            "grids": {"scatter": {"undercut_in": UNDERCUTS_IN,
                                  "attack_angle_deg": ATTACK_ANGLES_DEG},
                      "deterministic": {"undercut_in": FINE_UNDERCUTS_IN,
                                        "attack_angle_deg": FINE_ATTACK_ANGLES_DEG}},
            "units": {"undercut": "in", "undercut_cm": "cm", "attack_angle": "deg",
                      "launch_speed": "mph", "launch_angle": "deg", "backspin": "rpm",
                      "distance": "ft"},
            "steps": rows, "seconds": time.perf_counter() - t0}


def format_markdown(result: dict) -> str:
    """The steps as a Markdown table: per pitch, the optimal undercut (cm), attack angle
    (deg), launch angle (deg), backspin (rpm), carry (ft), and the carry lost at
    Sawicki et al.'s undercut (ft)."""
    pitches = list(result["steps"][0]["optimum"])
    head = "| step | " + " | ".join(
        f"{p}: undercut (cm) | attack (°) | launch (°) | backspin (rpm) | carry (ft) | "
        "at 2.6 cm (ft)" for p in pitches) + " |"
    rule = "|---|" + "---|" * (6 * len(pitches))
    return "\n".join([head, rule] + [markdown_row(row) for row in result["steps"]])


def markdown_row(row: dict) -> str:
    """One step's row of ``format_markdown``'s table."""
    cells = []
    for o in row["optimum"].values():
        cells += [f"{o['undercut_cm']:.2f}", f"{o['attack_angle']:.0f}",
                  f"{o['launch_angle']:.1f}", f"{o['backspin']:.0f}",
                  f"{o['distance']:.1f}", f"−{o['loss_at_theirs']:.1f}"]
    return f"| {row['name']} | " + " | ".join(cells) + " |"


def to_json(result: dict) -> str:
    """``result`` as strict JSON text."""
    return json.dumps(result, indent=2, allow_nan=False, default=_plain) + "\n"


def _plain(value):
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON: {value!r}")
