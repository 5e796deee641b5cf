"""Sections and keys shared by every kind of study (bat-frame and game): the bodies
(``[ball]``, ``[bat]``), ``[solver]``, the study's name, and the columns the bodies fill.

The file format is described in ``docs/study-format.md``.
"""

from __future__ import annotations

import unicodedata

from mcbat.bodies import BALL_PRESETS, BAT_PRESETS, Ball, Bat, bat_preset
from mcbat.checks import check_keys, check_string, check_tolerance, integer
from mcbat.errors import InputError
from mcbat.solving import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.study import units as u
from mcbat.study.distributions import check_range, parse

__all__ = ["BALL_KEYS", "BAT_KEYS", "check_solver", "check_study_name", "exactly_one",
           "fill_bodies", "fixed_number", "parse_ball", "parse_bat"]

#: The explicit keys of ``[ball]`` and ``[bat]`` (besides ``preset``) and their quantities.
BALL_KEYS = {"mass": u.MASS, "radius": u.LENGTH, "inertia_factor": u.DIMENSIONLESS}
BAT_KEYS = {"mass": u.MASS, "radius": u.LENGTH, "transverse_inertia": u.INERTIA,
            "axial_inertia": u.INERTIA, "length": u.LENGTH, "cm_from_barrel_end": u.LENGTH,
            "cm_from_knob": u.LENGTH}
_BAT_REQUIRED = ("mass", "radius", "transverse_inertia", "axial_inertia")


def fixed_number(spec, field, quantity, *, positive=True):
    """A fixed number (plain or ``{value, unit}``) in SI, ``> 0`` if ``positive``."""
    dist = parse(spec, field, quantity, kinds=("fixed",))
    if positive:
        check_range(dist, minimum=0.0, strict_minimum=True, what=field.rsplit(".", 1)[-1])
    return dist.value


def _preset_name(table, section, presets):
    """The ``preset`` of a ``[ball]`` or ``[bat]`` table, alone and one of ``presets``."""
    for key in table:
        if key != "preset":
            raise InputError(f"{section}.{key}", "cannot be combined with 'preset' (give "
                                                 f"either a preset or the {section}'s "
                                                 "properties)")
    name = check_string(table["preset"], f"{section}.preset")
    if name not in presets:
        raise InputError(f"{section}.preset", f"unknown {section} preset {name!r} "
                                              f"(expected one of: {', '.join(presets)})")
    return name


def parse_ball(table):
    """The ``[ball]`` section: a ``mcbat.bodies.ball.Ball`` (preset or explicit keys)."""
    check_keys(table, "ball", (), ("preset",) + tuple(BALL_KEYS))
    if "preset" in table:
        return BALL_PRESETS[_preset_name(table, "ball", BALL_PRESETS)]
    check_keys(table, "ball", ("mass", "radius"), ("inertia_factor",))
    values = {k: fixed_number(v, f"ball.{k}", BALL_KEYS[k]) for k, v in table.items()}
    return Ball(**values)


def parse_bat(table):
    """The ``[bat]`` section: a ``mcbat.bodies.bat.Bat`` (preset or explicit keys)."""
    check_keys(table, "bat", (), ("preset",) + tuple(BAT_KEYS))
    if "preset" in table:
        return bat_preset(_preset_name(table, "bat", BAT_PRESETS))
    check_keys(table, "bat", _BAT_REQUIRED, ("length", "cm_from_barrel_end", "cm_from_knob"))
    values = {}
    for key, spec in table.items():
        values[key] = fixed_number(spec, f"bat.{key}", BAT_KEYS[key],
                                   positive=key not in ("cm_from_barrel_end", "cm_from_knob"))
    if "cm_from_knob" in values:  # the CM from the knob (game bats): from the barrel end
        if "cm_from_barrel_end" in values or "length" not in values:
            raise InputError("bat.cm_from_knob", "needs bat.length, and not "
                             "bat.cm_from_barrel_end too")
        values["cm_from_barrel_end"] = values["length"] - values.pop("cm_from_knob")
    cm = values.get("cm_from_barrel_end")
    if cm is not None:
        length = values.get("length")
        if cm < 0.0 or (length is not None and cm > length):
            limit = "" if length is None else f" and <= the length {length:.6g} m"
            raise InputError("bat.cm_from_barrel_end",
                             f"must be >= 0{limit}, got {cm:.6g} m")
    return Bat(**values)


def check_solver(table):
    """The ``[solver]`` section, validated, with the kernel's defaults filled in."""
    check_keys(table, "solver", (), ("steps", "tolerance", "max_steps"))
    # Upper bounds keep one impact's work bounded (a step budget of 10^6 is ~0.1 s).
    steps = integer(table.get("steps", DEFAULT_STEPS), "solver.steps", minimum=1,
                    maximum=10**4)
    max_steps = integer(table.get("max_steps", DEFAULT_MAX_STEPS), "solver.max_steps",
                        minimum=1, maximum=10**6)
    tolerance = check_tolerance(table.get("tolerance", DEFAULT_TOLERANCE), "solver.tolerance")
    return {"steps": steps, "tolerance": tolerance, "max_steps": max_steps}


def exactly_one(table, section, a, b):
    """The one of keys ``a`` and ``b`` that ``table`` (section ``section``) has, or
    ``InputError`` when it has both or neither."""
    if a in table and b in table:
        raise InputError(f"{section}.{b}", f"give exactly one of '{a}' or '{b}', not both")
    if a not in table and b not in table:
        raise InputError(section, f"missing key: give exactly one of '{a}' or '{b}'")
    return a if a in table else b


def check_study_name(name: str) -> None:
    """A study name is the default output directory's name (``results/<name>``): one
    plain directory name, never a path that leads elsewhere."""
    # Every control, format and line/paragraph separator character: C0 and C1 controls
    # (U+0085 ends a line in some tools), U+2028/2029, and the bidirectional overrides
    # (U+202E shows the name reversed in a listing).
    bad = next((c for c in name if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")),
               None)
    if bad is not None:
        raise InputError("study.name", f"must not contain control characters, got "
                         f"{name!r}")
    if not name.strip():
        raise InputError("study.name", "must not be empty")
    if "/" in name or "\\" in name or name.strip() in (".", "..") or len(name) > 120:
        raise InputError("study.name", f"must be a plain directory name (no '/' or '\\', "
                         f"not '.' or '..', at most 120 characters), got {name!r}")


def fill_bodies(cols, ball, bat) -> None:
    """Fill the ball's and the bat's mass and inertia columns of ``cols`` in place."""
    cols["ball_mass"][:] = ball.mass
    cols["ball_radius"][:] = ball.radius
    cols["ball_inertia_factor"][:] = ball.inertia_factor
    cols["bat_mass"][:] = bat.mass
    cols["bat_transverse_inertia"][:] = bat.transverse_inertia
    cols["bat_axial_inertia"][:] = bat.axial_inertia
