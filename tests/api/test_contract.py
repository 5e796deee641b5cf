"""mcbat.api.contract: JSON -> cases, results -> JSON with units, and a game's answer read
as a flight's input (``mcbat impact game.json | mcbat flight -``)."""

import json
import subprocess
import sys

import pytest

from mcbat.api import (
    FlightCase,
    any_case_from_dict,
    case_from_dict,
    flight_case_from_dict,
    solve_any,
    solve_flight,
)
from mcbat.errors import InputError
from tests.conftest import ROOT

# A game case as `mcbat impact` reads it, in Statcast's units, with a non-default ball.
GAME = {"ball": {"mass": 0.142, "radius": 0.0368},
        "bat": {"preset": "r161"}, "mu": 0.5,
        "pitch": {"speed": {"value": 90, "unit": "mph"},
                  "spin_rate": {"value": 2300, "unit": "rpm"}},
        "swing": {"bat_speed": {"value": 70, "unit": "mph"},
                  "attack_angle": {"value": 12, "unit": "deg"}},
        "contact": {"undercut": {"value": 0.5, "unit": "in"}}}


def _answer():
    """The game's answer, through JSON text as `mcbat impact` prints it."""
    return json.loads(json.dumps(solve_any(case_from_dict(GAME)).to_dict()))


def test_a_games_answer_is_a_flight_input_read_in_its_units():
    answer = _answer()
    case = flight_case_from_dict(answer)
    assert case.launch_speed == pytest.approx(answer["launch_speed"] * 0.44704, rel=1e-15)
    assert case.backspin == pytest.approx(answer["backspin"] * 3.141592653589793 / 30,
                                          rel=1e-12)
    assert (case.ball.mass, case.ball.radius) == (0.142, 0.0368)  # the game's ball
    assert isinstance(any_case_from_dict(answer), FlightCase)
    # an explicit ball and flight keys still apply
    other = flight_case_from_dict({**answer, "ball": {"preset": "baseball"},
                                   "atmosphere": {"elevation": {"value": 1000, "unit": "m"}}})
    assert other.ball.mass == 0.145 and other.settings.elevation == 1000
    in_feet = flight_case_from_dict({**answer, "atmosphere": {"elevation": 5200}})
    assert in_feet.settings.elevation == pytest.approx(5200 * 0.3048, rel=1e-15)


def test_a_games_answer_without_its_units_block_is_read_the_same():
    """Its bare numbers are in the field's units, which is what the block says."""
    answer = _answer()
    with_block = flight_case_from_dict(answer)
    del answer["units"]
    assert flight_case_from_dict(answer) == with_block


def test_a_units_block_names_launch_units_only_and_valid_ones():
    plain = {"launch_speed": 103, "launch_angle": 27, "backspin": 2000,
             "units": {"launch_speed": "mph", "launch_angle": "deg", "backspin": "rpm"}}
    by_block = flight_case_from_dict(plain)
    by_tables = flight_case_from_dict({"launch_speed": {"value": 103, "unit": "mph"},
                                       "launch_angle": {"value": 27, "unit": "deg"},
                                       "backspin": {"value": 2000, "unit": "rpm"}})
    assert by_block == by_tables
    for units, field in (({"launch_speed": "furlong"}, "units.launch_speed"),
                         ({"launch_angle": "mph"}, "units.launch_angle"),
                         ({"wind": "mph"}, "units.wind"),
                         ({"launch_speed": {"unit": "mph"}}, "units.launch_speed")):
        with pytest.raises(InputError) as info:
            flight_case_from_dict({"launch_speed": 90, "launch_angle": 25, "units": units})
        assert info.value.field == field
    with pytest.raises(InputError) as info:  # not a game's answer: its keys are unknown
        flight_case_from_dict({"launch_speed": 90, "launch_angle": 25, "status": "ok"})
    assert info.value.field == "status"
    # a unit the block names replaces the field's
    si = flight_case_from_dict({"launch_speed": 40, "launch_angle": 0.4,
                                "units": {"launch_speed": "m/s", "launch_angle": "rad"}})
    assert (si.launch_speed, si.launch_angle) == (40.0, 0.4)


def test_a_value_out_of_range_in_its_stated_unit_is_refused_with_its_value():
    with pytest.raises(InputError) as info:
        flight_case_from_dict({"launch_speed": -90, "launch_angle": 27,
                               "units": {"launch_speed": "mph", "launch_angle": "deg"}})
    assert info.value.field == "launch_speed" and "got -90 mph" in info.value.message


def test_mcbat_impact_piped_into_mcbat_flight(tmp_path):
    path = tmp_path / "game.json"
    path.write_text(json.dumps(GAME))
    impact = subprocess.run([sys.executable, "-m", "mcbat", "impact", str(path)],
                            capture_output=True, text=True, cwd=ROOT, check=False)
    assert impact.returncode == 0, impact.stderr
    assert json.loads(impact.stdout)["units"]["launch_speed"] == "mph"
    flight = subprocess.run([sys.executable, "-m", "mcbat", "flight", "-"],
                            input=impact.stdout, capture_output=True, text=True, cwd=ROOT,
                            check=False)
    assert flight.returncode == 0, flight.stderr
    expected = solve_flight(FlightCase.from_result(solve_any(case_from_dict(GAME))))
    assert json.loads(flight.stdout)["hit_distance"] == pytest.approx(expected.hit_distance,
                                                                      rel=1e-12)
