"""The sections every study shares (mcbat.study.sections): the bodies, the solver, the
study's name, and the columns the bodies fill."""

import numpy as np
import pytest

from mcbat.bodies import BALL_PRESETS
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.errors import InputError
from mcbat.study.sections import (
    check_solver,
    check_study_name,
    exactly_one,
    fill_bodies,
    fixed_number,
    parse_ball,
    parse_bat,
)

BAT = {"mass": 0.9, "radius": 0.033, "transverse_inertia": 0.05, "axial_inertia": 4e-4}


def test_a_ball_preset_or_its_properties_with_units():
    assert parse_ball({"preset": "baseball"}) is BALL_PRESETS["baseball"]
    ball = parse_ball({"mass": {"value": 145, "unit": "g"},
                       "radius": {"value": 3.6, "unit": "cm"}})
    assert (ball.mass, ball.radius, ball.inertia_factor) == (0.145, 0.036, 0.4)
    with pytest.raises(InputError) as info:
        parse_ball({"preset": "baseball", "mass": 0.2})
    assert info.value.field == "ball.mass" and "cannot be combined" in info.value.message
    with pytest.raises(InputError, match="unknown ball preset 'softball'"):
        parse_ball({"preset": "softball"})
    with pytest.raises(InputError) as info:
        parse_ball({"mass": 0.145})
    assert info.value.field == "ball.radius" and "missing" in info.value.message


def test_a_bat_places_its_cm_from_the_knob_or_the_barrel_end():
    bat = parse_bat({**BAT, "length": 0.84, "cm_from_knob": {"value": 56, "unit": "cm"}})
    assert bat.cm_from_barrel_end == pytest.approx(0.28, abs=1e-15)
    for extra, field in (({"cm_from_knob": 0.5}, "bat.cm_from_knob"),  # without a length
                         ({"length": 0.84, "cm_from_knob": 0.5, "cm_from_barrel_end": 0.3},
                          "bat.cm_from_knob"),
                         ({"length": 0.84, "cm_from_barrel_end": 0.9},
                          "bat.cm_from_barrel_end"),
                         ({"cm_from_barrel_end": -0.1}, "bat.cm_from_barrel_end")):
        with pytest.raises(InputError) as info:
            parse_bat({**BAT, **extra})
        assert info.value.field == field, extra
    with pytest.raises(InputError) as info:
        parse_bat({**BAT, "mass": 0.0})
    assert info.value.field == "bat.mass" and "> 0" in info.value.message


def test_a_fixed_number_refuses_distributions_and_non_positive_values():
    assert fixed_number({"value": 2, "unit": "in"}, "bat.radius", "length") == 0.0508
    assert fixed_number(-1.0, "noise.spin", "spin", positive=False) == -1.0
    with pytest.raises(InputError, match="not allowed here"):
        fixed_number({"dist": "uniform", "low": 1, "high": 2}, "ball.mass", "mass")
    with pytest.raises(InputError, match="must be > 0"):
        fixed_number(0, "ball.mass", "mass")


def test_the_solver_section_fills_the_kernel_defaults_and_bounds_the_work():
    assert check_solver({}) == {"steps": DEFAULT_STEPS, "tolerance": DEFAULT_TOLERANCE,
                                "max_steps": DEFAULT_MAX_STEPS}
    assert check_solver({"steps": 8, "tolerance": 1e-10})["steps"] == 8
    for table, field in (({"steps": 10**4 + 1}, "solver.steps"),
                         ({"max_steps": 0}, "solver.max_steps"),
                         ({"tolerance": 1.0}, "solver.tolerance"),
                         ({"step": 3}, "solver.step")):
        with pytest.raises(InputError) as info:
            check_solver(table)
        assert info.value.field == field


def test_exactly_one_of_two_keys():
    assert exactly_one({"e": 0.5}, "restitution", "e", "loss_fraction") == "e"
    with pytest.raises(InputError, match="not both") as info:
        exactly_one({"e": 1, "loss_fraction": 1}, "restitution", "e", "loss_fraction")
    assert info.value.field == "restitution.loss_fraction"
    with pytest.raises(InputError, match="missing key") as info:
        exactly_one({}, "restitution", "e", "loss_fraction")
    assert info.value.field == "restitution"


@pytest.mark.parametrize("name", ["", "  ", "a/b", "..", "a\\b", "x" * 121, "tab\there",
                                  "rtl\u202eevil"])
def test_a_study_name_is_one_plain_directory_name(name):
    with pytest.raises(InputError) as info:
        check_study_name(name)
    assert info.value.field == "study.name"


def test_a_plain_study_name_is_accepted():
    check_study_name("Sec. V drop test, 2012 (20k)")


def test_fill_bodies_writes_the_mass_and_inertia_columns():
    names = ("ball_mass", "ball_radius", "ball_inertia_factor", "bat_mass",
             "bat_transverse_inertia", "bat_axial_inertia")
    cols = {name: np.full(3, np.nan) for name in names}
    fill_bodies(cols, BALL_PRESETS["baseball"], parse_bat(BAT))
    assert [cols[n][0] for n in names] == [0.145, 0.036, 0.4, 0.9, 0.05, 4e-4]
    assert all(np.all(cols[n] == cols[n][0]) for n in names)
