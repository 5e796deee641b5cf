"""A unit a measured table states is checked against where the column's real values lie:
launch speeds near 90 stated in m/s, or near 40 stated in mph, are refused with the unit
they look like; values that fit their stated unit pass."""

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.stats.compare.units import PLAUSIBLE_ROWS, unit_contradiction


@pytest.mark.parametrize("values, unit, looks_like", [
    (np.full(50, 89.6), "m/s", "mph"),        # a Statcast export read as m/s
    (np.full(50, 40.1), "mph", "m/s"),        # m/s labelled mph
    (np.full(50, 144.0), "mph", "km/h"),      # km/h labelled mph
    (np.full(50, 0.3), "deg", None),          # launch angles in rad labelled deg: in range
])
def test_launch_speeds_in_the_wrong_unit(values, unit, looks_like):
    column = "launch_speed" if looks_like or unit != "deg" else "launch_angle"
    error = unit_contradiction(column, values, unit)
    if looks_like is None:
        assert error is None
        return
    assert isinstance(error, InputError)
    assert error.field == column
    assert f"stated in {unit}, but the values' median {np.median(values):.4g} {unit}" in \
        error.message
    assert error.mentions["units"] == {column: looks_like}


@pytest.mark.parametrize("column, values, unit", [
    ("launch_speed", np.linspace(60, 115, 60), "mph"),
    ("launch_speed", np.linspace(60, 115, 60) * 0.44704, "m/s"),
    ("hit_distance", np.linspace(5, 430, 60), "ft"),
    ("launch_angle", np.linspace(-40, 60, 60), "deg"),
    ("launch_angle", np.radians(np.linspace(-40, 60, 60)), "rad"),
    ("pitch_speed", np.linspace(75, 100, 60), "mph"),
    ("exit_speed", np.linspace(1, 3, 60), "furlong"),  # a unit it does not know: no check
    ("impact_parameter", np.linspace(-0.02, 0.02, 60), "m"),  # a column it has no range of
])
def test_values_that_fit_their_unit_pass(column, values, unit):
    assert unit_contradiction(column, values, unit) is None


def test_too_few_values_are_not_judged():
    assert unit_contradiction("launch_speed", np.full(PLAUSIBLE_ROWS - 1, 90.0), "m/s") \
        is None
    assert unit_contradiction("launch_speed", np.full(PLAUSIBLE_ROWS, 90.0), "m/s") \
        is not None


def test_a_degree_angle_stated_in_radians_is_refused():
    error = unit_contradiction("launch_angle", np.full(30, 25.0), "rad")
    assert error is not None and error.mentions["units"] == {"launch_angle": "deg"}
